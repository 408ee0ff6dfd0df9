// SPDX-License-Identifier: MIT
#include "graphslam/geometry/se2.h"

namespace graphslam::geometry {

namespace {
/// Below this |theta| the ratios of sin and cos use their Taylor series to the 8th power
/// (first omitted term below 1e-20 there); above it the direct forms lose at most about
/// eps / theta^2 = 2e-12 relative to cancellation.
constexpr double kSeriesAngle = 1e-2;

/// sin(t)/t, (1 - cos t)/t, (t - sin t)/t^2, (1 - cos t)/t^2 and (t/2) cot(t/2).
struct Ratios {
  double a, b, c, d, h;
  explicit Ratios(double t) {
    if (std::abs(t) < kSeriesAngle) {
      const double t2 = t * t;
      a = 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0)));
      d = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0 * (1.0 - t2 / 90.0)));
      c = t / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0)));
      h = 1.0 - t2 / 12.0 - t2 * t2 / 720.0 - t2 * t2 * t2 / 30240.0;
      b = t * d;
    } else {
      a = std::sin(t) / t;
      b = (1.0 - std::cos(t)) / t;
      c = (t - std::sin(t)) / (t * t);
      d = (1.0 - std::cos(t)) / (t * t);
      h = 0.5 * t * std::cos(0.5 * t) / std::sin(0.5 * t);
    }
  }
};
}  // namespace

SE2 SE2::exp(const Eigen::Vector3d& xi) {
  const Ratios r(xi[2]);
  // V(theta) = [a -b; b a]
  return SE2(Eigen::Vector2d(r.a * xi[0] - r.b * xi[1], r.b * xi[0] + r.a * xi[1]), xi[2]);
}

Eigen::Vector3d SE2::log() const {
  // V^-1 = [h t/2; -t/2 h] with h = (t/2) cot(t/2): the half angle keeps it exact at +-pi,
  // where the cotangent vanishes.
  const double t = theta_;
  const double h = Ratios(t).h;
  return {h * t_.x() + 0.5 * t * t_.y(), -0.5 * t * t_.x() + h * t_.y(), t};
}

Eigen::Matrix3d SE2::adjoint() const {
  Eigen::Matrix3d ad = Eigen::Matrix3d::Identity();
  ad.topLeftCorner<2, 2>() = rotation();
  ad(0, 2) = t_.y();
  ad(1, 2) = -t_.x();
  return ad;
}

Eigen::Matrix3d rightJacobianSE2(const Eigen::Vector3d& xi) {
  const Ratios r(xi[2]);
  const double x = xi[0], y = xi[1];
  Eigen::Matrix3d j;
  j << r.a, r.b, x * r.c - y * r.d,  //
      -r.b, r.a, x * r.d + y * r.c,  //
      0.0, 0.0, 1.0;
  return j;
}

Eigen::Matrix3d leftJacobianSE2(const Eigen::Vector3d& xi) { return rightJacobianSE2(-xi); }

}  // namespace graphslam::geometry
