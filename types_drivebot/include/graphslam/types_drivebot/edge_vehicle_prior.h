// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

namespace graphslam::types_drivebot {

/// Prior on a vehicle state (the DriveBot initial condition with a non-zero covariance) —
/// `.g2o` tag EDGE_VEHICLE_PRIOR, line `EDGE_VEHICLE_PRIOR id x y psi info(6)`.
/// Error: e = x - z with e_3 wrapped. Analytic Jacobian: identity.
class EdgeVehiclePrior final : public BaseUnaryEdge<3, Eigen::Vector3d, VertexVehicle> {
 public:
  EdgeVehiclePrior() { setMeasurement(Eigen::Vector3d::Zero()); }
  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector3d& x) const override {
    ErrorVector e = x - measurement();
    e[2] = wrapAngle(e[2]);
    return e;
  }
  void linearizeOplus() override { jacobian<0>().setIdentity(); }
};

}  // namespace graphslam::types_drivebot
