// SPDX-License-Identifier: MIT
#include "graphslam/geometry/se3.h"

#include <cmath>
#include <limits>

namespace graphslam::geometry {

SE3 SE3::fromVectorQT(const Vector7d& v) {
  const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
  // A quaternion that is unit to rounding is kept as it is, so that a transform written
  // with all its digits reads back bit for bit; any other is normalised.
  constexpr double kUnitTolerance = 4.0 * std::numeric_limits<double>::epsilon();
  if (std::abs(q.squaredNorm() - 1.0) <= kUnitTolerance) return {SO3::fromUnit(q), v.head<3>()};
  return {q, v.head<3>()};
}

Vector7d SE3::toVectorQT() const {
  Vector7d v;
  const Eigen::Quaterniond& q = quaternion();
  v << t_, q.x(), q.y(), q.z(), q.w();
  return v;
}

Vector6d SE3::toCompactVector() const {
  Vector6d v;
  v << t_, positiveScalar(quaternion()).vec();
  return v;
}

SE3 SE3::exp(const Vector6d& xi) {
  const Eigen::Vector3d phi = xi.tail<3>();
  return {SO3::exp(phi), leftJacobianSO3(phi) * xi.head<3>()};
}

Vector6d SE3::log() const {
  Vector6d xi;
  const Eigen::Vector3d phi = r_.log();
  xi << leftJacobianInverseSO3(phi) * t_, phi;
  return xi;
}

Eigen::Isometry3d SE3::isometry() const {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = rotation();
  iso.translation() = t_;
  return iso;
}

Matrix6d SE3::adjoint() const {
  const Eigen::Matrix3d r = rotation();
  Matrix6d ad = Matrix6d::Zero();
  ad.topLeftCorner<3, 3>() = r;
  ad.topRightCorner<3, 3>() = hat(t_) * r;
  ad.bottomRightCorner<3, 3>() = r;
  return ad;
}

namespace {

/// The coupling block Q(rho, phi) of the SE(3) left Jacobian [Jl(phi), Q; 0, Jl(phi)]
/// (closed form of the series sum_n (ad xi)^n / (n+1)! restricted to that block).
Eigen::Matrix3d leftJacobianCoupling(const Eigen::Vector3d& rho, const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const double t2 = theta * theta;
  double b = 0.0, c = 0.0, d = 0.0;
  if (theta < 1e-3) {  // series: the closed forms cancel catastrophically near 0
    b = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0;
    c = 1.0 / 24.0 - t2 / 720.0 + t2 * t2 / 40320.0;
    d = 1.0 / 120.0 - t2 / 2520.0 + t2 * t2 / 120960.0;
  } else {
    const double s = std::sin(theta);
    const double co = std::cos(theta);
    b = (theta - s) / (t2 * theta);
    c = (t2 + 2.0 * co - 2.0) / (2.0 * t2 * t2);
    d = (2.0 * theta - 3.0 * s + theta * co) / (2.0 * t2 * t2 * theta);
  }
  const Eigen::Matrix3d p = hat(phi);
  const Eigen::Matrix3d r = hat(rho);
  const Eigen::Matrix3d pr = p * r;
  const Eigen::Matrix3d rp = r * p;
  const Eigen::Matrix3d prp = pr * p;
  return 0.5 * r + b * (pr + rp + prp) + c * (p * pr + rp * p - 3.0 * prp) +
         d * (prp * p + p * prp);
}

}  // namespace

Matrix6d leftJacobianSE3(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.tail<3>();
  const Eigen::Matrix3d jl = leftJacobianSO3(phi);
  Matrix6d j = Matrix6d::Zero();
  j.topLeftCorner<3, 3>() = jl;
  j.bottomRightCorner<3, 3>() = jl;
  j.topRightCorner<3, 3>() = leftJacobianCoupling(rho, phi);
  return j;
}

Matrix6d rightJacobianSE3(const Vector6d& xi) { return leftJacobianSE3(-xi); }

}  // namespace graphslam::geometry
