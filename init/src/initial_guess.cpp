// SPDX-License-Identifier: MIT
#include "graphslam/init/initial_guess.h"

#include <cstdio>

#include "graphslam/init/chordal_se3.h"
#include "graphslam/init/global_se2.h"

namespace graphslam::init {

namespace {
std::string describe(const char* kind, const InitializationReport& r) {
  if (!r.message.empty()) return r.message;
  char text[160];
  std::snprintf(text, sizeof text, "%s, %zu poses and %zu landmarks placed in %.4f s", kind,
                r.poses, r.landmarks, r.seconds);
  return text;
}
}  // namespace

InitialGuessReport initializeGraph(Graph& graph, const SolverRegistry& solvers,
                                   const std::string& solver) {
  const auto linear_solver = solvers.create(solver);
  const InitializationReport r2 = initializeGlobal(graph, linear_solver.get());
  const InitializationReport r3 = initializeChordal3d(graph, linear_solver.get());
  InitialGuessReport out;
  out.poses = r2.poses + r3.poses;
  out.landmarks = r2.landmarks + r3.landmarks;
  if (r2.poses > 0 || (!r2.message.empty() && r3.poses == 0 && r3.message.empty())) {
    out.lines.push_back(describe("global", r2));
  }
  if (r3.poses > 0 || (!r3.message.empty() && r2.poses == 0 && r2.message.empty())) {
    out.lines.push_back(describe("global 3D (chordal)", r3));
  }
  if (r2.poses == 0 && r3.poses == 0 && !r2.message.empty() && !r3.message.empty()) {
    out.lines.push_back("no EDGE_SE2 or EDGE_SE3:QUAT in the graph: nothing to initialise");
  }
  return out;
}

}  // namespace graphslam::init
