// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/base_vertex.h"
#include "graphslam/types_slam2d/se2.h"

namespace graphslam::types_slam2d {

/// 2D robot pose (x, y, theta) — `.g2o` tag VERTEX_SE2.
/// Update as in g2o: x (+) d = (x + dx, y + dy, theta + dtheta), translation in the world
/// frame, angle wrapped.
class VertexSE2 final : public BaseVertex<3, SE2> {
 public:
  [[nodiscard]] SE2 plus(const SE2& x, const TangentVector& d) const override {
    return SE2(x.translation() + d.head<2>(), x.angle() + d[2]);
  }
  bool minusEstimate(const SE2& x, const SE2& from, TangentVector& d) const override {
    d << x.translation() - from.translation(), normalizeAngle(x.angle() - from.angle());
    return true;
  }
};

}  // namespace graphslam::types_slam2d
