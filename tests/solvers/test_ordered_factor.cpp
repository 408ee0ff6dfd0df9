// SPDX-License-Identifier: MIT
// OrderedFactor (CHOLMOD supernodal in the caller's order) and METIS's vertex separator.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>
#include <vector>

#include "graphslam/solvers/ordered_factor.h"
#include "graphslam/solvers/register.h"

using namespace graphslam;

namespace {

/// A random sparse SPD matrix of n rows: a chain with random extra couplings, diagonally
/// dominant, its last `dense_tail` rows coupled to everything before them.
Eigen::MatrixXd randomSpd(int n, int dense_tail, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  auto couple = [&](int i, int j) { m(i, j) = m(j, i) = value(rng); };
  for (int i = 0; i + 1 < n; ++i) couple(i, i + 1);
  for (int k = 0; k < n; ++k) couple(static_cast<int>(rng() % n), static_cast<int>(rng() % n));
  for (int j = n - dense_tail; j < n; ++j) {
    for (int i = 0; i < j; ++i) couple(i, j);
  }
  for (int i = 0; i < n; ++i) {
    m(i, i) = 0.0;
    m(i, i) = m.row(i).cwiseAbs().sum() + 1.0;
  }
  return m;
}

Eigen::SparseMatrix<double> upperOf(const Eigen::MatrixXd& m) {
  Eigen::SparseMatrix<double> s = m.sparseView();
  Eigen::SparseMatrix<double> upper = s.triangularView<Eigen::Upper>();
  upper.makeCompressed();
  return upper;
}

}  // namespace

// The trailing block of L is the Cholesky factor of the Schur complement onto the trailing
// variables, and the two triangular solves invert L and L^T.
TEST(Solvers_OrderedFactor, TrailingBlockFactorsTheSchurComplement) {
  if (!solvers::haveSuiteSparse()) GTEST_SKIP() << "needs SuiteSparse";
  const int n = 60, ds = 7, di = n - ds;
  const Eigen::MatrixXd m = randomSpd(n, ds, 3);
  auto factor = solvers::makeOrderedSupernodalFactor();
  ASSERT_TRUE(factor->factorize(upperOf(m)));

  const Eigen::MatrixXd a = m.topLeftCorner(di, di);
  const Eigen::MatrixXd b = m.topRightCorner(di, ds);
  const Eigen::MatrixXd schur = m.bottomRightCorner(ds, ds) - b.transpose() * a.llt().solve(b);
  const Eigen::MatrixXd ls = factor->trailingBlock(ds);
  EXPECT_TRUE(ls.isLowerTriangular());
  EXPECT_LT((ls * ls.transpose() - schur).norm(), 1e-10 * schur.norm());

  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  const Eigen::VectorXd y = factor->solveTriangular(rhs, /*transposed=*/false);
  const Eigen::VectorXd x = factor->solveTriangular(y, /*transposed=*/true);
  EXPECT_LT((m * x - rhs).norm(), 1e-10 * rhs.norm());
  // The order is the caller's: L's leading block is the Cholesky factor of A itself.
  const Eigen::MatrixXd la = a.llt().matrixL();
  EXPECT_LT((y.head(di) - la.triangularView<Eigen::Lower>().solve(rhs.head(di))).norm(), 1e-10);
}

// After release() the same analysis factorises new values of the same pattern; a matrix
// that is not positive definite gives false.
TEST(Solvers_OrderedFactor, RefactorisesAfterReleaseAndRefusesAnIndefiniteMatrix) {
  if (!solvers::haveSuiteSparse()) GTEST_SKIP() << "needs SuiteSparse";
  const int n = 40;
  Eigen::MatrixXd m = randomSpd(n, 3, 5);
  auto factor = solvers::makeOrderedSupernodalFactor();
  ASSERT_TRUE(factor->factorize(upperOf(m)));
  factor->release();
  m.diagonal() *= 2.0;
  ASSERT_TRUE(factor->factorize(upperOf(m)));
  const Eigen::MatrixXd l = factor->trailingBlock(n);
  EXPECT_LT((l * l.transpose() - m).norm(), 1e-10 * m.norm());

  m(n - 1, n - 1) = -1.0;
  EXPECT_FALSE(factor->factorize(upperOf(m)));
}

// On a grid the separator splits the vertices into two non-empty sides no edge joins.
TEST(Solvers_MetisVertexSeparator, NoEdgeJoinsTheTwoSides) {
  if (!solvers::haveSuiteSparse()) GTEST_SKIP() << "needs SuiteSparse";
  const int side = 30, n = side * side;
  std::vector<int> column_starts(1, 0), rows;
  for (int j = 0; j < n; ++j) {  // upper triangle: the left and upper neighbours
    if (j % side > 0) rows.push_back(j - 1);
    if (j >= side) rows.push_back(j - side);
    std::sort(rows.end() - ((j % side > 0) + (j >= side)), rows.end());
    column_starts.push_back(static_cast<int>(rows.size()));
  }
  const std::vector<int> part = solvers::metisVertexSeparator(column_starts, rows);
  ASSERT_EQ(part.size(), static_cast<std::size_t>(n));
  const auto count = [&](int s) { return std::count(part.begin(), part.end(), s); };
  EXPECT_GT(count(0), n / 4);
  EXPECT_GT(count(1), n / 4);
  EXPECT_GT(count(2), 0);
  EXPECT_LE(count(2), 2 * side);  // a grid's best separator is one row or column
  for (int j = 0; j < n; ++j) {
    for (int k = column_starts[j]; k < column_starts[j + 1]; ++k) {
      const int a = part[j], b = part[rows[k]];
      EXPECT_FALSE((a == 0 && b == 1) || (a == 1 && b == 0)) << "edge " << rows[k] << "-" << j;
    }
  }
}
