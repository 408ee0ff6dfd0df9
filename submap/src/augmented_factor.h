// SPDX-License-Identifier: MIT
// Private: a submap's whole system factorised with its separator last (CHOLMOD supernodal,
// through the solvers' OrderedFactor), which gives the interior's elimination onto the
// separator from one factorisation.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

namespace graphslam::solvers {
class OrderedFactor;
}

namespace graphslam::submap::detail {

/// With the submap's system [A B; B^T C] already in its elimination order (A's rows
/// permuted so that those B touches come last), the factorisation
///   M = [A B; B^T C + delta I] = L L^T,   L = [L_A 0; Y^T L_S]
/// holds everything the elimination needs: L_A L_A^T = A, Y = L_A^-1 B and
/// L_S L_S^T = C + delta I - Y^T Y = S + delta I, so S = L_S L_S^T - delta I. The shift
/// delta (the largest diagonal entry of C) makes the trailing block positive definite: S is
/// only semidefinite (a submap rarely determines its separator on its own), and S + delta I
/// has a condition number of at most the separator's dimension plus one, so S comes out
/// with the accuracy of forming C - Y^T Y directly. CHOLMOD's supernodal factorisation runs
/// the interior and the rank update onto the separator as BLAS-3 on dense supernodes.
/// The symbolic analysis is made once (the structure never changes); the values are freed
/// by release() and made again by the next factorize().
class AugmentedFactor {
 public:
  /// Whether this build has CHOLMOD (SuiteSparse).
  [[nodiscard]] static bool available();

  /// Throws graphslam::Error when the SuiteSparse backend cannot be loaded.
  AugmentedFactor();
  ~AugmentedFactor();
  AugmentedFactor(const AugmentedFactor&) = delete;
  AugmentedFactor& operator=(const AugmentedFactor&) = delete;

  /// Factorises M from A's upper triangle (interior x interior), B (interior x separator)
  /// and the dense C, all in the elimination order, with the shift `delta` (> 0). False
  /// when M is not positive definite (A is not, or `delta` is too small to make S + delta I
  /// so).
  [[nodiscard]] bool factorize(const Eigen::SparseMatrix<double>& a_upper,
                               const Eigen::SparseMatrix<double>& b, const Eigen::MatrixXd& c,
                               double delta);
  /// S = C - B^T A^-1 B and r = g_S - B^T A^-1 g_I (full symmetric S). Needs factorize().
  void contribution(const Eigen::VectorXd& g_interior, const Eigen::VectorXd& g_separator,
                    Eigen::MatrixXd& schur, Eigen::VectorXd& reduced) const;
  /// A^-1 v for v in the interior's (elimination) order. Needs factorize().
  [[nodiscard]] Eigen::VectorXd solveInterior(const Eigen::VectorXd& v) const;
  /// Frees the numeric values (the symbolic analysis stays).
  void release();

 private:
  std::unique_ptr<solvers::OrderedFactor> factor_;
  int di_ = 0, ds_ = 0;
  double delta_ = 0.0;
};

}  // namespace graphslam::submap::detail
