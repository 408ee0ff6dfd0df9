// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::incremental {

/// A state of the fixed-lag window (IncrementalOptimizer::addState): a vertex and its time
/// stamp (seconds; NaN when the stream has none).
struct WindowState {
  VertexId id = -1;
  double stamp = std::numeric_limits<double>::quiet_NaN();
};

/// Fixed-lag smoothing: which states leave the optimisation, and what is told when they do.
/// With every bound unset (the default) the optimizer keeps the full history. States are the
/// vertices declared with IncrementalOptimizer::addState, oldest first; every other vertex
/// (a landmark) leaves with the last state it has an edge to. A vertex that leaves is
/// marginalised: the edges that touch it are linearised at the current estimates and the
/// information they carry about the vertices that stay (the separator) is kept as one
/// LinearPriorEdge on them (linear_prior_edge.h: the Schur complement of the leaving
/// vertices). The prior is fixed at that linearisation point: later relinearisation of the
/// separator does not change what the marginalised measurements said (the first-estimate
/// consistency caveat of every fixed-lag smoother: the prior's linearisation point and the
/// separator's current one differ, so the prior's Jacobian is that of the old point, and
/// the estimate may be slightly overconfident in directions the data do not determine).
struct WindowOptions {
  /// Keep at most this many states (0: no bound by count)...
  std::size_t states = 0;
  /// ...marginalising only when the window holds more than states + slack, then down to
  /// `states`: each marginalisation makes the next update() eliminate the whole window
  /// afresh, so a slack of B does that once every B updates instead of at every one (the
  /// updates between are incremental), for a window of up to states + B.
  std::size_t slack = 0;
  /// Keep only the states whose stamp is within this many seconds of the newest state's
  /// (0: no bound by time; every state then needs a finite stamp).
  double seconds = 0.0;
  /// A keyframe policy: called after every successful update() with the window's states,
  /// oldest first; returns states to marginalise now (any of them, not only the oldest;
  /// ids that are not states of the window are an error). Combined with the bounds above.
  std::function<std::vector<VertexId>(const std::vector<WindowState>& window)> policy;
  /// Called with every vertex about to be marginalised (states oldest first, then the
  /// landmarks by id), at its final estimate: to write the trajectory as it leaves.
  std::function<void(const Vertex& vertex, const WindowState* state)> on_marginalised;
  /// Directions of the Schur complement whose eigenvalue is below this fraction of the
  /// largest are left out of the prior (the data do not determine them; 1e-12 is rounding
  /// level for a condition number of 1e6 in the Jacobian).
  double rank_tolerance = 1e-12;
  /// A marginalised landmark (a vertex that is not a state) seen again: false (the default)
  /// refuses the edge like one to a marginalised state; true accepts the landmark again as
  /// a new vertex under its id (addVertex, initialised by the caller), with no information
  /// from before (that went into the prior on the states), as a fixed-lag smoother starts a
  /// new track. Marginalised states are refused either way.
  bool reinitialize_landmarks = false;
  /// Landmarks (vertices that are not states) never leave: only states are marginalised,
  /// their information going into a prior on the landmarks they saw and the states they
  /// connect to. A landmark seen again laps later then closes the loop with everything
  /// known of it, as the full history would (the window's trajectory stays close to the
  /// full history's; docs/BENCHMARKS.md, "Soak"), but the window no longer bounds the
  /// map: memory and the cost of the update that eliminates the window afresh grow with
  /// the number of landmarks (their prior is dense), not with the drive. For a robot that
  /// works in a bounded area. Excludes reinitialize_landmarks.
  bool keep_landmarks = false;

  [[nodiscard]] bool enabled() const { return states > 0 || seconds > 0.0 || policy; }
};

/// Tuning of IncrementalOptimizer. Measurements behind the defaults: docs/BENCHMARKS.md,
/// section "Incremental optimisation".
struct Options {
  /// A vertex is relinearised (its linearisation point moved to its current estimate and
  /// its edges linearised again) when an entry of its step from the linearisation point
  /// exceeds this (in the tangent units of its type: metres and radians for poses). The
  /// default is iSAM2's. A smaller value ends closer to the optimum of the nonlinear problem
  /// at every update, for more relinearised edges: replaying m3500, chi2 ends 6e-4 above the
  /// batch optimum at 0.1, 1.3e-5 at 0.03 and 8e-7 at 0.01, for 1.5 and 1.7 times the time
  /// (docs/BENCHMARKS.md, "Incremental optimisation"); refine() closes the rest when it
  /// matters.
  double relinearize_threshold = 0.1;
  /// Relinearise-and-solve passes per update(): after a pass, vertices whose step exceeds
  /// relinearize_threshold are relinearised and the system solved again, up to this many
  /// times (the update's stats say when the limit was reached); those still beyond it after
  /// the last pass are relinearised at the next update that checks. 1 is iSAM2's scheme: one
  /// solve per update, the vertices beyond the threshold relinearised at the start of the
  /// next checking update, with its new edges. That saves the second elimination of the
  /// part near the root (sphere2500's replay: a third less time) and ends the replays about
  /// as close to the optimum (docs/BENCHMARKS.md, "Incremental optimisation"), but after a
  /// loop closure an update stands one Gauss-Newton step from the optimum, not within the
  /// threshold.
  int max_passes = 10;
  /// Relinearise-and-solve passes of refine() at most.
  int refine_max_passes = 10;
  /// Relinearisation is checked at every this-many-th update only (iSAM2's
  /// relinearizeSkip, there 10 by default); the other updates solve the new edges at the
  /// current linearisation points in one pass, and the vertices whose step exceeded the
  /// threshold meanwhile are relinearised at the next check (when it still does). 10 takes
  /// a third to two thirds off the replays of five of the seven public files (not m3500's or
  /// intel's) and ends them about as close to the optimum (docs/BENCHMARKS.md, "Incremental
  /// optimisation"), but the updates between checks stand further from a batch solve of the
  /// same graph; 1 keeps every update within the threshold.
  int relinearize_skip = 1;
  /// Back-substitution solves a vertex again only when it is re-eliminated or a step it
  /// depends on changed, and keeps the new step only when it differs from the old by more
  /// than this fraction of the relinearisation threshold in force (relinearize_threshold in
  /// update(), refine()'s threshold in refine()), so that changes below it cannot add up
  /// unseen. 1e-2 is iSAM2's "wildfire" threshold (0.001 against its relinearisation
  /// threshold 0.1). Smaller fractions bring each update closer to the optimum for more time,
  /// most on graphs with landmarks (docs/BENCHMARKS.md, "Incremental optimisation"); 0 solves
  /// every step the re-eliminated part reaches.
  double backsubstitution_fraction = 1e-2;
  /// A vertex is eliminated in one front with its child in the elimination tree when the
  /// child's rows are the vertex and the vertex's rows (a supernode, iSAM2's clique) and that
  /// front has at least this many rows: the members are factorised at once, with one rank-k
  /// update of the rest of the front, and only the last keeps an update matrix. A supernode
  /// is eliminated again whole, so where fronts are small merging costs more than it saves
  /// (docs/BENCHMARKS.md, "Incremental optimisation", compares values).
  int chain_min_front_rows = 48;
  /// Fixed-lag smoothing (default: full history).
  WindowOptions window;
};

/// What one update() did.
struct UpdateStats {
  int new_vertices = 0;
  int new_edges = 0;
  int removed_edges = 0;
  int passes = 0;  ///< relinearise-and-solve passes
  bool pass_limit_reached = false;
  int relinearized_vertices = 0;  ///< over all passes
  int relinearized_edges = 0;
  int eliminated_columns = 0;     ///< vertex columns of the factor ordered and eliminated again
  bool rebuilt = false;           ///< the graph changed outside the optimizer: full rebuild
  int marginalized_vertices = 0;  ///< left the window after the update (states and landmarks)
};

/// Error of update(): a factor that is not positive definite (a vertex the edges do not
/// determine), with the vertex whose column failed.
struct UpdateFailure {
  VertexId vertex = -1;
  std::string message;
};

/// An optimizer for a graph that grows: vertices and edges are added (and edges removed)
/// through it, and update() after each batch of changes brings the estimates to the optimum
/// of the graph as it is (to within what Options::relinearize_threshold leaves; refine()
/// for the exact optimum), doing work that follows what changed (iSAM2's idea in matrix
/// form, docs/BENCHMARKS.md "Incremental optimisation" of its design notes):
///  - the Cholesky factor of H = sum J^T Omega J is kept with its elimination order; when
///    columns of H change (new edges, relinearised edges), only they and their ancestors in
///    the elimination tree are ordered again (CAMD, the vertices of the new edges last) and
///    eliminated again (multifrontal: each vertex keeps what its subtree passes up) -- the
///    rest of the factor does not depend on them;
///  - each vertex has a linearisation point; an edge is linearised again only when it is new
///    or one of its vertices moved further than Options::relinearize_threshold from it.
/// Any registered vertex and edge type works, 2D or 3D, with robust kernels (reweighted at
/// the linearisation point). Fixed vertices are constants. When nothing anchors the graph
/// (no fixed vertex, no unary edge) at the first update(), the vertex that fixGaugeIfFree
/// picks is fixed. Changes made to the graph directly (not through this class) are found
/// by the graph's structure version and cost one full rebuild at the next update().
class IncrementalOptimizer {
 public:
  /// Optimises `graph` (which must outlive this object); what it holds already is new at
  /// the first update().
  explicit IncrementalOptimizer(Graph& graph, Options options = {});
  ~IncrementalOptimizer();
  IncrementalOptimizer(const IncrementalOptimizer&) = delete;
  IncrementalOptimizer& operator=(const IncrementalOptimizer&) = delete;

  [[nodiscard]] Graph& graph() { return graph_; }
  [[nodiscard]] const Options& options() const { return options_; }

  /// Adds to the graph (Graph::addVertex / addEdge: the same checks and exceptions) and
  /// records the change for the next update().
  Vertex& addVertex(std::unique_ptr<Vertex> vertex);
  Edge& addEdge(std::unique_ptr<Edge> edge);
  /// Removes an edge (it is destroyed). Returns false when it is not in the graph.
  /// Removal changes the pattern of the factor: the next update() reorders and rebuilds it.
  bool removeEdge(const Edge* edge);

  /// Brings the estimates of the graph's vertices to the optimum of the current graph (to
  /// the relinearisation threshold). Returns false, with failure() set and the estimates
  /// as before the call, when the factor is not positive definite.
  bool update();
  /// Relinearises every vertex whose step from its linearisation point exceeds `threshold`
  /// and solves again, until none does (or Options::refine_max_passes): Gauss-Newton to that
  /// step size, for when the exact optimum matters more than the time (before writing the
  /// map, at the end of a replay). Needs an update() after the last change of the graph
  /// (throws graphslam::Error otherwise). Returns false as update() does.
  bool refine(double threshold = 1e-6);
  /// Starts again from the graph as it is, as a new optimizer on it would (after the
  /// estimates were changed from outside, e.g. by a batch optimisation of the same graph):
  /// the next update() linearises every edge at the current estimates and eliminates the
  /// factor afresh. Unlike a new optimizer it keeps the fixed-lag window: its states, what
  /// was marginalised (still refused) and the count.
  void restart();
  /// What the last update() or refine() did.
  [[nodiscard]] const UpdateStats& lastStats() const;
  [[nodiscard]] const UpdateFailure& failure() const;

  /// Objective (sum of the edges' robust chi2) at the current estimates.
  [[nodiscard]] double chi2();

  /// Marginal covariance of a free vertex at the last update()'s linearisation (the block of
  /// H^-1): cheap for recent vertices, which sit near the root of the elimination tree.
  /// Throws graphslam::Error for a fixed or unknown vertex, or before the first update().
  [[nodiscard]] Eigen::MatrixXd marginalCovariance(VertexId id) const;

  /// Declares vertex `id` (in the graph) a state of the fixed-lag window, newer than those
  /// declared before, with its time stamp. Throws graphslam::Error for an unknown vertex,
  /// one declared already, or a stamp older than the newest state's.
  void addState(VertexId id, double stamp = std::numeric_limits<double>::quiet_NaN());
  /// Marginalises these states (and the landmarks that leave with them) now, as the window
  /// does after an update; returns every vertex marginalised. Throws graphslam::Error for an
  /// id that is not a state of the window, or for a vertex type without Vertex::minus.
  std::vector<VertexId> marginalize(const std::vector<VertexId>& states);
  /// Whether `id` was marginalised (and, for a landmark, not added again). Edges to it and
  /// vertices with its id are refused (addEdge, addVertex throw graphslam::InputError
  /// naming it), except a landmark's id with WindowOptions::reinitialize_landmarks.
  [[nodiscard]] bool isMarginalized(VertexId id) const;
  /// The window's states, oldest first.
  [[nodiscard]] std::vector<WindowState> windowStates() const;
  /// Vertices marginalised so far.
  [[nodiscard]] std::size_t marginalizedCount() const;

  /// Saves everything the optimizer needs to continue (graph, estimates, window, counters)
  /// to `path`, atomically (support::writeFileAtomically: the previous file or the new one,
  /// never a partial one), in the versioned checkpoint format of checkpoint.h, with the
  /// caller's `note` (the position in its stream). The next update() relinearises every
  /// vertex at its current estimate and eliminates the factor afresh, as an optimizer
  /// resumed from this file does: so a run that checkpoints and the same run killed and
  /// resumed reach bit-identical estimates. Needs an update() after the last change (throws
  /// graphslam::Error otherwise, or for an edge with a robust kernel, which the format does
  /// not hold yet).
  void saveCheckpoint(const std::string& path, const TypeRegistry& types,
                      const std::string& note = {});
  /// Loads a checkpoint into this optimizer, whose graph must be empty and whose options
  /// must be those the file was written with; returns the note saved with it. Throws
  /// graphslam::InputError naming the file and what is wrong (not a checkpoint, another
  /// version, truncated, checksum mismatch, an unknown type, other options); the graph is
  /// then unchanged.
  std::string loadCheckpoint(const std::string& path, const TypeRegistry& types);

  /// Vertex columns of the current factor and its non-zero blocks below the diagonal.
  [[nodiscard]] std::size_t factorColumns() const;
  [[nodiscard]] std::size_t factorBlocks() const;

 private:
  struct Impl;
  Graph& graph_;
  Options options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace graphslam::incremental
