// SPDX-License-Identifier: MIT
#include "symbolic.h"

#include <algorithm>

namespace graphslam::solvers::detail {

namespace {

/// Elimination tree and cost of the factor of a pattern given by `neighbours(k, visit)`
/// (visit(i) for every neighbour i of position k; those >= k are ignored) and the
/// dimension of the block at every position; optionally the tree and, per block, the
/// scalar rows of L in its first column.
template <typename Neighbours, typename Dim>
SymbolicCost costOf(int nb, Neighbours&& neighbours, Dim&& dim, std::vector<int>* parent_out,
                    std::vector<int>* counts_out) {
  std::vector<int> parent = eliminationTree(nb, neighbours);
  // Row subtrees: block row k of L holds every block on the tree paths from the
  // neighbours i < k of k up to k; each visit adds k's rows to column i's count.
  std::vector<double> below(static_cast<std::size_t>(nb), 0.0);  // scalar rows below the block
  std::vector<int> flag(static_cast<std::size_t>(nb), -1);
  for (int k = 0; k < nb; ++k) {
    flag[k] = k;
    const int dk = dim(k);
    neighbours(k, [&](int r) {
      for (int i = r; i < k && flag[i] != k; i = parent[i]) {
        below[i] += dk;
        flag[i] = k;
      }
    });
  }
  SymbolicCost cost;
  for (int j = 0; j < nb; ++j) {
    const int d = dim(j);
    for (int t = 0; t < d; ++t) {
      const double c = (d - t) + below[j];
      cost.factor_nonzeros += c;
      cost.flops += c * c;
    }
  }
  if (counts_out) {
    counts_out->resize(static_cast<std::size_t>(nb));
    for (int j = 0; j < nb; ++j) (*counts_out)[j] = dim(j) + static_cast<int>(below[j]);
  }
  if (parent_out) *parent_out = std::move(parent);
  return cost;
}

}  // namespace

SymbolicCost symbolicCost(const SparseStructure& s, const std::vector<int>& order) {
  return symbolicCost(s, blockGraph(s), order);
}

namespace {
/// Blocks in the order their first column appears in `order`: position -> block, and
/// block -> position.
void blockSequence(const SparseStructure& s, const std::vector<int>& order,
                   std::vector<int>& old_of, std::vector<int>& new_of) {
  const int nb = s.num_blocks;
  const std::vector<int> block = blockOfColumn(s.block_starts, nb, s.n);
  new_of.assign(static_cast<std::size_t>(nb), -1);
  old_of.clear();
  old_of.reserve(static_cast<std::size_t>(nb));
  for (int c : order) {
    const int b = block[c];
    if (new_of[b] < 0) {
      new_of[b] = static_cast<int>(old_of.size());
      old_of.push_back(b);
    }
  }
}

/// symbolicCost() on the block sequence, with the tree and counts if asked for.
SymbolicCost permutedCost(const SparseStructure& s, const BlockGraph& g,
                          const std::vector<int>& old_of, const std::vector<int>& new_of,
                          std::vector<int>* parent, std::vector<int>* counts) {
  auto dim = [&](int pos) {
    const int b = old_of[pos];
    return s.block_starts[b + 1] - s.block_starts[b];
  };
  auto neighbours = [&](int k, auto&& visit) {
    const int b = old_of[k];
    for (int p = g.ptr[b]; p < g.ptr[b + 1]; ++p) visit(new_of[g.idx[p]]);
  };
  return costOf(s.num_blocks, neighbours, dim, parent, counts);
}
}  // namespace

std::vector<int> postorderedBlocks(const SparseStructure& s, const BlockGraph& g,
                                   const std::vector<int>& order) {
  std::vector<int> old_of, new_of, parent, counts;
  blockSequence(s, order, old_of, new_of);
  permutedCost(s, g, old_of, new_of, &parent, &counts);
  const std::vector<int> post = postorder(parent, counts);
  std::vector<int> blocks(post.size());
  for (std::size_t k = 0; k < post.size(); ++k) blocks[k] = old_of[post[k]];
  return blocks;
}

SymbolicCost symbolicCost(const SparseStructure& s, const BlockGraph& g,
                          const std::vector<int>& order) {
  std::vector<int> old_of, new_of;
  blockSequence(s, order, old_of, new_of);
  return permutedCost(s, g, old_of, new_of, nullptr, nullptr);
}

SymbolicCost symbolicCostNatural(const SparseStructure& s, std::vector<int>* parent,
                                 std::vector<int>* counts) {
  const int nb = s.num_blocks;
  const std::vector<int> block = blockOfColumn(s.block_starts, nb, s.n);
  auto dim = [&](int b) { return s.block_starts[b + 1] - s.block_starts[b]; };
  // Block rows r < k of block column k: H's upper column k, every block's first row.
  auto upper_neighbours = [&](int k, auto&& visit) {
    const int c = s.block_starts[k];
    for (int p = s.col_ptr[c]; p < s.col_ptr[c + 1];) {
      const int r = block[s.row_idx[p]];
      if (r >= k) break;
      visit(r);
      p += dim(r);
    }
  };
  return costOf(nb, upper_neighbours, dim, parent, counts);
}

std::vector<int> postorder(const std::vector<int>& parent, const std::vector<int>& weight) {
  const int n = static_cast<int>(parent.size());
  // Nodes by decreasing weight (a counting sort; ties by decreasing index), each put in
  // front of its parent's child list: every list is in increasing weight.
  int max_weight = 0;
  for (int w : weight) max_weight = std::max(max_weight, w);
  std::vector<int> bucket(static_cast<std::size_t>(max_weight) + 2, 0);
  for (int j = 0; j < n; ++j) ++bucket[weight[j] + 1];
  for (int w = 0; w <= max_weight; ++w) bucket[w + 1] += bucket[w];
  std::vector<int> by_weight(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) by_weight[bucket[weight[j]]++] = j;
  std::vector<int> head(static_cast<std::size_t>(n), -1), next(static_cast<std::size_t>(n), -1);
  for (int q = n - 1; q >= 0; --q) {
    const int j = by_weight[q];
    if (parent[j] >= 0) {
      next[j] = head[parent[j]];
      head[parent[j]] = j;
    }
  }
  std::vector<int> post;
  post.reserve(static_cast<std::size_t>(n));
  std::vector<int> stack;
  for (int root = 0; root < n; ++root) {
    if (parent[root] >= 0) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int j = stack.back();
      if (head[j] >= 0) {  // descend into the next unvisited child
        const int child = head[j];
        head[j] = next[child];
        stack.push_back(child);
      } else {
        post.push_back(j);
        stack.pop_back();
      }
    }
  }
  return post;
}

}  // namespace graphslam::solvers::detail
