// SPDX-License-Identifier: MIT
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <memory>

#include "graphslam/core/block_ordering.h"
#include "graphslam/solvers/register.h"

namespace graphslam::solvers {

namespace {

using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Perm = Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>;

/// Eigen's simplicial Cholesky (LDL^T or LL^T) on H permuted by a block AMD ordering.
template <typename Factorization>
class EigenSimplicialSolver final : public LinearSolver {
 public:
  explicit EigenSimplicialSolver(std::string name) : name_(std::move(name)) {}

  std::string name() const override { return name_; }

  LinearSolverResult analyze(const SparseStructure& s) override {
    structure_ = s;
    order_ = blockAmdOrdering(s);  // order_[k] = original column at position k
    p_.resize(s.n);
    for (int k = 0; k < s.n; ++k) p_.indices()[order_[k]] = k;  // original -> new
    pattern_done_ = false;
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* values) override {
    const Eigen::Map<const SpMat> a(structure_.n, structure_.n, static_cast<int>(structure_.nnz()),
                                    structure_.col_ptr, structure_.row_idx, values);
    permuted_.resize(structure_.n, structure_.n);
    permuted_.template selfadjointView<Eigen::Upper>() =
        a.template selfadjointView<Eigen::Upper>().twistedBy(p_);
    if (!pattern_done_) {
      factor_.analyzePattern(permuted_);
      pattern_done_ = true;
    }
    factor_.factorize(permuted_);
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
    const Eigen::Map<const Eigen::VectorXd> b(rhs, structure_.n);
    Eigen::Map<Eigen::VectorXd> out(x, structure_.n);
    work_ = p_ * b;
    work_ = factor_.solve(work_);
    out = p_.transpose() * work_;
    if (!out.allFinite()) {
      return LinearSolverResult::failure(LinearSolverStatus::kSingular, "solution is not finite");
    }
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    return static_cast<std::size_t>(factor_.matrixL().nestedExpression().nonZeros());
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
  SparseStructure structure_;
  std::vector<int> order_;
  Perm p_;
  SpMat permuted_;
  Factorization factor_;
  Eigen::VectorXd work_;
  bool pattern_done_ = false;
};

using Ldlt = Eigen::SimplicialLDLT<SpMat, Eigen::Upper, Eigen::NaturalOrdering<int>>;
using Llt = Eigen::SimplicialLLT<SpMat, Eigen::Upper, Eigen::NaturalOrdering<int>>;

}  // namespace

void registerEigenSolvers(SolverRegistry& registry) {
  registry.registerSolver("eigen-ldlt", "Eigen SimplicialLDLT, block AMD ordering", [] {
    return std::make_unique<EigenSimplicialSolver<Ldlt>>("eigen-ldlt");
  });
  registry.registerSolver("eigen-llt", "Eigen SimplicialLLT, block AMD ordering",
                          [] { return std::make_unique<EigenSimplicialSolver<Llt>>("eigen-llt"); });
}

void registerSolvers(SolverRegistry& registry) {
  registerEigenSolvers(registry);
  if (haveCholmod()) registerCholmodSolvers(registry);
}

}  // namespace graphslam::solvers
