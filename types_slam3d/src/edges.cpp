// SPDX-License-Identifier: MIT
// Analytic Jacobians of the 3D edges, with respect to the vertices' right-multiplied
// increments (VertexSE3: X * (Exp(d_rot), d_trans)).
#include "graphslam/types_slam3d/edges.h"

namespace graphslam::types_slam3d {

namespace {

using geometry::hat;
using geometry::Matrix6d;

/// d compact(E delta) / d delta at delta = 0 (E's own right increment):
/// [R_E, 0; 0, (q_w I + [q_vec]x) / 2], q the quaternion of E with q_w >= 0.
Matrix6d rightIncrementJacobian(const SE3& e) {
  Matrix6d j = Matrix6d::Zero();
  j.topLeftCorner<3, 3>() = e.rotation();
  j.bottomRightCorner<3, 3>() =
      geometry::compactQuaternionRightDerivative(geometry::positiveScalar(e.quaternion()));
  return j;
}

/// For E = Z^-1 X_i^-1 X_j: d compact(E) / d delta_i, the right increment of X_i.
/// E' = (Z^-1 delta^-1 Z) E, and Z^-1 delta^-1 Z moves E's translation by
/// R_Z^T ([t_Z]x d_rot - d_trans) and rotates it on the left by Exp(-R_Z^T d_rot).
Matrix6d firstPoseJacobian(const SE3& z, const SE3& e) {
  const Eigen::Matrix3d rzt = z.rotation().transpose();
  Matrix6d j = Matrix6d::Zero();
  j.topLeftCorner<3, 3>() = -rzt;
  j.topRightCorner<3, 3>() = hat(e.translation()) * rzt + rzt * hat(z.translation());
  j.bottomRightCorner<3, 3>() =
      -geometry::compactQuaternionRightDerivative(geometry::positiveScalar(e.quaternion())) *
      e.rotation().transpose() * rzt;
  return j;
}

/// The increment of X P caused by the increment delta of X: P^-1 delta P, to first order
/// (R_P^T d_trans - R_P^T [t_P]x d_rot, R_P^T d_rot).
Matrix6d offsetIncrementMap(const SE3& p) {
  const Eigen::Matrix3d rpt = p.rotation().transpose();
  Matrix6d m = Matrix6d::Zero();
  m.topLeftCorner<3, 3>() = rpt;
  m.topRightCorner<3, 3>() = -rpt * hat(p.translation());
  m.bottomRightCorner<3, 3>() = rpt;
  return m;
}

}  // namespace

void EdgeSE3::linearizeOplus() {
  const SE3& xi = vertexXi<0>().estimate();
  const SE3& xj = vertexXi<1>().estimate();
  const SE3 e = measurement().inverse() * (xi.inverse() * xj);
  jacobian<0>() = firstPoseJacobian(measurement(), e);
  jacobian<1>() = rightIncrementJacobian(e);
}

void EdgeSE3Offset::linearizeOplus() {
  // E = (P_i Z)^-1 X_i^-1 (X_j P_j): EdgeSE3's form with measurement P_i Z and second
  // pose X_j P_j.
  const SE3& xi = vertexXi<0>().estimate();
  const SE3& xj = vertexXi<1>().estimate();
  const SE3& pj = typedParameter<1>().offset();
  const SE3 z = typedParameter<0>().offset() * measurement();
  const SE3 e = z.inverse() * (xi.inverse() * (xj * pj));
  jacobian<0>() = firstPoseJacobian(z, e);
  jacobian<1>() = rightIncrementJacobian(e) * offsetIncrementMap(pj);
}

void EdgeSE3Prior::linearizeOplus() {
  const SE3& p = typedParameter<0>().offset();
  const SE3 e = measurement().inverse() * (vertexXi<0>().estimate() * p);
  jacobian<0>() = rightIncrementJacobian(e) * offsetIncrementMap(p);
}

void EdgeSE3XYZPrior::linearizeOplus() {
  auto& j = jacobian<0>();
  j.setZero();
  j.leftCols<3>() = vertexXi<0>().estimate().rotation();
}

void EdgeSE3PointXYZ::linearizeOplus() {
  // e = R_P^T (y - t_P) - z with y = X^-1 p; X's increment moves y by [y]x d_rot - d_trans.
  const SE3& x = vertexXi<0>().estimate();
  const Eigen::Matrix3d rpt = typedParameter<0>().offset().rotation().transpose();
  const Eigen::Matrix3d rxt = x.rotation().transpose();
  const Eigen::Vector3d y = rxt * (vertexXi<1>().estimate() - x.translation());
  auto& jx = jacobian<0>();
  jx.leftCols<3>() = -rpt;
  jx.rightCols<3>() = rpt * hat(y);
  jacobian<1>() = rpt * rxt;
}

void EdgePointXYZ::linearizeOplus() {
  jacobian<0>() = -Eigen::Matrix3d::Identity();
  jacobian<1>() = Eigen::Matrix3d::Identity();
}

void EdgeXYZPrior::linearizeOplus() { jacobian<0>().setIdentity(); }

}  // namespace graphslam::types_slam3d
