// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "graphslam/core/base_vertex.h"
#include "graphslam/types_slam2d/se2.h"

namespace graphslam::types_drivebot {

/// Wraps an angle to [-pi, pi) (a full wrap, any number of turns). The coursework's
/// normalize_theta applies a single +-2 pi correction instead; the two agree for every
/// angle in (-3 pi, 3 pi) except that +pi maps to -pi here.
[[nodiscard]] inline double wrapAngle(double a) { return types_slam2d::normalizeAngle(a); }

/// Vehicle state (x, y, psi) at time `time()`: position of the platform in the world frame
/// [m] and heading [rad] — `.g2o` tag VERTEX_VEHICLE, line `VERTEX_VEHICLE id x y psi time`.
/// Update: x (+) d = (x + dx, y + dy, wrap(psi + dpsi)), with the full wrap of wrapAngle()
/// (the result is always in [-pi, pi), whatever the size of the step).
/// The time [s] is a constant of the problem (a parameter of the `.g2o` line), never
/// estimated.
class VertexVehicle final : public BaseVertex<3, Eigen::Vector3d> {
 public:
  VertexVehicle() { setEstimate(Eigen::Vector3d::Zero()); }

  [[nodiscard]] Eigen::Vector3d plus(const Eigen::Vector3d& x,
                                     const TangentVector& d) const override {
    return {x[0] + d[0], x[1] + d[1], wrapAngle(x[2] + d[2])};
  }
  bool minusEstimate(const Eigen::Vector3d& x, const Eigen::Vector3d& from,
                     TangentVector& d) const override {
    d << x[0] - from[0], x[1] - from[1], wrapAngle(x[2] - from[2]);
    return true;
  }

  [[nodiscard]] double time() const { return time_; }
  void setTime(double time) { time_ = time; }

  [[nodiscard]] int parameterDataDimension() const override { return 1; }
  void getParameterData(double* data) const override { data[0] = time_; }
  void setParameterData(const double* data) override { time_ = data[0]; }

 private:
  double time_ = 0.0;
};

}  // namespace graphslam::types_drivebot
