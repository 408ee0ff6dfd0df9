// SPDX-License-Identifier: MIT
#include "graphslam/core/block_ordering.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>

namespace graphslam {

std::vector<int> blockAmdOrdering(const SparseStructure& s) {
  const int nb = s.num_blocks;
  std::vector<int> block_of_col(static_cast<std::size_t>(s.n));
  for (int b = 0; b < nb; ++b) {
    for (int c = s.block_starts[b]; c < s.block_starts[b + 1]; ++c) block_of_col[c] = b;
  }
  std::vector<Eigen::Triplet<double, int>> triplets;
  for (int b = 0; b < nb; ++b) {
    const int c = s.block_starts[b];  // every column of a block has the same pattern
    int last = -1;
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      const int rb = block_of_col[s.row_idx[k]];
      if (rb == last) continue;
      last = rb;
      triplets.emplace_back(rb, b, 1.0);
      if (rb != b) triplets.emplace_back(b, rb, 1.0);
    }
  }
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> pattern(nb, nb);
  pattern.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> block_perm;
  Eigen::AMDOrdering<int> amd;
  amd(pattern, block_perm);
  std::vector<int> perm;
  perm.reserve(static_cast<std::size_t>(s.n));
  for (int k = 0; k < nb; ++k) {
    const int b = block_perm.indices()[k];
    for (int c = s.block_starts[b]; c < s.block_starts[b + 1]; ++c) perm.push_back(c);
  }
  return perm;
}

}  // namespace graphslam
