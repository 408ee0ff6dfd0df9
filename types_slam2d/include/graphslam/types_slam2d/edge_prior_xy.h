// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

/// Absolute position prior on a point — `.g2o` tag EDGE_PRIOR_XY (g2o's tag and format:
/// measurement x y, then the upper triangle of the 2x2 information).
/// Error: e = x - z. Analytic Jacobian (I) w.r.t. VertexXY's additive update.
class EdgePriorXY final : public BaseUnaryEdge<2, Eigen::Vector2d, VertexXY> {
 public:
  EdgePriorXY() { setMeasurement(Eigen::Vector2d::Zero()); }
  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector2d& x) const override {
    return x - measurement();
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
