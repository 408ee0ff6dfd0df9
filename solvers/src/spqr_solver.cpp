// SPDX-License-Identifier: MIT
#include <SuiteSparseQR.hpp>
#include <cmath>
#include <cstring>
#include <memory>

#include "common.h"
#include "suitesparse_backend.h"

namespace graphslam::solvers::suitesparse {

namespace {

using Long = SuiteSparse_long;

int spqrOrdering(Ordering o) {
  switch (o) {
    case Ordering::kNatural:
      return SPQR_ORDERING_FIXED;
    case Ordering::kAmd:
      return SPQR_ORDERING_AMD;
    case Ordering::kMetis:
      return SPQR_ORDERING_METIS;
    case Ordering::kColamd:
    case Ordering::kDefault:
    case Ordering::kRcm:  // not offered (SPQR orders J for fill)
      break;
  }
  return SPQR_ORDERING_COLAMD;
}

/// SuiteSparseQR on the whitened Jacobian: symbolic analysis once, numeric QR every
/// iteration, x = E (R \ (Q^T b)). SPQR orders J's scalar columns itself and detects
/// rank deficiency (dead columns). Two patterns are analysed lazily: J alone (no damping)
/// and J with its damping rows, whose structural zeros would otherwise fill Q.
class SpqrSolver final : public LinearSolver {
 public:
  explicit SpqrSolver(Ordering ordering) : ordering_(ordering) {
    cholmod_l_start(&cc_);
    cc_.print = 0;
    cc_.error_handler = nullptr;
  }
  ~SpqrSolver() override {
    release();
    cholmod_l_finish(&cc_);
  }

  std::string name() const override { return "spqr"; }
  SystemForm form() const override { return SystemForm::kJacobian; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyzeJacobian(const JacobianStructure& s) override {
    release();
    structure_ = s;
    const std::vector<int> identity = [&] {
      std::vector<int> p(static_cast<std::size_t>(s.cols));
      for (int i = 0; i < s.cols; ++i) p[i] = i;
      return p;
    }();
    for (int damped = 0; damped < 2; ++damped) {
      Variant& v = variants_[damped];
      detail::PermutedColumns pc;
      pc.build(s, identity, damped == 0);
      v.col_ptr.assign(pc.col_ptr.begin(), pc.col_ptr.end());  // SPQR takes 64-bit indices
      v.row_idx.assign(pc.row_idx.begin(), pc.row_idx.end());
      v.source = std::move(pc.source);
      v.a = cholmod_sparse{};
      v.a.nrow = static_cast<size_t>(pc.rows);
      v.a.ncol = static_cast<size_t>(pc.cols);
      v.a.nzmax = v.row_idx.size();
      v.a.p = v.col_ptr.data();
      v.a.i = v.row_idx.data();
      v.a.stype = 0;
      v.a.itype = CHOLMOD_LONG;
      v.a.xtype = CHOLMOD_REAL;
      v.a.dtype = CHOLMOD_DOUBLE;
      v.a.sorted = 1;
      v.a.packed = 1;
    }
    active_ = nullptr;
    // The undamped pattern is the common case: analyse it now (values are ignored).
    Variant& v = variants_[0];
    v.values.assign(v.source.size(), 0.0);
    v.a.x = v.values.data();
    v.qr = SuiteSparseQR_symbolic<double>(spqrOrdering(ordering_), 1, &v.a, &cc_);
    if (!v.qr) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "SuiteSparseQR_symbolic failed: " + cholmodStatusText(cc_.status));
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult factorizeJacobian(const double* values) override {
    if (variants_[0].col_ptr.empty()) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    }
    Variant& v = variants_[detail::dampingIsZero(structure_, values) ? 0 : 1];
    active_ = &v;
    v.values.resize(v.source.size());
    for (std::size_t k = 0; k < v.source.size(); ++k) v.values[k] = values[v.source[k]];
    v.a.x = v.values.data();
    if (!v.qr) {
      v.qr = SuiteSparseQR_symbolic<double>(spqrOrdering(ordering_), 1, &v.a, &cc_);
      if (!v.qr) {
        return LinearSolverResult::failure(
            LinearSolverStatus::kFailure,
            "SuiteSparseQR_symbolic failed: " + cholmodStatusText(cc_.status));
      }
    }
    if (!SuiteSparseQR_numeric<double>(SPQR_DEFAULT_TOL, &v.a, v.qr, &cc_)) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "SuiteSparseQR_numeric failed: " + cholmodStatusText(cc_.status));
    }
    r_nnz_ = static_cast<std::size_t>(cc_.SPQR_istat[0]);
    const Long cols = structure_.cols;
    if (v.qr->rank < cols) {
      int col = -1;
      for (Long j = 0; j < cols && v.qr->Rmap; ++j) {
        if (v.qr->Rmap[j] >= v.qr->rank) {
          col = static_cast<int>(v.qr->Q1fill ? v.qr->Q1fill[j] : j);
          break;
        }
      }
      return LinearSolverResult::failure(
          LinearSolverStatus::kSingular,
          "rank " + std::to_string(v.qr->rank) + " < " + std::to_string(cols) + " (dead column)",
          col);
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult solveJacobian(const double* rhs, double* x) override {
    if (!active_)
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not factorised");
    const auto rows = active_->a.nrow;
    const auto cols = static_cast<std::size_t>(structure_.cols);
    cholmod_dense* b = cholmod_l_allocate_dense(rows, 1, rows, CHOLMOD_REAL, &cc_);
    if (!b) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "out of memory");
    std::memcpy(b->x, rhs, sizeof(double) * rows);
    cholmod_dense* y = SuiteSparseQR_qmult<double>(SPQR_QTX, active_->qr, b, &cc_);
    cholmod_dense* sol =
        y ? SuiteSparseQR_solve<double>(SPQR_RETX_EQUALS_B, active_->qr, y, &cc_) : nullptr;
    LinearSolverResult result = LinearSolverResult::success();
    if (!sol) {
      result =
          LinearSolverResult::failure(LinearSolverStatus::kFailure, "SuiteSparseQR_solve failed");
    } else {
      std::memcpy(x, sol->x, sizeof(double) * cols);
      if (!detail::allFinite(x, structure_.cols)) result = detail::notFinite();
    }
    cholmod_l_free_dense(&b, &cc_);
    if (y) cholmod_l_free_dense(&y, &cc_);
    if (sol) cholmod_l_free_dense(&sol, &cc_);
    return result;
  }

  /// nnz(R) of the last factorisation.
  std::size_t factorNonZeros() const override { return r_nnz_; }

  /// R's pattern, from a separate QR of the last matrix (only for pictures: the
  /// factorization object keeps R in SPQR's internal multifrontal form).
  bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const override {
    if (!active_) return false;
    cholmod_sparse a = active_->a;
    cholmod_sparse* r = nullptr;
    Long* e = nullptr;
    SuiteSparseQR<double>(spqrOrdering(ordering_), SPQR_DEFAULT_TOL, 0, &a, &r, &e, &cc_);
    if (!r) return false;
    const auto* p = static_cast<const Long*>(r->p);
    const auto* i = static_cast<const Long*>(r->i);
    col_ptr.assign(p, p + r->ncol + 1);
    row_idx.assign(i, i + p[r->ncol]);
    cholmod_l_free_sparse(&r, &cc_);
    if (e) cholmod_l_free(a.ncol, sizeof(Long), e, &cc_);
    return true;
  }

 private:
  struct Variant {
    std::vector<Long> col_ptr, row_idx;
    std::vector<int> source;
    std::vector<double> values;
    cholmod_sparse a{};
    SuiteSparseQR_factorization<double>* qr = nullptr;
  };
  void release() {
    for (Variant& v : variants_) {
      if (v.qr) SuiteSparseQR_free<double>(&v.qr, &cc_);
    }
    active_ = nullptr;
  }

  Ordering ordering_;
  mutable cholmod_common cc_{};
  JacobianStructure structure_;
  Variant variants_[2];  // [0]: without damping rows, [1]: with
  Variant* active_ = nullptr;
  std::size_t r_nnz_ = 0;
};

}  // namespace

std::unique_ptr<LinearSolver> makeSpqrSolver(Ordering ordering) {
  return std::make_unique<SpqrSolver>(ordering);
}

}  // namespace graphslam::solvers::suitesparse
