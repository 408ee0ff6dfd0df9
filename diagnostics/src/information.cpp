// SPDX-License-Identifier: MIT
#include "graphslam/diagnostics/information.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>

namespace graphslam {

double inverseTraceWeight(const Eigen::MatrixXd& block) {
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(block);
  if (!lu.isInvertible()) return std::nan("");
  const double trace = lu.inverse().trace();
  return std::isfinite(trace) && trace > 0.0 ? static_cast<double>(block.rows()) / trace
                                             : std::nan("");
}

double isotropicWeight(const Eigen::MatrixXd& block) {
  const double w = inverseTraceWeight(block);
  if (std::isfinite(w) && w > 0.0) return w;
  const double mean = block.diagonal().cwiseAbs().mean();
  return mean > 0.0 ? mean : 1.0;
}

bool repairInformation(Eigen::MatrixXd& omega, InformationRepair how, double floor) {
  const Eigen::Index d = omega.rows();
  if (how == InformationRepair::kRefuse) return false;
  if (how == InformationRepair::kNearestPd) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(omega);
    Eigen::VectorXd values = eig.eigenvalues();
    const double largest = values.cwiseAbs().maxCoeff();
    const double lowest = largest > 0.0 ? floor * largest : 1.0;
    values = values.cwiseMax(lowest);
    omega = eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
    omega = 0.5 * (omega + omega.transpose()).eval();
    return true;
  }
  Eigen::Index first = d;  // size of the first block
  if (d == 3) first = 2;
  if (d == 6) first = 3;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(d, d);
  out.topLeftCorner(first, first)
      .diagonal()
      .setConstant(isotropicWeight(omega.topLeftCorner(first, first)));
  if (first < d) {
    out.bottomRightCorner(d - first, d - first)
        .diagonal()
        .setConstant(isotropicWeight(omega.bottomRightCorner(d - first, d - first)));
  }
  omega = out;
  return true;
}

}  // namespace graphslam
