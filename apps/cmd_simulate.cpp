// SPDX-License-Identifier: MIT
// graphslam simulate: a seeded Manhattan-world graph and its ground truth.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "graphslam/core/io_g2o.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::apps {

namespace {

/// Refuses sizes whose graph would not fit in three quarters of this machine's memory (the
/// simulator would otherwise run on for minutes and then be killed).
void checkSimulationSize(const simulation::ManhattanOptions& sim) {
  const simulation::ManhattanSize size = simulation::estimateSize(sim);
  const double memory =
      static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGESIZE));
  if (memory > 0 && size.bytes > 0.75 * memory) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "%d poses and %d landmarks would make about %.3g landmark observations and "
                  "take about %.1f GB, more than this machine's memory allows (%.1f GB)",
                  sim.num_poses, sim.num_landmarks, size.observations, size.bytes / 1e9,
                  memory / 1e9);
    throw UsageError(text);
  }
}

}  // namespace

int cmdSimulate(const std::vector<std::string>& args) {
  std::string output, truth;
  simulation::ManhattanOptions sim;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("output,o", po::value(&output),
                                                 "write the graph (odometry initial guess) here")(
      "truth", po::value(&truth), "write the ground truth graph (same edges, true vertices) here")(
      "poses", po::value(&sim.num_poses)->default_value(sim.num_poses), "number of poses")(
      "landmarks", po::value(&sim.num_landmarks)->default_value(0), "number of landmarks")(
      "seed", po::value(&sim.seed)->default_value(sim.seed), "random seed")(
      "world-size", po::value(&sim.world_size)->default_value(0),
      "side of the square world in grid cells (0: automatic)");
  const auto vm = parse(args, desc);
  if (vm.count("help")) {
    printHelp(
        "usage: graphslam simulate -o OUT.g2o [--truth GT.g2o] [--poses N] [--landmarks L] [--seed "
        "S]\n"
        "Writes a seeded synthetic Manhattan-world pose graph, optionally with landmarks.",
        desc);
    return kExitOk;
  }
  if (output.empty()) throw UsageError("simulate needs -o OUT.g2o");
  if (sim.num_poses < 2) throw UsageError("--poses must be at least 2");
  if (sim.num_landmarks < 0) throw UsageError("--landmarks must be at least 0");
  if (sim.world_size < 0) throw UsageError("--world-size must be at least 0 (0: automatic)");
  checkSimulationSize(sim);
  if (!truth.empty() && truth == output) {
    throw UsageError("--truth and -o name the same file, " + output);
  }
  Registries reg;
  loadRegistries(reg, {});
  auto result = simulation::simulateManhattan(sim);
  io::saveG2o(output, result.graph, reg.types);
  std::cout << "wrote " << output << ": " << result.graph.numVertices() << " vertices, "
            << result.graph.numEdges() << " edges (" << result.num_loop_closures
            << " loop closures, " << result.num_observations << " landmark observations)\n";
  if (!truth.empty()) {
    for (int i = 0; i < sim.num_poses; ++i) {
      static_cast<types_slam2d::VertexSE2*>(result.graph.vertex(i))
          ->setEstimate(result.true_poses[i]);
    }
    for (std::size_t k = 0; k < result.true_landmarks.size(); ++k) {
      static_cast<types_slam2d::VertexXY*>(result.graph.vertex(sim.num_poses + static_cast<int>(k)))
          ->setEstimate(result.true_landmarks[k]);
    }
    io::saveG2o(truth, result.graph, reg.types);
    std::cout << "wrote " << truth << " (ground truth)\n";
  }
  return kExitOk;
}

}  // namespace graphslam::apps
