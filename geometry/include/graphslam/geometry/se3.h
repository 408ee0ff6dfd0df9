// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "graphslam/geometry/so3.h"

namespace graphslam::geometry {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector7d = Eigen::Matrix<double, 7, 1>;

/// Rigid 3D transform a_T_b (p_a = R p_b + t): a rotation and a translation.
/// Tangent vectors are ordered (translation rho, rotation phi), as g2o's errors and
/// information matrices: exp(rho, phi) = (Exp(phi), Jl(phi) rho).
class SE3 {
 public:
  SE3() = default;
  SE3(const SO3& r, const Eigen::Vector3d& t) : r_(r), t_(t) {}
  /// Normalises `q`.
  SE3(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) : r_(q), t_(t) {}

  /// From (x, y, z, qx, qy, qz, qw), the quaternion normalised (a `.g2o` line's layout).
  [[nodiscard]] static SE3 fromVectorQT(const Vector7d& v);
  /// (x, y, z, qx, qy, qz, qw) with the stored (unit) quaternion.
  [[nodiscard]] Vector7d toVectorQT() const;
  /// (x, y, z, qx, qy, qz) with qw >= 0: g2o's error vector of a transform.
  [[nodiscard]] Vector6d toCompactVector() const;

  [[nodiscard]] static SE3 exp(const Vector6d& xi);
  [[nodiscard]] Vector6d log() const;

  [[nodiscard]] const SO3& so3() const { return r_; }
  [[nodiscard]] const Eigen::Quaterniond& quaternion() const { return r_.quaternion(); }
  [[nodiscard]] Eigen::Matrix3d rotation() const { return r_.matrix(); }
  [[nodiscard]] const Eigen::Vector3d& translation() const { return t_; }
  [[nodiscard]] Eigen::Isometry3d isometry() const;

  [[nodiscard]] SE3 inverse() const {
    const SO3 ri = r_.inverse();
    return {ri, -(ri * t_)};
  }
  [[nodiscard]] SE3 operator*(const SE3& b) const { return {r_ * b.r_, t_ + r_ * b.t_}; }
  [[nodiscard]] Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return t_ + r_ * p; }
  /// Ad(T) = [R, [t]x R; 0, R]: T exp(xi) T^-1 = exp(Ad(T) xi).
  [[nodiscard]] Matrix6d adjoint() const;

  void normalize() { r_.normalize(); }

 private:
  SO3 r_;
  Eigen::Vector3d t_ = Eigen::Vector3d::Zero();
};

/// Left Jacobian of SE(3): exp(xi + d) = exp(Jl(xi) d) exp(xi) to first order.
[[nodiscard]] Matrix6d leftJacobianSE3(const Vector6d& xi);
/// Right Jacobian of SE(3) = Jl(-xi): exp(xi + d) = exp(xi) exp(Jr(xi) d).
[[nodiscard]] Matrix6d rightJacobianSE3(const Vector6d& xi);

}  // namespace graphslam::geometry
