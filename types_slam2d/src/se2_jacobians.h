// SPDX-License-Identifier: MIT
// Jacobians shared by the slam2d edges, w.r.t. VertexSE2's update (x + dx, y + dy,
// theta + dtheta) and VertexXY's (p + d).
#pragma once

#include <Eigen/Core>

#include "graphslam/types_slam2d/se2.h"

namespace graphslam::types_slam2d::detail {

/// d(X^-1 l)/d(update of X) = [-R^T, dR^T/dtheta (l - t)]; w.r.t. l it is R^T.
[[nodiscard]] inline Eigen::Matrix<double, 2, 3> pointInPoseJacobian(const SE2& x,
                                                                     const Eigen::Vector2d& l) {
  Eigen::Matrix<double, 2, 3> j;
  j.leftCols<2>() = -x.rotation().transpose();
  j.col(2) = x.rotationTransposedDerivative() * (l - x.translation());
  return j;
}

/// The Jacobians of X^-1 l w.r.t. the updates of X and l.
inline void pointInPoseJacobians(const SE2& x, const Eigen::Vector2d& l,
                                 Eigen::Matrix<double, 2, 3>& j_x, Eigen::Matrix2d& j_l) {
  j_x = pointInPoseJacobian(x, l);
  j_l = x.rotation().transpose();
}

/// d(X O)/d(update of X) for a constant O with translation t_o: X O = (t + R t_o,
/// theta + theta_o), so [[I, dR/dtheta t_o], [0, 1]].
[[nodiscard]] inline Eigen::Matrix3d composedPoseJacobian(const SE2& x,
                                                          const Eigen::Vector2d& t_o) {
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j.block<2, 1>(0, 2) = x.rotation() * Eigen::Vector2d(-t_o.y(), t_o.x());
  return j;
}

/// d(X C)/d(update of C) for a constant X: [[R, 0], [0, 1]].
[[nodiscard]] inline Eigen::Matrix3d composedOffsetJacobian(const SE2& x) {
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j.topLeftCorner<2, 2>() = x.rotation();
  return j;
}

/// Jacobians of relativePoseError(z, a, b) w.r.t. the updates of a and b.
inline void relativePoseJacobians(const SE2& z, const SE2& a, const SE2& b, Eigen::Matrix3d& j_a,
                                  Eigen::Matrix3d& j_b) {
  const Eigen::Matrix2d rzt = z.rotation().transpose();
  const Eigen::Matrix2d rat = a.rotation().transpose();
  j_a.setZero();
  j_b.setZero();
  j_a.topLeftCorner<2, 2>() = -rzt * rat;
  j_a.block<2, 1>(0, 2) =
      rzt * a.rotationTransposedDerivative() * (b.translation() - a.translation());
  j_a(2, 2) = -1.0;
  j_b.topLeftCorner<2, 2>() = rzt * rat;
  j_b(2, 2) = 1.0;
}

}  // namespace graphslam::types_slam2d::detail
