// SPDX-License-Identifier: MIT
#include "block_kernels.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>

#include "graphslam/solvers/register.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define GRAPHSLAM_HAVE_AVX2_KERNELS 1
#endif

namespace graphslam::solvers::detail {
namespace {

/// EnvelopeGroupFn's end: the group's own triangle (gram[u][t] = the sum over the columns
/// before the group of L(g + t, k) L(g + u, k)). Returns -1 or the first row whose pivot
/// is not positive.
int finishGroup(double* inv_diag, int g, int m, double* tw, const double (*gram)[4]) {
  for (int u = 0; u < m; ++u) {
    const std::ptrdiff_t cu = 4 * static_cast<std::ptrdiff_t>(g + u);
    double pivot = tw[cu + u] - gram[u][u];
    for (int q = 0; q < u; ++q) {
      const double l = tw[4 * static_cast<std::ptrdiff_t>(g + q) + u];
      pivot -= l * l;
    }
    if (!(pivot > 0.0) || !std::isfinite(pivot)) return g + u;
    const double diagonal = std::sqrt(pivot);
    tw[cu + u] = diagonal;
    inv_diag[g + u] = 1.0 / diagonal;
    for (int t = u + 1; t < m; ++t) {
      double sum = gram[u][t];
      for (int q = 0; q < u; ++q) {
        const std::ptrdiff_t cq = 4 * static_cast<std::ptrdiff_t>(g + q);
        sum += tw[cq + t] * tw[cq + u];
      }
      tw[cu + t] = (tw[cu + t] - sum) * inv_diag[g + u];
    }
  }
  return -1;
}

/// Portable: Eigen's fixed-size products (SSE2 in the baseline build).
template <int B>
void eliminatePortable(const double* work_i, const double* inv_i, double* out, const double* v,
                       const int* rows, int count, double* work, double* diag) {
  constexpr int P = paddedRows(B);
  using Block = Eigen::Matrix<double, B, B>;
  using Padded = Eigen::Map<Block, 0, Eigen::OuterStride<P>>;
  const Block lki = Eigen::Map<const Block, 0, Eigen::OuterStride<P>>(work_i) *
                    Eigen::Map<const Block>(inv_i).transpose();
  Eigen::Map<Block> l_out(out);
  l_out = lki;
  for (int t = 0; t < count; ++t, v += B * B) {
    Padded w(work + static_cast<std::ptrdiff_t>(rows[t]) * P * B);
    w.noalias() -= lki * Eigen::Map<const Block>(v).transpose();
  }
  Padded(diag).noalias() -= lki * lki.transpose();
}

template <int B>
void forwardPortable(const double* inv_i, double* y_i, const double* v, const int* rows, int count,
                     double* y) {
  constexpr int P = paddedRows(B);
  using Block = Eigen::Matrix<double, B, B>;
  using Vec = Eigen::Matrix<double, B, 1>;
  Eigen::Map<Vec> yi(y_i);
  yi = Eigen::Map<const Block>(inv_i) * yi;
  for (int t = 0; t < count; ++t, v += B * B) {
    Eigen::Map<Vec>(y + static_cast<std::ptrdiff_t>(rows[t]) * P).noalias() -=
        Eigen::Map<const Block>(v) * yi;
  }
}

template <int B>
void backwardPortable(const double* inv_i, double* y_i, const double* v, const int* rows, int count,
                      const double* y) {
  constexpr int P = paddedRows(B);
  using Block = Eigen::Matrix<double, B, B>;
  using Vec = Eigen::Matrix<double, B, 1>;
  Eigen::Map<Vec> yi(y_i);
  for (int t = 0; t < count; ++t, v += B * B) {
    yi.noalias() -= Eigen::Map<const Block>(v).transpose() *
                    Eigen::Map<const Vec>(y + static_cast<std::ptrdiff_t>(rows[t]) * P);
  }
  yi = Eigen::Map<const Block>(inv_i).transpose() * yi;
}

#ifdef GRAPHSLAM_HAVE_AVX2_KERNELS
/// 3 x 3: every column of a block is one 256-bit vector (the fourth lane zero or scratch);
/// L(k, i)'s columns stay in three registers for the whole run of blocks.
__attribute__((target("avx2,fma"))) void eliminate3Avx2(const double* work_i, const double* inv_i,
                                                        double* out, const double* v,
                                                        const int* rows, int count, double* work,
                                                        double* diag) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d y0 = _mm256_loadu_pd(work_i);
  const __m256d y1 = _mm256_loadu_pd(work_i + 4);
  const __m256d y2 = _mm256_loadu_pd(work_i + 8);
  // L(:, m) = sum_n Y(:, n) Inv(m, n); the scratch lane cleared.
  __m256d l0 = _mm256_mul_pd(y0, _mm256_broadcast_sd(inv_i));
  l0 = _mm256_fmadd_pd(y1, _mm256_broadcast_sd(inv_i + 3), l0);
  l0 = _mm256_blend_pd(_mm256_fmadd_pd(y2, _mm256_broadcast_sd(inv_i + 6), l0), zero, 0x8);
  __m256d l1 = _mm256_mul_pd(y0, _mm256_broadcast_sd(inv_i + 1));
  l1 = _mm256_fmadd_pd(y1, _mm256_broadcast_sd(inv_i + 4), l1);
  l1 = _mm256_blend_pd(_mm256_fmadd_pd(y2, _mm256_broadcast_sd(inv_i + 7), l1), zero, 0x8);
  __m256d l2 = _mm256_mul_pd(y0, _mm256_broadcast_sd(inv_i + 2));
  l2 = _mm256_fmadd_pd(y1, _mm256_broadcast_sd(inv_i + 5), l2);
  l2 = _mm256_blend_pd(_mm256_fmadd_pd(y2, _mm256_broadcast_sd(inv_i + 8), l2), zero, 0x8);
  // out is 3 x 3 with nothing of ours after it: the last column is stored as 2 + 1.
  _mm256_storeu_pd(out, l0);
  _mm256_storeu_pd(out + 3, l1);
  _mm_storeu_pd(out + 6, _mm256_castpd256_pd128(l2));
  _mm_store_sd(out + 8, _mm256_extractf128_pd(l2, 1));
  // work[rows[t]] for t < count, then diag with L(k, i) itself.
  for (int t = 0; t <= count; ++t, v += 9) {
    double* w = t < count ? work + static_cast<std::ptrdiff_t>(rows[t]) * 12 : diag;
    const double* vb = t < count ? v : out;
    for (int c = 0; c < 3; ++c) {
      __m256d a = _mm256_loadu_pd(w + 4 * c);
      a = _mm256_fnmadd_pd(l0, _mm256_broadcast_sd(vb + c), a);
      a = _mm256_fnmadd_pd(l1, _mm256_broadcast_sd(vb + c + 3), a);
      a = _mm256_fnmadd_pd(l2, _mm256_broadcast_sd(vb + c + 6), a);
      _mm256_storeu_pd(w + 4 * c, a);
    }
  }
}

/// 2 x 2: the same with 128-bit vectors (a column is two doubles).
__attribute__((target("avx2,fma"))) void eliminate2Avx2(const double* work_i, const double* inv_i,
                                                        double* out, const double* v,
                                                        const int* rows, int count, double* work,
                                                        double* diag) {
  const __m128d y0 = _mm_loadu_pd(work_i);
  const __m128d y1 = _mm_loadu_pd(work_i + 2);
  const __m128d l0 =
      _mm_fmadd_pd(y1, _mm_loaddup_pd(inv_i + 2), _mm_mul_pd(y0, _mm_loaddup_pd(inv_i)));
  const __m128d l1 =
      _mm_fmadd_pd(y1, _mm_loaddup_pd(inv_i + 3), _mm_mul_pd(y0, _mm_loaddup_pd(inv_i + 1)));
  _mm_storeu_pd(out, l0);
  _mm_storeu_pd(out + 2, l1);
  // work[rows[t]] for t < count, then diag with L(k, i) itself.
  for (int t = 0; t <= count; ++t, v += 4) {
    double* w = t < count ? work + static_cast<std::ptrdiff_t>(rows[t]) * 4 : diag;
    const double* vb = t < count ? v : out;
    __m128d a = _mm_loadu_pd(w);
    a = _mm_fnmadd_pd(l0, _mm_loaddup_pd(vb), a);
    a = _mm_fnmadd_pd(l1, _mm_loaddup_pd(vb + 2), a);
    _mm_storeu_pd(w, a);
    __m128d b = _mm_loadu_pd(w + 2);
    b = _mm_fnmadd_pd(l0, _mm_loaddup_pd(vb + 1), b);
    b = _mm_fnmadd_pd(l1, _mm_loaddup_pd(vb + 3), b);
    _mm_storeu_pd(w + 2, b);
  }
}

/// The three lanes of a 3 x 3 block's column (the fourth zero, nothing read past it).
__attribute__((target("avx2,fma"))) inline __m256d column3(const double* c) {
  return _mm256_maskload_pd(c, _mm256_setr_epi64x(-1, -1, -1, 0));
}

/// [sum(a), sum(b), sum(c), 0] of three vectors whose fourth lanes are zero.
__attribute__((target("avx2,fma"))) inline __m256d sums3(__m256d a, __m256d b, __m256d c) {
  const __m256d ab = _mm256_hadd_pd(a, b);                    // a01 b01 a23 b23
  const __m256d c0 = _mm256_hadd_pd(c, _mm256_setzero_pd());  // c01 0 c23 0
  return _mm256_add_pd(_mm256_permute2f128_pd(ab, c0, 0x20), _mm256_permute2f128_pd(ab, c0, 0x31));
}

__attribute__((target("avx2,fma"))) void forward3Avx2(const double* inv_i, double* y_i,
                                                      const double* v, const int* rows, int count,
                                                      double* y) {
  __m256d yi = _mm256_mul_pd(column3(inv_i), _mm256_broadcast_sd(y_i));
  yi = _mm256_fmadd_pd(column3(inv_i + 3), _mm256_broadcast_sd(y_i + 1), yi);
  yi = _mm256_fmadd_pd(column3(inv_i + 6), _mm256_broadcast_sd(y_i + 2), yi);
  _mm256_storeu_pd(y_i, yi);
  const __m256d b0 = _mm256_permute4x64_pd(yi, 0x00);
  const __m256d b1 = _mm256_permute4x64_pd(yi, 0x55);
  const __m256d b2 = _mm256_permute4x64_pd(yi, 0xAA);
  for (int t = 0; t < count; ++t, v += 9) {
    double* w = y + static_cast<std::ptrdiff_t>(rows[t]) * 4;
    __m256d a = _mm256_loadu_pd(w);
    a = _mm256_fnmadd_pd(column3(v), b0, a);
    a = _mm256_fnmadd_pd(column3(v + 3), b1, a);
    a = _mm256_fnmadd_pd(column3(v + 6), b2, a);
    _mm256_storeu_pd(w, a);
  }
}

__attribute__((target("avx2,fma"))) void backward3Avx2(const double* inv_i, double* y_i,
                                                       const double* v, const int* rows, int count,
                                                       const double* y) {
  // acc_c = sum_t L(:, c)_t .* y_p: L(:, c)^T y_p is its sum of lanes.
  __m256d acc0 = _mm256_setzero_pd(), acc1 = acc0, acc2 = acc0;
  for (int t = 0; t < count; ++t, v += 9) {
    const __m256d yp = _mm256_loadu_pd(y + static_cast<std::ptrdiff_t>(rows[t]) * 4);
    acc0 = _mm256_fmadd_pd(column3(v), yp, acc0);
    acc1 = _mm256_fmadd_pd(column3(v + 3), yp, acc1);
    acc2 = _mm256_fmadd_pd(column3(v + 6), yp, acc2);
  }
  const __m256d z = _mm256_sub_pd(_mm256_loadu_pd(y_i), sums3(acc0, acc1, acc2));
  // y_i(c) = Inv(:, c)^T z
  const __m256d x = sums3(_mm256_mul_pd(column3(inv_i), z), _mm256_mul_pd(column3(inv_i + 3), z),
                          _mm256_mul_pd(column3(inv_i + 6), z));
  _mm256_storeu_pd(y_i, x);
}

__attribute__((target("avx2,fma"))) void forward2Avx2(const double* inv_i, double* y_i,
                                                      const double* v, const int* rows, int count,
                                                      double* y) {
  const __m128d yi = _mm_fmadd_pd(_mm_loadu_pd(inv_i + 2), _mm_loaddup_pd(y_i + 1),
                                  _mm_mul_pd(_mm_loadu_pd(inv_i), _mm_loaddup_pd(y_i)));
  _mm_storeu_pd(y_i, yi);
  const __m128d b0 = _mm_unpacklo_pd(yi, yi);
  const __m128d b1 = _mm_unpackhi_pd(yi, yi);
  for (int t = 0; t < count; ++t, v += 4) {
    double* w = y + static_cast<std::ptrdiff_t>(rows[t]) * 2;
    __m128d a = _mm_loadu_pd(w);
    a = _mm_fnmadd_pd(_mm_loadu_pd(v), b0, a);
    a = _mm_fnmadd_pd(_mm_loadu_pd(v + 2), b1, a);
    _mm_storeu_pd(w, a);
  }
}

__attribute__((target("avx2,fma"))) void backward2Avx2(const double* inv_i, double* y_i,
                                                       const double* v, const int* rows, int count,
                                                       const double* y) {
  __m128d acc0 = _mm_setzero_pd(), acc1 = acc0;
  for (int t = 0; t < count; ++t, v += 4) {
    const __m128d yp = _mm_loadu_pd(y + static_cast<std::ptrdiff_t>(rows[t]) * 2);
    acc0 = _mm_fmadd_pd(_mm_loadu_pd(v), yp, acc0);
    acc1 = _mm_fmadd_pd(_mm_loadu_pd(v + 2), yp, acc1);
  }
  const __m128d z = _mm_sub_pd(_mm_loadu_pd(y_i), _mm_hadd_pd(acc0, acc1));
  _mm_storeu_pd(
      y_i, _mm_hadd_pd(_mm_mul_pd(_mm_loadu_pd(inv_i), z), _mm_mul_pd(_mm_loadu_pd(inv_i + 2), z)));
}

/// Entries at..at+3 of pairProductAvx2's row: lo += their first two, hi += the others.
__attribute__((target("avx2,fma"))) inline void pairProductStep(const double* val, const int* col,
                                                                const double* p, int at,
                                                                __m256d& lo, __m256d& hi) {
  const auto pair = [p](int c) { return _mm_loadu_pd(p + 2 * static_cast<std::ptrdiff_t>(c)); };
  const __m256d v = _mm256_loadu_pd(val + at);
  const __m256d p01 =
      _mm256_insertf128_pd(_mm256_castpd128_pd256(pair(col[at])), pair(col[at + 1]), 1);
  const __m256d p23 =
      _mm256_insertf128_pd(_mm256_castpd128_pd256(pair(col[at + 2])), pair(col[at + 3]), 1);
  lo = _mm256_fmadd_pd(_mm256_permute4x64_pd(v, 0x50), p01, lo);  // v0 v0 v1 v1
  hi = _mm256_fmadd_pd(_mm256_permute4x64_pd(v, 0xFA), p23, hi);  // v2 v2 v3 v3
}

/// PairProductFn with 256-bit vectors: two entries (their two coordinates each) per
/// multiply-add, eight entries per step in four independent sums.
__attribute__((target("avx2,fma"))) void pairProductAvx2(const int* ptr, const int* col,
                                                         const double* val, int m, const double* p,
                                                         double* q, double* pq) {
  const auto pair = [p](int c) { return _mm_loadu_pd(p + 2 * static_cast<std::ptrdiff_t>(c)); };
  __m128d dot = _mm_setzero_pd();
  for (int i = 0; i < m; ++i) {
    __m256d s0 = _mm256_setzero_pd(), s1 = s0, s2 = s0, s3 = s0;
    int k = ptr[i];
    const int end = ptr[i + 1];
    for (; k + 8 <= end; k += 8) {
      pairProductStep(val, col, p, k, s0, s1);
      pairProductStep(val, col, p, k + 4, s2, s3);
    }
    if (k + 4 <= end) {
      pairProductStep(val, col, p, k, s0, s1);
      k += 4;
    }
    const __m256d s = _mm256_add_pd(_mm256_add_pd(s0, s1), _mm256_add_pd(s2, s3));
    __m128d a = _mm_add_pd(_mm256_castpd256_pd128(s), _mm256_extractf128_pd(s, 1));
    for (; k < end; ++k) a = _mm_fmadd_pd(_mm_set1_pd(val[k]), pair(col[k]), a);
    _mm_storeu_pd(q + 2 * static_cast<std::ptrdiff_t>(i), a);
    dot = _mm_fmadd_pd(_mm_loadu_pd(p + 2 * static_cast<std::ptrdiff_t>(i)), a, dot);
  }
  _mm_storeu_pd(pq, _mm_add_pd(_mm_loadu_pd(pq), dot));
}

/// Entry k of the four interleaved rows of EnvelopeGroupFn.
__attribute__((target("avx2,fma"))) inline __m256d interleaved(const double* tw, int k) {
  return _mm256_loadu_pd(tw + 4 * static_cast<std::ptrdiff_t>(k));
}

/// EnvelopeGroupFn with 256-bit vectors: entry k of the group's four rows is one vector,
/// each L(j, k) a broadcast against it, so that a sum over k is four sums at once and a
/// new entry of the four rows one vector store; two rows j, j + 1 per pass, two
/// accumulators each.
__attribute__((target("avx2,fma"))) int envelopeGroupAvx2(double* values,
                                                          const std::ptrdiff_t* group_offset,
                                                          const int* start, double* inv_diag, int g,
                                                          int m) {
  const int from = start[g];
  double* tw = values + group_offset[g >> 2];  // tw[4k + t]: L(g + t, k)
  int j = from;
  // The last pair's entries stay in registers (pv: column j - 2, pe: j - 1) and enter
  // the next pair's sums last: the chain from one pair to the next is two multiply-adds
  // (no store and reload), with the division by L(j, j) folded into them.
  __m256d pv = _mm256_setzero_pd(), pe = pv;
  bool have_prev = false;
  for (; j + 1 < g; j += 2) {
    const double* lj = envelopeRow(values, group_offset, j);
    const double* lj1 = envelopeRow(values, group_offset, j + 1);
    // Row j + 1 may start at j + 1 (then L(j + 1, j) = 0 and only row j's sums run).
    const int sa = std::max(from, start[j]), sb = std::max(from, start[j + 1]);
    const int cut = have_prev ? j - 2 : j;  // columns k < cut are read from `work`
    const int s = std::min(std::max(sa, sb), cut);
    __m256d a0 = _mm256_setzero_pd(), a1 = a0, b0 = a0, b1 = a0;
    for (int k = sa; k < s; ++k)
      a0 = _mm256_fmadd_pd(interleaved(tw, k), _mm256_broadcast_sd(lj + 4 * k), a0);
    for (int k = sb; k < s; ++k)
      b0 = _mm256_fmadd_pd(interleaved(tw, k), _mm256_broadcast_sd(lj1 + 4 * k), b0);
    int k = s;
    for (; k + 2 <= cut; k += 2) {
      const __m256d x0 = interleaved(tw, k), x1 = interleaved(tw, k + 1);
      a0 = _mm256_fmadd_pd(x0, _mm256_broadcast_sd(lj + 4 * k), a0);
      b0 = _mm256_fmadd_pd(x0, _mm256_broadcast_sd(lj1 + 4 * k), b0);
      a1 = _mm256_fmadd_pd(x1, _mm256_broadcast_sd(lj + 4 * (k + 1)), a1);
      b1 = _mm256_fmadd_pd(x1, _mm256_broadcast_sd(lj1 + 4 * (k + 1)), b1);
    }
    if (k < cut) {
      const __m256d x0 = interleaved(tw, k);
      a0 = _mm256_fmadd_pd(x0, _mm256_broadcast_sd(lj + 4 * k), a0);
      b0 = _mm256_fmadd_pd(x0, _mm256_broadcast_sd(lj1 + 4 * k), b0);
    }
    __m256d a = _mm256_add_pd(a0, a1), b = _mm256_add_pd(b0, b1);
    if (have_prev) {
      if (j - 2 >= sa) a = _mm256_fmadd_pd(pv, _mm256_broadcast_sd(lj + 4 * (j - 2)), a);
      if (j - 2 >= sb) b = _mm256_fmadd_pd(pv, _mm256_broadcast_sd(lj1 + 4 * (j - 2)), b);
      if (j - 1 >= sa) a = _mm256_fmadd_pd(pe, _mm256_broadcast_sd(lj + 4 * (j - 1)), a);
      if (j - 1 >= sb) b = _mm256_fmadd_pd(pe, _mm256_broadcast_sd(lj1 + 4 * (j - 1)), b);
    }
    // v = (A(., j) - a) / L(j, j); e = (A(., j + 1) - b - v L(j + 1, j)) / L(j + 1, j + 1).
    const __m256d dj = _mm256_set1_pd(inv_diag[j]), dj1 = _mm256_set1_pd(inv_diag[j + 1]);
    const double l10 = start[j + 1] <= j ? lj1[4 * j] : 0.0;
    const __m256d v = _mm256_fnmadd_pd(a, dj, _mm256_mul_pd(interleaved(tw, j), dj));
    const __m256d e0 = _mm256_fnmadd_pd(b, dj1, _mm256_mul_pd(interleaved(tw, j + 1), dj1));
    const __m256d e = _mm256_fnmadd_pd(v, _mm256_set1_pd(l10 * inv_diag[j + 1]), e0);
    _mm256_storeu_pd(tw + 4 * static_cast<std::ptrdiff_t>(j), v);
    _mm256_storeu_pd(tw + 4 * static_cast<std::ptrdiff_t>(j + 1), e);
    pv = v;
    pe = e;
    have_prev = true;
  }
  if (j < g) {
    const double* lj = envelopeRow(values, group_offset, j);
    __m256d a0 = _mm256_setzero_pd();
    for (int k = std::max(from, start[j]); k < j; ++k) {
      a0 = _mm256_fmadd_pd(interleaved(tw, k), _mm256_broadcast_sd(lj + 4 * k), a0);
    }
    _mm256_storeu_pd(
        tw + 4 * static_cast<std::ptrdiff_t>(j),
        _mm256_mul_pd(_mm256_sub_pd(interleaved(tw, j), a0), _mm256_set1_pd(inv_diag[j])));
  }
  // The four rows' products over the columns before the group: gram[u][t] = sum_k L(g + t, k)
  // L(g + u, k).
  alignas(32) double gram[4][4];
  __m256d c0 = _mm256_setzero_pd(), c1 = c0, c2 = c0, c3 = c0;
  for (int k = from; k < g; ++k) {
    const __m256d x = interleaved(tw, k);
    const double* xk = tw + 4 * static_cast<std::ptrdiff_t>(k);
    c0 = _mm256_fmadd_pd(x, _mm256_broadcast_sd(xk), c0);
    c1 = _mm256_fmadd_pd(x, _mm256_broadcast_sd(xk + 1), c1);
    c2 = _mm256_fmadd_pd(x, _mm256_broadcast_sd(xk + 2), c2);
    c3 = _mm256_fmadd_pd(x, _mm256_broadcast_sd(xk + 3), c3);
  }
  _mm256_store_pd(gram[0], c0);
  _mm256_store_pd(gram[1], c1);
  _mm256_store_pd(gram[2], c2);
  _mm256_store_pd(gram[3], c3);
  return finishGroup(inv_diag, g, m, tw, gram);
}
#endif

/// PairProductFn, portable: four independent sums per row.
void pairProductPortable(const int* ptr, const int* col, const double* val, int m, const double* p,
                         double* q, double* pq) {
  for (int i = 0; i < m; ++i) {
    double s[4][2] = {};
    int k = ptr[i];
    const int end = ptr[i + 1];
    for (; k + 4 <= end; k += 4) {
      for (int u = 0; u < 4; ++u) {
        const double* pj = p + 2 * static_cast<std::ptrdiff_t>(col[k + u]);
        s[u][0] += val[k + u] * pj[0];
        s[u][1] += val[k + u] * pj[1];
      }
    }
    for (; k < end; ++k) {
      const double* pj = p + 2 * static_cast<std::ptrdiff_t>(col[k]);
      s[0][0] += val[k] * pj[0];
      s[0][1] += val[k] * pj[1];
    }
    for (int t = 0; t < 2; ++t) {
      const double a = (s[0][t] + s[1][t]) + (s[2][t] + s[3][t]);
      q[2 * static_cast<std::ptrdiff_t>(i) + t] = a;
      pq[t] += p[2 * static_cast<std::ptrdiff_t>(i) + t] * a;
    }
  }
}

/// EnvelopeGroupFn, portable: the four rows' sums for one row j at a time.
int envelopeGroupPortable(double* values, const std::ptrdiff_t* group_offset, const int* start,
                          double* inv_diag, int g, int m) {
  const int from = start[g];
  double* tw = values + group_offset[g >> 2];
  for (int j = from; j < g; ++j) {
    const double* lj = envelopeRow(values, group_offset, j);
    double sum[4] = {};
    for (int k = std::max(from, start[j]); k < j; ++k) {
      for (int t = 0; t < 4; ++t) sum[t] += tw[4 * k + t] * lj[4 * k];
    }
    for (int t = 0; t < 4; ++t) tw[4 * j + t] = (tw[4 * j + t] - sum[t]) * inv_diag[j];
  }
  double gram[4][4] = {};
  for (int k = from; k < g; ++k) {
    for (int u = 0; u < 4; ++u) {
      for (int t = 0; t < 4; ++t) gram[u][t] += tw[4 * k + t] * tw[4 * k + u];
    }
  }
  return finishGroup(inv_diag, g, m, tw, gram);
}

}  // namespace

bool useAvx2() {
#ifdef GRAPHSLAM_HAVE_AVX2_KERNELS
  static const bool use = [] {
    const char* env = std::getenv("GRAPHSLAM_SIMD");
    if (env && std::strcmp(env, "portable") == 0) return false;
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return use;
#else
  return false;
#endif
}

EliminateFn eliminateKernel(int block_size) {
#ifdef GRAPHSLAM_HAVE_AVX2_KERNELS
  if (useAvx2()) {
    if (block_size == 3) return eliminate3Avx2;
    if (block_size == 2) return eliminate2Avx2;
  }
#endif
  if (block_size == 6) return eliminatePortable<6>;
  if (block_size == 3) return eliminatePortable<3>;
  if (block_size == 2) return eliminatePortable<2>;
  return eliminatePortable<1>;
}

SolveKernels solveKernels(int block_size) {
#ifdef GRAPHSLAM_HAVE_AVX2_KERNELS
  if (useAvx2()) {
    if (block_size == 3) return {forward3Avx2, backward3Avx2};
    if (block_size == 2) return {forward2Avx2, backward2Avx2};
  }
#endif
  if (block_size == 6) return {forwardPortable<6>, backwardPortable<6>};
  if (block_size == 3) return {forwardPortable<3>, backwardPortable<3>};
  if (block_size == 2) return {forwardPortable<2>, backwardPortable<2>};
  return {forwardPortable<1>, backwardPortable<1>};
}

PairProductFn pairProductKernel() {
#ifdef GRAPHSLAM_HAVE_AVX2_KERNELS
  if (useAvx2()) return pairProductAvx2;
#endif
  return pairProductPortable;
}

EnvelopeGroupFn envelopeGroupKernel() {
#ifdef GRAPHSLAM_HAVE_AVX2_KERNELS
  if (useAvx2()) return envelopeGroupAvx2;
#endif
  return envelopeGroupPortable;
}

}  // namespace graphslam::solvers::detail

namespace graphslam::solvers {
const char* blockKernelPath() { return detail::useAvx2() ? "avx2-fma" : "portable"; }
}  // namespace graphslam::solvers
