// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "graphslam/core/base_vertex.h"

namespace graphslam::types_slam2d {

/// 2D point (landmark or point robot position) in the world frame — `.g2o` tag VERTEX_XY.
/// Update: p (+) d = p + d.
class VertexXY final : public BaseVertex<2, Eigen::Vector2d> {
 public:
  VertexXY() { setEstimate(Eigen::Vector2d::Zero()); }
  [[nodiscard]] Eigen::Vector2d plus(const Eigen::Vector2d& x,
                                     const TangentVector& d) const override {
    return x + d;
  }
  bool minusEstimate(const Eigen::Vector2d& x, const Eigen::Vector2d& from,
                     TangentVector& d) const override {
    d = x - from;
    return true;
  }
};

}  // namespace graphslam::types_slam2d
