// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "graphslam/core/base_vertex.h"

namespace graphslam::types_drivebot {

/// Landmark position (x, y) in the world frame [m] — `.g2o` tag VERTEX_LANDMARK, line
/// `VERTEX_LANDMARK id x y`. Update: l (+) d = l + d.
class VertexLandmark final : public BaseVertex<2, Eigen::Vector2d> {
 public:
  VertexLandmark() { setEstimate(Eigen::Vector2d::Zero()); }
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

}  // namespace graphslam::types_drivebot
