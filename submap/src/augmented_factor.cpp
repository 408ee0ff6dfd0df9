// SPDX-License-Identifier: MIT
#include "augmented_factor.h"

#include <utility>

#include "graphslam/solvers/ordered_factor.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"

namespace graphslam::submap::detail {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

/// M's upper triangle: A's columns, then B's rows above C + delta I (C's zeros left out).
SparseMatrix assemble(const SparseMatrix& a_upper, const SparseMatrix& b, const Eigen::MatrixXd& c,
                      double delta) {
  const auto di = static_cast<int>(a_upper.rows());
  const auto ds = static_cast<int>(c.rows());
  Eigen::Index nnz = a_upper.nonZeros() + b.nonZeros();
  for (int j = 0; j < ds; ++j) {
    for (int i = 0; i <= j; ++i) nnz += (i == j || c(i, j) != 0.0) ? 1 : 0;
  }
  SparseMatrix m(di + ds, di + ds);
  m.resizeNonZeros(nnz);
  int* p = m.outerIndexPtr();
  int* rows = m.innerIndexPtr();
  double* x = m.valuePtr();
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

}  // namespace

bool AugmentedFactor::available() { return solvers::haveSuiteSparse(); }

AugmentedFactor::AugmentedFactor() : factor_(solvers::makeOrderedSupernodalFactor()) {}
AugmentedFactor::~AugmentedFactor() = default;

bool AugmentedFactor::factorize(const SparseMatrix& a_upper, const SparseMatrix& b,
                                const Eigen::MatrixXd& c, double delta) {
  di_ = static_cast<int>(a_upper.rows());
  ds_ = static_cast<int>(c.rows());
  delta_ = delta;
  return factor_->factorize(assemble(a_upper, b, c, delta));
}

void AugmentedFactor::contribution(const Eigen::VectorXd& g_interior,
                                   const Eigen::VectorXd& g_separator, Eigen::MatrixXd& schur,
                                   Eigen::VectorXd& reduced) const {
  const Eigen::MatrixXd ls = factor_->trailingBlock(ds_);
  schur.setZero(ds_, ds_);
  schur.selfadjointView<Eigen::Lower>().rankUpdate(ls);
  schur.diagonal().array() -= delta_;
  schur.triangularView<Eigen::StrictlyUpper>() = schur.transpose();
  Eigen::VectorXd g(di_ + ds_);
  g << g_interior, g_separator;
  const Eigen::VectorXd z = factor_->solveTriangular(std::move(g), /*transposed=*/false);
  reduced.noalias() = ls.triangularView<Eigen::Lower>() * z.tail(ds_);
}

Eigen::VectorXd AugmentedFactor::solveInterior(const Eigen::VectorXd& v) const {
  Eigen::VectorXd b = Eigen::VectorXd::Zero(di_ + ds_);
  b.head(di_) = v;
  Eigen::VectorXd w = factor_->solveTriangular(std::move(b), /*transposed=*/false);
  w.tail(ds_).setZero();  // L^T [u_I; 0] = [w_I; 0] gives L_A^T u_I = w_I
  return factor_->solveTriangular(std::move(w), /*transposed=*/true).head(di_);
}

void AugmentedFactor::release() { factor_->release(); }

}  // namespace graphslam::submap::detail
