// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_drivebot/vertex_landmark.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

namespace graphslam::types_drivebot {

/// Range and bearing of a landmark seen from the vehicle — `.g2o` tag
/// EDGE_LANDMARK_RANGE_BEARING, line `EDGE_LANDMARK_RANGE_BEARING vehicle landmark r b info(3)`.
/// Measurement z = (range [m], bearing [rad] relative to the heading). With d = l - p,
/// r = |d|: error e = [r - z_r; wrap(atan2(d_y, d_x) - psi - z_b)]. Analytic Jacobians
///   J_vehicle  = [[-d_x/r, -d_y/r, 0], [d_y/r^2, -d_x/r^2, -1]],
///   J_landmark = [[d_x/r, d_y/r], [-d_y/r^2, d_x/r^2]].
/// At r = 0 the bearing is undefined: the Jacobians are zero there (the edge then adds no
/// information; a landmark constrained by nothing else makes H singular, reported by id).
class EdgeLandmarkRangeBearing final
    : public BaseBinaryEdge<2, Eigen::Vector2d, VertexVehicle, VertexLandmark> {
 public:
  EdgeLandmarkRangeBearing() { setMeasurement(Eigen::Vector2d::Zero()); }

  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector3d& x,
                                     const Eigen::Vector2d& l) const override;
  void linearizeOplus() override;

  /// Landmark position from a vehicle state and a measurement:
  /// p + r (cos(b + psi), sin(b + psi)).
  [[nodiscard]] static Eigen::Vector2d landmarkFrom(const Eigen::Vector3d& x,
                                                    const Eigen::Vector2d& z);
  /// Sets the landmark's estimate to landmarkFrom(vehicle estimate, measurement()) (the
  /// coursework's edge.initialize() for a newly seen landmark). The edge must be in a
  /// graph; throws graphslam::Error otherwise.
  void initializeLandmark();
};

}  // namespace graphslam::types_drivebot
