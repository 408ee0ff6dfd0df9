// SPDX-License-Identifier: MIT
// Which vertices a graph's edges cannot determine, found before anything is solved.
#pragma once

#include <string>
#include <vector>

#include "graphslam/core/graph.h"

namespace graphslam {

/// Non-fixed vertices whose estimates the edges cannot determine (necessary conditions,
/// cheap: O(vertices + edges)). Every list is sorted by id.
struct ConstraintReport {
  /// Non-fixed vertices without any edge: nothing says where they are.
  std::vector<VertexId> without_edges;
  /// Connected groups of non-fixed vertices (connected through edges between non-fixed
  /// vertices) that touch no fixed vertex and no unary edge: the whole group can move
  /// (gauge freedom). Complete id lists; vertices without edges are not repeated here.
  std::vector<std::vector<VertexId>> unanchored;
  /// Non-fixed vertices whose edges together have fewer error dimensions than the vertex
  /// has unknowns (e.g. a vehicle pose seen by one range-bearing measurement only).
  std::vector<VertexId> too_few_measurements;

  [[nodiscard]] bool ok() const {
    return without_edges.empty() && unanchored.empty() && too_few_measurements.empty();
  }
  /// One line per finding, ids compressed to ranges ("3-7, 12"), at most `max_ids` per list.
  [[nodiscard]] std::string describe(std::size_t max_ids = 40) const;
};

[[nodiscard]] ConstraintReport checkConstraints(const Graph& graph);

/// "1-4, 7, 9-10" for sorted ids; after `max_ids` ids, "... (N in total)".
[[nodiscard]] std::string formatIdRanges(const std::vector<VertexId>& sorted_ids,
                                         std::size_t max_ids = 40);

/// The gauge rule shared by fixGaugeIfFree, the optimizer's per-component anchors and the
/// observability report: visiting vertices in id order, `v` replaces `current` as the anchor
/// when there is none yet or `v` has a larger dimension (the lowest id of the largest
/// dimension: a pose rather than a landmark, as g2o's findGauge).
[[nodiscard]] inline bool betterGaugeAnchor(const Vertex& v, const Vertex* current) {
  return current == nullptr || v.dimension() > current->dimension();
}

}  // namespace graphslam
