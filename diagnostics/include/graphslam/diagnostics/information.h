// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

namespace graphslam {

/// What the `.g2o` reader does with an information matrix that is not positive definite
/// (io::LoadOptions::information).
enum class InformationRepair {
  kRefuse,     ///< the default: such edges are an error (all of them counted and listed)
  kNearestPd,  ///< the nearest positive definite matrix: eigenvalues raised to a floor
  kIsotropic,  ///< one weight per block: translation and rotation (or the whole matrix)
};

/// k / tr(B^-1) of a k x k information block B: the weight of the isotropic information
/// with the same mean variance (the weights SE-Sync derives from a pose edge's blocks).
/// NaN when B is singular or tr(B^-1) is not positive.
[[nodiscard]] double inverseTraceWeight(const Eigen::MatrixXd& block);

/// inverseTraceWeight(block), or the mean magnitude of its diagonal when that is not a
/// positive finite number (1 for an all-zero block).
[[nodiscard]] double isotropicWeight(const Eigen::MatrixXd& block);

/// Replaces `omega` (symmetric, d x d) by a positive definite matrix as `how` says;
/// returns false for kRefuse (nothing changed).
///  - kNearestPd: eigenvalues below `floor` times the largest magnitude among them are set
///    to that value (the nearest matrix, in the Frobenius norm, with eigenvalues >= it).
///  - kIsotropic: the weight k / tr(B^-1) of each k x k diagonal block B (the weights
///    SE-Sync derives from a pose edge's information), on that block's diagonal; blocks are
///    translation and rotation for d = 3 (2 + 1) and d = 6 (3 + 3), else the whole matrix.
///    A block whose inverse has no positive trace gets the mean magnitude of its diagonal.
bool repairInformation(Eigen::MatrixXd& omega, InformationRepair how, double floor = 1e-6);

}  // namespace graphslam
