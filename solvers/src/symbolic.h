// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: the cost of a Cholesky factorisation predicted from the
// pattern of H and an ordering, before any numeric work.
#pragma once

#include <vector>

#include "graphslam/core/linear_solver.h"
#include "ordering.h"

namespace graphslam::solvers::detail {

/// Elimination tree of a symmetric pattern on positions 0..n-1 (Liu's algorithm with path
/// compression): parent[i], -1 for a root. `neighbours(k, visit)` calls visit(i) for every
/// neighbour i of k (any order; those >= k are ignored).
template <typename Neighbours>
std::vector<int> eliminationTree(int n, Neighbours&& neighbours) {
  std::vector<int> parent(static_cast<std::size_t>(n), -1);
  std::vector<int> ancestor(static_cast<std::size_t>(n), -1);
  for (int k = 0; k < n; ++k) {
    neighbours(k, [&](int r) {
      if (r >= k) return;
      while (ancestor[r] >= 0 && ancestor[r] != k) {
        const int next = ancestor[r];
        ancestor[r] = k;
        r = next;
      }
      if (ancestor[r] < 0) {
        ancestor[r] = k;
        parent[r] = k;
      }
    });
  }
  return parent;
}

/// Predicted size and work of the Cholesky factor L of P H P^T.
struct SymbolicCost {
  double factor_nonzeros = 0.0;  ///< scalar non-zeros of L, diagonal included
  double flops = 0.0;            ///< sum over columns of (column count)^2
};

/// Elimination tree and column counts on the block graph of H (blocks stay together in
/// every ordering of this library), expanded to scalar columns. `order[k]` is the
/// original column at position k and must keep each block's columns contiguous. Work
/// and memory are O(non-zero blocks of L).
[[nodiscard]] SymbolicCost symbolicCost(const SparseStructure& s, const std::vector<int>& order);
/// The same with H's block graph already built (blockGraph(s)).
[[nodiscard]] SymbolicCost symbolicCost(const SparseStructure& s, const BlockGraph& g,
                                        const std::vector<int>& order);
/// The same for the identity order, read from H's upper triangle alone (no block
/// graph). If given, `parent` receives the block elimination tree (-1: a root) and
/// `counts` the scalar rows of L in every block's first column.
[[nodiscard]] SymbolicCost symbolicCostNatural(const SparseStructure& s,
                                               std::vector<int>* parent = nullptr,
                                               std::vector<int>* counts = nullptr);

/// The blocks of `order` (scalar columns, each block's contiguous), as a permutation of
/// the blocks (result[k]: the block at position k), postordered by the block elimination
/// tree of P H P^T as CHOLMOD postorders (postorder() with the column counts): a
/// factorisation in this order, without a postorder of its own, has the fill and the
/// supernodes of `order` postordered.
[[nodiscard]] std::vector<int> postorderedBlocks(const SparseStructure& s, const BlockGraph& g,
                                                 const std::vector<int>& order);

/// A postorder of a forest, weighted as CHOLMOD's: each node's children in increasing
/// `weight` (column counts), so the heaviest child comes right before its parent and can
/// share its supernode. post[k] = node at position k.
[[nodiscard]] std::vector<int> postorder(const std::vector<int>& parent,
                                         const std::vector<int>& weight);

}  // namespace graphslam::solvers::detail
