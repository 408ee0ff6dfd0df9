// SPDX-License-Identifier: MIT
// The sparse matrices of a certify::Problem and the Cholesky factors built from them.
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <vector>

#include "graphslam/certify/problem.h"

namespace graphslam::certify {

using SparseMatrix = Eigen::SparseMatrix<double>;

/// A sparse Cholesky factor of the matrix K(Lambda, sigma) = M' - diag(0, Lambda) +
/// sigma diag(0, I), M' being M without the first pose's translation row and column
/// (translations first, then the rotation rows). Its Schur complement on the rotation rows
/// is Q - Lambda + sigma I, so K is positive definite exactly when Q - Lambda + sigma I is,
/// and the rotation rows of K^-1 [0; V] are (Q - Lambda + sigma I)^-1 V. The symbolic
/// analysis (AMD ordering) is done once per factor object.
class ShiftedFactor {
 public:
  explicit ShiftedFactor(const Problem& problem) : problem_(&problem) {}
  /// Factorises K(Lambda, sigma) (Lambda: d x dn blocks, empty for zero); false when K is
  /// not numerically positive definite.
  bool factorize(const Eigen::MatrixXd& lambda, double sigma);
  /// (Q - Lambda + sigma I)^-1 V for V (dn x r).
  [[nodiscard]] Eigen::MatrixXd solve(const Eigen::MatrixXd& v) const;

 private:
  const Problem* problem_;
  bool analyzed_ = false;
  Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> llt_;
  SparseMatrix k_;
};

struct Problem::Impl {
  SparseMatrix mxx;  ///< dn x dn
  SparseMatrix mxt;  ///< dn x (n - 1): the translations of poses 1..n-1
  SparseMatrix mtx;  ///< its transpose
  /// The grounded translation Laplacian ((n - 1) square) and its factor.
  Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ltt;
  /// M' (lower triangle), the pattern of every ShiftedFactor, with every entry of the
  /// rotation rows' diagonal d x d blocks stored.
  SparseMatrix k;
  /// Index into k's values of entry (a, b), a >= b, of diagonal block i:
  /// block_entries[i * d * d + a * d + b] (-1 above the diagonal).
  std::vector<int> block_entries;
};

/// A pose not connected to pose 0 by the measurements (-1 when all are), and the number
/// of connected components.
int unconnectedPose(const std::vector<Measurement>& ms, int n, int* components);

}  // namespace graphslam::certify
