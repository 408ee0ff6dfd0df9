// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/incremental/incremental_optimizer.h"
#include "graphslam/optimizer/optimizer.h"

namespace graphslam::incremental {

/// Replaying a loaded graph pose by pose through an IncrementalOptimizer, as a robot would
/// have built it. The protocol (fixed, so that figures of different optimizers compare):
///  - poses are the vertices of the pose type, the tag of the vertices of the largest
///    dimension (the most common such tag when several have it: VERTEX_SE2,
///    VERTEX_SE3:QUAT), taken in id order; every other vertex is a landmark;
///  - step k adds pose k and every edge whose largest pose endpoint is k (the edges of a
///    step in file order, those without a pose endpoint last), then calls update() once;
///    the step's time is that update()'s wall time (std::chrono::steady_clock);
///  - pose k starts at the estimate composed from the current estimate of pose k-1 (the
///    previous pose in id order, in the optimizer's graph) and the odometry edge between
///    the two (the first edge in file order joining exactly those two poses); the first
///    pose, a fixed pose and a pose without such an edge (a gap) take the file's estimate;
///  - a landmark is added with its first observation (the first edge of the earliest step
///    that refers to it) and starts where that edge puts it;
///  - an edge without a pose endpoint comes at the step where the last of its landmarks
///    is added; a landmark without any edge to a pose is added at the first step with the
///    file's estimate;
///  - the file's parameters (PARAMS_* lines) are copied before the first step; inactive
///    edges are left out, as optimizers leave them out.
/// "Where an edge puts a vertex" is found for any edge type by solving that one edge's
/// error for the vertex (the other vertices held at their current estimates): Gauss-Newton
/// on e^T Omega e with the edge's Jacobian of the vertex's slot, from the estimate of a
/// vertex of the same type in the edge (the pose it is composed from), or else the type's
/// default estimate. When that Jacobian is rank deficient (a bearing-only observation
/// determines no range) the vertex takes the file's estimate and is counted.
/// Every object is created through the TypeRegistry (graph_copy.h), so any registered type
/// replays.

/// What replayGraph records of each step.
struct ReplayStep {
  VertexId pose = -1;
  int new_edges = 0;
  int new_landmarks = 0;
  double seconds = 0.0;  ///< wall time of the step's update()
  UpdateStats stats;     ///< the update()'s lastStats()
  /// Objective after the step (sum of the edges' robust chi2), with record_chi2.
  double chi2 = std::numeric_limits<double>::quiet_NaN();
};

/// Options of replayGraph.
struct ReplayOptions {
  /// The incremental optimizer's options.
  Options optimizer;
  /// Compute the objective after every step (ReplayStep::chi2): one evaluation of every
  /// edge per step, outside the timed part. Off: NaN.
  bool record_chi2 = false;
  /// Single-edge initialisation: Gauss-Newton iterations at most...
  int init_max_iterations = 20;
  /// ...stopping when the step's Euclidean norm is below this.
  double init_step_tolerance = 1e-12;
  /// The Jacobian of the vertex's slot counts as rank deficient when the smallest
  /// eigenvalue of J^T Omega J is below this fraction of the largest (1e-10: a condition
  /// number of 1e5 in J; a bearing-only Jacobian's zero eigenvalue is at rounding level).
  double init_rank_tolerance = 1e-10;
  /// When Gauss-Newton fails from the first start (J rank deficient or not finite there: a
  /// range-bearing landmark started at the observing pose's position), it starts once more
  /// from that start moved by this in every tangent direction before the vertex is counted.
  double init_restart_offset = 1.0;
  /// After the last step, IncrementalOptimizer::refine(refine_threshold) when > 0: every
  /// vertex whose step from its linearisation point exceeds it relinearised until none
  /// does. Not a step (not in total_seconds); ReplayResult reports it apart. 0: off.
  double refine_threshold = 0.0;
  /// Called after every step, outside the timed part, with the step's index, what it
  /// recorded and the graph as it now stands (e.g. to compare it with a batch solve).
  std::function<void(std::size_t step, const ReplayStep&, const Graph&)> after_step;
  /// Fixed-lag smoothing (optimizer.window enabled): every pose is a state of the window
  /// (IncrementalOptimizer::addState), stamped with its first line parameter when its type
  /// has one (VERTEX_VEHICLE's time), else unstamped. An edge of the file to a marginalised
  /// vertex (a loop closure or landmark observation reaching behind the window) is refused
  /// by the optimizer and counted (ReplayResult::refused_edges), not added; with
  /// optimizer.window.reinitialize_landmarks a marginalised landmark seen again is added
  /// anew, placed by that observation (the protocol's first observation).
  ///
  /// Checkpoints: after every checkpoint_every-th step (0: never), the optimizer's state
  /// and the replay's position go to checkpoint_path (IncrementalOptimizer::saveCheckpoint),
  /// with checkpoint_note()'s string when set (the caller's own position, e.g. the length of
  /// a file it appends to).
  std::string checkpoint_path;
  std::size_t checkpoint_every = 0;
  std::function<std::string()> checkpoint_note;
  /// Resume from this checkpoint (written by a replay of the same source with the same
  /// options): the target starts as the file's graph and the replay continues at the step
  /// after it; on_resume receives the caller's note. Fed the same source, the replay then
  /// reaches the estimates of the uninterrupted replay bit for bit.
  std::string resume_path;
  std::function<void(const std::string& note)> on_resume;
};

/// Result of replayGraph.
struct ReplayResult {
  std::vector<ReplayStep> steps;
  std::string pose_tag;  ///< the tag of the poses
  std::size_t num_landmarks = 0;
  double total_seconds = 0.0;  ///< sum of the steps' update() times
  /// Objective after the last step's update (of the graph replayed up to the failing step,
  /// on a failure), before any refine().
  double final_chi2 = 0.0;
  /// With ReplayOptions::refine_threshold: the objective after refine(), its wall time and
  /// what it did (NaN, 0 and empty otherwise).
  double refined_chi2 = std::numeric_limits<double>::quiet_NaN();
  double refine_seconds = 0.0;
  UpdateStats refine_stats;
  /// Vertices that took the file's estimate because their first edge's Jacobian was rank
  /// deficient (or that have no edge to a pose: landmarks only).
  int initialised_from_file = 0;
  /// Poses after the first without an odometry edge to the previous pose (file's estimate).
  int gaps = 0;
  /// The step the replay started at (after a resume: the step after the checkpoint's).
  std::size_t first_step = 0;
  /// Edges of the file refused because they reach a marginalised vertex, and the first
  /// refusal's message (naming the vertex).
  std::size_t refused_edges = 0;
  std::string first_refusal;
  std::size_t marginalized = 0;     ///< vertices marginalised out of the window in all
  std::size_t window_vertices = 0;  ///< vertices in the graph at the end
  bool ok = true;
  /// On a failed update(): "step S (pose P): " and the failure's message, which names the
  /// vertex whose column failed ("the final refine(): " and the message when refine() failed).
  std::string error;
};

/// Replays `source` into `target` (which must be empty: throws graphslam::Error otherwise)
/// with the protocol above, through an IncrementalOptimizer with `options.optimizer`.
/// Objects are created through `types` (graphslam::Error for a type it does not know;
/// the Graph's exceptions for an edge it refuses). A failing update() ends the replay with
/// ok = false; `target` then holds the graph up to that step.
[[nodiscard]] ReplayResult replayGraph(const Graph& source, const TypeRegistry& types,
                                       Graph& target, const ReplayOptions& options = {});

/// A graph's estimates against the batch optimizer's solution of the same graph.
struct BatchComparison {
  double chi2 = 0.0;        ///< objective at the graph's estimates
  double batch_chi2 = 0.0;  ///< objective after the batch optimizer
  /// (chi2 - batch_chi2) / batch_chi2 (chi2 - batch_chi2 when batch_chi2 is 0).
  double relative_gap = 0.0;
  /// Largest difference of an entry of a vertex's flat estimate data (metres, radians,
  /// quaternion components; angle-like differences taken modulo 2 pi, so that -pi and pi
  /// agree) between the graph and the batch solution, and the vertex where it is.
  double max_difference = 0.0;
  VertexId worst_vertex = -1;
  Summary summary;  ///< the batch optimizer's
  [[nodiscard]] bool ok() const { return summary.succeeded(); }
};

/// Runs the batch Optimizer with `options` on a copy of `graph` (copyGraph, so from its
/// estimates) and compares. `graph` is not changed.
[[nodiscard]] BatchComparison compareWithBatch(const Graph& graph, const TypeRegistry& types,
                                               const SolverRegistry& solvers,
                                               const Optimizer::Options& options = {});

}  // namespace graphslam::incremental
