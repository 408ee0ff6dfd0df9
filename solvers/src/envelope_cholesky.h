// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: the envelope (profile) Cholesky LL^T of the envelope
// solver (George and Liu's envelope method), on a scalar matrix in its own order.
//
// Row i of L is stored densely from its first non-zero column f_i to the diagonal: the
// fill of a Cholesky factor stays inside A's envelope (the columns between f_i and i of
// every row), so there is no symbolic analysis beyond the f_i, and each entry is a dot
// product of two contiguous runs:
//   L(i, j) = (A(i, j) - sum_{k = max(f_i, f_j)}^{j-1} L(i, k) L(j, k)) / L(j, j).
// Rows are taken four at a time, each of the four stored from the group's smallest f_i
// (zeros before its own), so that one pass over the rows j before the group serves all
// four; the four rows are stored interleaved (entry k of the four together), so that a
// sum over k is four sums at once (EnvelopeGroupFn, block_kernels.h: AVX2/FMA at run
// time), and so are the solves' sums over a group. An order that keeps the
// envelope small (reverse Cuthill-McKee) makes this the cheapest factorisation of
// systems whose graph is a band or a ring (a pose chain with its landmarks, a loop).
#pragma once

#include <cstddef>
#include <vector>

#include "block_kernels.h"
#include "common.h"

namespace graphslam::solvers::detail {

/// Envelopes above this many stored entries (512 MiB of doubles) are declined at
/// layout: the order does not suit the method.
inline constexpr std::size_t kMaxEnvelopeEntries = std::size_t{1} << 26;

class EnvelopeCholesky {
 public:
  /// Lays L out for rows whose first non-zero column is first[i] (<= i); fails when the
  /// envelope exceeds kMaxEnvelopeEntries. Values are allocated by clear().
  [[nodiscard]] LinearSolverResult layout(const std::vector<int>& first);
  /// Where A(i, j), first[i] <= j <= i, is written before factorize().
  [[nodiscard]] std::ptrdiff_t position(int i, int j) const {
    return group_offset_[i >> 2] + 4 * static_cast<std::ptrdiff_t>(j) + (i & 3);
  }
  /// Zeroes the stored values; A's entries are then written at position() into values().
  void clear();
  [[nodiscard]] double* values() { return values_.data(); }
  /// Factorises A in place. A non-positive pivot fails naming its row in `column`.
  [[nodiscard]] LinearSolverResult factorize();
  /// Solves L L^T X = B for `d` right-hand sides interleaved (B(i, c) at b[i d + c]),
  /// in place.
  [[nodiscard]] LinearSolverResult solveInterleaved(double* b, int d) const;
  [[nodiscard]] int size() const { return n_; }
  [[nodiscard]] bool laidOut() const { return laid_out_; }
  /// Entries of the envelope (diagonal included, the groups' padding not).
  [[nodiscard]] std::size_t entries() const { return envelope_entries_; }

 private:
  int n_ = 0;
  bool laid_out_ = false, factorized_ = false;
  std::vector<int> start_;  // first stored column of every row (its group's)
  // L(i, k) at values_[group_offset_[i / 4] + 4 k + i % 4] (envelopeRow, block_kernels.h).
  std::vector<std::ptrdiff_t> group_offset_;
  std::size_t stored_ = 0;  // values_ entries, the groups' padding included
  std::vector<double> values_, inv_diag_;
  std::size_t envelope_entries_ = 0;
  EnvelopeGroupFn group_kernel_ = envelopeGroupKernel();
};

}  // namespace graphslam::solvers::detail
