// SPDX-License-Identifier: MIT
#include "graphslam/init/initial_guess.h"

#include <cstdio>
#include <set>
#include <string>
#include <typeinfo>

#include "graphslam/init/chordal_se3.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam3d/edges.h"

namespace graphslam::init {

namespace {
std::string describe(const char* kind, const InitializationReport& r) {
  if (!r.message.empty()) return r.message;
  char text[200];
  const int n = std::snprintf(text, sizeof text, "%s, %zu poses and %zu landmarks placed in %.4f s",
                              kind, r.poses, r.landmarks, r.seconds);
  if (r.analysis_seconds > 0.0 && n > 0 && static_cast<std::size_t>(n) < sizeof text) {
    // The ordering is the pose graph's: a solver sharing the ordering cache reuses it.
    std::snprintf(text + n, sizeof text - static_cast<std::size_t>(n),
                  " (%.4f s of it ordering and analysing the pose graph)", r.analysis_seconds);
  }
  return text;
}

/// Whether an edge takes part in initializeGlobal() or initializeChordal3d().
bool usedByInitialisation(const Edge& e) {
  return dynamic_cast<const types_slam2d::EdgeSE2*>(&e) ||
         dynamic_cast<const types_slam2d::EdgePriorSE2*>(&e) ||
         dynamic_cast<const types_slam2d::EdgeSE2XY*>(&e) ||
         dynamic_cast<const types_slam3d::EdgeSE3*>(&e) ||
         dynamic_cast<const types_slam3d::EdgeSE3PointXYZ*>(&e);
}

/// "N edges (T, ...) take no part ..." when the initial guess placed
/// vertices and some edges (custom ones, say) were not used for it; else empty.
std::string unusedEdgesLine(const Graph& graph) {
  std::size_t unused = 0;
  std::set<std::string> types;
  for (const auto& e : graph.edges()) {
    if (usedByInitialisation(*e)) continue;
    ++unused;
    if (types.size() < 3) types.insert(typeName(typeid(*e)));
  }
  if (unused == 0) return {};
  std::string names;
  for (const auto& t : types) names += (names.empty() ? "" : ", ") + t;
  return std::to_string(unused) + (unused == 1 ? " edge (" : " edges (") + names +
         (types.size() < 3 ? "" : ", ...") + (unused == 1 ? ") takes" : ") take") +
         " no part in the initial guess: only the optimisation uses " +
         (unused == 1 ? "it" : "them");
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
  // A failure is always said; "nothing to initialise" only when neither part applies.
  if (r2.poses > 0 || r2.failed || (!r2.message.empty() && r3.poses == 0 && r3.message.empty())) {
    out.lines.push_back(describe("global", r2));
  }
  if (r3.poses > 0 || r3.failed || (!r3.message.empty() && r2.poses == 0 && r2.message.empty())) {
    out.lines.push_back(describe("global 3D (chordal)", r3));
  }
  if (r2.failed || r3.failed) {
    // said above
  } else if (r2.poses == 0 && r3.poses == 0 && !r2.message.empty() && !r3.message.empty()) {
    out.lines.push_back("no EDGE_SE2 or EDGE_SE3:QUAT in the graph: nothing to initialise");
  } else if (std::string unused = unusedEdgesLine(graph); !unused.empty()) {
    out.lines.push_back(std::move(unused));
  }
  return out;
}

}  // namespace graphslam::init
