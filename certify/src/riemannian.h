// SPDX-License-Identifier: MIT
// The product of Stiefel manifolds St(d, r)^n in certify's row layout (X: dn x r, block i =
// rows d i .. d i + d-1 with orthonormal rows), and the Riemannian trust region on it.
#pragma once

#include <Eigen/Core>

#include "graphslam/certify/certify.h"
#include "problem_impl.h"

namespace graphslam::certify {

/// sym(A_i X_i^T) of every block, side by side (d x dn).
[[nodiscard]] Eigen::MatrixXd symmetricBlockProducts(const Eigen::MatrixXd& a,
                                                     const Eigen::MatrixXd& x, int d);
/// Z_i - B_i X_i for every block (B: d x dn).
[[nodiscard]] Eigen::MatrixXd subtractBlockProducts(const Eigen::MatrixXd& z,
                                                    const Eigen::MatrixXd& b,
                                                    const Eigen::MatrixXd& x, int d);
/// The orthogonal projection of Z onto the tangent space at X.
[[nodiscard]] Eigen::MatrixXd projectTangent(const Eigen::MatrixXd& x, const Eigen::MatrixXd& z,
                                             int d);
/// The polar retraction: each block of X + V replaced by its nearest matrix with
/// orthonormal rows.
[[nodiscard]] Eigen::MatrixXd retract(const Eigen::MatrixXd& x, const Eigen::MatrixXd& v, int d);

/// Where the trust region stopped.
struct TrustRegionResult {
  Eigen::MatrixXd x;
  double objective = 0.0;
  double gradient_norm = 0.0;
  int iterations = 0;
  int inner_iterations = 0;
};

/// Minimises F(X) = tr(X^T Q X) over St(d, r)^n from `x0` by a Riemannian trust region
/// with truncated conjugate gradients (Absil, Baker, Gallivan 2007), preconditioned by
/// `preconditioner` (a factor of Q + mu I).
[[nodiscard]] TrustRegionResult trustRegion(const Problem& problem, const Eigen::MatrixXd& x0,
                                            const ShiftedFactor& preconditioner,
                                            const Options& options);

}  // namespace graphslam::certify
