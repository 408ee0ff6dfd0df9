// SPDX-License-Identifier: MIT
#include <cs.h>

#include <Eigen/SparseCholesky>
#include <memory>
#include <utility>

#include "common.h"
#include "ordering.h"
#include "suitesparse_backend.h"

namespace graphslam::solvers::suitesparse {

namespace {

/// CXSparse's up-looking Cholesky (cs_schol + cs_chol) of P H P^T, P from the chosen
/// ordering on the block graph.
class CsparseSolver final : public LinearSolver {
 public:
  CsparseSolver(Ordering ordering, std::shared_ptr<OrderingCache> cache)
      : ordering_(ordering), cache_(std::move(cache)) {}
  ~CsparseSolver() override { release(); }

  std::string name() const override { return "csparse"; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyze(const SparseStructure& s) override {
    release();
    order_ = detail::orderColumns(ordering_, s, cache_.get());
    permuted_.build(s, order_);
    values_.assign(permuted_.source.size(), 0.0);
    matrix_ = cs_di{};
    matrix_.nzmax = static_cast<int>(values_.size());
    matrix_.m = matrix_.n = s.n;
    matrix_.p = permuted_.col_ptr.data();
    matrix_.i = permuted_.row_idx.data();
    matrix_.x = values_.data();
    matrix_.nz = -1;
    symbolic_ = cs_di_schol(0, &matrix_);  // natural: the matrix is already permuted
    if (!symbolic_) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "cs_schol failed");
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* values) override {
    if (!symbolic_)
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    permuted_.fill(values, values_);
    matrix_.x = values_.data();
    if (numeric_) numeric_ = cs_di_nfree(numeric_);
    numeric_ = cs_di_chol(&matrix_, symbolic_);
    if (!numeric_) {
      return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                         "cs_chol met a non-positive pivot", failedColumn());
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    if (!numeric_)
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not factorised");
    const int n = matrix_.n;
    work_.resize(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) work_[k] = rhs[order_[k]];
    cs_di_lsolve(numeric_->L, work_.data());
    cs_di_ltsolve(numeric_->L, work_.data());
    for (int k = 0; k < n; ++k) x[order_[k]] = work_[k];
    if (!detail::allFinite(x, n)) return detail::notFinite();
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    return numeric_ ? static_cast<std::size_t>(numeric_->L->p[numeric_->L->n]) : 0u;
  }
  bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const override {
    if (!numeric_) return false;
    const cs_di* l = numeric_->L;
    col_ptr.assign(l->p, l->p + l->n + 1);
    row_idx.assign(l->i, l->i + l->p[l->n]);
    return true;
  }

 private:
  /// cs_chol does not say where it stopped: an LDL^T of the same permuted matrix finds
  /// the first non-positive pivot (only on failure).
  int failedColumn() const {
    const auto a = permuted_.map(values_);
    Eigen::SimplicialLDLT<detail::SpMat, Eigen::Upper, Eigen::NaturalOrdering<int>> ldlt(a);
    const auto& d = ldlt.vectorD();
    for (int k = 0; k < d.size(); ++k) {
      if (!(d[k] > 0.0)) return order_[k];
    }
    return -1;
  }
  void release() {
    if (numeric_) numeric_ = cs_di_nfree(numeric_);
    if (symbolic_) symbolic_ = cs_di_sfree(symbolic_);
  }

  Ordering ordering_;
  std::shared_ptr<OrderingCache> cache_;  // block orderings kept between analyses (may be null)
  std::vector<int> order_;
  detail::PermutedUpper permuted_;
  std::vector<double> values_;
  cs_di matrix_{};
  cs_dis* symbolic_ = nullptr;
  cs_din* numeric_ = nullptr;
  std::vector<double> work_;
};

}  // namespace

std::unique_ptr<LinearSolver> makeCsparseSolver(Ordering ordering,
                                                std::shared_ptr<OrderingCache> cache) {
  return std::make_unique<CsparseSolver>(ordering, std::move(cache));
}

}  // namespace graphslam::solvers::suitesparse
