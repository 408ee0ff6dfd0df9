// SPDX-License-Identifier: MIT
// Which vertices the edges do not determine, and why, found before anything is solved.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"

namespace graphslam {

struct ObservabilityOptions {
  /// A direction of a vertex's own information block (below) counts as undetermined when
  /// its eigenvalue is below this fraction of the block's largest. An exact degeneracy (one
  /// range, parallel bearings) leaves a ratio of rounding size (about 1e-16); two bearings
  /// 1e-5 rad apart leave about 1e-11, which still counts as determined.
  double rank_tolerance = 1e-12;
  /// The reason words for a vertex whose edges each measure one direction of it: the edges'
  /// Jacobians are evaluated again at the vertex moved this far along its undetermined
  /// direction (in its update coordinates: metres for a point). An edge that still does
  /// not see that direction there (relative size below straight_tolerance) leaves the
  /// vertex free along a straight line, as a bearing does (the line of sight); one that
  /// does, along a curve, as a range does (a circle).
  double probe_step = 1.0;
  double straight_tolerance = 1e-6;
  /// Threads testing the vertices' blocks (the edges are linearised serially, in edge order);
  /// the result is the same for every count.
  int threads = 1;
  /// When given, vertices are named with their tag in the report ("vertex 7 (VERTEX_XY)").
  const TypeRegistry* types = nullptr;
};

/// A non-fixed vertex that its edges do not determine.
struct UndeterminedVertex {
  VertexId id = -1;
  std::string tag;     ///< its registered tag (ObservabilityOptions::types), else empty
  int dimension = 0;   ///< unknowns
  int rank = 0;        ///< rank of its own block (0 without edges)
  std::string reason;  ///< in words: "no edges", "one range-only edge (from vertex 3) ..."
  /// Its active edges, as indices into graph.edges() at the time of the check.
  std::vector<std::size_t> edges;
  /// The other vertices of those edges, sorted.
  std::vector<VertexId> neighbours;
};

/// What checkObservability() found.
struct ObservabilityReport {
  /// By id. A vertex is here when it has no active edge, or when the sum of its active
  /// edges' J^T Omega J on its own block (the other vertices held fixed) is rank deficient
  /// at the current estimate: then H is singular whatever the other vertices do.
  std::vector<UndeterminedVertex> undetermined;
  /// Information, not an error: connected groups of non-fixed vertices with no fixed vertex
  /// and no unary edge (complete, sorted id lists; checkConstraints). Such a group can move
  /// as a whole; the optimizer fixes its lowest id for the run (Optimizer::Options::fix_gauge).
  std::vector<std::vector<VertexId>> unanchored;
  /// Per unanchored group, the vertex the optimizer fixes for it: the lowest id among its
  /// vertices of the largest dimension (a pose rather than a landmark).
  std::vector<VertexId> anchors;

  [[nodiscard]] bool ok() const { return undetermined.empty(); }
  [[nodiscard]] std::vector<VertexId> undeterminedIds() const;
  /// A heading, then one line per undetermined vertex ("vertex 7 (VERTEX_XY): no edges"
  /// followed by `note(vertex)` when given), the first `max_listed`, then a count of the
  /// rest; empty when there is none.
  [[nodiscard]] std::string describeUndetermined(
      std::size_t max_listed = 20,
      const std::function<std::string(const UndeterminedVertex&)>& note = {}) const;
  /// One information line on the unanchored groups; empty when there is none.
  [[nodiscard]] std::string describeUnanchored() const;
  /// Both, on separate lines.
  [[nodiscard]] std::string describe(std::size_t max_listed = 20) const;
};

/// Rank of the sum of J^T Omega J of the active edges of `v` on its own block, from the
/// Jacobians the edges hold (their last linearisation); -1 when the block is not finite.
/// Below v.dimension(), H is singular whatever the other vertices do.
[[nodiscard]] int ownBlockRank(const Vertex& v, double rank_tolerance = 1e-12);

/// Finds the non-fixed vertices the edges cannot determine (ObservabilityReport), with a
/// reason for each. The reason words are generic, from the vertex's block and its edges:
/// "no edges"; when every edge measures one direction of the vertex and one direction is
/// left (ObservabilityOptions::probe_step), "one range-only edge", "range-only edges ...
/// along one line", "seen from one vertex (N) by bearing only", "bearing-only edges all
/// along one line (parallel bearings)"; otherwise "its N edges determine only R of its D
/// directions". Evaluates every active edge's error and Jacobians at the current estimates
/// (the edges keep them); changes no estimate. O(edges + vertices).
[[nodiscard]] ObservabilityReport checkObservability(Graph& graph,
                                                     const ObservabilityOptions& options = {});

}  // namespace graphslam
