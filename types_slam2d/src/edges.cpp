// SPDX-License-Identifier: MIT
// Analytic Jacobians of the slam2d edges (all w.r.t. VertexSE2's and VertexXY's updates).
#include "graphslam/types_slam2d/edge_bearing_se2_xy.h"
#include "graphslam/types_slam2d/edge_pointxy.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_prior_se2_xy.h"
#include "graphslam/types_slam2d/edge_prior_xy.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_offset.h"
#include "graphslam/types_slam2d/edge_se2_pointxy_offset.h"
#include "graphslam/types_slam2d/edge_se2_twopointsxy.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/edge_se2_xy_calib.h"
#include "graphslam/types_slam2d/edge_xy_bearing_range.h"
#include "se2_jacobians.h"

namespace graphslam::types_slam2d {

void EdgeSE2::linearizeOplus() {
  detail::relativePoseJacobians(measurement(), vertexXi<0>().estimate(), vertexXi<1>().estimate(),
                                jacobian<0>(), jacobian<1>());
}

void EdgeSE2Offset::linearizeOplus() {
  // The error is EdgeSE2's of the sensor poses A = X_i O_i and B = X_j O_j: chain rule.
  const SE2& xi = vertexXi<0>().estimate();
  const SE2& xj = vertexXi<1>().estimate();
  const SE2& oi = typedParameter<0>().offset();
  const SE2& oj = typedParameter<1>().offset();
  Eigen::Matrix3d j_a, j_b;
  detail::relativePoseJacobians(measurement(), xi * oi, xj * oj, j_a, j_b);
  jacobian<0>() = j_a * detail::composedPoseJacobian(xi, oi.translation());
  jacobian<1>() = j_b * detail::composedPoseJacobian(xj, oj.translation());
}

void EdgeSE2XY::linearizeOplus() {
  detail::pointInPoseJacobians(vertexXi<0>().estimate(), vertexXi<1>().estimate(), jacobian<0>(),
                               jacobian<1>());
}

void EdgeSE2PointXYOffset::linearizeOplus() {
  // The offset is not part of the error (see the class): EdgeSE2XY's Jacobians.
  detail::pointInPoseJacobians(vertexXi<0>().estimate(), vertexXi<1>().estimate(), jacobian<0>(),
                               jacobian<1>());
}

void EdgeSE2XYCalib::linearizeOplus() {
  // e = A^-1 l - z with the sensor pose A = X C: chain rule through A.
  const SE2& x = vertexXi<0>().estimate();
  const Eigen::Vector2d& l = vertexXi<1>().estimate();
  const SE2& c = vertexXi<2>().estimate();
  const SE2 a = x * c;
  const Eigen::Matrix<double, 2, 3> j_a = detail::pointInPoseJacobian(a, l);
  jacobian<0>() = j_a * detail::composedPoseJacobian(x, c.translation());
  jacobian<1>() = a.rotation().transpose();
  jacobian<2>() = j_a * detail::composedOffsetJacobian(x);
}

void EdgeSE2TwoPointsXY::linearizeOplus() {
  const SE2& x = vertexXi<0>().estimate();
  const Eigen::Matrix2d rt = x.rotation().transpose();
  auto& jx = jacobian<0>();
  jx.topRows<2>() = detail::pointInPoseJacobian(x, vertexXi<1>().estimate());
  jx.bottomRows<2>() = detail::pointInPoseJacobian(x, vertexXi<2>().estimate());
  jacobian<1>() << rt, Eigen::Matrix2d::Zero();
  jacobian<2>() << Eigen::Matrix2d::Zero(), rt;
}

void EdgeBearingSE2XY::linearizeOplus() {
  // e = wrap(z - atan2(w_y, w_x) + theta) with w = l - t (the bearing in the world frame).
  const SE2& x = vertexXi<0>().estimate();
  const Eigen::Vector2d w = vertexXi<1>().estimate() - x.translation();
  const double q = w.squaredNorm();
  const Eigen::RowVector2d d_atan(-w.y() / q, w.x() / q);  // d atan2(w_y, w_x) / dw
  jacobian<0>() << d_atan, 1.0;
  jacobian<1>() = -d_atan;
}

void EdgePriorSE2::linearizeOplus() {
  auto& j = jacobian<0>();
  j.setZero();
  j.topLeftCorner<2, 2>() = measurement().rotation().transpose();
  j(2, 2) = 1.0;
}

void EdgePriorSE2XY::linearizeOplus() {
  jacobian<0>() << Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero();
}

void EdgePointXY::linearizeOplus() {
  jacobian<0>() = -Eigen::Matrix2d::Identity();
  jacobian<1>() = Eigen::Matrix2d::Identity();
}

void EdgePriorXY::linearizeOplus() { jacobian<0>().setIdentity(); }

void EdgeXYBearingRange::linearizeOplus() {
  const Eigen::Vector2d d = vertexXi<1>().estimate() - vertexXi<0>().estimate();
  const double q = d.squaredNorm();
  const double range = std::sqrt(q);
  // Rows: bearing, range; columns: the landmark's x, y (the robot's are the negatives).
  Eigen::Matrix2d j_l;
  j_l << -d.y() / q, d.x() / q, d.x() / range, d.y() / range;
  jacobian<0>() = -j_l;
  jacobian<1>() = j_l;
}

}  // namespace graphslam::types_slam2d
