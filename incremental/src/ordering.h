// SPDX-License-Identifier: MIT
// Fill-reducing ordering of the vertex blocks for the incremental factor.
#pragma once

#include <vector>

namespace graphslam::incremental {

/// Elimination order of n blocks with the given (symmetric) adjacency: order[k] is the block
/// eliminated k-th. Approximate minimum degree with the blocks whose `last` flag is set
/// constrained to the end (CAMD); the natural order without SuiteSparse.
[[nodiscard]] std::vector<int> constrainedBlockOrdering(
    const std::vector<std::vector<int>>& adjacency, const std::vector<char>& last);

}  // namespace graphslam::incremental
