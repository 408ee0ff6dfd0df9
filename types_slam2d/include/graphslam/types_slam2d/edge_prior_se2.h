// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::types_slam2d {

/// Absolute pose prior on one pose — `.g2o` tag EDGE_PRIOR_SE2 (measurement x y theta,
/// then the upper triangle of the 3x3 information).
/// Error (g2o's convention): e = t2v(Z^-1 X) = [R_z^T (t - t_z); wrap(theta - theta_z)].
/// Analytic Jacobian.
class EdgePriorSE2 final : public BaseUnaryEdge<3, SE2, VertexSE2> {
 public:
  [[nodiscard]] ErrorVector evaluate(const SE2& x) const override {
    const SE2& z = measurement();
    ErrorVector e;
    e.head<2>() = z.rotation().transpose() * (x.translation() - z.translation());
    e[2] = normalizeAngle(x.angle() - z.angle());
    return e;
  }
  void linearizeOplus() override;
};

}  // namespace graphslam::types_slam2d
