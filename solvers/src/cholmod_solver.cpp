// SPDX-License-Identifier: MIT
#include <cholmod.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "common.h"
#include "graphslam/solvers/options.h"
#include "openmp_control.h"
#include "ordering.h"
#include "suitesparse_backend.h"

namespace graphslam::solvers::suitesparse {

std::string cholmodStatusText(int status) {
  const std::string code = "status " + std::to_string(status);
  if (status == CHOLMOD_OUT_OF_MEMORY) return "out of memory (" + code + ")";
  if (status == CHOLMOD_TOO_LARGE) return "problem too large (" + code + ")";
  return code;
}

namespace {

/// CHOLMOD Cholesky (supernodal or simplicial LL^T) with an ordering computed on the
/// block graph and given to CHOLMOD. H is passed without copying: the cholmod_sparse header points
/// at the optimizer's CSC arrays (upper triangle, stype = 1). A complex solver takes a
/// Hermitian matrix: values, right-hand side and solution are interleaved complex numbers
/// (re, im), two doubles per entry of the pattern and per unknown.
///
/// A pre-permuted solver takes the LOWER triangle of a matrix its caller has already put
/// in its fill-reducing (and postordered) order, and only the identity order: CHOLMOD then
/// factorises the caller's arrays as they are, without the permuted transposed copy it
/// otherwise makes in every factorisation.
class CholmodSolver final : public detail::OrderedSolver {
 public:
  CholmodSolver(std::string name, bool supernodal, Ordering ordering, bool complex,
                bool prepermuted_lower, const CholmodOptions& options)
      : options_(options),
        name_(std::move(name)),
        supernodal_(supernodal),
        ordering_(ordering),
        xtype_(complex ? CHOLMOD_COMPLEX : CHOLMOD_REAL),
        scalars_(complex ? 2 : 1),
        prepermuted_lower_(prepermuted_lower) {
    cholmod_start(&common_);
    common_.supernodal = supernodal_ ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    common_.final_ll = 1;  // keep LL^T (simplicial would convert to LDL^T otherwise)
    common_.nmethods = 1;
    common_.method[0].ordering = prepermuted_lower_ ? CHOLMOD_NATURAL : CHOLMOD_GIVEN;
    // A postorder would turn the natural order into a permuted one (and bring the copy
    // back): the caller postorders.
    common_.postorder = prepermuted_lower_ ? 0 : 1;
    common_.quick_return_if_not_posdef = 1;
    common_.print = 0;
    common_.error_handler = nullptr;
  }
  ~CholmodSolver() override {
    freeFactor();
    freeDense();
    cholmod_finish(&common_);
  }

  std::string name() const override { return name_; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering label) override {
    ordering_ = label;
    freeFactor();
    freeDense();
    n_ = s.n;
    std::memset(&a_, 0, sizeof(a_));
    a_.nrow = static_cast<size_t>(s.n);
    a_.ncol = static_cast<size_t>(s.n);
    a_.nzmax = s.nnz();
    a_.p = const_cast<int*>(s.col_ptr);  // CHOLMOD reads the pattern, never writes it
    a_.i = const_cast<int*>(s.row_idx);
    a_.stype = prepermuted_lower_ ? -1 : 1;
    a_.itype = CHOLMOD_INT;
    a_.xtype = CHOLMOD_PATTERN;
    a_.dtype = CHOLMOD_DOUBLE;
    a_.sorted = 1;
    a_.packed = 1;
    perm_ = std::move(order);
    if (prepermuted_lower_) {
      for (std::size_t k = 0; k < perm_.size(); ++k) {
        if (perm_[k] != static_cast<int>(k)) {
          return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                             "cholmod: a pre-permuted matrix takes the identity "
                                             "order only");
        }
      }
    }
    setRelaxation(s);
    const detail::SerialOpenMp serial;
    factor_ =
        cholmod_analyze_p(&a_, prepermuted_lower_ ? nullptr : perm_.data(), nullptr, 0, &common_);
    if (!factor_ || common_.status < CHOLMOD_OK) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "cholmod_analyze failed: " + cholmodStatusText(common_.status));
    }
    // The analysis leaves a workspace of 6n integers and more; the
    // factorisation allocates the smaller one it needs itself, so this one would only add
    // to the peak memory of the first factorisation.
    cholmod_free_work(&common_);
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* values) override {
    if (!factor_) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    a_.xtype = xtype_;
    a_.x = const_cast<double*>(values);  // read only
    int ok = 0;
    {
      const detail::SerialOpenMp serial;
      ok = cholmod_factorize(&a_, factor_, &common_);
    }
    a_.x = nullptr;
    a_.xtype = CHOLMOD_PATTERN;
    if (common_.status == CHOLMOD_NOT_POSDEF ||
        (factor_->minor < factor_->n && common_.status >= CHOLMOD_OK)) {
      const std::size_t minor = factor_->minor;
      const int col = minor < factor_->n ? static_cast<const int*>(factor_->Perm)[minor] : -1;
      return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                         "matrix is not positive definite", col);
    }
    if (!ok || common_.status < CHOLMOD_OK) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "cholmod_factorize failed: " + cholmodStatusText(common_.status));
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    return solveColumns(rhs, x, n_, 1);
  }

  /// A pre-permuted supernodal factor solves every column in one pass over L (L is read
  /// once, not once per column); otherwise one column at a time.
  LinearSolverResult solveColumns(const double* rhs, double* x, int n, int columns) override {
    if (!factor_ || factor_->xtype == CHOLMOD_PATTERN)
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not factorised");
    if (n != n_ || columns < 1) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                         "cholmod: right-hand sides of the wrong size");
    }
    if (columns > 1 && !(prepermuted_lower_ && factor_->is_super)) {
      return OrderedSolver::solveColumns(rhs, x, n, columns);
    }
    const std::size_t len = static_cast<std::size_t>(n_) * static_cast<std::size_t>(scalars_) *
                            static_cast<std::size_t>(columns);
    const detail::SerialOpenMp serial;
    const double* sol = x;
    if (prepermuted_lower_ && factor_->is_super) {
      // No permutation: the two triangular solves in place in x, with no copies of the
      // right-hand side (three vectors of n).
      if (x != rhs) std::memmove(x, rhs, sizeof(double) * len);
      cholmod_dense in_place{};
      in_place.nrow = a_.nrow;
      in_place.ncol = static_cast<std::size_t>(columns);
      in_place.nzmax = a_.nrow * static_cast<std::size_t>(columns);
      in_place.d = a_.nrow;
      in_place.x = x;
      in_place.xtype = xtype_;
      in_place.dtype = CHOLMOD_DOUBLE;
      // CHOLMOD's workspace: the largest supernode's rows for every column.
      const std::size_t e_size = factor_->maxesize * static_cast<std::size_t>(columns);
      if (e_ && e_->nzmax < e_size) cholmod_free_dense(&e_, &common_);
      if (!e_) e_ = cholmod_allocate_dense(e_size, 1, e_size, xtype_, &common_);
      if (!e_ || !cholmod_super_lsolve(factor_, &in_place, e_, &common_) ||
          !cholmod_super_ltsolve(factor_, &in_place, e_, &common_)) {
        return LinearSolverResult::failure(LinearSolverStatus::kFailure, "cholmod_solve failed");
      }
    } else {
      if (!b_) b_ = cholmod_allocate_dense(a_.nrow, 1, a_.nrow, xtype_, &common_);
      if (!b_) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "out of memory");
      std::memcpy(b_->x, rhs, sizeof(double) * len);
      const int ok =
          cholmod_solve2(CHOLMOD_A, factor_, b_, nullptr, &x_, nullptr, &y_, &e_, &common_);
      if (!ok || !x_) {
        return LinearSolverResult::failure(LinearSolverStatus::kFailure, "cholmod_solve failed");
      }
      sol = static_cast<const double*>(x_->x);
    }
    for (std::size_t i = 0; i < len; ++i) {
      if (!std::isfinite(sol[i])) {
        return LinearSolverResult::failure(LinearSolverStatus::kSingular, "solution is not finite");
      }
      x[i] = sol[i];
    }
    return LinearSolverResult::success();
  }

  /// Real and complex values share the symbolic analysis (the same supernodes): switching
  /// drops the numeric factor of the other kind (CHOLMOD frees its values and keeps the
  /// symbolic factor) and the solve's workspaces.
  bool setComplexValues(bool complex) override {
    const int xtype = complex ? CHOLMOD_COMPLEX : CHOLMOD_REAL;
    if (xtype == xtype_) return true;
    if (factor_ && factor_->xtype != CHOLMOD_PATTERN &&
        !cholmod_change_factor(CHOLMOD_PATTERN, common_.final_ll, factor_->is_super, 1, 1, factor_,
                               &common_)) {
      return false;
    }
    freeDense();
    xtype_ = xtype;
    scalars_ = complex ? 2 : 1;
    return true;
  }

  std::size_t factorNonZeros() const override {
    if (!factor_) return 0;
    if (factor_->is_super) {
      // Sum of the lower-trapezoidal parts of every supernode.
      const auto* super = static_cast<const int*>(factor_->super);
      const auto* pi = static_cast<const int*>(factor_->pi);
      std::size_t nnz = 0;
      for (std::size_t s = 0; s < factor_->nsuper; ++s) {
        const std::size_t ncols = static_cast<std::size_t>(super[s + 1] - super[s]);
        const std::size_t nrows = static_cast<std::size_t>(pi[s + 1] - pi[s]);
        nnz += ncols * nrows - ncols * (ncols - 1) / 2;
      }
      return nnz;
    }
    const auto* colcount = static_cast<const int*>(factor_->ColCount);
    std::size_t nnz = 0;
    for (std::size_t j = 0; j < factor_->n; ++j) nnz += static_cast<std::size_t>(colcount[j]);
    return nnz;
  }

  bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const override {
    if (!factor_) return false;
    cholmod_factor* copy = cholmod_copy_factor(factor_, &common_);
    if (!copy) return false;
    cholmod_sparse* l = cholmod_factor_to_sparse(copy, &common_);
    bool ok = l != nullptr;
    if (ok) {
      const auto* p = static_cast<const int*>(l->p);
      const auto* i = static_cast<const int*>(l->i);
      col_ptr.assign(p, p + l->ncol + 1);
      row_idx.assign(i, i + p[l->ncol]);
      cholmod_free_sparse(&l, &common_);
    }
    cholmod_free_factor(&copy, &common_);
    return ok;
  }

 private:
  /// Supernodal amalgamation (CholmodOptions): systems of blocks (vertices of dimension
  /// > 1, supernodes at least one block wide) and scalar systems have settings of their own.
  void setRelaxation(const SparseStructure& s) {
    const bool scalar = s.num_blocks == s.n;
    const double* zrelax = scalar ? options_.scalar_zrelax : options_.block_zrelax;
    for (int k = 0; k < 3; ++k) common_.zrelax[k] = zrelax[k];
  }

  void freeFactor() {
    if (factor_) cholmod_free_factor(&factor_, &common_);
  }
  void freeDense() {
    if (b_) cholmod_free_dense(&b_, &common_);
    if (x_) cholmod_free_dense(&x_, &common_);
    if (y_) cholmod_free_dense(&y_, &common_);
    if (e_) cholmod_free_dense(&e_, &common_);
  }

  CholmodOptions options_;
  std::string name_;
  bool supernodal_;
  Ordering ordering_;
  int xtype_;                        // CHOLMOD_REAL or CHOLMOD_COMPLEX
  int scalars_;                      // doubles per value
  bool prepermuted_lower_;           // lower triangle, already in factor order
  mutable cholmod_common common_{};  // CHOLMOD statistics change in const queries
  cholmod_sparse a_{};
  cholmod_factor* factor_ = nullptr;
  cholmod_dense* b_ = nullptr;
  cholmod_dense* x_ = nullptr;
  cholmod_dense* y_ = nullptr;
  cholmod_dense* e_ = nullptr;
  std::vector<int> perm_;
  int n_ = 0;
};

}  // namespace

std::unique_ptr<detail::OrderedSolver> makeCholmodSolver(bool supernodal, Ordering ordering,
                                                         bool prepermuted_lower,
                                                         const CholmodOptions& options) {
  return std::make_unique<CholmodSolver>(supernodal ? "cholmod" : "cholmod-simplicial", supernodal,
                                         ordering, false, prepermuted_lower, options);
}

std::unique_ptr<detail::OrderedSolver> makeCholmodComplexSolver(bool supernodal, Ordering ordering,
                                                                bool prepermuted_lower,
                                                                const CholmodOptions& options) {
  return std::make_unique<CholmodSolver>("cholmod-complex", supernodal, ordering, true,
                                         prepermuted_lower, options);
}

}  // namespace graphslam::solvers::suitesparse
