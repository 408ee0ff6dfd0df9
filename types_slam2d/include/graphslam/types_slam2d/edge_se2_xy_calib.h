// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

/// Landmark l observed by a sensor whose pose C on the robot is estimated with the map —
/// `.g2o` tag EDGE_SE2_XY_CALIB (g2o's layout: `EDGE_SE2_XY_CALIB pose point calibration px
/// py`, then the upper triangle of the 2x2 information; the calibration is a VERTEX_SE2,
/// robot_T_sensor, usually shared by all the observations of one sensor).
/// Error (g2o's convention): e = (X C)^-1 l - z, the landmark in the sensor's frame.
/// Analytic Jacobians w.r.t. the vertices' updates (g2o's type differentiates numerically).
class EdgeSE2XYCalib final : public FixedEdge<2, Eigen::Vector2d, VertexSE2, VertexXY, VertexSE2> {
 public:
  EdgeSE2XYCalib() { setMeasurement(Eigen::Vector2d::Zero()); }
  [[nodiscard]] ErrorVector evaluate(const SE2& x, const Eigen::Vector2d& l,
                                     const SE2& c) const override {
    return (x * c).inverseTimes(l) - measurement();
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
