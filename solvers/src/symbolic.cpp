// SPDX-License-Identifier: MIT
#include "symbolic.h"

namespace graphslam::solvers::detail {

SymbolicCost symbolicCost(const SparseStructure& s, const std::vector<int>& order) {
  return symbolicCost(s, blockGraph(s), order);
}

SymbolicCost symbolicCost(const SparseStructure& s, const BlockGraph& g,
                          const std::vector<int>& order) {
  const int nb = s.num_blocks;
  const std::vector<int> block = blockOfColumn(s.block_starts, nb, s.n);
  // Block order: blocks in the order their first column appears.
  std::vector<int> new_of(static_cast<std::size_t>(nb), -1);  // original block -> position
  std::vector<int> old_of;                                    // position -> original block
  old_of.reserve(static_cast<std::size_t>(nb));
  for (int c : order) {
    const int b = block[c];
    if (new_of[b] < 0) {
      new_of[b] = static_cast<int>(old_of.size());
      old_of.push_back(b);
    }
  }
  auto dim = [&](int pos) {
    const int b = old_of[pos];
    return s.block_starts[b + 1] - s.block_starts[b];
  };

  const std::vector<int> parent = eliminationTree(nb, [&](int k, auto&& visit) {
    const int b = old_of[k];
    for (int p = g.ptr[b]; p < g.ptr[b + 1]; ++p) visit(new_of[g.idx[p]]);
  });

  // Row subtrees: block row k of L holds every block on the tree paths from the
  // neighbours i < k of k up to k; each visit adds k's rows to column i's count.
  std::vector<double> below(static_cast<std::size_t>(nb), 0.0);  // scalar rows below the block
  std::vector<int> flag(static_cast<std::size_t>(nb), -1);
  for (int k = 0; k < nb; ++k) {
    flag[k] = k;
    const int b = old_of[k];
    const int dk = dim(k);
    for (int p = g.ptr[b]; p < g.ptr[b + 1]; ++p) {
      for (int i = new_of[g.idx[p]]; i < k && flag[i] != k; i = parent[i]) {
        below[i] += dk;
        flag[i] = k;
      }
    }
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
  return cost;
}

}  // namespace graphslam::solvers::detail
