// SPDX-License-Identifier: MIT
// OrderedFactor (graphslam/solvers/ordered_factor.h) by CHOLMOD's supernodal Cholesky, part of
// the SuiteSparse backend (loaded on first use).
#include <cholmod.h>

#include <algorithm>
#include <string>
#include <utility>

#include "graphslam/solvers/ordered_factor.h"
#include "graphslam/support/error.h"
#include "openmp_control.h"
#include "suitesparse_backend.h"

namespace graphslam::solvers::suitesparse {

namespace {

class CholmodOrderedFactor final : public OrderedFactor {
 public:
  CholmodOrderedFactor() {
    cholmod_start(&common_);
    common_.print = 0;
    common_.error_handler = nullptr;
    common_.supernodal = CHOLMOD_SUPERNODAL;
    common_.nmethods = 1;  // the caller's order, kept as it is
    common_.method[0].ordering = CHOLMOD_NATURAL;
    common_.postorder = 0;
  }
  ~CholmodOrderedFactor() override {
    if (factor_ != nullptr) cholmod_free_factor(&factor_, &common_);
    cholmod_finish(&common_);
  }
  CholmodOrderedFactor(const CholmodOrderedFactor&) = delete;
  CholmodOrderedFactor& operator=(const CholmodOrderedFactor&) = delete;

  bool factorize(const Eigen::SparseMatrix<double>& upper) override {
    if (!upper.isCompressed() || upper.rows() != upper.cols()) {
      throw Error("OrderedFactor: the matrix must be square and compressed");
    }
    cholmod_sparse m = view(upper);
    const detail::SerialOpenMp serial;
    if (factor_ == nullptr) factor_ = cholmod_analyze(&m, &common_);
    const bool ok = factor_ != nullptr && cholmod_factorize(&m, factor_, &common_) &&
                    common_.status == CHOLMOD_OK;
    if (factor_ == nullptr || common_.status < CHOLMOD_OK) {
      throw Error("CHOLMOD could not factorise an ordered matrix of " +
                  std::to_string(upper.rows()) + " rows (status " + std::to_string(common_.status) +
                  ", out of memory?)");
    }
    return ok;
  }

  Eigen::MatrixXd trailingBlock(int n) const override {
    // The supernodes' values are column-major with the supernode's row count as leading
    // dimension; a supernode's own columns are its first rows, in order.
    const cholmod_factor& f = *factor_;
    const int first_trailing = static_cast<int>(f.n) - n;
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(n, n);
    const auto* super = static_cast<const int*>(f.super);
    const auto* pi = static_cast<const int*>(f.pi);
    const auto* px = static_cast<const int*>(f.px);
    const auto* s = static_cast<const int*>(f.s);
    const auto* x = static_cast<const double*>(f.x);
    for (std::size_t sn = 0; sn < f.nsuper; ++sn) {
      const int first = super[sn], end = super[sn + 1];
      if (end <= first_trailing) continue;
      const int height = pi[sn + 1] - pi[sn];
      const int* rows = s + pi[sn];
      const double* values = x + px[sn];
      for (int col = std::max(first, first_trailing); col < end; ++col) {
        const int local = col - first;
        for (int r = local; r < height; ++r) {
          block(rows[r] - first_trailing, col - first_trailing) =
              values[static_cast<std::size_t>(local) * height + r];
        }
      }
    }
    return block;
  }

  Eigen::VectorXd solveTriangular(Eigen::VectorXd b, bool transposed) const override {
    cholmod_dense in{};
    in.nrow = in.nzmax = in.d = static_cast<std::size_t>(b.size());
    in.ncol = 1;
    in.x = b.data();
    in.xtype = CHOLMOD_REAL;
    in.dtype = CHOLMOD_DOUBLE;
    const detail::SerialOpenMp serial;
    cholmod_dense* out = cholmod_solve(transposed ? CHOLMOD_Lt : CHOLMOD_L, factor_, &in, &common_);
    if (out == nullptr) throw Error("CHOLMOD's triangular solve failed (out of memory?)");
    Eigen::VectorXd x =
        Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(out->x), b.size());
    cholmod_free_dense(&out, &common_);
    return x;
  }

  void release() override {
    if (factor_ != nullptr && factor_->xtype != CHOLMOD_PATTERN) {
      cholmod_change_factor(CHOLMOD_PATTERN, 1, factor_->is_super, 1, 1, factor_, &common_);
    }
  }

 private:
  /// The upper triangle as CHOLMOD's matrix (no copy: CHOLMOD only reads it).
  static cholmod_sparse view(const Eigen::SparseMatrix<double>& upper) {
    cholmod_sparse m{};
    m.nrow = m.ncol = static_cast<std::size_t>(upper.rows());
    m.nzmax = static_cast<std::size_t>(upper.nonZeros());
    m.p = const_cast<int*>(upper.outerIndexPtr());
    m.i = const_cast<int*>(upper.innerIndexPtr());
    m.x = const_cast<double*>(upper.valuePtr());
    m.stype = 1;
    m.itype = CHOLMOD_INT;
    m.xtype = CHOLMOD_REAL;
    m.dtype = CHOLMOD_DOUBLE;
    m.sorted = 0;  // Eigen's symmetric permutations leave a column's rows unsorted
    m.packed = 1;
    return m;
  }

  // mutable: CHOLMOD's solves take a non-const workspace (statistics, status).
  mutable cholmod_common common_{};
  cholmod_factor* factor_ = nullptr;
};

}  // namespace

std::unique_ptr<OrderedFactor> makeOrderedFactor() {
  return std::make_unique<CholmodOrderedFactor>();
}

}  // namespace graphslam::solvers::suitesparse
