// SPDX-License-Identifier: MIT
// SO(3), SE(3) and SE(2): exp/log round trips, Jacobians against numeric derivatives, near the
// identity and near pi.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "graphslam/geometry/se2.h"
#include "graphslam/geometry/se3.h"

using namespace graphslam::geometry;

namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
}

/// Rotation vectors of the three regimes: tiny (series), ordinary, and within 1e-7 of pi.
std::vector<Eigen::Vector3d> testRotations(std::mt19937& rng) {
  std::vector<Eigen::Vector3d> out;
  std::uniform_real_distribution<double> angle(0.0, kPi);
  for (int i = 0; i < 50; ++i) {
    out.push_back(randomUnit(rng) * angle(rng));
    out.push_back(randomUnit(rng) * 1e-4 * angle(rng));
    out.push_back(randomUnit(rng) * 1e-9 * angle(rng));
    out.push_back(randomUnit(rng) * (kPi - 1e-7 * angle(rng)));
  }
  out.push_back(Eigen::Vector3d::Zero());
  return out;
}

TEST(Geometry_SO3, ExpLogRoundTripIsExactInEveryRegime) {
  std::mt19937 rng(1);
  for (const Eigen::Vector3d& w : testRotations(rng)) {
    const Eigen::Vector3d back = SO3::exp(w).log();
    EXPECT_LT((back - w).norm(), 1e-15 + 1e-13 * w.norm()) << w.transpose();
    // The matrix exponential agrees (Rodrigues, evaluated directly).
    const double t = w.norm();
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
    if (t > 0) r = Eigen::AngleAxisd(t, w / t).toRotationMatrix();
    EXPECT_LT((SO3::exp(w).matrix() - r).cwiseAbs().maxCoeff(), 1e-14);
  }
}

TEST(Geometry_SO3, LogNearPiKeepsTheAngle) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
  for (double eps : {1e-3, 1e-8, 1e-12, 0.0}) {
    const SO3 r(Eigen::Quaterniond(Eigen::AngleAxisd(kPi - eps, axis)));
    const Eigen::Vector3d w = r.log();
    EXPECT_NEAR(w.norm(), kPi - eps, 1e-14);
    EXPECT_LT((w.normalized() - axis).norm(), 1e-12);
  }
}

TEST(Geometry_SO3, JacobiansMatchNumericDerivatives) {
  std::mt19937 rng(2);
  const double h = 1e-6;
  for (const Eigen::Vector3d& w : testRotations(rng)) {
    if (w.norm() > kPi - 1e-3) continue;  // log jumps across pi: differences meaningless
    const SO3 r = SO3::exp(w);
    Eigen::Matrix3d jr_num, jl_num;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k) * h;
      // Exp(w + d) = Exp(w) Exp(Jr d) = Exp(Jl d) Exp(w).
      jr_num.col(k) =
          ((r.inverse() * SO3::exp(w + d)).log() - (r.inverse() * SO3::exp(w - d)).log()) / (2 * h);
      jl_num.col(k) =
          ((SO3::exp(w + d) * r.inverse()).log() - (SO3::exp(w - d) * r.inverse()).log()) / (2 * h);
    }
    EXPECT_LT((rightJacobianSO3(w) - jr_num).cwiseAbs().maxCoeff(), 1e-8) << w.transpose();
    EXPECT_LT((leftJacobianSO3(w) - jl_num).cwiseAbs().maxCoeff(), 1e-8) << w.transpose();
    EXPECT_LT((rightJacobianInverseSO3(w) * rightJacobianSO3(w) - Eigen::Matrix3d::Identity())
                  .cwiseAbs()
                  .maxCoeff(),
              1e-12);
    EXPECT_LT((leftJacobianInverseSO3(w) * leftJacobianSO3(w) - Eigen::Matrix3d::Identity())
                  .cwiseAbs()
                  .maxCoeff(),
              1e-12);
  }
}

TEST(Geometry_SO3, CompactQuaternionDerivative) {
  std::mt19937 rng(3);
  const double h = 1e-6;
  for (const Eigen::Vector3d& w : testRotations(rng)) {
    if (w.norm() > 3.0) continue;  // the sign flip at pi
    const SO3 r = SO3::exp(w);
    Eigen::Matrix3d num;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k) * h;
      num.col(k) = (positiveScalar((r * SO3::exp(d)).quaternion()).vec() -
                    positiveScalar((r * SO3::exp(-d)).quaternion()).vec()) /
                   (2 * h);
    }
    EXPECT_LT((compactQuaternionRightDerivative(positiveScalar(r.quaternion())) - num)
                  .cwiseAbs()
                  .maxCoeff(),
              1e-8);
  }
}

TEST(Geometry_SE3, GroupAxiomsAndExpLog) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-5, 5);
  for (const Eigen::Vector3d& w : testRotations(rng)) {
    Vector6d xi;
    xi << u(rng), u(rng), u(rng), w;
    const SE3 a = SE3::exp(xi);
    EXPECT_LT((a.log() - xi).norm(), 1e-11 * (1 + xi.norm())) << xi.transpose();
    const SE3 id = a * a.inverse();
    EXPECT_LT(id.translation().norm(), 1e-13);
    EXPECT_LT(id.so3().log().norm(), 1e-14);
    // Adjoint: T exp(x) T^-1 = exp(Ad x).
    Vector6d x;
    x << 0.1, -0.2, 0.3, 0.01, 0.02, -0.03;
    const SE3 lhs = a * SE3::exp(x) * a.inverse();
    EXPECT_LT((lhs.log() - a.adjoint() * x).norm(), 1e-10);
    // Quaternion layout round trip, with a non-unit quaternion normalised.
    Vector7d v = a.toVectorQT();
    v.tail<4>() *= 3.0;
    EXPECT_LT((SE3::fromVectorQT(v).toVectorQT() - a.toVectorQT()).norm(), 1e-15);
  }
}

TEST(Geometry_SE3, JacobiansMatchNumericDerivatives) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2, 2);
  const double h = 1e-6;
  for (const Eigen::Vector3d& w : testRotations(rng)) {
    if (w.norm() > kPi - 1e-3) continue;
    Vector6d xi;
    xi << u(rng), u(rng), u(rng), w;
    const SE3 t = SE3::exp(xi);
    Matrix6d jr_num, jl_num;
    for (int k = 0; k < 6; ++k) {
      const Vector6d d = Vector6d::Unit(k) * h;
      jr_num.col(k) =
          ((t.inverse() * SE3::exp(xi + d)).log() - (t.inverse() * SE3::exp(xi - d)).log()) /
          (2 * h);
      jl_num.col(k) =
          ((SE3::exp(xi + d) * t.inverse()).log() - (SE3::exp(xi - d) * t.inverse()).log()) /
          (2 * h);
    }
    EXPECT_LT((rightJacobianSE3(xi) - jr_num).cwiseAbs().maxCoeff(), 1e-7) << xi.transpose();
    EXPECT_LT((leftJacobianSE3(xi) - jl_num).cwiseAbs().maxCoeff(), 1e-7) << xi.transpose();
  }
}

/// Angles of the three regimes for SE(2): tiny (series), ordinary, and within 1e-7 of pi.
std::vector<double> testAngles(std::mt19937& rng) {
  std::vector<double> out{0.0};
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  for (int i = 0; i < 50; ++i) {
    out.push_back(angle(rng));
    out.push_back(1e-4 * angle(rng));
    out.push_back(1e-9 * angle(rng));
    out.push_back(std::copysign(kPi - 1e-7 * std::abs(angle(rng)), angle(rng)));
  }
  return out;
}

TEST(Geometry_SE2, GroupAxiomsAndExpLog) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-5, 5);
  for (double theta : testAngles(rng)) {
    const Eigen::Vector3d xi(u(rng), u(rng), theta);
    const SE2 a = SE2::exp(xi);
    EXPECT_LT((a.log() - xi).norm(), 1e-11 * (1 + xi.norm())) << xi.transpose();
    const SE2 id = a * a.inverse();
    EXPECT_LT(id.translation().norm(), 1e-13);
    EXPECT_LT(std::abs(id.angle()), 1e-15);
    const Eigen::Vector3d x(0.1, -0.2, 0.03);
    const SE2 lhs = a * SE2::exp(x) * a.inverse();
    EXPECT_LT((lhs.log() - a.adjoint() * x).norm(), 1e-12) << xi.transpose();
  }
  // exp of a pure translation, and of a quarter turn: the arc's chord.
  EXPECT_LT((SE2::exp({1, 2, 0}).translation() - Eigen::Vector2d(1, 2)).norm(), 1e-16);
  const SE2 quarter = SE2::exp({kPi / 2, 0, kPi / 2});
  EXPECT_LT((quarter.translation() - Eigen::Vector2d(1, 1)).norm(), 1e-15);
}

TEST(Geometry_SE2, JacobiansMatchNumericDerivatives) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  const double h = 1e-6;
  for (double theta : testAngles(rng)) {
    if (std::abs(theta) > kPi - 1e-3) continue;
    const Eigen::Vector3d xi(u(rng), u(rng), theta);
    const SE2 t = SE2::exp(xi);
    Eigen::Matrix3d jr_num, jl_num;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k) * h;
      jr_num.col(k) =
          ((t.inverse() * SE2::exp(xi + d)).log() - (t.inverse() * SE2::exp(xi - d)).log()) /
          (2 * h);
      jl_num.col(k) =
          ((SE2::exp(xi + d) * t.inverse()).log() - (SE2::exp(xi - d) * t.inverse()).log()) /
          (2 * h);
    }
    EXPECT_LT((rightJacobianSE2(xi) - jr_num).cwiseAbs().maxCoeff(), 1e-8) << xi.transpose();
    EXPECT_LT((leftJacobianSE2(xi) - jl_num).cwiseAbs().maxCoeff(), 1e-8) << xi.transpose();
  }
}

}  // namespace
