// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::types_slam2d {

/// Prior on the position of a pose, its heading free (a GPS fix) — `.g2o` tag
/// EDGE_PRIOR_SE2_XY (g2o's layout: `EDGE_PRIOR_SE2_XY pose x y`, then the upper triangle of
/// the 2x2 information).
/// Error (g2o's convention): e = t - z, in the world frame. Analytic Jacobian [I 0].
class EdgePriorSE2XY final : public BaseUnaryEdge<2, Eigen::Vector2d, VertexSE2> {
 public:
  EdgePriorSE2XY() { setMeasurement(Eigen::Vector2d::Zero()); }
  [[nodiscard]] ErrorVector evaluate(const SE2& x) const override {
    return x.translation() - measurement();
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
