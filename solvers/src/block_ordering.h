// SPDX-License-Identifier: MIT
// Private to graphslam::solvers.
#pragma once

#include <vector>

#include "graphslam/core/linear_solver.h"

namespace graphslam::solvers::detail {

/// Fill-reducing ordering computed on the block graph (one node per variable block) with
/// approximate minimum degree, then expanded to scalar columns. Returns `perm` with
/// perm[k] = original column placed at position k (CHOLMOD's convention). Ordering the
/// block graph is cheaper than the scalar one and keeps blocks contiguous.
[[nodiscard]] std::vector<int> blockAmdOrdering(const SparseStructure& s);

}  // namespace graphslam::solvers::detail
