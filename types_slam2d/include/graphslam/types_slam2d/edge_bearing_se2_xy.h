// SPDX-License-Identifier: MIT
#pragma once

#include <cmath>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

/// Bearing of landmark l seen from pose X, in X's frame — `.g2o` tag EDGE_BEARING_SE2_XY
/// (g2o's layout: `EDGE_BEARING_SE2_XY pose point bearing information`).
/// Error (g2o's convention, measurement minus prediction): with d = R^T (l - t),
///   e = wrap(z - atan2(d_y, d_x)).
/// Analytic Jacobians w.r.t. VertexSE2's and VertexXY's updates (undefined when l = t).
class EdgeBearingSE2XY final : public BaseBinaryEdge<1, double, VertexSE2, VertexXY> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE2& x, const Eigen::Vector2d& l) const override {
    const Eigen::Vector2d d = x.inverseTimes(l);
    return ErrorVector(normalizeAngle(measurement() - std::atan2(d.y(), d.x())));
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
