// SPDX-License-Identifier: MIT
#include "envelope_cholesky.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

namespace graphslam::solvers::detail {

namespace {
/// Rows factorised together by the kernel (EnvelopeRowsFn).
constexpr int kGroup = 4;
}  // namespace

LinearSolverResult EnvelopeCholesky::analyzeOrdered(const SparseStructure& s,
                                                    std::vector<int> order, Ordering /*label*/) {
  factorized_ = false;
  n_ = s.n;
  values_.clear();
  for (int k = 0; k < n_; ++k) {
    if (order[k] != k) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                         "envelope-llt factorises its matrix in its own order");
    }
  }
  if (s.lower) {
    return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                       "envelope-llt takes the upper triangle");
  }
  // Row i of the lower triangle is column i of the upper one: its first row is f_i.
  std::vector<int> first(static_cast<std::size_t>(n_));
  envelope_entries_ = 0;
  for (int i = 0; i < n_; ++i) {
    const int p = s.col_ptr[i];
    first[i] = p < s.col_ptr[i + 1] ? std::min(s.row_idx[p], i) : i;
    envelope_entries_ += static_cast<std::size_t>(i - first[i] + 1);
  }
  start_.assign(static_cast<std::size_t>(n_), 0);
  for (int g = 0; g < n_; g += kGroup) {
    const int end = std::min(n_, g + kGroup);
    const int from = *std::min_element(first.begin() + g, first.begin() + end);
    for (int i = g; i < end; ++i) start_[i] = from;
  }
  offset_.resize(static_cast<std::size_t>(n_));
  std::size_t stored = 0;
  for (int i = 0; i < n_; ++i) {
    offset_[i] = static_cast<std::ptrdiff_t>(stored) - start_[i];
    stored += static_cast<std::size_t>(i - start_[i] + 1);
    if (stored > kMaxEnvelopeEntries) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "envelope-llt: the envelope of this order exceeds " +
              std::to_string(kMaxEnvelopeEntries) +
              " entries (an ordering that keeps it small, rcm, or another solver)");
    }
  }
  dest_.resize(s.nnz());
  for (int c = 0; c < n_; ++c) {
    for (int p = s.col_ptr[c]; p < s.col_ptr[c + 1]; ++p) {
      const int r = s.row_idx[p];
      // Upper entry (r, c), r <= c: row c, column r. Entries below the diagonal (a
      // structure that stores them) are not read.
      dest_[static_cast<std::size_t>(p)] = r <= c ? offset_[c] + r : -1;
    }
  }
  values_.assign(stored, 0.0);
  inv_diag_.assign(static_cast<std::size_t>(n_), 0.0);
  return LinearSolverResult::success();
}

LinearSolverResult EnvelopeCholesky::factorize(const double* a) {
  factorized_ = false;
  if (offset_.size() != static_cast<std::size_t>(n_) || (n_ > 0 && values_.empty())) {
    return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
  }
  std::fill(values_.begin(), values_.end(), 0.0);
  for (std::size_t p = 0; p < dest_.size(); ++p) {
    if (dest_[p] >= 0) values_[static_cast<std::size_t>(dest_[p])] = a[p];
  }
  double* v = values_.data();
  for (int g = 0; g < n_; g += kGroup) {
    const bool whole = g + kGroup <= n_;
    // The entries of the group's rows before it, four rows at a time.
    if (whole) rows_kernel_(v, offset_.data(), start_.data(), inv_diag_.data(), g, start_[g]);
    // The group's own triangle (every entry of a last, partial group).
    for (int i = g; i < std::min(n_, g + kGroup); ++i) {
      double* li = v + offset_[i];
      for (int j = whole ? g : start_[i]; j < i; ++j) {
        const double* lj = v + offset_[j];
        double sum = 0.0;
        for (int k = std::max(start_[i], start_[j]); k < j; ++k) sum += li[k] * lj[k];
        li[j] = (li[j] - sum) * inv_diag_[j];
      }
      double pivot = li[i];
      for (int k = start_[i]; k < i; ++k) pivot -= li[k] * li[k];
      if (!(pivot > 0.0) || !std::isfinite(pivot)) {
        return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                           "non-positive pivot", i);
      }
      li[i] = std::sqrt(pivot);
      inv_diag_[i] = 1.0 / li[i];
    }
  }
  factorized_ = true;
  return LinearSolverResult::success();
}

namespace {
/// L y = b by rows, then L^T x = y by columns of L^T (rows of L), in place, with D
/// values per unknown (D = 0: d of them, not fixed). For a fixed D the forward sums run
/// in two accumulators per value, the D values of an unknown together.
template <int D>
void solveRows(const double* v, const std::ptrdiff_t* offset, const int* start,
               const double* inv_diag, int n, double* b, int d) {
  if constexpr (D > 0) {
    d = D;
    for (int i = 0; i < n; ++i) {
      const double* li = v + offset[i];
      double* bi = b + static_cast<std::ptrdiff_t>(i) * D;
      double s0[D] = {}, s1[D] = {};
      int k = start[i];
      for (; k + 1 < i; k += 2) {
        const double* bk = b + static_cast<std::ptrdiff_t>(k) * D;
        for (int c = 0; c < D; ++c) {
          s0[c] += li[k] * bk[c];
          s1[c] += li[k + 1] * bk[D + c];
        }
      }
      if (k < i) {
        for (int c = 0; c < D; ++c) s0[c] += li[k] * b[static_cast<std::ptrdiff_t>(k) * D + c];
      }
      for (int c = 0; c < D; ++c) bi[c] = (bi[c] - (s0[c] + s1[c])) * inv_diag[i];
    }
  } else {
    for (int i = 0; i < n; ++i) {
      const double* li = v + offset[i];
      double* bi = b + static_cast<std::ptrdiff_t>(i) * d;
      for (int k = start[i]; k < i; ++k) {
        const double* bk = b + static_cast<std::ptrdiff_t>(k) * d;
        for (int c = 0; c < d; ++c) bi[c] -= li[k] * bk[c];
      }
      for (int c = 0; c < d; ++c) bi[c] *= inv_diag[i];
    }
  }
  for (int i = n - 1; i >= 0; --i) {
    const double* li = v + offset[i];
    double* bi = b + static_cast<std::ptrdiff_t>(i) * d;
    for (int c = 0; c < d; ++c) bi[c] *= inv_diag[i];
    for (int k = start[i]; k < i; ++k) {
      double* bk = b + static_cast<std::ptrdiff_t>(k) * d;
      for (int c = 0; c < d; ++c) bk[c] -= li[k] * bi[c];
    }
  }
}
}  // namespace

LinearSolverResult EnvelopeCholesky::solveInterleaved(double* b, int d) const {
  if (!factorized_)
    return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not factorised");
  const auto run = [&](auto size) {
    solveRows<decltype(size)::value>(values_.data(), offset_.data(), start_.data(),
                                     inv_diag_.data(), n_, b, d);
  };
  if (d == 1) {
    run(std::integral_constant<int, 1>{});
  } else if (d == 2) {
    run(std::integral_constant<int, 2>{});
  } else if (d == 3) {
    run(std::integral_constant<int, 3>{});
  } else {
    run(std::integral_constant<int, 0>{});
  }
  if (!allFinite(b, n_ * d)) return notFinite();
  return LinearSolverResult::success();
}

LinearSolverResult EnvelopeCholesky::solve(const double* rhs, double* x) {
  std::copy(rhs, rhs + n_, x);
  return solveInterleaved(x, 1);
}

}  // namespace graphslam::solvers::detail
