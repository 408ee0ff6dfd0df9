// SPDX-License-Identifier: MIT
#include "graphslam/types_slam2d/edge_pointxy.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_prior_xy.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/edge_xy_bearing_range.h"

namespace graphslam::types_slam2d {

void EdgeSE2::linearizeOplus() {
  const SE2& xi = vertexXi<0>().estimate();
  const SE2& xj = vertexXi<1>().estimate();
  const Eigen::Matrix2d rzt = measurement().rotation().transpose();
  const Eigen::Matrix2d rit = xi.rotation().transpose();
  const Eigen::Vector2d dt = xj.translation() - xi.translation();
  auto& ji = jacobian<0>();
  auto& jj = jacobian<1>();
  ji.setZero();
  jj.setZero();
  ji.topLeftCorner<2, 2>() = -rzt * rit;
  ji.block<2, 1>(0, 2) = rzt * xi.rotationTransposedDerivative() * dt;
  ji(2, 2) = -1.0;
  jj.topLeftCorner<2, 2>() = rzt * rit;
  jj(2, 2) = 1.0;
}

void EdgeSE2XY::linearizeOplus() {
  const SE2& x = vertexXi<0>().estimate();
  const Eigen::Vector2d& l = vertexXi<1>().estimate();
  const Eigen::Matrix2d rt = x.rotation().transpose();
  auto& jx = jacobian<0>();
  jx.leftCols<2>() = -rt;
  jx.col(2) = x.rotationTransposedDerivative() * (l - x.translation());
  jacobian<1>() = rt;
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
