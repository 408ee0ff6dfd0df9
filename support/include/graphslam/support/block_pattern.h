// SPDX-License-Identifier: MIT
#pragma once

#include <utility>
#include <vector>

namespace graphslam::support {

/// The upper block pattern of a symmetric block matrix: for every block column c, the
/// block rows r <= c it holds (the diagonal always), sorted, without repeats. Built by
/// counting (no per-column lists); the optimizer's H and the linear systems of the SE(2)
/// initial guess are laid out from it.
struct BlockPattern {
  std::vector<int> ptr;   ///< num_blocks + 1 offsets into rows
  std::vector<int> rows;  ///< row blocks of column c: rows[ptr[c] .. ptr[c + 1])

  /// The pattern of `num_blocks` diagonal blocks and the blocks (a, b) and (b, a) of
  /// every pair (any order; repeated pairs are one block). Every index in [0, num_blocks).
  [[nodiscard]] static BlockPattern fromPairs(int num_blocks,
                                              const std::vector<std::pair<int, int>>& pairs);

  [[nodiscard]] int numBlocks() const { return static_cast<int>(ptr.size()) - 1; }
  /// Index into `rows` of block (r, c), r <= c, which must be in the pattern.
  [[nodiscard]] int find(int r, int c) const;
};

}  // namespace graphslam::support
