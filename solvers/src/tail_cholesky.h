// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: tail-llt, the isotropic solver's scalar Cholesky LL^T
// for systems whose factor is cheap apart from a dense trailing block, which BLAS takes.
// Built with BLAS / LAPACK only.
//
// Ordered poses first, the few landmarks seen from most poses fill the factor's last rows:
// L's last k columns are a dense triangle, and the columns before them are sparse (a pose
// chain, each column a handful of rows plus its rows in the tail). The columns [0, t) are
// factorised left-looking, scalar by scalar, their rows in the tail included; the tail's
// own entries never are. The tail is then a dense Schur complement
//   C = A_TT - W W^T,  W = L(T, 0:t) (the sparse columns' tail rows, k x m dense),
// formed by one BLAS rank-k update (dsyrk) and factorised by LAPACK (dpotrf): the
// products a sparse factorisation makes entry by entry through index arrays run in
// BLAS's blocked kernels. Without a tail worth BLAS (blasTailPays) every column goes
// through the loop: a plain left-looking scalar Cholesky, for small systems.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "common.h"
#include "symbolic.h"

#ifdef GRAPHSLAM_HAVE_LAPACK

#include "graphslam/support/blas.h"

namespace graphslam::solvers::detail {

/// A fully dense trailing part of L of at least this many scalar rows may take its Schur
/// complement from BLAS.
inline constexpr int kBlasTailMinRows = 32;

/// Whether the Schur complement of a dense tail of `tail_rows` scalar rows is formed by one
/// BLAS rank update with a dense W of `panel_columns` columns (the columns before the tail
/// holding rows in it), where a sparse loop would make `pair_flops` products (the sum over
/// those columns of their rows in the tail squared). dsyrk makes tail_rows^2 *
/// panel_columns / 2 multiply-adds against the loop's pair_flops / 2, each several times
/// slower than BLAS's; the dense tail stays below 128 MiB, W below 64 MiB.
inline bool blasTailPays(double tail_rows, double panel_columns, double pair_flops) {
  return tail_rows >= kBlasTailMinRows && tail_rows <= 4096.0 &&
         tail_rows * panel_columns <= 8.0 * 1024 * 1024 &&
         tail_rows * tail_rows * panel_columns <= 4.0 * pair_flops;
}

/// Row patterns of L are kept up to this many entries (8 MiB); a larger factor is declined
/// (its loop alone would cost far more than the isotropic solver allows it).
inline constexpr std::size_t kMaxRowEntries = std::size_t{1} << 21;

class TailCholesky final : public OrderedSolver {
 public:
  /// The analysis fails (and the caller factorises otherwise) when the columns its loop
  /// factorises (those before a dense tail worth BLAS, else all) take more than
  /// `max_sparse_flops`.
  explicit TailCholesky(double max_sparse_flops) : max_sparse_flops_(max_sparse_flops) {}

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
    if (!findRowPatterns(s)) return noTail();
    std::vector<int> in_tail;
    if (chooseDenseTail(in_tail) > max_sparse_flops_) return noTail();
    buildColumnStorage(in_tail);
    gatherLowerTriangle(s);
    values_.assign(static_cast<std::size_t>(col_ptr_[t_]), 0.0);
    work_.assign(static_cast<std::size_t>(n_), 0.0);
    cursor_.assign(static_cast<std::size_t>(t_), 0);
    tail_.assign(static_cast<std::size_t>(k_) * k_, 0.0);
    panel_matrix_.assign(static_cast<std::size_t>(k_) * m_, 0.0);
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* a) override {
    if (a_ptr_.empty()) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    }
    double* x = work_.data();
    for (int j = 0; j < t_; ++j) cursor_[j] = col_ptr_[j] + 1;
    for (int j = 0; j < t_; ++j) {
      // Column j: its rows before the tail in x, those in the tail in W's column w.
      double* const w = panelColumn(j);
      if (w) std::fill(w, w + k_, 0.0);
      for (int p = a_ptr_[j]; p < a_ptr_[j + 1]; ++p) {
        const int r = a_row_[p];
        if (r < t_) {
          x[r] = a[a_src_[p]];
        } else {
          w[r - t_] = a[a_src_[p]];  // a row in the tail: column j has a W column
        }
      }
      // Column j -= L(j:n, p) L(j, p) for the columns p < j with L(j, p) != 0; each
      // column's cursor is at row j (rows are reached in increasing order).
      for (int q = row_ptr_[j]; q < row_ptr_[j + 1]; ++q) {
        const int p = row_col_[q];
        int e = cursor_[p]++;
        const double ljp = values_[e];
        for (const int end = col_ptr_[p + 1]; e < end; ++e) x[col_row_[e]] -= values_[e] * ljp;
        if (const double* wp = panelColumn(p)) {
          for (int i = 0; i < k_; ++i) w[i] -= wp[i] * ljp;
        }
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
      if (w) {
        for (int i = 0; i < k_; ++i) w[i] *= inv;
      }
    }
    if (k_ == 0) return LinearSolverResult::success();
    // The tail: C = A_TT (lower), C -= W W^T, C = L_TT L_TT^T.
    std::fill(tail_.begin(), tail_.end(), 0.0);
    for (int j = t_; j < n_; ++j) {
      for (int p = a_ptr_[j]; p < a_ptr_[j + 1]; ++p) {
        tail_[static_cast<std::size_t>(j - t_) * k_ + (a_row_[p] - t_)] = a[a_src_[p]];
      }
    }
    const double minus_one = -1.0, one = 1.0;
    support::blas::dsyrk("L", "N", &k_, &m_, &minus_one, panel_matrix_.data(), &k_, &one, tail_.data(), &k_);
    int info = 0;
    support::blas::dpotrf("L", &k_, tail_.data(), &k_, &info);
    if (info != 0) return notPositive(t_ + info - 1, ", dense tail");
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    if (a_ptr_.empty()) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    }
    std::copy(rhs, rhs + n_, x);
    return solveInterleaved(x, 1);
  }

  /// Solves for `d` right-hand sides at once, in place: y[k * d + c] is entry k of the
  /// c-th (the layout of H = H_s (x) I_d's unknowns). One pass over L for all of them.
  LinearSolverResult solveInterleaved(double* y, int d) {
    if (a_ptr_.empty()) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    }
    withFixedSize(d, [&](auto size) { solveSparse<decltype(size)::value>(y, d); });
    if (!allFinite(y, n_ * d)) return notFinite();
    return LinearSolverResult::success();
  }

  /// The elimination tree and the column counts (diagonal included) of the last analysis,
  /// also when it declined (unless it failed before computing them: empty then).
  const std::vector<int>& parent() const { return parent_; }
  const std::vector<int>& counts() const { return counts_; }

  std::size_t factorNonZeros() const override {
    return values_.size() + tail_entries_ + static_cast<std::size_t>(k_) * (k_ + 1) / 2;
  }

 private:
  /// One walk: the elimination tree (parent_), then row k of L (the columns on the tree
  /// paths from A's rows i < k of column k up to k: its row subtree) for every k, stored by
  /// rows (row_ptr_, row_col_), and the column counts (counts_). False when the rows are too
  /// many to keep (kMaxRowEntries; the counts are complete all the same).
  bool findRowPatterns(const SparseStructure& s) {
    const auto upper = [&](int k, auto&& visit) {
      for (int p = s.col_ptr[k]; p < s.col_ptr[k + 1] && s.row_idx[p] < k; ++p) {
        visit(s.row_idx[p]);
      }
    };
    parent_ = eliminationTree(n_, upper);
    counts_.assign(static_cast<std::size_t>(n_), 1);
    row_ptr_.assign(static_cast<std::size_t>(n_) + 1, 0);
    row_col_.clear();
    row_col_.reserve(2 * s.nnz());  // a guess: L has about twice A's entries here
    bool stored = true;
    std::vector<int> flag(static_cast<std::size_t>(n_), -1);
    int* const count = counts_.data();
    const int* const parent = parent_.data();
    for (int k = 0; k < n_; ++k) {
      flag[k] = k;
      upper(k, [&](int r) {
        for (int i = r; flag[i] != k; i = parent[i]) {
          flag[i] = k;
          ++count[i];
          if (stored) row_col_.push_back(i);
        }
      });
      if (stored && row_col_.size() > kMaxRowEntries) {  // too large to be worth it: count on
        stored = false;
        std::vector<int>().swap(row_col_);
      }
      row_ptr_[k + 1] = static_cast<int>(row_col_.size());
    }
    return stored;
  }

  /// The dense tail (t_, k_): the last columns, each holding every row below it, when BLAS
  /// pays for it (the rows in it of the columns before it, from the tail's row patterns);
  /// else none, every column by the loop. Fills in_tail[j] (column j's rows in the tail)
  /// and returns the work of the columns the loop factorises.
  double chooseDenseTail(std::vector<int>& in_tail) {
    t_ = n_;
    while (t_ > 0 && counts_[t_ - 1] == n_ - t_ + 1) --t_;
    k_ = n_ - t_;
    double sparse = 0.0;
    in_tail.assign(static_cast<std::size_t>(t_), 0);
    if (k_ >= kBlasTailMinRows) {
      for (int q = row_ptr_[t_]; q < row_ptr_[n_]; ++q) {
        if (row_col_[q] < t_) ++in_tail[row_col_[q]];
      }
      double pairs = 0.0, panel_columns = 0.0;
      for (int j = 0; j < t_; ++j) {
        const double c = counts_[j], r = in_tail[j];
        pairs += r * r;
        sparse += c * c - r * r;
        panel_columns += r > 0 ? 1.0 : 0.0;
      }
      if (!blasTailPays(k_, panel_columns, pairs)) k_ = 0;
    } else {
      k_ = 0;
    }
    if (k_ == 0) {
      t_ = n_;
      in_tail.assign(static_cast<std::size_t>(n_), 0);
      sparse = 0.0;
      for (const int c : counts_) sparse += static_cast<double>(c) * c;
    }
    return sparse;
  }

  /// Columns before the tail (col_ptr_, col_row_): the diagonal, then their rows before the
  /// tail, ascending; their rows in the tail are a dense column of W (k rows, zeros
  /// included) for every column that has any (panel_pos_). Only the rows before the tail
  /// keep their patterns (the loop's).
  void buildColumnStorage(const std::vector<int>& in_tail) {
    col_ptr_.assign(static_cast<std::size_t>(t_) + 1, 0);
    panel_pos_.assign(static_cast<std::size_t>(t_), -1);
    m_ = 0;
    tail_entries_ = 0;
    for (int j = 0; j < t_; ++j) {
      col_ptr_[j + 1] = col_ptr_[j] + counts_[j] - in_tail[j];
      if (in_tail[j] > 0) panel_pos_[j] = m_++;
      tail_entries_ += static_cast<std::size_t>(in_tail[j]);
    }
    col_row_.resize(static_cast<std::size_t>(col_ptr_[t_]));
    std::vector<int> next(col_ptr_.begin(), col_ptr_.end() - 1);
    for (int j = 0; j < t_; ++j) col_row_[next[j]++] = j;
    int* const rows = col_row_.data();
    int* const cols = row_col_.data();
    int* const slot = next.data();
    for (int k = 0; k < t_; ++k) {  // row k's columns are all before it: kept in place
      for (int q = row_ptr_[k]; q < row_ptr_[k + 1]; ++q) rows[slot[cols[q]]++] = k;
    }
    for (int k = t_; k < n_; ++k) row_ptr_[k + 1] = row_ptr_[t_];
    row_col_.resize(static_cast<std::size_t>(row_ptr_[t_]));
  }

  /// A's lower triangle by columns (rows >= j) with the position of every value in the
  /// caller's array (a_ptr_, a_row_, a_src_): the left-looking loop gathers column j.
  void gatherLowerTriangle(const SparseStructure& s) {
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
  }

  /// L L^T Y = B for the d interleaved columns of y (D: d fixed at compile time, or 0):
  /// the columns before the tail by sparse substitution, the tail's k x d block by dtrsm.
  template <int D>
  void solveSparse(double* y, int d) {
    if constexpr (D > 0) d = D;
    // Column j's entries, held in registers (rows of a column differ from j: no alias).
    constexpr int kHeld = D > 0 ? D : 1;
    double held[kHeld];
    if constexpr (D == 0) {
      solveSparseAnyWidth(y, d);
      return;
    }
    double* const yt = y + static_cast<std::ptrdiff_t>(t_) * d;  // the tail's rows
    for (int j = 0; j < t_; ++j) {                               // L z = b, by columns
      double* yj = y + static_cast<std::ptrdiff_t>(j) * d;
      const double inv = 1.0 / values_[col_ptr_[j]];
      for (int c = 0; c < kHeld; ++c) held[c] = yj[c] *= inv;
      for (int e = col_ptr_[j] + 1; e < col_ptr_[j + 1]; ++e) {
        double* yr = y + static_cast<std::ptrdiff_t>(col_row_[e]) * d;
        const double l = values_[e];
        for (int c = 0; c < kHeld; ++c) yr[c] -= l * held[c];
      }
      if (const double* w = panelColumn(j)) {
        for (int i = 0; i < k_; ++i) {
          for (int c = 0; c < kHeld; ++c) yt[i * kHeld + c] -= w[i] * held[c];
        }
      }
    }
    solveTail(y, d);
    for (int j = t_ - 1; j >= 0; --j) {  // L^T x = z
      double* yj = y + static_cast<std::ptrdiff_t>(j) * d;
      for (int c = 0; c < kHeld; ++c) held[c] = yj[c];
      for (int e = col_ptr_[j] + 1; e < col_ptr_[j + 1]; ++e) {
        const double* yr = y + static_cast<std::ptrdiff_t>(col_row_[e]) * d;
        const double l = values_[e];
        for (int c = 0; c < kHeld; ++c) held[c] -= l * yr[c];
      }
      if (const double* w = panelColumn(j)) {
        // Four independent sums over W's column: the additions do not wait for each other.
        double s[4][kHeld] = {};
        int i = 0;
        for (; i + 4 <= k_; i += 4) {
          for (int u = 0; u < 4; ++u) {
            for (int c = 0; c < kHeld; ++c) s[u][c] += w[i + u] * yt[(i + u) * kHeld + c];
          }
        }
        for (; i < k_; ++i) {
          for (int c = 0; c < kHeld; ++c) s[0][c] += w[i] * yt[i * kHeld + c];
        }
        for (int c = 0; c < kHeld; ++c) held[c] -= (s[0][c] + s[1][c]) + (s[2][c] + s[3][c]);
      }
      const double inv = 1.0 / values_[col_ptr_[j]];
      for (int c = 0; c < kHeld; ++c) yj[c] = held[c] * inv;
    }
  }

  /// The tail's rows of the d interleaved right-hand sides, made contiguous (k x d), by
  /// dtrsm both ways.
  void solveTail(double* y, int d) {
    if (k_ == 0) return;
    // The tail's d columns, contiguous (k x d), both ways.
    const double* yt = y + static_cast<std::ptrdiff_t>(t_) * d;
    tail_rhs_.resize(static_cast<std::size_t>(k_) * d);
    for (int i = 0; i < k_; ++i) {
      for (int c = 0; c < d; ++c) tail_rhs_[static_cast<std::size_t>(c) * k_ + i] = yt[i * d + c];
    }
    const double one = 1.0;
    support::blas::dtrsm("L", "L", "N", "N", &k_, &d, &one, tail_.data(), &k_, tail_rhs_.data(), &k_);
    support::blas::dtrsm("L", "L", "T", "N", &k_, &d, &one, tail_.data(), &k_, tail_rhs_.data(), &k_);
    for (int i = 0; i < k_; ++i) {
      for (int c = 0; c < d; ++c) {
        y[static_cast<std::ptrdiff_t>(t_ + i) * d + c] =
            tail_rhs_[static_cast<std::size_t>(c) * k_ + i];
      }
    }
  }

  /// solveSparse for any d, one right-hand side after the other (strided).
  void solveSparseAnyWidth(double* y, int d) {
    const auto at = [d](int row, int c) { return static_cast<std::ptrdiff_t>(row) * d + c; };
    for (int c = 0; c < d; ++c) {
      for (int j = 0; j < t_; ++j) {
        const double v = y[at(j, c)] /= values_[col_ptr_[j]];
        for (int e = col_ptr_[j] + 1; e < col_ptr_[j + 1]; ++e) {
          y[at(col_row_[e], c)] -= values_[e] * v;
        }
        if (const double* w = panelColumn(j)) {
          for (int i = 0; i < k_; ++i) y[at(t_ + i, c)] -= w[i] * v;
        }
      }
    }
    solveTail(y, d);
    for (int c = 0; c < d; ++c) {
      for (int j = t_ - 1; j >= 0; --j) {
        double v = y[at(j, c)];
        for (int e = col_ptr_[j] + 1; e < col_ptr_[j + 1]; ++e) {
          v -= values_[e] * y[at(col_row_[e], c)];
        }
        if (const double* w = panelColumn(j)) {
          for (int i = 0; i < k_; ++i) v -= w[i] * y[at(t_ + i, c)];
        }
        y[at(j, c)] = v / values_[col_ptr_[j]];
      }
    }
  }

  LinearSolverResult noTail() {
    a_ptr_.clear();
    return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                       "tail-llt: the factor is too costly for its loop");
  }

  static LinearSolverResult notPositive(int column, const char* where = "") {
    return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                       std::string("non-positive pivot (tail-llt") + where + ")",
                                       column);
  }

  /// Column j's rows in the tail (W's column), or null when it has none.
  double* panelColumn(int j) {
    return panel_pos_[j] < 0
               ? nullptr
               : panel_matrix_.data() + static_cast<std::ptrdiff_t>(panel_pos_[j]) * k_;
  }

  double max_sparse_flops_;
  std::vector<int> parent_, counts_;
  int n_ = 0, t_ = 0, k_ = 0;
  std::vector<int> row_ptr_, row_col_;  // row patterns of L's rows before the tail
  std::vector<int> col_ptr_, col_row_;  // columns < t_: diagonal, then rows < t_ ascending
  std::vector<int> panel_pos_;          // W's column of each column before the tail, or -1
  int m_ = 0;                           // W's columns
  std::size_t tail_entries_ = 0;        // L's non-zeros in W
  std::vector<int> a_ptr_, a_row_, a_src_;
  std::vector<int> cursor_;
  std::vector<double> values_, work_, tail_, panel_matrix_, tail_rhs_;
};

}  // namespace graphslam::solvers::detail

#endif  // GRAPHSLAM_HAVE_LAPACK
