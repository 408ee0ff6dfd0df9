// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"

namespace graphslam::init {

/// What initializeGlobal() did.
struct InitializationReport {
  std::size_t poses = 0;      ///< VertexSE2 estimates replaced
  std::size_t landmarks = 0;  ///< VertexXY estimates replaced
  double seconds = 0.0;
  /// Of `seconds`, those of the linear solver's analyses: its fill-reducing ordering of the
  /// pose graph, which a solver sharing its OrderingCache (the optimizer's, in the tool)
  /// reuses, included.
  double analysis_seconds = 0.0;
  std::string message;  ///< empty on success; says what was skipped otherwise
  /// A system was not solved (the message says which, and the linear solver's reason):
  /// the estimates were kept. False when there was merely nothing to initialise.
  bool failed = false;
};

/// Global initial guess for SE(2) graphs, in two linear least-squares steps:
///  1. orientations by chordal relaxation: each rotation as a vector (cos, sin) of R^2,
///     EDGE_SE2 asking r_j = R(dtheta) r_i and EDGE_PRIOR_SE2 r_i = r(z), weighted by the
///     angular information; the solution's directions are the angles (no 2*pi ambiguity,
///     robust to large rotation noise);
///  2. positions of poses and landmarks: with orientations known, EDGE_SE2, EDGE_SE2_XY
///     and EDGE_PRIOR_SE2 are linear in the translations and are solved jointly.
/// Fixed vertices and priors anchor the solution; a connected group without either keeps
/// its lowest-id pose where it is (so the result stays in the caller's frame).
/// Replaces the estimates of every free VertexSE2 reached by an EDGE_SE2 and of every
/// free VertexXY observed by an EDGE_SE2_XY from such a pose; other vertices and edge
/// types are left alone. Works on graphs whose estimates are all zero (edges-only files).
/// The two systems (2 unknowns per pose, 2 per pose and landmark) are solved with Eigen's
/// simplicial LDL^T (AMD ordering).
InitializationReport initializeGlobal(Graph& graph);

/// The same, solving both systems with `solver` (from a SolverRegistry; "auto" picks a
/// nested-dissection ordering and a supernodal factorisation on large graphs, where the
/// default takes minutes). A null solver means the default.
InitializationReport initializeGlobal(Graph& graph, LinearSolver* solver);

/// Which edges an initialisation may use (true: use it).
using EdgeFilter = std::function<bool(const Edge&)>;

/// The same from the edges `use_edge` accepts only (all when it is empty): e.g. the
/// odometry and priors of a graph whose loop closures may be wrong, which would spoil a
/// guess made from every edge. Vertices that no accepted edge reaches are left alone.
InitializationReport initializeGlobal(Graph& graph, LinearSolver* solver,
                                      const EdgeFilter& use_edge);

/// A factor on an edge's information in the initialisation (0: the edge is not used).
using EdgeWeight = std::function<double(const Edge&)>;

/// The same with every edge's information scaled by `weight` (all 1 when it is empty):
/// the weighted least-squares problems of both steps, e.g. for graduated non-convexity
/// over the initialisation (outliers::robustInitialization).
InitializationReport initializeGlobalWeighted(Graph& graph, LinearSolver* solver,
                                              const EdgeWeight& weight);

}  // namespace graphslam::init
