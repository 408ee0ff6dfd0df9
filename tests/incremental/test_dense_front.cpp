// SPDX-License-Identifier: MIT
// The dense elimination of a front's leading columns (incremental/src/dense_front.h) against
// Eigen's LLT, for every kernel: the plain loops with a fixed or a run-time column count,
// and the blocked kernels (BLAS's, or Eigen's in a build without LAPACK).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <random>

#include "dense_front.h"

namespace graphslam::incremental {
namespace {

Eigen::MatrixXd randomSpd(int n, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd b(n, n + 2);
  for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = normal(rng);
  return b * b.transpose() + Eigen::MatrixXd::Identity(n, n);
}

TEST(Incremental_DenseFront, LeadingColumnsMatchLltForEveryKernel) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  for (int k = 1; k <= 12; ++k) {  // fixed 2-6, run-time 1, 7 and 8, blocked above 8
    for (int h : {0, 1, 5, 17}) {
      const int n = k + h;
      const Eigen::MatrixXd a = randomSpd(n, rng);
      Eigen::VectorXd b(n);
      for (int i = 0; i < n; ++i) b[i] = normal(rng);
      Eigen::MatrixXd f = a;
      f.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);  // never read
      Eigen::VectorXd rhs = b;
      Eigen::Map<Eigen::MatrixXd> fm(f.data(), n, n);
      Eigen::Map<Eigen::VectorXd> rm(rhs.data(), n);
      ASSERT_TRUE(eliminateLeading(fm, rm, k)) << "k " << k << " h " << h;

      const Eigen::LLT<Eigen::MatrixXd> llt(a.topLeftCorner(k, k));
      const Eigen::MatrixXd l11 = llt.matrixL();
      const Eigen::VectorXd y1 = l11.triangularView<Eigen::Lower>().solve(b.head(k));
      const double tol = 1e-10 * a.cwiseAbs().maxCoeff();
      const Eigen::MatrixXd got11 = f.topLeftCorner(k, k).triangularView<Eigen::Lower>();
      EXPECT_LE((got11 - l11).cwiseAbs().maxCoeff(), tol) << "L11, k " << k << " h " << h;
      EXPECT_LE((rhs.head(k) - y1).cwiseAbs().maxCoeff(), tol) << "y1, k " << k << " h " << h;
      if (h == 0) continue;  // (Eigen's solve of an empty right-hand side reads no data)

      const Eigen::MatrixXd l21 = l11.triangularView<Eigen::Lower>()
                                      .solve(a.bottomLeftCorner(h, k).transpose())
                                      .transpose();
      const Eigen::MatrixXd schur = a.bottomRightCorner(h, h) - l21 * l21.transpose();
      const Eigen::VectorXd rhs2 = b.tail(h) - l21 * y1;
      EXPECT_LE((f.bottomLeftCorner(h, k) - l21).cwiseAbs().maxCoeff(), tol)
          << "L21, k " << k << " h " << h;
      const Eigen::MatrixXd got22 = f.bottomRightCorner(h, h).triangularView<Eigen::Lower>();
      const Eigen::MatrixXd want22 = schur.triangularView<Eigen::Lower>();
      EXPECT_LE((got22 - want22).cwiseAbs().maxCoeff(), tol) << "F22, k " << k << " h " << h;
      EXPECT_LE((rhs.tail(h) - rhs2).cwiseAbs().maxCoeff(), tol) << "rhs2, k " << k << " h " << h;
    }
  }
}

TEST(Incremental_DenseFront, LeadingBlockNotPositiveDefiniteIsAFailure) {
  std::mt19937 rng(11);
  for (int k : {3, 6, 7, 12}) {  // the plain loops and the blocked kernels
    const int n = k + 4;
    Eigen::MatrixXd f = randomSpd(n, rng);
    f(k - 1, k - 1) = -1.0;
    Eigen::VectorXd rhs = Eigen::VectorXd::Ones(n);
    Eigen::Map<Eigen::MatrixXd> fm(f.data(), n, n);
    Eigen::Map<Eigen::VectorXd> rm(rhs.data(), n);
    EXPECT_FALSE(eliminateLeading(fm, rm, k)) << "k " << k;
  }
}

}  // namespace
}  // namespace graphslam::incremental
