// SPDX-License-Identifier: MIT
#include "dense_front.h"

#include <Eigen/Cholesky>
#include <cmath>

#include "graphslam/support/fixed_size.h"

#ifdef GRAPHSLAM_INCREMENTAL_HAVE_LAPACK
#include "graphslam/support/blas.h"
#endif

namespace graphslam::incremental {

using Eigen::Index;

// Fronts whose eliminated block has at most this many columns (one vertex, or two small
// ones) are eliminated with plain loops: the blocked level-3 kernels (BLAS's or Eigen's),
// made for large matrices, cost several times the arithmetic there.
constexpr int kSmallFrontColumns = 8;

namespace {

#ifdef GRAPHSLAM_INCREMENTAL_HAVE_LAPACK
// LAPACK's dpotrf, BLAS's dtrsm, dsyrk and the two level-2 products: the BLAS's kernels for
// the machine it runs on (OpenBLAS picks them at run time), where Eigen's are compiled for
// the baseline instruction set.
bool eliminateLeadingBlocked(Eigen::Map<Eigen::MatrixXd>& f, Eigen::Map<Eigen::VectorXd>& rhs,
                             int k) {
  const int n = static_cast<int>(f.rows());
  const int h = n - k;
  double* a = f.data();
  int info = 0;
  support::blas::dpotrf("L", &k, a, &n, &info);
  if (info != 0) return false;
  const int inc = 1;
  support::blas::dtrsv("L", "N", "N", &k, a, &n, rhs.data(), &inc);
  if (h == 0) return true;
  const double one = 1.0;
  const double minus_one = -1.0;
  double* below = a + k;
  support::blas::dtrsm("R", "L", "T", "N", &h, &k, &one, a, &n, below, &n);
  support::blas::dsyrk("L", "N", &h, &k, &minus_one, below, &n, &one,
                       below + static_cast<Index>(k) * n, &n);
  support::blas::dgemv("N", &h, &k, &minus_one, below, &n, rhs.data(), &inc, &one, rhs.data() + k,
                       &inc);
  return true;
}
#else
// Eigen's blocked LLT, triangular solve and rank update.
bool eliminateLeadingBlocked(Eigen::Map<Eigen::MatrixXd>& f, Eigen::Map<Eigen::VectorXd>& rhs,
                             int k) {
  const Index h = f.rows() - k;
  Eigen::Ref<Eigen::MatrixXd> l11 = f.topLeftCorner(k, k);
  const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(l11);  // in place
  if (llt.info() != Eigen::Success) return false;
  auto y = rhs.head(k);
  llt.matrixL().solveInPlace(y);
  if (h == 0) return true;  // (Eigen's solves of empty blocks would reach null data)
  auto below = f.bottomLeftCorner(h, k);
  llt.matrixU().solveInPlace<Eigen::OnTheRight>(below);
  f.bottomRightCorner(h, h).selfadjointView<Eigen::Lower>().rankUpdate(below, -1.0);
  rhs.tail(h).noalias() -= below * y;
  return true;
}
#endif

// f22 -= f21 f21^T (lower triangle) and rhs2 -= f21 rhs1 for the leading k columns (K when
// K > 0) of the n x n front a: one pass down each output column, each entry read and
// written once for all k products (subtracted in column order).
template <int K>
void subtractOuterProduct(double* a, Index n, int k_at_run_time, double* r) {
  const int k = K > 0 ? K : k_at_run_time;
  double b[K > 0 ? K : kSmallFrontColumns];
  for (Index j = k; j < n; ++j) {
    for (int l = 0; l < k; ++l) b[l] = a[j + l * n];
    double* __restrict out = a + j * n;  // column j >= k: none of the columns read
    for (Index i = j; i < n; ++i) {
      double v = out[i];
      for (int l = 0; l < k; ++l) v -= a[i + l * n] * b[l];
      out[i] = v;
    }
    for (int l = 0; l < k; ++l) r[j] -= b[l] * r[l];
  }
}

// Column by column (the inner loops run down contiguous columns).
bool eliminateLeadingSmall(Eigen::Map<Eigen::MatrixXd>& f, Eigen::Map<Eigen::VectorXd>& rhs,
                           int k) {
  const Index n = f.rows();
  double* a = f.data();
  const auto at = [a, n](Index i, Index j) -> double& { return a[i + j * n]; };
  for (Index j = 0; j < k; ++j) {  // L11 and f21 L11^-T, one column at a time
    for (Index l = 0; l < j; ++l) {
      const double ljl = at(j, l);
      for (Index i = j; i < n; ++i) at(i, j) -= at(i, l) * ljl;
    }
    const double d = at(j, j);
    if (!(d > 0.0)) return false;
    const double s = std::sqrt(d);
    at(j, j) = s;
    for (Index i = j + 1; i < n; ++i) at(i, j) /= s;
  }
  double* r = rhs.data();
  for (Index j = 0; j < k; ++j) {  // L11^-1 rhs1
    for (Index l = 0; l < j; ++l) r[j] -= at(j, l) * r[l];
    r[j] /= at(j, j);
  }
  support::withFixedSize<2, 3, 4, 5, 6>(
      k, [&](auto fixed) { subtractOuterProduct<decltype(fixed)::value>(a, n, k, r); });
  return true;
}

}  // namespace

bool eliminateLeading(Eigen::Map<Eigen::MatrixXd>& f, Eigen::Map<Eigen::VectorXd>& rhs, int k) {
  return k <= kSmallFrontColumns ? eliminateLeadingSmall(f, rhs, k)
                                 : eliminateLeadingBlocked(f, rhs, k);
}

}  // namespace graphslam::incremental
