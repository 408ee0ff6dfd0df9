// SPDX-License-Identifier: MIT
// Fill-reducing ordering of the vertex blocks for the incremental factor.
#pragma once

#include <vector>

namespace graphslam::incremental {

/// Symmetric pattern of n blocks in compressed columns: the rows of column j are
/// rows[col_ptr[j] .. col_ptr[j + 1]), in any order, without duplicates.
struct BlockPattern {
  std::vector<int> col_ptr;
  std::vector<int> rows;
};

/// Elimination order of the blocks of `pattern`: order[k] is the block eliminated k-th.
/// Approximate minimum degree with the blocks whose `last` flag is set constrained to the
/// end (CAMD); the natural order without SuiteSparse.
[[nodiscard]] std::vector<int> constrainedBlockOrdering(const BlockPattern& pattern,
                                                        const std::vector<char>& last);

}  // namespace graphslam::incremental
