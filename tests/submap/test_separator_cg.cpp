// SPDX-License-Identifier: MIT
// The separator system's conjugate gradients (submap/src/separator_cg.h) against dense
// solves: the symmetric product from the stored upper triangle, convergence and refusals.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>
#include <vector>

#include "separator_cg.h"

using graphslam::submap::detail::BlockUpperCsc;
using graphslam::submap::detail::CgOutcome;
using graphslam::submap::detail::coarseSystem;
using graphslam::submap::detail::solveByConjugateGradients;

namespace {

/// A dense symmetric matrix in the separator system's storage: upper triangle by columns,
/// every stored block (a, b), a <= b, whole (diagonal blocks too), zero blocks left out.
struct Stored {
  std::vector<int> col_ptr{0}, row_idx, diagonal, block_starts;
  std::vector<double> values;
  /// Aggregate of each block for the coarse level; empty: none.
  std::vector<int> groups;
  BlockUpperCsc view(int n) const {
    const int num_groups = groups.empty() ? 0 : *std::max_element(groups.begin(), groups.end()) + 1;
    return {n,
            col_ptr.data(),
            row_idx.data(),
            values.data(),
            diagonal.data(),
            block_starts.data(),
            static_cast<int>(block_starts.size()) - 1,
            groups.empty() ? nullptr : groups.data(),
            num_groups};
  }
};

Stored store(const Eigen::MatrixXd& m, const std::vector<int>& block_starts) {
  Stored s;
  s.block_starts = block_starts;
  const int nb = static_cast<int>(block_starts.size()) - 1;
  for (int b = 0; b < nb; ++b) {
    for (int col = block_starts[b]; col < block_starts[b + 1]; ++col) {
      for (int a = 0; a <= b; ++a) {
        const int rows = block_starts[a + 1] - block_starts[a];
        if (a < b &&
            m.block(block_starts[a], block_starts[b], rows, block_starts[b + 1] - block_starts[b])
                .isZero(0.0)) {
          continue;
        }
        for (int row = block_starts[a]; row < block_starts[a + 1]; ++row) {
          if (row == col) s.diagonal.push_back(static_cast<int>(s.values.size()));
          s.row_idx.push_back(row);
          s.values.push_back(m(row, col));
        }
      }
      s.col_ptr.push_back(static_cast<int>(s.values.size()));
    }
  }
  return s;
}

/// A random symmetric positive definite matrix of blocks of dimensions 3, 2, 3, 1, 3 with
/// some off-diagonal blocks zero (a sparse block pattern).
Eigen::MatrixXd randomSpd(std::vector<int>& block_starts) {
  block_starts = {0, 3, 5, 8, 9, 12};
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd a(12, 12);
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 12; ++j) a(i, j) = normal(rng);
  }
  Eigen::MatrixXd m = a * a.transpose() + 0.5 * Eigen::MatrixXd::Identity(12, 12);
  m.block(0, 8, 3, 4).setZero();  // blocks (0, 3) and (0, 4)
  m.block(8, 0, 4, 3).setZero();
  m.block(3, 9, 2, 3).setZero();  // block (1, 4)
  m.block(9, 3, 3, 2).setZero();
  m += 20.0 * Eigen::MatrixXd::Identity(12, 12);  // still positive definite
  return m;
}

}  // namespace

TEST(Submap_SeparatorCg, SolvesTheDampedSystemFromTheUpperTriangle) {
  std::vector<int> starts;
  const Eigen::MatrixXd m = randomSpd(starts);
  Stored s = store(m, starts);
  ASSERT_LT(s.values.size(), static_cast<std::size_t>(12 * 12));  // zero blocks left out
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(12, -1.0, 2.0);
  for (const std::vector<int>& groups : {std::vector<int>{}, std::vector<int>{0, 1, 0, 2, 1}}) {
    s.groups = groups;  // block Jacobi alone, then with a coarse level
    for (const double lambda : {0.0, 0.7}) {
      Eigen::VectorXd x;
      const CgOutcome out = solveByConjugateGradients(s.view(12), lambda, b, x, 1e-13, 100);
      ASSERT_TRUE(out.ok) << out.message;
      const Eigen::MatrixXd damped = m + lambda * Eigen::MatrixXd::Identity(12, 12);
      const Eigen::VectorXd expected = damped.llt().solve(b);
      EXPECT_LT((x - expected).norm(), 1e-11 * expected.norm())
          << "lambda " << lambda << ", aggregates " << groups.size();
      EXPECT_LE(out.relative_residual, 1e-13);
      EXPECT_LE(out.iterations, 12);  // exact arithmetic: at most n
      EXPECT_GT(out.iterations, 1);   // the preconditioner alone does not solve it
    }
  }
}

TEST(Submap_SeparatorCg, AZeroRightHandSideTakesNoIteration) {
  std::vector<int> starts;
  const Stored s = store(randomSpd(starts), starts);
  Eigen::VectorXd x = Eigen::VectorXd::Ones(12);
  const CgOutcome out =
      solveByConjugateGradients(s.view(12), 0.0, Eigen::VectorXd::Zero(12), x, 1e-12, 10);
  EXPECT_TRUE(out.ok);
  EXPECT_EQ(out.iterations, 0);
  EXPECT_TRUE(x.isZero(0.0));
}

TEST(Submap_SeparatorCg, RefusesAnIndefiniteSystemAndRunningOutOfIterations) {
  std::vector<int> starts;
  Eigen::MatrixXd m = randomSpd(starts);
  Eigen::VectorXd x, b = Eigen::VectorXd::Ones(12);
  {  // Too few iterations for the tolerance: refused, saying so.
    const CgOutcome out = solveByConjugateGradients(store(m, starts).view(12), 0.0, b, x, 1e-14, 2);
    EXPECT_FALSE(out.ok);
    EXPECT_NE(out.message.find("did not reach a relative residual"), std::string::npos)
        << out.message;
  }
  {  // A diagonal block that is not positive definite.
    Eigen::MatrixXd bad = m;
    bad(3, 3) = -1.0;
    const CgOutcome out =
        solveByConjugateGradients(store(bad, starts).view(12), 0.0, b, x, 1e-12, 50);
    EXPECT_FALSE(out.ok);
    EXPECT_NE(out.message.find("separator columns 3-4 is not positive definite"), std::string::npos)
        << out.message;
  }
  {  // The same, factorised with the other block of its aggregate (local chunks).
    Eigen::MatrixXd bad = m;
    bad(3, 3) = -1.0;
    Stored stored = store(bad, starts);
    stored.groups = {0, 1, 0, 2, 1};
    const CgOutcome out =
        solveByConjugateGradients(stored.view(12), 0.0, b, x, 1e-12, 50, {true, 300});
    EXPECT_FALSE(out.ok);
    EXPECT_NE(out.message.find("separator columns 3-4 (factorised with 1 more block(s) of its "
                               "aggregate) is not positive definite"),
              std::string::npos)
        << out.message;
  }
  {  // Positive definite diagonal blocks, an indefinite whole: b along a direction of
     // negative curvature stops the first iteration, no answer is given.
    Eigen::MatrixXd bad = Eigen::MatrixXd::Identity(12, 12);
    bad(0, 3) = bad(3, 0) = 5.0;
    Eigen::VectorXd along = Eigen::VectorXd::Zero(12);
    along(0) = 1.0;
    along(3) = -1.0;  // along^T bad along = 2 - 10 < 0
    const CgOutcome out =
        solveByConjugateGradients(store(bad, starts).view(12), 0.0, along, x, 1e-12, 50);
    EXPECT_FALSE(out.ok);
    EXPECT_NE(out.message.find("non-positive curvature"), std::string::npos) << out.message;
  }
}

// The coarse level's E = Z^T (S + lambda I) Z, against the dense product: aggregates of
// blocks of different dimensions (as wide as the widest), off-diagonal blocks within and
// across aggregates, zero blocks left out of the storage.
TEST(Submap_SeparatorCg, CoarseSystemIsTheRestrictionToMovingAggregatesAsOne) {
  std::vector<int> starts;
  const Eigen::MatrixXd m = randomSpd(starts);  // blocks of dimensions 3, 2, 3, 1, 3
  Stored s = store(m, starts);
  s.groups = {0, 1, 0, 2, 1};  // widths 3, 3, 1
  Eigen::MatrixXd z = Eigen::MatrixXd::Zero(12, 7);
  const int offset[] = {0, 3, 6};
  for (int b = 0; b < 5; ++b) {
    for (int c = 0; c < starts[b + 1] - starts[b]; ++c)
      z(starts[b] + c, offset[s.groups[b]] + c) = 1.0;
  }
  for (const double lambda : {0.0, 0.7}) {
    const Eigen::MatrixXd expected =
        z.transpose() * (m + lambda * Eigen::MatrixXd::Identity(12, 12)) * z;
    const Eigen::MatrixXd e = coarseSystem(s.view(12), lambda);
    EXPECT_LT((e - expected).norm(), 1e-12 * expected.norm()) << "lambda " << lambda << "\n" << e;
  }
}

// A chain of 60 blocks (a discrete Laplacian in each of 3 components, anchored at one end):
// with aggregates of 10 neighbouring blocks the two-level preconditioner reaches the same
// solution in fewer iterations than block Jacobi alone, which needs about one per block.
TEST(Submap_SeparatorCg, TheCoarseLevelCutsTheIterationsOnAChain) {
  const int nb = 60, n = 3 * nb;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  std::vector<int> starts;
  for (int b = 0; b <= nb; ++b) starts.push_back(3 * b);
  for (int b = 0; b + 1 < nb; ++b) {
    for (int c = 0; c < 3; ++c) {
      const int i = 3 * b + c, j = 3 * (b + 1) + c;
      const double w = 1.0 + 0.5 * c;
      m(i, i) += w;
      m(j, j) += w;
      m(i, j) -= w;
      m(j, i) -= w;
    }
  }
  m.topLeftCorner(3, 3) += Eigen::Matrix3d::Identity();
  Stored plain = store(m, starts), two_level = plain;
  for (int b = 0; b < nb; ++b) two_level.groups.push_back(b / 10);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(n, 1.0, -2.0);
  const Eigen::VectorXd expected = m.llt().solve(rhs);
  Eigen::VectorXd x_plain, x_two;
  const CgOutcome a = solveByConjugateGradients(plain.view(n), 0.0, rhs, x_plain, 1e-12, 1000);
  const CgOutcome b = solveByConjugateGradients(two_level.view(n), 0.0, rhs, x_two, 1e-12, 1000);
  ASSERT_TRUE(a.ok) << a.message;
  ASSERT_TRUE(b.ok) << b.message;
  EXPECT_LT((x_plain - expected).norm(), 1e-9 * expected.norm());
  EXPECT_LT((x_two - expected).norm(), 1e-9 * expected.norm());
  EXPECT_LT(b.iterations * 3, a.iterations * 2)
      << "block Jacobi " << a.iterations << ", two-level " << b.iterations;
}
