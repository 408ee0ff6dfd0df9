// SPDX-License-Identifier: MIT
// The graphslam tool's commands, known to the launcher (main.cpp) without loading them.
#pragma once

#include <cstring>

namespace graphslam::apps {

inline constexpr const char* kMainUsage =
    "usage: graphslam COMMAND [options]   (graphslam COMMAND --help for each)\n"
    "\n"
    "commands:\n"
    "  optimize       optimise a .g2o graph, a .npz homework file or the built-in default graph\n"
    "  simulate       write a synthetic Manhattan-world graph with ground truth\n"
    "  eval           trajectory error: eval ape|rpe REF EST (evo's definitions)\n"
    "  deadreckon     compose relative poses (3xN matrix file or a pose graph's odometry chain)\n"
    "  convert        graphs between formats (.g2o, TORO, iSAM, .npz, matrix); poses to TUM/KITTI\n"
    "  info           counts, components, fixed vertices, sparsity picture of H\n"
    "  drivebot       DriveBot simulator + online SLAM (UCL COMP0130 coursework 2 experiments)\n"
    "  solvers        every linear solver and ordering on a graph's system: times, fill, accuracy\n"
    "  add-outliers   append seeded random wrong loop closures to a 2D pose graph\n"
    "  incremental    replay a graph pose by pose through the incremental optimizer, timed\n"
    "  view           write one self-contained web page to explore a 2D or 3D graph\n"
    "  calibrate      measure the factorisation backends and fit the default solver's cost model\n"
    "  certify        prove a pose graph's SE-Sync optimum global (certificate, staircase)\n"
    "  list-types     list the .g2o tags this build knows\n"
    "  list-solvers   list the linear solvers this build knows\n"
    "  list-kernels   list the robust kernels this build knows (optimize --robust-kernel)\n";

/// The command names of kMainUsage.
inline constexpr const char* kCommands[] = {
    "optimize", "simulate",   "eval",         "deadreckon",  "convert", "info",
    "drivebot", "solvers",    "add-outliers", "incremental", "view",    "calibrate",
    "certify",  "list-types", "list-solvers", "list-kernels"};

[[nodiscard]] inline bool isCommand(const char* name) {
  for (const char* c : kCommands) {
    if (std::strcmp(c, name) == 0) return true;
  }
  return false;
}

}  // namespace graphslam::apps
