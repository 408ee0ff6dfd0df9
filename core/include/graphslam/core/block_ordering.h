// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "graphslam/core/linear_solver.h"

namespace graphslam {

/// Fill-reducing ordering computed on the block graph (one node per variable block) with
/// approximate minimum degree (Eigen's AMD), then expanded to scalar columns. Returns
/// `perm` with perm[k] = original column placed at position k (CHOLMOD's convention).
/// Ordering the block graph is cheaper than the scalar one and keeps blocks contiguous.
/// Used by the linear solvers and by the marginal covariances.
[[nodiscard]] std::vector<int> blockAmdOrdering(const SparseStructure& s);

}  // namespace graphslam
