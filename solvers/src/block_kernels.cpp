// SPDX-License-Identifier: MIT
#include "block_kernels.h"

#include <Eigen/Core>
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
#endif

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
  if (block_size == 3) return eliminatePortable<3>;
  if (block_size == 2) return eliminatePortable<2>;
  return eliminatePortable<1>;
}

}  // namespace graphslam::solvers::detail

namespace graphslam::solvers {
const char* blockKernelPath() { return detail::useAvx2() ? "avx2-fma" : "portable"; }
}  // namespace graphslam::solvers
