// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::types_slam2d {

/// Relative pose measurement z = X_i^-1 X_j between two poses — `.g2o` tag EDGE_SE2
/// (measurement dx dy dtheta, then the upper triangle of the 3x3 information).
/// Error (g2o's convention): e = t2v(Z^-1 (X_i^-1 X_j)) =
///   [R_z^T (R_i^T (t_j - t_i) - t_z); wrap(theta_j - theta_i - theta_z)].
/// Analytic Jacobians w.r.t. VertexSE2's update.
class EdgeSE2 final : public BaseBinaryEdge<3, SE2, VertexSE2, VertexSE2> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE2& xi, const SE2& xj) const override {
    const SE2& z = measurement();
    const Eigen::Vector2d d = xi.rotation().transpose() * (xj.translation() - xi.translation());
    ErrorVector e;
    e.head<2>() = z.rotation().transpose() * (d - z.translation());
    e[2] = normalizeAngle(xj.angle() - xi.angle() - z.angle());
    return e;
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
