// SPDX-License-Identifier: MIT
// Dense elimination of the leading columns of a frontal matrix.
#pragma once

#include <Eigen/Core>

namespace graphslam::incremental {

/// Eliminates the leading k columns of the front f (its lower triangle is read) and its
/// right-hand side in place: f11 = L11 L11^T, f21 <- f21 L11^-T, f22 <- f22 - f21 f21^T
/// (lower triangle), rhs1 <- L11^-1 rhs1, rhs2 <- rhs2 - f21 rhs1. Returns false when f11 is
/// not positive definite.
bool eliminateLeading(Eigen::Map<Eigen::MatrixXd>& f, Eigen::Map<Eigen::VectorXd>& rhs, int k);

}  // namespace graphslam::incremental
