// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace graphslam::geometry {

/// The skew-symmetric matrix [w]x with [w]x v = w x v.
[[nodiscard]] inline Eigen::Matrix3d hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}

/// The vector w of a skew-symmetric matrix [w]x (its skew part, for any matrix).
[[nodiscard]] inline Eigen::Vector3d vee(const Eigen::Matrix3d& m) {
  return {0.5 * (m(2, 1) - m(1, 2)), 0.5 * (m(0, 2) - m(2, 0)), 0.5 * (m(1, 0) - m(0, 1))};
}

/// The unit quaternion of `q` with a non-negative scalar part (the same rotation): the
/// representative whose vector part is g2o's "compact quaternion".
[[nodiscard]] inline Eigen::Quaterniond positiveScalar(const Eigen::Quaterniond& q) {
  return q.w() < 0.0 ? Eigen::Quaterniond(-q.w(), -q.x(), -q.y(), -q.z()) : q;
}

/// Rotations in 3D: a unit quaternion (Hamilton convention, as Eigen's), with the
/// exponential map on the rotation vector (axis times angle). exp and log are exact to
/// rounding near the identity (series) and near pi (log uses atan2 of the half angle).
class SO3 {
 public:
  SO3() = default;
  /// Normalises `q` (any non-zero quaternion).
  explicit SO3(const Eigen::Quaterniond& q) : q_(q.normalized()) {}
  /// From a rotation matrix (assumed orthonormal; the quaternion is normalised).
  static SO3 fromMatrix(const Eigen::Matrix3d& r) { return SO3(Eigen::Quaterniond(r)); }

  /// Exp: the rotation of angle |w| about w / |w|.
  [[nodiscard]] static SO3 exp(const Eigen::Vector3d& w);
  /// Log: the rotation vector, of norm in [0, pi].
  [[nodiscard]] Eigen::Vector3d log() const;

  [[nodiscard]] const Eigen::Quaterniond& quaternion() const { return q_; }
  [[nodiscard]] Eigen::Matrix3d matrix() const { return q_.toRotationMatrix(); }
  [[nodiscard]] SO3 inverse() const { return fromUnit(q_.conjugate()); }
  [[nodiscard]] SO3 operator*(const SO3& b) const { return fromUnit(q_ * b.q_); }
  [[nodiscard]] Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return q_ * p; }
  /// Ad(R) = R: R Exp(w) R^T = Exp(R w).
  [[nodiscard]] Eigen::Matrix3d adjoint() const { return matrix(); }

  /// Renormalises (products of unit quaternions drift by rounding).
  void normalize() { q_.normalize(); }

  /// Takes `q` as it is: the caller guarantees it is unit (to rounding).
  [[nodiscard]] static SO3 fromUnit(const Eigen::Quaterniond& q) {
    SO3 r;
    r.q_ = q;
    return r;
  }

 private:
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
};

/// The right Jacobian Jr(w): Exp(w + d) = Exp(w) Exp(Jr(w) d) to first order in d.
[[nodiscard]] Eigen::Matrix3d rightJacobianSO3(const Eigen::Vector3d& w);
/// The left Jacobian Jl(w) = Jr(-w): Exp(w + d) = Exp(Jl(w) d) Exp(w).
[[nodiscard]] Eigen::Matrix3d leftJacobianSO3(const Eigen::Vector3d& w);
/// Jr(w)^-1 (defined for |w| < 2 pi).
[[nodiscard]] Eigen::Matrix3d rightJacobianInverseSO3(const Eigen::Vector3d& w);
/// Jl(w)^-1 = Jr(-w)^-1.
[[nodiscard]] Eigen::Matrix3d leftJacobianInverseSO3(const Eigen::Vector3d& w);

/// d(vec(q))/d(w) of the unit quaternion q (scalar part >= 0) of R Exp(w) at w = 0:
/// (q_w I + [q_vec]x) / 2. The derivative of g2o's compact-quaternion error under a
/// right-multiplied rotation increment.
[[nodiscard]] inline Eigen::Matrix3d compactQuaternionRightDerivative(const Eigen::Quaterniond& q) {
  Eigen::Matrix3d d = hat(q.vec());
  d.diagonal().array() += q.w();
  return 0.5 * d;
}

}  // namespace graphslam::geometry
