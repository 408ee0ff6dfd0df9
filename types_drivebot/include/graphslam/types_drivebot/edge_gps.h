// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

namespace graphslam::types_drivebot {

/// GPS fix of an antenna mounted at `offset()` in the platform frame — `.g2o` tag EDGE_GPS,
/// line `EDGE_GPS id z_x z_y offset_x offset_y info(3)`.
/// Error: e = p + R(psi) offset - z (world frame, metres). Analytic Jacobian, including
/// the heading column d(R(psi) offset)/d(psi) = (-s o_x - c o_y, c o_x - s o_y).
class EdgeGps final : public BaseUnaryEdge<2, Eigen::Vector2d, VertexVehicle> {
 public:
  EdgeGps() { setMeasurement(Eigen::Vector2d::Zero()); }

  /// Antenna position in the platform frame [m]; default (10, -20), the DriveBot
  /// simulator's gpsPositionOffset.
  [[nodiscard]] const Eigen::Vector2d& offset() const { return offset_; }
  void setOffset(const Eigen::Vector2d& offset) { offset_ = offset; }

  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector3d& x) const override;
  void linearizeOplus() override;

  [[nodiscard]] int parameterDataDimension() const override { return 2; }
  void getParameterData(double* data) const override {
    data[0] = offset_.x();
    data[1] = offset_.y();
  }
  void setParameterData(const double* data) override { offset_ = {data[0], data[1]}; }

 private:
  Eigen::Vector2d offset_{10.0, -20.0};
};

}  // namespace graphslam::types_drivebot
