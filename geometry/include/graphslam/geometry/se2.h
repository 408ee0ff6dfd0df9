// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace graphslam::geometry {

// SO(2) is the angle itself: normalizeAngle wraps it, rotation2 is its matrix; Exp and Log
// are the identity on [-pi, pi).

/// Wraps an angle to [-pi, pi).
[[nodiscard]] inline double normalizeAngle(double a) {
  constexpr double kPi = 3.14159265358979323846;
  if (a >= -kPi && a < kPi) return a;
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a - kPi;
}

/// 2D rotation matrix of angle `theta`.
[[nodiscard]] inline Eigen::Matrix2d rotation2(double theta) {
  const double c = std::cos(theta);
  const double s = std::sin(theta);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

/// Rigid 2D transform a_T_b: maps points of frame b into frame a, p_a = R p_b + t.
/// Stored as translation and angle (kept in [-pi, pi)), with the angle's cosine and sine
/// computed once (edges ask for the rotation several times per iteration).
/// Tangent vectors are ordered (translation rho, angle theta), as g2o's SE(2) errors:
/// exp(rho, theta) = (V(theta) rho, theta), exact to rounding near 0 (series) and at +-pi.
class SE2 {
 public:
  SE2() = default;
  SE2(double x, double y, double theta) : SE2(Eigen::Vector2d(x, y), theta) {}
  SE2(const Eigen::Vector2d& t, double theta)
      : t_(t), theta_(normalizeAngle(theta)), c_(std::cos(theta_)), s_(std::sin(theta_)) {}
  /// From (x, y, theta).
  static SE2 fromVector(const Eigen::Vector3d& v) { return SE2(v[0], v[1], v[2]); }

  [[nodiscard]] const Eigen::Vector2d& translation() const { return t_; }
  [[nodiscard]] double angle() const { return theta_; }
  [[nodiscard]] Eigen::Matrix2d rotation() const {
    Eigen::Matrix2d r;
    r << c_, -s_, s_, c_;
    return r;
  }
  /// d(R^T)/d(theta).
  [[nodiscard]] Eigen::Matrix2d rotationTransposedDerivative() const {
    Eigen::Matrix2d d;
    d << -s_, c_, -c_, -s_;
    return d;
  }
  /// (x, y, theta): g2o's t2v.
  [[nodiscard]] Eigen::Vector3d toVector() const { return {t_.x(), t_.y(), theta_}; }

  [[nodiscard]] SE2 operator*(const SE2& b) const {
    return SE2(t_ + rotation() * b.t_, theta_ + b.theta_);
  }
  [[nodiscard]] Eigen::Vector2d operator*(const Eigen::Vector2d& p) const {
    return t_ + rotation() * p;
  }
  /// this^-1 * p = R^T (p - t): a point of the outer frame in this frame.
  [[nodiscard]] Eigen::Vector2d inverseTimes(const Eigen::Vector2d& p) const {
    return rotation().transpose() * (p - t_);
  }
  [[nodiscard]] SE2 inverse() const {
    const Eigen::Matrix2d rt = rotation().transpose();
    return SE2(-(rt * t_), -theta_);
  }
  [[nodiscard]] static SE2 exp(const Eigen::Vector3d& xi);
  /// The tangent vector of this transform, angle in [-pi, pi).
  [[nodiscard]] Eigen::Vector3d log() const;
  /// Ad(X): X exp(xi) X^-1 = exp(Ad(X) xi).
  [[nodiscard]] Eigen::Matrix3d adjoint() const;

  /// Homogeneous 3x3 matrix.
  [[nodiscard]] Eigen::Matrix3d matrix() const {
    Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
    m.topLeftCorner<2, 2>() = rotation();
    m.topRightCorner<2, 1>() = t_;
    return m;
  }

 private:
  Eigen::Vector2d t_ = Eigen::Vector2d::Zero();
  double theta_ = 0.0;
  double c_ = 1.0;
  double s_ = 0.0;
};

/// The right Jacobian Jr(xi): exp(xi + d) = exp(xi) exp(Jr(xi) d) to first order in d.
[[nodiscard]] Eigen::Matrix3d rightJacobianSE2(const Eigen::Vector3d& xi);
/// The left Jacobian Jl(xi) = Jr(-xi): exp(xi + d) = exp(Jl(xi) d) exp(xi).
[[nodiscard]] Eigen::Matrix3d leftJacobianSE2(const Eigen::Vector3d& xi);

}  // namespace graphslam::geometry
