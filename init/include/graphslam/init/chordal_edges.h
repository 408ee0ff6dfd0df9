// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam3d/vertex_se3.h"

namespace graphslam::init {

/// SE-Sync's term of one SE(2) measurement (R~, t~):
///   kappa |R_j - R_i R~|_F^2 + tau |t_j - t_i - R_i t~|^2,
/// as the residual (vec(R_j - R_i R~), t_j - t_i - R_i t~) (column-major vec) with the
/// information diag(kappa x4, tau x2). Measurement: (x, y, theta) of R~, t~.
class EdgeSE2Chordal final
    : public BaseBinaryEdge<6, Eigen::Vector3d, types_slam2d::VertexSE2, types_slam2d::VertexSE2> {
 public:
  [[nodiscard]] ErrorVector evaluate(const types_slam2d::SE2& xi,
                                     const types_slam2d::SE2& xj) const override;
  void linearizeOplus() override;
  /// Sets the information diag(kappa x4, tau x2).
  void setWeights(double kappa, double tau);
};

/// SE-Sync's term of one SE(3) measurement, as EdgeSE2Chordal in 3D: residual
/// (vec(R_j - R_i R~) (9), t_j - t_i - R_i t~ (3)), information diag(kappa x9, tau x3).
/// Measurement: R~ column-major (9), then t~ (3).
class EdgeSE3Chordal final
    : public BaseBinaryEdge<12, Eigen::Matrix<double, 12, 1>, types_slam3d::VertexSE3,
                            types_slam3d::VertexSE3> {
 public:
  [[nodiscard]] ErrorVector evaluate(const geometry::SE3& xi,
                                     const geometry::SE3& xj) const override;
  void linearizeOplus() override;
  void setWeights(double kappa, double tau);
};

}  // namespace graphslam::init
