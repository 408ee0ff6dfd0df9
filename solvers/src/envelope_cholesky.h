// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: envelope-llt, the envelope (profile) Cholesky LL^T of
// the envelope solver (George and Liu's envelope method).
//
// Row i of L is stored densely from its first non-zero column f_i to the diagonal: the
// fill of a Cholesky factor stays inside A's envelope (the columns between f_i and i of
// every row), so there is no symbolic analysis beyond the f_i, and each entry is a dot
// product of two contiguous runs:
//   L(i, j) = (A(i, j) - sum_{k = max(f_i, f_j)}^{j-1} L(i, k) L(j, k)) / L(j, j).
// Rows are taken four at a time, each of the four stored from the group's smallest f_i
// (zeros before its own), so that one pass over the rows j before the group serves all
// four (EnvelopeRowsFn, block_kernels.h: AVX2/FMA at run time). An order that keeps the
// envelope small (reverse Cuthill-McKee) makes this the cheapest factorisation of
// systems whose graph is a band or a ring (a pose chain with its landmarks, a loop).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "block_kernels.h"
#include "common.h"

namespace graphslam::solvers::detail {

/// Envelopes above this many stored entries (512 MiB of doubles) are declined at
/// analysis: the order does not suit the method.
inline constexpr std::size_t kMaxEnvelopeEntries = std::size_t{1} << 26;

class EnvelopeCholesky final : public OrderedSolver {
 public:
  std::string name() const override { return "envelope-llt"; }

  /// `s`: a scalar matrix's upper triangle (rows sorted, diagonal stored), factorised in
  /// its own order; `order` must be the identity.
  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering label) override;
  /// `a`: the values of the analysed structure.
  LinearSolverResult factorize(const double* a) override;
  LinearSolverResult solve(const double* rhs, double* x) override;
  /// Solves L L^T X = B for `d` right-hand sides interleaved (B(i, c) at b[i d + c]),
  /// in place.
  LinearSolverResult solveInterleaved(double* b, int d) const;
  /// Entries of the envelope (diagonal included, the groups' padding not).
  std::size_t factorNonZeros() const override { return envelope_entries_; }

 private:
  int n_ = 0;
  std::vector<int> start_;              // first stored column of every row
  std::vector<std::ptrdiff_t> offset_;  // row i's entry k at values_[offset_[i] + k]
  std::vector<std::ptrdiff_t> dest_;    // where each stored entry of A goes in values_
  std::vector<double> values_, inv_diag_;
  std::size_t envelope_entries_ = 0;
  bool factorized_ = false;
  EnvelopeRowsFn rows_kernel_ = envelopeRowsKernel();
};

}  // namespace graphslam::solvers::detail
