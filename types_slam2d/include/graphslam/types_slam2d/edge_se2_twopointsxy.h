// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

/// Two landmarks l1, l2 observed together from pose X — `.g2o` tag EDGE_SE2_TWOPOINTSXY
/// (g2o's layout: `EDGE_SE2_TWOPOINTSXY pose point1 point2 p1x p1y p2x p2y`, then the upper
/// triangle of the 4x4 information, which may correlate the two points).
/// Error (g2o's convention): e = [R^T (l1 - t) - z_1; R^T (l2 - t) - z_2].
/// Analytic Jacobians w.r.t. the vertices' updates.
class EdgeSE2TwoPointsXY final
    : public FixedEdge<4, Eigen::Vector4d, VertexSE2, VertexXY, VertexXY> {
 public:
  EdgeSE2TwoPointsXY() { setMeasurement(Eigen::Vector4d::Zero()); }
  [[nodiscard]] ErrorVector evaluate(const SE2& x, const Eigen::Vector2d& l1,
                                     const Eigen::Vector2d& l2) const override {
    ErrorVector e;
    e.head<2>() = x.inverseTimes(l1) - measurement().head<2>();
    e.tail<2>() = x.inverseTimes(l2) - measurement().tail<2>();
    return e;
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
