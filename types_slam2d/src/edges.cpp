// SPDX-License-Identifier: MIT
// Analytic Jacobians of the slam2d edges (all w.r.t. VertexSE2's and VertexXY's updates).
#include "graphslam/types_slam2d/edge_pointxy.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_prior_xy.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/edge_xy_bearing_range.h"
#include "se2_jacobians.h"

namespace graphslam::types_slam2d {

void EdgeSE2::linearizeOplus() {
  detail::relativePoseJacobians(measurement(), vertexXi<0>().estimate(), vertexXi<1>().estimate(),
                                jacobian<0>(), jacobian<1>());
}

void EdgeSE2XY::linearizeOplus() {
  detail::pointInPoseJacobians(vertexXi<0>().estimate(), vertexXi<1>().estimate(), jacobian<0>(),
                               jacobian<1>());
}

void EdgePriorSE2::linearizeOplus() {
  auto& j = jacobian<0>();
  j.setZero();
  j.topLeftCorner<2, 2>() = measurement().rotation().transpose();
  j(2, 2) = 1.0;
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
