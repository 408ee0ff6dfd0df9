// SPDX-License-Identifier: MIT
// Residuals and analytic Jacobians of SE-Sync's chordal terms, with respect to the poses'
// own updates: VertexSE2 (t + d_t in the world frame, theta + d_theta) and VertexSE3
// (X * (Exp(d_rot), d_trans)).
#include "graphslam/init/chordal_edges.h"

#include "graphslam/types_slam2d/se2.h"

namespace graphslam::init {

namespace {

using geometry::hat;

/// dR(theta)/dtheta = R(theta) J, J = [0 -1; 1 0].
Eigen::Matrix2d quarterTurn() {
  Eigen::Matrix2d j;
  j << 0.0, -1.0, 1.0, 0.0;
  return j;
}

}  // namespace

EdgeSE2Chordal::ErrorVector EdgeSE2Chordal::evaluate(const types_slam2d::SE2& xi,
                                                     const types_slam2d::SE2& xj) const {
  const Eigen::Matrix2d ri = xi.rotation();
  const Eigen::Matrix2d r = xj.rotation() - ri * types_slam2d::rotation2(measurement()[2]);
  ErrorVector e;
  e.head<4>() = Eigen::Map<const Eigen::Vector4d>(r.data());
  e.tail<2>() = xj.translation() - xi.translation() - ri * measurement().head<2>();
  return e;
}

void EdgeSE2Chordal::linearizeOplus() {
  const Eigen::Matrix2d ri = vertexXi<0>().estimate().rotation();
  const Eigen::Matrix2d rj = vertexXi<1>().estimate().rotation();
  const Eigen::Matrix2d j = quarterTurn();
  const Eigen::Matrix2d di = -ri * j * types_slam2d::rotation2(measurement()[2]);
  const Eigen::Matrix2d dj = rj * j;
  auto& ji = jacobian<0>();
  auto& jj = jacobian<1>();
  ji.setZero();
  jj.setZero();
  ji.block<4, 1>(0, 2) = Eigen::Map<const Eigen::Vector4d>(di.data());
  jj.block<4, 1>(0, 2) = Eigen::Map<const Eigen::Vector4d>(dj.data());
  ji.block<2, 2>(4, 0) = -Eigen::Matrix2d::Identity();
  ji.block<2, 1>(4, 2) = -ri * j * measurement().head<2>();
  jj.block<2, 2>(4, 0) = Eigen::Matrix2d::Identity();
}

void EdgeSE2Chordal::setWeights(double kappa, double tau) {
  InformationMatrix omega = InformationMatrix::Zero();
  omega.diagonal() << kappa, kappa, kappa, kappa, tau, tau;
  setInformation(omega);
}

EdgeSE3Chordal::ErrorVector EdgeSE3Chordal::evaluate(const geometry::SE3& xi,
                                                     const geometry::SE3& xj) const {
  const Eigen::Matrix3d ri = xi.rotation();
  const Eigen::Map<const Eigen::Matrix3d> rz(measurement().data());
  const Eigen::Matrix3d r = xj.rotation() - ri * rz;
  ErrorVector e;
  e.head<9>() = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(r.data());
  e.tail<3>() = xj.translation() - xi.translation() - ri * measurement().tail<3>();
  return e;
}

void EdgeSE3Chordal::linearizeOplus() {
  // Column c of R_j Exp(w): d/dw = -R_j [e_c]x; of -R_i Exp(w) R~: d/dw = R_i [R~ e_c]x.
  const Eigen::Matrix3d ri = vertexXi<0>().estimate().rotation();
  const Eigen::Matrix3d rj = vertexXi<1>().estimate().rotation();
  const Eigen::Map<const Eigen::Matrix3d> rz(measurement().data());
  auto& ji = jacobian<0>();
  auto& jj = jacobian<1>();
  ji.setZero();
  jj.setZero();
  for (int c = 0; c < 3; ++c) {
    ji.block<3, 3>(3 * c, 3) = ri * hat(rz.col(c));
    jj.block<3, 3>(3 * c, 3) = -rj * hat(Eigen::Vector3d::Unit(c));
  }
  ji.block<3, 3>(9, 0) = -ri;
  ji.block<3, 3>(9, 3) = ri * hat(measurement().tail<3>());
  jj.block<3, 3>(9, 0) = rj;
}

void EdgeSE3Chordal::setWeights(double kappa, double tau) {
  InformationMatrix omega = InformationMatrix::Zero();
  omega.diagonal().head<9>().setConstant(kappa);
  omega.diagonal().tail<3>().setConstant(tau);
  setInformation(omega);
}

}  // namespace graphslam::init
