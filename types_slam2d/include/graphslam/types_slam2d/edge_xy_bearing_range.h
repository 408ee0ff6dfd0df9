// SPDX-License-Identifier: MIT
#pragma once

#include <cmath>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

/// Global bearing and range from a point robot r to a point landmark l — `.g2o` tag
/// EDGE_XY_BEARING_RANGE (measurement bearing range, then the upper triangle of the 2x2
/// information). The robot has no heading ("always faces +x"), so the bearing is the
/// world-frame direction of d = l - r. This is the observation model of the CMU 16-833
/// nonlinear SLAM homework.
/// Error: e = [wrap(atan2(d_y, d_x) - z_bearing); |d| - z_range], wrap to [-pi, pi) as
/// the homework's warp2pi(a) = a - 2 pi floor((a + pi) / (2 pi)). Analytic Jacobians w.r.t.
/// VertexXY's additive update (undefined when r and l coincide).
class EdgeXYBearingRange final : public BaseBinaryEdge<2, Eigen::Vector2d, VertexXY, VertexXY> {
 public:
  EdgeXYBearingRange() { setMeasurement(Eigen::Vector2d::Zero()); }
  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector2d& r,
                                     const Eigen::Vector2d& l) const override {
    const Eigen::Vector2d d = l - r;
    ErrorVector e;
    e[0] = normalizeAngle(std::atan2(d.y(), d.x()) - measurement()[0]);
    e[1] = d.norm() - measurement()[1];
    return e;
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
