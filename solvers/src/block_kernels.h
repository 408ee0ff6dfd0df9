// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: the innermost loops of block-llt (elimination and
// triangular solves) and of pcg's isotropic product, with AVX2/FMA versions chosen at run time on
// CPUs that have them (the library itself is built for the portable x86-64 baseline, SSE2, as
// Debian builds).
#pragma once

#include <cstddef>

namespace graphslam::solvers::detail {

/// Rows of the accumulator blocks of block-llt for B x B blocks: 3 x 3 blocks are kept
/// in 4 x 3 (each column one 256-bit vector; the fourth row is scratch), the others as
/// they are.
constexpr int paddedRows(int block_size) { return block_size == 3 ? 4 : block_size; }

/// One entry L(k, i) of block-llt's up-looking row k, B x B blocks (column-major):
///   L(k, i) = Y_i Inv_i^T, written to `out` (Y_i = work_i, the accumulated row entry,
///   Inv_i = L(i, i)^-1);
///   work[rows[t]] -= L(k, i) V_t^T for t = 0..count-1 (V_t the B x B blocks at
///   v + t B^2: L(p, i) for the rows p < k of column i);
///   diag -= L(k, i) L(k, i)^T.
/// work_i, work[r] (at work + r paddedRows(B) B) and diag are paddedRows(B) x B; the
/// padding row is scratch, never read back.
using EliminateFn = void (*)(const double* work_i, const double* inv_i, double* out,
                             const double* v, const int* rows, int count, double* work,
                             double* diag);

/// Column i of block-llt's triangular solves, B x B blocks (column-major) and vectors
/// y_k of paddedRows(B) doubles (padding zero), v/rows/count as in EliminateFn (the
/// blocks L(p, i) below the diagonal of column i):
///   forward (L y = b):    y_i = Inv_i y_i, then y_p -= L(p, i) y_i;
///   backward (L^T x = y): y_i -= sum_p L(p, i)^T y_p, then y_i = Inv_i^T y_i.
struct SolveKernels {
  void (*forward)(const double* inv_i, double* y_i, const double* v, const int* rows, int count,
                  double* y);
  void (*backward)(const double* inv_i, double* y_i, const double* v, const int* rows, int count,
                   const double* y);
};

/// pcg's product with H_s on two interleaved right-hand sides: for the rows i < m of
/// the CSR matrix (ptr, col, val), q_i = sum_k val[k] p_col[k] and pq += p_i * q_i,
/// where x_i is the pair x[2i], x[2i + 1] (pq: two sums, one per right-hand side).
using PairProductFn = void (*)(const int* ptr, const int* col, const double* val, int m,
                               const double* p, double* q, double* pq);

/// The envelope factorisation's storage: rows in groups of four, g = 4G..4G+3, each
/// stored from the group's first column start[g]; L(i, k) at
/// values[group_offset[i / 4] + 4 k + i % 4] (entry k of a group's four rows together).
inline const double* envelopeRow(const double* values, const std::ptrdiff_t* group_offset, int i) {
  return values + group_offset[i >> 2] + (i & 3);  // L(i, k) at [4 k]
}

/// The envelope factorisation's group of rows g..g+m-1 (g a multiple of 4, m <= 4): on
/// entry they hold A's entries (zeros before a row's own first non-zero and in the rows
/// past m), the rows j < g hold L's and inv_diag[j] = 1 / L(j, j); on exit the group's
/// rows hold L's,
///   L(g+t, j) = (A(g+t, j) - sum_{k = max(start[g], start[j])}^{j-1} L(g+t, k) L(j, k)) / L(j, j),
/// and inv_diag has their entries. Returns -1, or the first row whose pivot is not
/// positive.
using EnvelopeGroupFn = int (*)(double* values, const std::ptrdiff_t* group_offset,
                                const int* start, double* inv_diag, int g, int m);

/// Whether the AVX2/FMA kernels are used (decided once per process).
[[nodiscard]] bool useAvx2();

/// The kernel for B = 1, 2, 3 or 6, on the path of solvers::blockKernelPath() (register.h;
/// B = 6 is portable on every path).
[[nodiscard]] EliminateFn eliminateKernel(int block_size);
[[nodiscard]] SolveKernels solveKernels(int block_size);
[[nodiscard]] PairProductFn pairProductKernel();
[[nodiscard]] EnvelopeGroupFn envelopeGroupKernel();

}  // namespace graphslam::solvers::detail
