// SPDX-License-Identifier: MIT
// Solvers built on Eigen alone: sparse LDL^T / LL^T, sparse QR on J, dense LDL^T, dense
// pseudo-inverse (block-Jacobi preconditioned conjugate gradients: pcg_solver.cpp).
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseQR>
#include <memory>

#include "common.h"
#include "factories.h"
#include "graphslam/solvers/ordering.h"
#include "graphslam/solvers/register.h"
#include "ordering.h"

namespace graphslam::solvers {

namespace {

using detail::SpMat;

/// Eigen's simplicial Cholesky (LDL^T or LL^T) on P H P^T, P from the chosen ordering.
template <typename Factorization>
class EigenSimplicialSolver final : public detail::OrderedSolver {
 public:
  EigenSimplicialSolver(std::string name, Ordering ordering)
      : name_(std::move(name)), ordering_(ordering) {}

  std::string name() const override { return name_; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering label) override {
    n_ = s.n;
    ordering_ = label;
    order_ = std::move(order);  // order_[k] = original column at k
    permuted_.build(s, order_);
    pattern_done_ = false;
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* values) override {
    permuted_.fill(values, values_);
    const auto a = permuted_.map(values_);
    if (!pattern_done_) {
      factor_.analyzePattern(a);
      pattern_done_ = true;
    }
    factor_.factorize(a);
    if (factor_.info() != Eigen::Success) {
      return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                         "Cholesky factorisation failed", firstBadColumn());
    }
    if (const int bad = firstBadColumn(); bad >= 0) {
      return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                         "non-positive pivot", bad);
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    work_.resize(n_);
    for (int k = 0; k < n_; ++k) work_[k] = rhs[order_[k]];
    work_ = factor_.solve(work_);
    for (int k = 0; k < n_; ++k) x[order_[k]] = work_[k];
    if (!detail::allFinite(x, n_)) return detail::notFinite();
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    return static_cast<std::size_t>(factor_.matrixL().nestedExpression().nonZeros());
  }
  bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const override {
    return detail::exportPattern(factor_.matrixL().nestedExpression(), col_ptr, row_idx);
  }

 private:
  /// First pivot <= 0 mapped back to the original column (LDL^T only), else -1.
  int firstBadColumn() const {
    if constexpr (std::is_same_v<
                      Factorization,
                      Eigen::SimplicialLDLT<SpMat, Eigen::Upper, Eigen::NaturalOrdering<int>>>) {
      const auto& d = factor_.vectorD();
      for (int k = 0; k < d.size(); ++k) {
        if (!(d[k] > 0.0)) return order_[k];
      }
    }
    return -1;
  }

  std::string name_;
  Ordering ordering_;
  int n_ = 0;
  std::vector<int> order_;
  detail::PermutedUpper permuted_;
  std::vector<double> values_;
  Factorization factor_;
  Eigen::VectorXd work_;
  bool pattern_done_ = false;
};

using Ldlt = Eigen::SimplicialLDLT<SpMat, Eigen::Upper, Eigen::NaturalOrdering<int>>;
using Llt = Eigen::SimplicialLLT<SpMat, Eigen::Upper, Eigen::NaturalOrdering<int>>;

/// Eigen's SparseQR on the whitened Jacobian with its columns in the chosen order. Two
/// patterns are analysed lazily: J alone (no damping) and J with its damping rows.
class EigenQrSolver final : public LinearSolver {
 public:
  explicit EigenQrSolver(Ordering ordering) : ordering_(ordering) {}
  std::string name() const override { return "eigen-qr"; }
  SystemForm form() const override { return SystemForm::kJacobian; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyzeJacobian(const JacobianStructure& s) override {
    structure_ = s;
    order_ = detail::orderColumns(ordering_, s);
    for (int damped = 0; damped < 2; ++damped) {
      variants_[damped].columns.build(s, order_, damped == 0, true);
      variants_[damped].analyzed = false;
    }
    active_ = nullptr;
    // The undamped pattern is the common case: analyse it now (values are ignored).
    Variant& v = variants_[0];
    values_.assign(v.columns.source.size(), 0.0);
    v.matrix = v.columns.map(values_);
    v.qr.analyzePattern(v.matrix);
    v.analyzed = true;
    return LinearSolverResult::success();
  }

  LinearSolverResult factorizeJacobian(const double* values) override {
    Variant& v = variants_[detail::dampingIsZero(structure_, values) ? 0 : 1];
    active_ = &v;
    v.columns.fill(values, values_);
    v.matrix = v.columns.map(values_);
    if (!v.analyzed) {
      v.qr.analyzePattern(v.matrix);
      v.analyzed = true;
    }
    v.qr.factorize(v.matrix);
    if (v.qr.info() != Eigen::Success) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                         "SparseQR failed: " + v.qr.lastErrorMessage());
    }
    const int n = v.columns.cols;
    if (v.qr.rank() < n) {
      const int dead = v.qr.colsPermutation().indices()[v.qr.rank()];
      return LinearSolverResult::failure(
          LinearSolverStatus::kSingular,
          "rank " + std::to_string(v.qr.rank()) + " < " + std::to_string(n), order_[dead]);
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult solveJacobian(const double* rhs, double* x) override {
    if (!active_)
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not factorised");
    const auto& rows = active_->columns.row_order;
    rhs_.resize(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k) rhs_[static_cast<Eigen::Index>(k)] = rhs[rows[k]];
    work_ = active_->qr.solve(rhs_);
    for (int k = 0; k < active_->columns.cols; ++k) x[order_[k]] = work_[k];
    if (!detail::allFinite(x, active_->columns.cols)) return detail::notFinite();
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    return active_ ? static_cast<std::size_t>(active_->qr.matrixR().nonZeros()) : 0u;
  }
  bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const override {
    return active_ && detail::exportPattern(active_->qr.matrixR(), col_ptr, row_idx);
  }

 private:
  struct Variant {
    detail::PermutedColumns columns;
    SpMat matrix;
    Eigen::SparseQR<SpMat, Eigen::NaturalOrdering<int>> qr;
    bool analyzed = false;
  };
  Ordering ordering_;
  JacobianStructure structure_;
  std::vector<int> order_;
  Variant variants_[2];  // [0]: without damping rows, [1]: with
  Variant* active_ = nullptr;
  std::vector<double> values_;
  Eigen::VectorXd rhs_, work_;
};

/// Dense LDL^T with symmetric pivoting (Eigen::LDLT) of the whole of H.
class DenseLdltSolver final : public LinearSolver {
 public:
  std::string name() const override { return "dense-ldlt"; }
  Ordering ordering() const override { return Ordering::kNatural; }

  LinearSolverResult analyze(const SparseStructure& s) override {
    structure_ = s;
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* values) override {
    ldlt_.compute(detail::denseSymmetric(structure_, values));
    if (ldlt_.info() != Eigen::Success) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "dense LDLT failed");
    }
    const Eigen::VectorXd d = ldlt_.vectorD();
    Eigen::VectorXi original = Eigen::VectorXi::LinSpaced(structure_.n, 0, structure_.n - 1);
    original = ldlt_.transpositionsP() * original;  // original[k] = column pivoted to k
    const double tol = detail::zeroTolerance(structure_.n, d.cwiseAbs().maxCoeff());
    for (int k = 0; k < d.size(); ++k) {
      if (d[k] < -tol) {
        return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                           "negative pivot", original[k]);
      }
    }
    for (int k = 0; k < d.size(); ++k) {
      if (d[k] <= tol) {
        return LinearSolverResult::failure(LinearSolverStatus::kSingular, "zero pivot",
                                           original[k]);
      }
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    const Eigen::Map<const Eigen::VectorXd> b(rhs, structure_.n);
    Eigen::Map<Eigen::VectorXd>(x, structure_.n) = ldlt_.solve(b);
    if (!detail::allFinite(x, structure_.n)) return detail::notFinite();
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    const auto n = static_cast<std::size_t>(structure_.n);
    return n * (n + 1) / 2;
  }

 private:
  SparseStructure structure_;
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
};

/// Dense pseudo-inverse of H from its eigendecomposition H = V diag(l) V^T:
/// x = V diag(1/l) V^T b. A negative eigenvalue is reported as not positive definite, a
/// zero one as singular, with the column the eigenvector weighs most.
class DensePinvSolver final : public LinearSolver {
 public:
  std::string name() const override { return "dense-pinv"; }
  Ordering ordering() const override { return Ordering::kNatural; }

  LinearSolverResult analyze(const SparseStructure& s) override {
    structure_ = s;
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* values) override {
    eig_.compute(detail::denseSymmetric(structure_, values));
    if (eig_.info() != Eigen::Success) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                         "eigendecomposition did not converge");
    }
    const Eigen::VectorXd& l = eig_.eigenvalues();  // ascending
    const double tol = detail::zeroTolerance(structure_.n, l.cwiseAbs().maxCoeff());
    int col = 0;
    if (l[0] < -tol) {
      eig_.eigenvectors().col(0).cwiseAbs().maxCoeff(&col);
      return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                         "negative eigenvalue " + std::to_string(l[0]), col);
    }
    if (l[0] <= tol) {
      eig_.eigenvectors().col(0).cwiseAbs().maxCoeff(&col);
      return LinearSolverResult::failure(LinearSolverStatus::kSingular,
                                         "zero eigenvalue (rank deficient)", col);
    }
    inverse_eigenvalues_ = l.cwiseInverse();
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    const Eigen::Map<const Eigen::VectorXd> b(rhs, structure_.n);
    const Eigen::VectorXd y =
        inverse_eigenvalues_.cwiseProduct(eig_.eigenvectors().transpose() * b);
    Eigen::Map<Eigen::VectorXd>(x, structure_.n) = eig_.eigenvectors() * y;
    if (!detail::allFinite(x, structure_.n)) return detail::notFinite();
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    const auto n = static_cast<std::size_t>(structure_.n);
    return n * n;
  }

 private:
  SparseStructure structure_;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_;
  Eigen::VectorXd inverse_eigenvalues_;
};

}  // namespace

std::unique_ptr<detail::OrderedSolver> makeEigenLdlt() {
  return std::make_unique<EigenSimplicialSolver<Ldlt>>("eigen-ldlt", Ordering::kAmd);
}

void registerEigenSolvers(SolverRegistry& registry, const SolverOptions& options) {
  const auto orderings = detail::availableOrderings();
  for (Ordering o : orderings) {
    registry.registerOrdering(o, [o](const SparseStructure& s) { return fillReducingOrdering(o, s); });
  }
  registry.registerSolver(
      "eigen-ldlt", "Eigen SimplicialLDLT on H (ordering on the block graph)",
      SystemForm::kNormalEquations, orderings, [options](const LinearSolverOptions& o) {
        return detail::withOrderingCache(
            std::make_unique<EigenSimplicialSolver<Ldlt>>("eigen-ldlt", o.ordering), options);
      });
  registry.registerSolver(
      "eigen-llt", "Eigen SimplicialLLT on H (ordering on the block graph)",
      SystemForm::kNormalEquations, orderings, [options](const LinearSolverOptions& o) {
        return detail::withOrderingCache(
            std::make_unique<EigenSimplicialSolver<Llt>>("eigen-llt", o.ordering), options);
      });
  registry.registerSolver(
      "block-llt",
      "block up-looking Cholesky LL^T on fixed-size 2x2 or 3x3 blocks (vertices of dimension "
      "at most 3; smaller ones padded)",
      SystemForm::kNormalEquations, orderings,
      [options](const LinearSolverOptions& o) {
        return detail::withOrderingCache(makeBlockCholesky(o.ordering, options.block_cholesky),
                                         options);
      });
  registry.registerSolver(
      "isotropic",
      "H = H_s (x) I_d (isotropic linear SLAM: every block a multiple of the identity): "
      "Cholesky of the scalar H_s on the block graph (CHOLMOD supernodal when its predicted "
      "work is large, else a dense-tail or up-looking LL^T), d right-hand sides; fails on "
      "other systems",
      SystemForm::kNormalEquations, orderings,
      [options](const LinearSolverOptions& o) {
        return detail::withOrderingCache(makeIsotropicSolver(o.ordering, options), options);
      });
  std::vector<Ordering> envelope_orderings{Ordering::kRcm};
  envelope_orderings.insert(envelope_orderings.end(), orderings.begin(), orderings.end());
  registry.registerSolver(
      "envelope",
      "envelope (profile) Cholesky, each row of L stored from its first non-zero, in a block "
      "order that keeps the envelope small (reverse Cuthill-McKee by default); of the scalar "
      "H_s with d right-hand sides when H = H_s (x) I_d, of H itself otherwise",
      SystemForm::kNormalEquations, envelope_orderings,
      [options](const LinearSolverOptions& o) {
        return detail::withOrderingCache(makeEnvelopeSolver(o.ordering), options);
      });
  registry.registerSolver(
      "eigen-qr", "Eigen SparseQR on the whitened Jacobian J", SystemForm::kJacobian, orderings,
      [](const LinearSolverOptions& o) { return std::make_unique<EigenQrSolver>(o.ordering); });
  registry.registerSolver(
      "dense-ldlt", "Eigen dense LDLT (pivoted) of the whole of H", SystemForm::kNormalEquations,
      {Ordering::kNatural},
      [](const LinearSolverOptions&) { return std::make_unique<DenseLdltSolver>(); });
  registry.registerSolver(
      "dense-pinv", "dense pseudo-inverse of H from its eigendecomposition (Eigen)",
      SystemForm::kNormalEquations, {Ordering::kNatural},
      [](const LinearSolverOptions&) { return std::make_unique<DensePinvSolver>(); });
  registry.registerSolver(
      "pcg",
      "conjugate gradients on H, block-Jacobi preconditioner, relative residual 1e-14 (at most "
      "5000 iterations); on H = H_s (x) I_d on H_s with d right-hand sides",
      SystemForm::kNormalEquations, {Ordering::kNatural},
      [](const LinearSolverOptions&) { return makePcgSolver(); });
}

void registerSolvers(SolverRegistry& registry, const SolverOptions& options) {
  registerAutoSolver(registry, options);
  registerEigenSolvers(registry, options);
  if (haveSuiteSparse()) registerSuiteSparseSolvers(registry, options);
}

}  // namespace graphslam::solvers
