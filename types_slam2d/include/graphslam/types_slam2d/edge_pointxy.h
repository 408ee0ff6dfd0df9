// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

/// Displacement between two points, measured in the world frame — `.g2o` tag EDGE_POINTXY
/// (g2o's tag and format: measurement dx dy, then the upper triangle of the 2x2
/// information). Serves both the odometry of a point robot (pose a -> pose b) and a
/// landmark seen from a point robot (pose a -> landmark b): the two are the same function
/// of the same vertex types, so one type and one tag cover both, as in g2o.
/// Error: e = (x_b - x_a) - z. Analytic Jacobians (-I, I) w.r.t. VertexXY's additive update.
class EdgePointXY final : public BaseBinaryEdge<2, Eigen::Vector2d, VertexXY, VertexXY> {
 public:
  EdgePointXY() { setMeasurement(Eigen::Vector2d::Zero()); }
  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector2d& a,
                                     const Eigen::Vector2d& b) const override {
    return (b - a) - measurement();
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
