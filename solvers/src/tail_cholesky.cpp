// SPDX-License-Identifier: MIT
// Scalar Cholesky LL^T whose trailing columns form one dense block, the isotropic solver's
// factorisation when such a tail holds most of the work.
//
// Ordered poses first, the few landmarks seen from most poses fill the factor's last rows:
// L's last k columns are a dense triangle, and the columns before them are sparse (a pose
// chain, each column a handful of rows plus its rows in the tail). The columns [0, t) are
// factorised left-looking, scalar by scalar, their rows in the tail included; the tail's
// own entries never are. The tail is then a dense Schur complement
//   C = A_TT - W W^T,  W = L(T, 0:t) (the sparse columns' tail rows, k x m dense),
// formed by one BLAS rank-k update (dsyrk) and factorised by LAPACK (dpotrf): the
// products a sparse factorisation makes entry by entry through index arrays run in
// BLAS's blocked kernels.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common.h"
#include "symbolic.h"

namespace graphslam::solvers {

#ifdef GRAPHSLAM_HAVE_LAPACK
extern "C" {
// The reference Fortran interface every BLAS / LAPACK exports (Debian's libblas.so.3 and
// liblapack.so.3; OpenBLAS with the README's set-up).
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a,
            const int* lda, double* x, const int* incx);
}
#endif

namespace detail {

bool blasTailPays(double tail_rows, double panel_columns, double pair_flops) {
#ifdef GRAPHSLAM_HAVE_LAPACK
  // dsyrk makes tail_rows^2 * panel_columns / 2 multiply-adds where a sparse loop makes
  // pair_flops / 2, each several times slower than BLAS's; W stays below 64 MiB.
  return tail_rows >= kBlasTailMinRows && tail_rows * panel_columns <= 8.0 * 1024 * 1024 &&
         tail_rows * tail_rows * panel_columns <= 4.0 * pair_flops;
#else
  static_cast<void>(tail_rows);
  static_cast<void>(panel_columns);
  static_cast<void>(pair_flops);
  return false;
#endif
}

}  // namespace detail

namespace {

#ifdef GRAPHSLAM_HAVE_LAPACK

class TailCholesky final : public detail::OrderedSolver {
 public:
  /// `parent` and `counts`: the elimination tree and column counts (diagonal included) of
  /// the matrix analyzeOrdered() will get (symbolicCostNatural's, computed again when their
  /// size differs). The analysis fails unless the factor has a dense tail worth BLAS
  /// (detail::blasTailPays) and the columns before it take at most `max_sparse_flops`.
  TailCholesky(std::vector<int> parent, std::vector<int> counts, double max_sparse_flops)
      : parent_(std::move(parent)),
        counts_(std::move(counts)),
        max_sparse_flops_(max_sparse_flops) {}

  std::string name() const override { return "tail-llt"; }

  /// `s`: a scalar matrix's upper triangle (rows sorted, diagonal stored), factorised in
  /// its own order (the isotropic solver's B); `order` must be the identity.
  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering /*label*/) override {
    a_ptr_.clear();
    n_ = s.n;
    for (int k = 0; k < n_; ++k) {
      if (order[k] != k) {
        return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                           "tail-llt: factorises in the given order only");
      }
    }
    if (s.lower) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                         "tail-llt: needs the upper triangle");
    }
    const auto upper = [&](int k, auto&& visit) {
      for (int p = s.col_ptr[k]; p < s.col_ptr[k + 1] && s.row_idx[p] < k; ++p) {
        visit(s.row_idx[p]);
      }
    };
    if (static_cast<int>(parent_.size()) != n_ || static_cast<int>(counts_.size()) != n_) {
      parent_ = detail::eliminationTree(n_, upper);
      counts_.assign(static_cast<std::size_t>(n_), 1);
      std::vector<int> flag(static_cast<std::size_t>(n_), -1);
      for (int k = 0; k < n_; ++k) {
        flag[k] = k;
        upper(k, [&](int r) {
          for (int i = r; flag[i] != k; i = parent_[i]) {
            flag[i] = k;
            ++counts_[i];
          }
        });
      }
    }
    // The dense tail: the last columns, each holding every row below it.
    t_ = n_;
    while (t_ > 0 && counts_[t_ - 1] == n_ - t_ + 1) --t_;
    k_ = n_ - t_;
    if (k_ < detail::kBlasTailMinRows) return noTail();
    // Columns before the tail: the diagonal, then rows ascending. Row k of L holds the
    // columns on the tree paths from A's rows i < k of column k up to k (its row
    // subtree); only those before the tail are kept (their ancestors from the tail on
    // are all in it).
    col_ptr_.assign(static_cast<std::size_t>(t_) + 1, 0);
    for (int j = 0; j < t_; ++j) col_ptr_[j + 1] = col_ptr_[j] + counts_[j];
    col_row_.resize(static_cast<std::size_t>(col_ptr_[t_]));
    row_col_.resize(static_cast<std::size_t>(col_ptr_[t_] - t_));
    row_ptr_.assign(static_cast<std::size_t>(n_) + 1, 0);
    std::vector<int> next(col_ptr_.begin(), col_ptr_.end() - 1);
    for (int j = 0; j < t_; ++j) col_row_[next[j]++] = j;
    std::vector<int> flag(static_cast<std::size_t>(n_), -1);
    int kept = 0;
    for (int k = 0; k < n_; ++k) {
      flag[k] = k;
      upper(k, [&](int r) {
        for (int i = r; i < t_ && flag[i] != k; i = parent_[i]) {
          flag[i] = k;
          row_col_[kept++] = i;
          col_row_[next[i]++] = k;
        }
      });
      row_ptr_[k + 1] = kept;
    }
    // W's columns (those before the tail with rows in it), and the work of the loop.
    tail_first_.assign(static_cast<std::size_t>(t_), 0);
    panel_.clear();
    double pairs = 0.0, sparse = 0.0;
    for (int j = 0; j < t_; ++j) {
      int e = col_ptr_[j + 1];
      while (e > col_ptr_[j] + 1 && col_row_[e - 1] >= t_) --e;
      tail_first_[j] = e;
      const double c = counts_[j], r = col_ptr_[j + 1] - e;
      pairs += r * r;
      sparse += c * c - r * r;
      if (r > 0) panel_.push_back(j);
    }
    if (!detail::blasTailPays(k_, static_cast<double>(panel_.size()), pairs) ||
        sparse > max_sparse_flops_) {
      return noTail();
    }
    // A's lower triangle by columns (rows >= j) with the position of every value in the
    // caller's array: the left-looking loop gathers column j.
    a_ptr_.assign(static_cast<std::size_t>(n_) + 1, 0);
    for (int c = 0; c < n_; ++c) {
      for (int p = s.col_ptr[c]; p < s.col_ptr[c + 1]; ++p) ++a_ptr_[s.row_idx[p] + 1];
    }
    for (int j = 0; j < n_; ++j) a_ptr_[j + 1] += a_ptr_[j];
    a_row_.resize(static_cast<std::size_t>(a_ptr_[n_]));
    a_src_.resize(a_row_.size());
    std::vector<int> at(a_ptr_.begin(), a_ptr_.end() - 1);
    for (int c = 0; c < n_; ++c) {
      for (int p = s.col_ptr[c]; p < s.col_ptr[c + 1]; ++p) {
        const int r = s.row_idx[p];  // upper (r, c) is lower (c, r): column r
        a_row_[at[r]] = c;
        a_src_[at[r]++] = p;
      }
    }
    values_.assign(static_cast<std::size_t>(col_ptr_[t_]), 0.0);
    work_.assign(static_cast<std::size_t>(n_), 0.0);
    cursor_.assign(static_cast<std::size_t>(t_), 0);
    tail_.assign(static_cast<std::size_t>(k_) * k_, 0.0);
    panel_matrix_.assign(static_cast<std::size_t>(k_) * panel_.size(), 0.0);  // zero between uses
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* a) override {
    if (a_ptr_.empty()) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    }
    double* x = work_.data();
    for (int j = 0; j < t_; ++j) cursor_[j] = col_ptr_[j] + 1;
    for (int j = 0; j < t_; ++j) {
      for (int p = a_ptr_[j]; p < a_ptr_[j + 1]; ++p) x[a_row_[p]] = a[a_src_[p]];
      // x -= L(j:n, p) L(j, p) for the columns p < j with L(j, p) != 0; each column's
      // cursor is at row j (rows are reached in increasing order).
      for (int q = row_ptr_[j]; q < row_ptr_[j + 1]; ++q) {
        const int p = row_col_[q];
        int e = cursor_[p]++;
        const double ljp = values_[e];
        for (const int end = col_ptr_[p + 1]; e < end; ++e) x[col_row_[e]] -= values_[e] * ljp;
      }
      const double d = x[j];
      x[j] = 0.0;
      if (!(d > 0.0)) return notPositive(j);
      const double ljj = std::sqrt(d);
      values_[col_ptr_[j]] = ljj;
      const double inv = 1.0 / ljj;
      for (int e = col_ptr_[j] + 1; e < col_ptr_[j + 1]; ++e) {
        values_[e] = x[col_row_[e]] * inv;
        x[col_row_[e]] = 0.0;
      }
    }
    // The tail: C = A_TT (lower), W = L(T, panel columns), C -= W W^T, C = L_TT L_TT^T.
    std::fill(tail_.begin(), tail_.end(), 0.0);
    for (int j = t_; j < n_; ++j) {
      for (int p = a_ptr_[j]; p < a_ptr_[j + 1]; ++p) {
        tail_[static_cast<std::size_t>(j - t_) * k_ + (a_row_[p] - t_)] = a[a_src_[p]];
      }
    }
    scatterPanel(false);
    const int m = static_cast<int>(panel_.size());
    const double minus_one = -1.0, one = 1.0;
    dsyrk_("L", "N", &k_, &m, &minus_one, panel_matrix_.data(), &k_, &one, tail_.data(), &k_);
    scatterPanel(true);
    int info = 0;
    dpotrf_("L", &k_, tail_.data(), &k_, &info);
    if (info != 0) return notPositive(t_ + info - 1, ", dense tail");
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    if (a_ptr_.empty()) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    }
    std::copy(rhs, rhs + n_, x);
    for (int j = 0; j < t_; ++j) {  // L y = b, by columns
      const double yj = x[j] / values_[col_ptr_[j]];
      x[j] = yj;
      for (int e = col_ptr_[j] + 1; e < col_ptr_[j + 1]; ++e) x[col_row_[e]] -= values_[e] * yj;
    }
    const int inc = 1;
    dtrsv_("L", "N", "N", &k_, tail_.data(), &k_, x + t_, &inc);
    dtrsv_("L", "T", "N", &k_, tail_.data(), &k_, x + t_, &inc);
    for (int j = t_ - 1; j >= 0; --j) {  // L^T x = y
      double v = x[j];
      for (int e = col_ptr_[j] + 1; e < col_ptr_[j + 1]; ++e) v -= values_[e] * x[col_row_[e]];
      x[j] = v / values_[col_ptr_[j]];
    }
    if (!detail::allFinite(x, n_)) return detail::notFinite();
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    return values_.size() + static_cast<std::size_t>(k_) * (k_ + 1) / 2;
  }

 private:
  LinearSolverResult noTail() {
    a_ptr_.clear();
    return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                       "tail-llt: the factor has no dense tail worth BLAS");
  }

  static LinearSolverResult notPositive(int column, const char* where = "") {
    return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                       std::string("non-positive pivot (tail-llt") + where + ")",
                                       column);
  }

  /// Writes the panel columns' tail rows into W (column c of W: panel_[c]), or zeros
  /// them again.
  void scatterPanel(bool clear) {
    for (std::size_t c = 0; c < panel_.size(); ++c) {
      const int j = panel_[c];
      double* w = panel_matrix_.data() + c * static_cast<std::size_t>(k_);
      for (int e = tail_first_[j]; e < col_ptr_[j + 1]; ++e) {
        w[col_row_[e] - t_] = clear ? 0.0 : values_[e];
      }
    }
  }

  std::vector<int> parent_, counts_;
  double max_sparse_flops_;
  int n_ = 0, t_ = 0, k_ = 0;
  std::vector<int> row_ptr_, row_col_;   // row patterns of L, columns < t_ only
  std::vector<int> col_ptr_, col_row_;   // columns < t_: diagonal first, rows ascending
  std::vector<int> tail_first_, panel_;  // first tail row of each column; W's columns
  std::vector<int> a_ptr_, a_row_, a_src_;
  std::vector<int> cursor_;
  std::vector<double> values_, work_, tail_, panel_matrix_;
};

#endif  // GRAPHSLAM_HAVE_LAPACK

}  // namespace

std::unique_ptr<detail::OrderedSolver> makeTailCholesky(std::vector<int> parent,
                                                        std::vector<int> counts,
                                                        double max_sparse_flops) {
#ifdef GRAPHSLAM_HAVE_LAPACK
  return std::make_unique<TailCholesky>(std::move(parent), std::move(counts), max_sparse_flops);
#else
  static_cast<void>(parent);
  static_cast<void>(counts);
  static_cast<void>(max_sparse_flops);
  return nullptr;
#endif
}

}  // namespace graphslam::solvers
