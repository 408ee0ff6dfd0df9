// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::types_slam2d {

/// t2v(Z^-1 (A^-1 B)) = [R_z^T (R_a^T (t_b - t_a) - t_z); wrap(theta_b - theta_a - theta_z)]:
/// how far the pose of b seen from a is from the measurement z (g2o's convention for
/// relative poses, EDGE_SE2 and EDGE_SE2_OFFSET).
[[nodiscard]] inline Eigen::Vector3d relativePoseError(const SE2& z, const SE2& a, const SE2& b) {
  const Eigen::Vector2d d = a.rotation().transpose() * (b.translation() - a.translation());
  Eigen::Vector3d e;
  e.head<2>() = z.rotation().transpose() * (d - z.translation());
  e[2] = normalizeAngle(b.angle() - a.angle() - z.angle());
  return e;
}

/// Relative pose measurement z = X_i^-1 X_j between two poses — `.g2o` tag EDGE_SE2
/// (measurement dx dy dtheta, then the upper triangle of the 3x3 information).
/// Error (g2o's convention): e = relativePoseError(Z, X_i, X_j) = t2v(Z^-1 (X_i^-1 X_j)) =
///   [R_z^T (R_i^T (t_j - t_i) - t_z); wrap(theta_j - theta_i - theta_z)].
/// Analytic Jacobians w.r.t. VertexSE2's update.
class EdgeSE2 final : public BaseBinaryEdge<3, SE2, VertexSE2, VertexSE2> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE2& xi, const SE2& xj) const override {
    return relativePoseError(measurement(), xi, xj);
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
