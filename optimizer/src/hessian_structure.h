// SPDX-License-Identifier: MIT
// Private to graphslam::core: the block sparsity structure of H, built once per graph
// change, with the position of every edge's blocks inside the CSC value array.
#pragma once

#include <cstdint>
#include <vector>

#include "graphslam/core/edge.h"
#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/support/block_pattern.h"
#include "graphslam/support/large_array.h"

namespace graphslam::detail {

class HessianStructure {
 public:
  /// Rebuilds from the graph: the active vertices are the non-fixed ones with at least
  /// one edge, ordered by id; the active edges those with at least one active vertex.
  /// With `block_order` (a permutation of the active vertices in id order:
  /// block_order[k] is the one placed at position k), the vertices take that order and H
  /// is stored as its lower triangle (LinearSolver::preferredBlockOrder).
  void build(Graph& graph, const std::vector<int>* block_order = nullptr);

  /// Whether the graph changed (vertices/edges added or removed, fixed flags changed)
  /// since the last build().
  [[nodiscard]] bool stale(const Graph& graph) const;

  [[nodiscard]] SparseStructure sparseStructure() const;
  [[nodiscard]] int dimension() const { return n_; }
  /// Whether H is stored as its lower triangle in a solver's block order.
  [[nodiscard]] bool reordered() const { return lower_; }
  [[nodiscard]] std::size_t nonZeros() const { return row_idx_.size(); }

  /// Zeroes H and b, then asks every active edge to add its blocks (their positions are
  /// found at the first call after a build).
  void assemble(support::LargeVector<double>& values, std::vector<double>& gradient);

  /// Positions of the diagonal entries of H inside the value array.
  [[nodiscard]] const std::vector<int>& diagonalPositions() const { return diag_pos_; }
  [[nodiscard]] const std::vector<Vertex*>& activeVertices() const { return active_vertices_; }
  /// activeVertices()[b] owns columns [blockStarts()[b], blockStarts()[b + 1]).
  [[nodiscard]] const std::vector<int>& blockStarts() const { return block_starts_; }
  /// The first column of every slot of active edge k (-1: the slot's vertex is fixed).
  [[nodiscard]] const int* slotColumns(std::size_t k) const {
    return b_offsets_.data() + edge_b_start_[k];
  }
  [[nodiscard]] const std::vector<Edge*>& activeEdges() const { return active_edges_; }
  /// Id of the vertex owning column `col`, -1 if out of range.
  [[nodiscard]] VertexId vertexOfColumn(int col) const;

  /// Connected groups of active vertices with no fixed vertex and no unary edge among
  /// their edges: their position is undetermined. Each group holds up to `max_ids` ids:
  /// first the one that anchors it (the lowest id among its vertices of the largest
  /// dimension, as fixGaugeIfFree chooses), then the smallest.
  [[nodiscard]] std::vector<std::vector<VertexId>> unanchoredGroups(std::size_t max_ids = 20) const;

 private:
  std::uint64_t version_ = ~std::uint64_t{0};
  std::vector<char> fixed_snapshot_;
  int n_ = 0;
  bool lower_ = false;
  std::vector<Vertex*> active_vertices_;
  std::vector<int> block_starts_;
  std::vector<int> col_ptr_;
  support::LargeVector<int> row_idx_;
  std::vector<int> diag_pos_;
  std::vector<Edge*> active_edges_;
  /// Block of every column.
  [[nodiscard]] std::vector<int> blockOfColumn() const;
  /// The position of every active edge's blocks in H (refs_, edge_ref_start_).
  void buildRefs();
  // The phases of build(): the active vertices and their columns; the active edges, their
  // slots' columns and the pairs of blocks they couple; in a solver's order, the edges
  // sorted by their first block; the scalar CSC pattern of the block pattern.
  void assignColumns(Graph& graph, const std::vector<int>* block_order);
  void collectEdges(const Graph& graph, std::vector<std::pair<int, int>>& pairs,
                    std::vector<int>& first_block);
  void sortEdgesByFirstBlock(const std::vector<int>& first_block);
  void buildScalarPattern(const support::BlockPattern& pattern);

  std::vector<std::uint32_t> edge_b_start_;    // per active edge (and one past), into b_offsets_
  std::vector<int> b_offsets_;                 // per edge slot: its vertex's column, or -1
  std::vector<std::uint32_t> edge_ref_start_;  // per active edge, into refs_ (empty: not built)
  support::LargeVector<HessianBlockRef> refs_;
};

/// Removes the gauge freedom for the lifetime of the object: if `enabled`, no vertex is
/// fixed and no unary edge exists, fixes a vertex that has edges (fixGaugeIfFree); the
/// destructor releases it.
class GaugeFix {
 public:
  GaugeFix(Graph& graph, bool enabled);
  ~GaugeFix();
  GaugeFix(const GaugeFix&) = delete;
  GaugeFix& operator=(const GaugeFix&) = delete;
  /// Also fixes the first vertex of each group (its anchor: the lowest id of the largest
  /// dimension): the components that nothing anchors (LinearSystem::unanchoredGroups), so
  /// that each has its own gauge fixed.
  void anchorGroups(Graph& graph, const std::vector<std::vector<VertexId>>& groups);
  /// Ids of the vertices fixed here.
  [[nodiscard]] const std::vector<VertexId>& fixedIds() const { return ids_; }

 private:
  std::vector<Vertex*> vertices_;
  std::vector<VertexId> ids_;
};

}  // namespace graphslam::detail
