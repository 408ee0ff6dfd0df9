// SPDX-License-Identifier: MIT
#include "graphslam/geometry/so3.h"

#include <cmath>

namespace graphslam::geometry {

namespace {

/// Below this angle the closed forms lose digits (cancellation in 1 - cos, theta - sin):
/// the series to theta^4 are used instead; their truncation error (theta^6 / 7!) is
/// far below rounding there.
constexpr double kSeriesAngle = 1e-3;

/// The coefficients of [w]x and [w]x^2 in the SO(3) Jacobians: (1 - cos t) / t^2 and
/// (t - sin t) / t^3.
void jacobianCoefficients(double theta, double& a, double& b) {
  const double t2 = theta * theta;
  if (theta < kSeriesAngle) {
    a = 0.5 - t2 / 24.0 + t2 * t2 / 720.0;
    b = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0;
  } else {
    const double s = std::sin(0.5 * theta);
    a = 2.0 * s * s / t2;  // 1 - cos t = 2 sin^2(t / 2), without cancellation
    b = (theta - std::sin(theta)) / (t2 * theta);
  }
}

/// The coefficient of [w]x^2 in the inverse Jacobians: 1/t^2 - (1 + cos t) / (2 t sin t).
double inverseCoefficient(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesAngle) return 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0;
  // (1 + cos t) / sin t = cot(t / 2): the half angle keeps digits near pi, where 1 + cos t
  // cancels.
  const double half = 0.5 * theta;
  return 1.0 / t2 - std::cos(half) / (2.0 * theta * std::sin(half));
}

}  // namespace

SO3 SO3::exp(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm();
  const double theta = std::sqrt(t2);
  double real = 0.0;
  double imag = 0.0;  // sin(theta / 2) / theta
  if (theta < kSeriesAngle) {
    real = 1.0 - t2 / 8.0 + t2 * t2 / 384.0;
    imag = 0.5 - t2 / 48.0 + t2 * t2 / 3840.0;
  } else {
    real = std::cos(0.5 * theta);
    imag = std::sin(0.5 * theta) / theta;
  }
  return fromUnit(Eigen::Quaterniond(real, imag * w.x(), imag * w.y(), imag * w.z()));
}

Eigen::Vector3d SO3::log() const {
  const Eigen::Quaterniond q = positiveScalar(q_);
  const double n = q.vec().norm();
  // theta = 2 atan2(n, w): exact near pi (w -> 0), where acos(w) would lose digits.
  double scale = 0.0;  // theta / n
  if (n < kSeriesAngle * 1e-3) {
    // atan(x) / x = 1 - x^2 / 3 with x = n / w; w is close to 1 here.
    const double x2 = (n * n) / (q.w() * q.w());
    scale = 2.0 / q.w() * (1.0 - x2 / 3.0);
  } else {
    scale = 2.0 * std::atan2(n, q.w()) / n;
  }
  return scale * q.vec();
}

Eigen::Matrix3d rightJacobianSO3(const Eigen::Vector3d& w) { return leftJacobianSO3(-w); }

Eigen::Matrix3d leftJacobianSO3(const Eigen::Vector3d& w) {
  double a = 0.0, b = 0.0;
  jacobianCoefficients(w.norm(), a, b);
  const Eigen::Matrix3d k = hat(w);
  return Eigen::Matrix3d::Identity() + a * k + b * k * k;
}

Eigen::Matrix3d rightJacobianInverseSO3(const Eigen::Vector3d& w) {
  return leftJacobianInverseSO3(-w);
}

Eigen::Matrix3d leftJacobianInverseSO3(const Eigen::Vector3d& w) {
  const Eigen::Matrix3d k = hat(w);
  return Eigen::Matrix3d::Identity() - 0.5 * k + inverseCoefficient(w.norm()) * k * k;
}

}  // namespace graphslam::geometry
