// SPDX-License-Identifier: MIT
// The certificate S = Q - Lambda(X) and its minimum eigenvalue (Spectra's Lanczos on the
// shift-inverted certificate).
#include <Spectra/SymEigsSolver.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>
#include <string>

#include "graphslam/certify/certify.h"
#include "problem_impl.h"
#include "riemannian.h"

namespace graphslam::certify {

namespace {

/// y = (S + sigma I)^-1 x through a ShiftedFactor, for Spectra.
class ShiftInvertedCertificate {
 public:
  using Scalar = double;
  explicit ShiftInvertedCertificate(const ShiftedFactor& factor, Eigen::Index size)
      : factor_(&factor), size_(size) {}
  [[nodiscard]] Eigen::Index rows() const { return size_; }
  [[nodiscard]] Eigen::Index cols() const { return size_; }
  void perform_op(const double* x_in, double* y_out) const {
    const Eigen::Map<const Eigen::VectorXd> x(x_in, size_);
    Eigen::Map<Eigen::VectorXd>(y_out, size_) = factor_->solve(x);
  }

 private:
  const ShiftedFactor* factor_;
  Eigen::Index size_;
};

/// S v.
Eigen::VectorXd applyCertificate(const Problem& problem, const Eigen::MatrixXd& lambda,
                                 const Eigen::VectorXd& v) {
  return subtractBlockProducts(problem.applyQ(v), lambda, v, problem.dimension());
}

/// The largest |Lambda_i|_2 (Q is positive semidefinite, so lambda_min(S) >= -this).
double multiplierBound(const Eigen::MatrixXd& lambda, int d) {
  double bound = 0.0;
  for (Eigen::Index i = 0; i < lambda.cols() / d; ++i) {
    bound = std::max(bound, lambda.middleCols(d * i, d).operatorNorm());
  }
  return bound;
}

/// A fixed pseudo-random start vector (the same on every run and machine: mt19937 is
/// specified exactly; the mapping to doubles is ours).
Eigen::VectorXd startVector(Eigen::Index size) {
  std::mt19937 rng(20190101u);
  Eigen::VectorXd v(size);
  for (Eigen::Index k = 0; k < size; ++k) v[k] = static_cast<double>(rng()) / 4294967296.0 - 0.5;
  return v.normalized();
}

}  // namespace

Eigen::MatrixXd lagrangeMultipliers(const Problem& problem, const Eigen::MatrixXd& x) {
  return symmetricBlockProducts(problem.objectiveAndProduct(x, nullptr), x, problem.dimension());
}

EigenResult minimumEigenvalue(const Problem& problem, const Eigen::MatrixXd& x,
                              const Options& options) {
  EigenResult out;
  const int d = problem.dimension();
  const Eigen::MatrixXd lambda = lagrangeMultipliers(problem, x);
  const Eigen::Index size = x.rows();
  // The smallest shift sigma = tolerance * 4^k at which S + sigma I is positive definite.
  ShiftedFactor factor(problem);
  const double limit = 2.0 * multiplierBound(lambda, d) + problem.scale();
  double sigma = std::max(options.eigenvalue_tolerance * problem.scale(), 1e-300);
  while (++out.factorizations, !factor.factorize(lambda, sigma)) {
    sigma *= 4.0;
    if (sigma > 4.0 * limit) {
      out.message = "no shift made the certificate positive definite (Cholesky failed up to " +
                    std::to_string(sigma) + ")";
      return out;
    }
  }
  // The largest eigenvalue 1 / (lambda_min + sigma) of (S + sigma I)^-1.
  ShiftInvertedCertificate op(factor, size);
  const Eigen::Index ncv = std::min<Eigen::Index>(size, 20);
  Spectra::SymEigsSolver<ShiftInvertedCertificate> eigs(op, 1, ncv);
  const Eigen::VectorXd v0 = startVector(size);
  eigs.init(v0.data());
  eigs.compute(Spectra::SortRule::LargestAlge, options.eigen_max_iterations,
               options.eigen_tolerance);
  out.operations = static_cast<int>(eigs.num_operations());
  if (eigs.info() != Spectra::CompInfo::Successful || eigs.eigenvalues().size() == 0) {
    out.message =
        "Lanczos did not converge in " + std::to_string(options.eigen_max_iterations) + " restarts";
    return out;
  }
  out.lambda_min = 1.0 / eigs.eigenvalues()[0] - sigma;
  out.vector = eigs.eigenvectors(1).col(0).normalized();
  out.residual =
      (applyCertificate(problem, lambda, out.vector) - out.lambda_min * out.vector).norm();
  out.converged = out.residual <= options.eigen_residual_tolerance * problem.scale();
  if (!out.converged) out.message = "the eigenpair's residual is above the tolerance";
  return out;
}

}  // namespace graphslam::certify
