// SPDX-License-Identifier: MIT
#include "envelope_cholesky.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

namespace graphslam::solvers::detail {

namespace {
/// Rows factorised together by the kernel (EnvelopeGroupFn).
constexpr int kGroup = 4;
}  // namespace

LinearSolverResult EnvelopeCholesky::layout(const std::vector<int>& first) {
  laid_out_ = factorized_ = false;
  n_ = static_cast<int>(first.size());
  values_.clear();
  envelope_entries_ = 0;
  for (int i = 0; i < n_; ++i) envelope_entries_ += static_cast<std::size_t>(i - first[i] + 1);
  start_.resize(static_cast<std::size_t>(n_));
  std::size_t widest = 0;  // of the groups, in columns
  for (int g = 0; g < n_; g += kGroup) {
    const int end = std::min(n_, g + kGroup);
    const int from = *std::min_element(first.begin() + g, first.begin() + end);
    for (int i = g; i < end; ++i) start_[i] = from;
    widest = std::max(widest, static_cast<std::size_t>(g + kGroup - from));
  }
  work_.assign(widest * kGroup, 0.0);
  offset_.resize(static_cast<std::size_t>(n_));
  stored_ = 0;
  for (int i = 0; i < n_; ++i) {
    offset_[i] = static_cast<std::ptrdiff_t>(stored_) - start_[i];
    stored_ += static_cast<std::size_t>(i - start_[i] + 1);
    if (stored_ > kMaxEnvelopeEntries) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "envelope: the envelope of this order exceeds " + std::to_string(kMaxEnvelopeEntries) +
              " entries (an ordering that keeps it small, rcm, or another solver)");
    }
  }
  inv_diag_.assign(static_cast<std::size_t>(n_), 0.0);
  laid_out_ = true;
  return LinearSolverResult::success();
}

void EnvelopeCholesky::clear() {
  factorized_ = false;
  values_.assign(stored_, 0.0);
}

LinearSolverResult EnvelopeCholesky::factorize() {
  factorized_ = false;
  if (!laid_out_ || values_.size() != stored_) {
    return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not laid out");
  }
  for (int g = 0; g < n_; g += kGroup) {
    const int bad = group_kernel_(values_.data(), offset_.data(), start_.data(), inv_diag_.data(),
                                  g, std::min(kGroup, n_ - g), work_.data());
    if (bad >= 0) {
      return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                         "non-positive pivot", bad);
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

}  // namespace graphslam::solvers::detail
