// SPDX-License-Identifier: MIT
#include "envelope_cholesky.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

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
  group_offset_.resize(static_cast<std::size_t>((n_ + kGroup - 1) / kGroup));
  stored_ = 0;
  for (int g = 0; g < n_; g += kGroup) {
    const int end = std::min(n_, g + kGroup);
    const int from = *std::min_element(first.begin() + g, first.begin() + end);
    for (int i = g; i < end; ++i) start_[i] = from;
    // Columns from..g+3 of four rows (a last, partial group too: its missing rows zero).
    group_offset_[g / kGroup] = static_cast<std::ptrdiff_t>(stored_) - kGroup * from;
    stored_ += static_cast<std::size_t>(kGroup) * static_cast<std::size_t>(g + kGroup - from);
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
    const int bad = group_kernel_(values_.data(), group_offset_.data(), start_.data(),
                                  inv_diag_.data(), g, std::min(kGroup, n_ - g));
    if (bad >= 0) {
      return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                         "non-positive pivot", bad);
    }
  }
  factorized_ = true;
  return LinearSolverResult::success();
}

namespace {
/// L y = b, then L^T x = y, in place, with D values per unknown (D = 0: d of them, not
/// fixed), a group of four rows at a time: its sums over the columns before it (forward)
/// and its updates of them (backward) read entry k of the four rows together.
template <int D>
void solveGroups(const double* v, const std::ptrdiff_t* group_offset, const int* start,
                 const double* inv_diag, int n, double* b, int d) {
  if constexpr (D > 0) d = D;
  const auto at = [b, d](int i, int c) -> double& {
    return b[static_cast<std::ptrdiff_t>(i) * d + c];
  };
  std::vector<double> dynamic(D > 0 ? 0 : static_cast<std::size_t>(4 * d));
  double fixed[4 * (D > 0 ? D : 1)];
  double* acc = D > 0 ? fixed : dynamic.data();  // acc[t d + c]
  for (int g = 0; g < n; g += 4) {
    const int m = std::min(4, n - g);
    const double* tw = v + group_offset[g >> 2];  // tw[4k + t] = L(g + t, k)
    std::fill(acc, acc + 4 * d, 0.0);
    for (int k = start[g]; k < g; ++k) {
      for (int c = 0; c < d; ++c) {
        const double bk = at(k, c);
        for (int t = 0; t < 4; ++t) acc[t * d + c] += tw[4 * k + t] * bk;
      }
    }
    for (int t = 0; t < m; ++t) {
      for (int c = 0; c < d; ++c) {
        double y = at(g + t, c) - acc[t * d + c];
        for (int q = 0; q < t; ++q) y -= tw[4 * (g + q) + t] * at(g + q, c);
        at(g + t, c) = y * inv_diag[g + t];
      }
    }
  }
  for (int g = (n - 1) / 4 * 4; g >= 0; g -= 4) {
    const int m = std::min(4, n - g);
    const double* tw = v + group_offset[g >> 2];
    for (int t = m - 1; t >= 0; --t) {
      for (int c = 0; c < d; ++c) {
        double x = at(g + t, c);
        for (int q = t + 1; q < m; ++q) x -= tw[4 * (g + t) + q] * at(g + q, c);
        at(g + t, c) = x * inv_diag[g + t];
      }
    }
    for (int t = m; t < 4; ++t) {  // the missing rows of a partial group: L is zero there
      for (int c = 0; c < d; ++c) acc[t * d + c] = 0.0;
    }
    for (int t = 0; t < m; ++t) {
      for (int c = 0; c < d; ++c) acc[t * d + c] = at(g + t, c);
    }
    for (int k = start[g]; k < g; ++k) {
      for (int c = 0; c < d; ++c) {
        double sum = 0.0;
        for (int t = 0; t < 4; ++t) sum += tw[4 * k + t] * acc[t * d + c];
        at(k, c) -= sum;
      }
    }
  }
}
}  // namespace

LinearSolverResult EnvelopeCholesky::solveInterleaved(double* b, int d) const {
  if (!factorized_)
    return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not factorised");
  withFixedSize(d, [&](auto size) {
    solveGroups<decltype(size)::value>(values_.data(), group_offset_.data(), start_.data(),
                                       inv_diag_.data(), n_, b, d);
  });
  if (!allFinite(b, n_ * d)) return notFinite();
  return LinearSolverResult::success();
}

}  // namespace graphslam::solvers::detail
