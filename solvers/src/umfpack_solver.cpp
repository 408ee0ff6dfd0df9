// SPDX-License-Identifier: MIT
#include <umfpack.h>

#include <memory>
#include <utility>

#include "common.h"
#include "ordering.h"
#include "suitesparse_backend.h"

namespace graphslam::solvers::suitesparse {

namespace {

/// UMFPACK's LU of the whole of H (both triangles), with the chosen ordering on the block
/// graph as its column pre-order and its symmetric strategy (diagonal pivots preferred).
/// LU does not need H positive definite, but the optimizer does: when UMFPACK pivoted
/// symmetrically (P = Q), a non-positive diagonal of U is reported as such.
class UmfpackSolver final : public LinearSolver {
 public:
  UmfpackSolver(Ordering ordering, std::shared_ptr<OrderingCache> cache)
      : ordering_(ordering), cache_(std::move(cache)) {
    umfpack_di_defaults(control_);
    control_[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_SYMMETRIC;
  }
  ~UmfpackSolver() override { release(); }

  std::string name() const override { return "umfpack"; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyze(const SparseStructure& s) override {
    release();
    full_.build(s);
    values_.assign(full_.source.size(), 0.0);
    const std::vector<int> qinit = detail::orderColumns(ordering_, s, cache_.get());
    const int status = umfpack_di_qsymbolic(s.n, s.n, full_.col_ptr.data(), full_.row_idx.data(),
                                            nullptr, qinit.data(), &symbolic_, control_, info_);
    if (status != UMFPACK_OK) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "umfpack_qsymbolic failed (status " + std::to_string(status) + ")");
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* values) override {
    if (!symbolic_)
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    full_.fill(values, values_);
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    const int status = umfpack_di_numeric(full_.col_ptr.data(), full_.row_idx.data(),
                                          values_.data(), symbolic_, &numeric_, control_, info_);
    if (status != UMFPACK_OK && status != UMFPACK_WARNING_singular_matrix) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "umfpack_numeric failed (status " + std::to_string(status) + ")");
    }
    // Pivots: U's diagonal with the row and column permutations.
    const int n = full_.n;
    p_.resize(static_cast<std::size_t>(n));
    q_.resize(static_cast<std::size_t>(n));
    d_.resize(static_cast<std::size_t>(n));
    int do_recip = 0;
    umfpack_di_get_numeric(nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, p_.data(),
                           q_.data(), d_.data(), &do_recip, nullptr, numeric_);
    for (int k = 0; k < n; ++k) {
      if (d_[k] == 0.0) {
        return LinearSolverResult::failure(LinearSolverStatus::kSingular, "zero pivot in U", q_[k]);
      }
    }
    if (status == UMFPACK_WARNING_singular_matrix) {
      return LinearSolverResult::failure(LinearSolverStatus::kSingular, "singular matrix");
    }
    if (p_ == q_) {
      for (int k = 0; k < n; ++k) {
        if (d_[k] < 0.0) {
          return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                             "negative pivot with symmetric pivoting", q_[k]);
        }
      }
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    if (!numeric_)
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not factorised");
    work_.assign(rhs, rhs + full_.n);  // rhs and x may alias
    const int status = umfpack_di_solve(UMFPACK_A, full_.col_ptr.data(), full_.row_idx.data(),
                                        values_.data(), x, work_.data(), numeric_, control_, info_);
    if (status != UMFPACK_OK) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kSingular,
          "umfpack_solve failed (status " + std::to_string(status) + ")");
    }
    if (!detail::allFinite(x, full_.n)) return detail::notFinite();
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    if (!numeric_) return 0;
    int lnz = 0, unz = 0, n_row = 0, n_col = 0, nz_udiag = 0;
    umfpack_di_get_lunz(&lnz, &unz, &n_row, &n_col, &nz_udiag, numeric_);
    return static_cast<std::size_t>(lnz) + static_cast<std::size_t>(unz);
  }
  /// The pattern of U (as the coursework pictured it).
  bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const override {
    if (!numeric_) return false;
    int lnz = 0, unz = 0, n_row = 0, n_col = 0, nz_udiag = 0;
    umfpack_di_get_lunz(&lnz, &unz, &n_row, &n_col, &nz_udiag, numeric_);
    col_ptr.assign(static_cast<std::size_t>(n_col) + 1, 0);
    row_idx.assign(static_cast<std::size_t>(unz), 0);
    std::vector<double> ux(static_cast<std::size_t>(unz));
    return umfpack_di_get_numeric(nullptr, nullptr, nullptr, col_ptr.data(), row_idx.data(),
                                  ux.data(), nullptr, nullptr, nullptr, nullptr, nullptr,
                                  numeric_) == UMFPACK_OK;
  }

 private:
  void release() {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    if (symbolic_) umfpack_di_free_symbolic(&symbolic_);
  }

  Ordering ordering_;
  std::shared_ptr<OrderingCache> cache_;  // block orderings kept between analyses (may be null)
  detail::FullPattern full_;
  std::vector<double> values_, work_, d_;
  std::vector<int> p_, q_;
  double control_[UMFPACK_CONTROL];
  double info_[UMFPACK_INFO];
  void* symbolic_ = nullptr;
  void* numeric_ = nullptr;
};

}  // namespace

std::unique_ptr<LinearSolver> makeUmfpackSolver(Ordering ordering,
                                                std::shared_ptr<OrderingCache> cache) {
  return std::make_unique<UmfpackSolver>(ordering, std::move(cache));
}

}  // namespace graphslam::solvers::suitesparse
