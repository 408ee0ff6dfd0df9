// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

/// Landmark l observed in the frame of pose X — `.g2o` tag EDGE_SE2_XY (measurement px py,
/// then the upper triangle of the 2x2 information).
/// Error: e = R^T (l - t) - z. Analytic Jacobians.
class EdgeSE2XY final : public BaseBinaryEdge<2, Eigen::Vector2d, VertexSE2, VertexXY> {
 public:
  EdgeSE2XY() { setMeasurement(Eigen::Vector2d::Zero()); }
  [[nodiscard]] ErrorVector evaluate(const SE2& x, const Eigen::Vector2d& l) const override {
    return x.inverseTimes(l) - measurement();
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
