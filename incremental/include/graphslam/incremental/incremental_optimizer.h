// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"

namespace graphslam::incremental {

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
  int eliminated_columns = 0;  ///< vertex columns of the factor ordered and eliminated again
  bool rebuilt = false;        ///< the graph changed outside the optimizer: full rebuild
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
  /// What the last update() or refine() did.
  [[nodiscard]] const UpdateStats& lastStats() const;
  [[nodiscard]] const UpdateFailure& failure() const;

  /// Objective (sum of the edges' robust chi2) at the current estimates.
  [[nodiscard]] double chi2();

  /// Marginal covariance of a free vertex at the last update()'s linearisation (the block of
  /// H^-1): cheap for recent vertices, which sit near the root of the elimination tree.
  /// Throws graphslam::Error for a fixed or unknown vertex, or before the first update().
  [[nodiscard]] Eigen::MatrixXd marginalCovariance(VertexId id) const;

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
