// SPDX-License-Identifier: MIT
#include "augmented_factor.h"

#include <algorithm>
#include <string>
#include <utility>

#include "graphslam/solvers/process.h"
#include "graphslam/support/error.h"

#ifdef GRAPHSLAM_SUBMAP_HAVE_CHOLMOD
#include <cholmod.h>
#endif

namespace graphslam::submap::detail {

#ifdef GRAPHSLAM_SUBMAP_HAVE_CHOLMOD

using SparseMatrix = Eigen::SparseMatrix<double>;

struct AugmentedFactor::Impl {
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  int di = 0, ds = 0;
  double delta = 0.0;

  Impl() {
    cholmod_start(&common);
    common.print = 0;
    common.error_handler = nullptr;
    common.supernodal = CHOLMOD_SUPERNODAL;
    common.nmethods = 1;  // M comes in its elimination order, the separator last
    common.method[0].ordering = CHOLMOD_NATURAL;
    common.postorder = 0;
  }
  ~Impl() {
    if (factor != nullptr) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  /// A column vector viewed as CHOLMOD's (no copy).
  static cholmod_dense view(Eigen::VectorXd& v) {
    cholmod_dense d{};
    d.nrow = d.nzmax = d.d = static_cast<std::size_t>(v.size());
    d.ncol = 1;
    d.x = v.data();
    d.xtype = CHOLMOD_REAL;
    d.dtype = CHOLMOD_DOUBLE;
    return d;
  }

  /// x = L^-1 b (system CHOLMOD_L) or L^-T b (CHOLMOD_Lt).
  Eigen::VectorXd solve(int system, Eigen::VectorXd b) {
    cholmod_dense in = view(b);
    const solvers::CholmodOpenMpScope serial;
    cholmod_dense* out = cholmod_solve(system, factor, &in, &common);
    if (out == nullptr) throw Error("submaps: CHOLMOD's triangular solve failed (out of memory?)");
    Eigen::VectorXd x =
        Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(out->x), b.size());
    cholmod_free_dense(&out, &common);
    return x;
  }

  /// M's upper triangle as CHOLMOD's matrix: A's columns, then B's rows above C + delta I.
  cholmod_sparse* assemble(const SparseMatrix& a_upper, const SparseMatrix& b,
                           const Eigen::MatrixXd& c) {
    std::size_t nnz = static_cast<std::size_t>(a_upper.nonZeros() + b.nonZeros());
    for (int j = 0; j < ds; ++j) {
      for (int i = 0; i <= j; ++i) nnz += (i == j || c(i, j) != 0.0) ? 1 : 0;
    }
    const auto n = static_cast<std::size_t>(di + ds);
    cholmod_sparse* m = cholmod_allocate_sparse(n, n, nnz, /*sorted=*/0, /*packed=*/1,
                                                /*stype=*/1, CHOLMOD_REAL, &common);
    if (m == nullptr) throw Error("submaps: CHOLMOD could not allocate a submap's system");
    auto* p = static_cast<int*>(m->p);
    auto* rows = static_cast<int*>(m->i);
    auto* x = static_cast<double*>(m->x);
    int k = 0;
    auto put = [&](Eigen::Index row, double value) {
      rows[k] = static_cast<int>(row);
      x[k++] = value;
    };
    p[0] = 0;
    for (int j = 0; j < di; ++j) {
      for (SparseMatrix::InnerIterator it(a_upper, j); it; ++it) put(it.row(), it.value());
      p[j + 1] = k;
    }
    for (int j = 0; j < ds; ++j) {
      for (SparseMatrix::InnerIterator it(b, j); it; ++it) put(it.row(), it.value());
      for (int i = 0; i <= j; ++i) {
        if (i == j) {
          put(di + i, c(i, j) + delta);
        } else if (c(i, j) != 0.0) {
          put(di + i, c(i, j));
        }
      }
      p[di + j + 1] = k;
    }
    return m;
  }
};

bool AugmentedFactor::available() { return true; }

AugmentedFactor::AugmentedFactor() : impl_(std::make_unique<Impl>()) {}
AugmentedFactor::~AugmentedFactor() = default;

bool AugmentedFactor::factorize(const SparseMatrix& a_upper, const SparseMatrix& b,
                                const Eigen::MatrixXd& c, double delta) {
  Impl& m = *impl_;
  m.di = static_cast<int>(a_upper.rows());
  m.ds = static_cast<int>(c.rows());
  m.delta = delta;
  cholmod_sparse* matrix = m.assemble(a_upper, b, c);
  const solvers::CholmodOpenMpScope serial;  // CHOLMOD's fixed 4 OpenMP threads (process.h)
  if (m.factor == nullptr) m.factor = cholmod_analyze(matrix, &m.common);
  const bool ok = m.factor != nullptr && cholmod_factorize(matrix, m.factor, &m.common) &&
                  m.common.status == CHOLMOD_OK;
  cholmod_free_sparse(&matrix, &m.common);
  if (m.factor == nullptr || m.common.status < CHOLMOD_OK) {
    throw Error("submaps: CHOLMOD could not factorise a submap (status " +
                std::to_string(m.common.status) + ", out of memory?)");
  }
  return ok;
}

void AugmentedFactor::contribution(const Eigen::VectorXd& g_interior,
                                   const Eigen::VectorXd& g_separator, Eigen::MatrixXd& schur,
                                   Eigen::VectorXd& reduced) const {
  const Impl& m = *impl_;
  const cholmod_factor& f = *m.factor;
  // L_S: the trailing columns of the supernodes (column-major, leading dimension the
  // supernode's row count; its own columns are its first rows, in order).
  Eigen::MatrixXd ls = Eigen::MatrixXd::Zero(m.ds, m.ds);
  const auto* super = static_cast<const int*>(f.super);
  const auto* pi = static_cast<const int*>(f.pi);
  const auto* px = static_cast<const int*>(f.px);
  const auto* s = static_cast<const int*>(f.s);
  const auto* x = static_cast<const double*>(f.x);
  for (std::size_t sn = 0; sn < f.nsuper; ++sn) {
    const int first = super[sn], end = super[sn + 1];
    if (end <= m.di) continue;
    const int height = pi[sn + 1] - pi[sn];
    const int* rows = s + pi[sn];
    const double* values = x + px[sn];
    for (int col = std::max(first, m.di); col < end; ++col) {
      const int local = col - first;
      for (int r = local; r < height; ++r) {
        ls(rows[r] - m.di, col - m.di) = values[static_cast<std::size_t>(local) * height + r];
      }
    }
  }
  schur.setZero(m.ds, m.ds);
  schur.selfadjointView<Eigen::Lower>().rankUpdate(ls);
  schur.diagonal().array() -= m.delta;
  schur.triangularView<Eigen::StrictlyUpper>() = schur.transpose();
  Eigen::VectorXd g(m.di + m.ds);
  g << g_interior, g_separator;
  const Eigen::VectorXd z = impl_->solve(CHOLMOD_L, std::move(g));
  reduced.noalias() = ls.triangularView<Eigen::Lower>() * z.tail(m.ds);
}

Eigen::VectorXd AugmentedFactor::solveInterior(const Eigen::VectorXd& v) const {
  Impl& m = *impl_;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(m.di + m.ds);
  b.head(m.di) = v;
  Eigen::VectorXd w = m.solve(CHOLMOD_L, std::move(b));
  w.tail(m.ds).setZero();  // L^T [u_I; 0] = [w_I; 0] gives L_A^T u_I = w_I
  return m.solve(CHOLMOD_Lt, std::move(w)).head(m.di);
}

void AugmentedFactor::release() {
  Impl& m = *impl_;
  if (m.factor != nullptr && m.factor->xtype != CHOLMOD_PATTERN) {
    cholmod_change_factor(CHOLMOD_PATTERN, 1, m.factor->is_super, 1, 1, m.factor, &m.common);
  }
}

#else

struct AugmentedFactor::Impl {};
bool AugmentedFactor::available() { return false; }
AugmentedFactor::AugmentedFactor() = default;
AugmentedFactor::~AugmentedFactor() = default;
bool AugmentedFactor::factorize(const Eigen::SparseMatrix<double>&,
                                const Eigen::SparseMatrix<double>&, const Eigen::MatrixXd&,
                                double) {
  throw Error("submaps: supernodal interiors need SuiteSparse's CHOLMOD, which this build lacks");
}
void AugmentedFactor::contribution(const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::MatrixXd&,
                                   Eigen::VectorXd&) const {}
Eigen::VectorXd AugmentedFactor::solveInterior(const Eigen::VectorXd&) const { return {}; }
void AugmentedFactor::release() {}

#endif

}  // namespace graphslam::submap::detail
