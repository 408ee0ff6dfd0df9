// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

namespace graphslam::types_drivebot {

/// Process model between consecutive vehicle states x_k, x_{k+1} — `.g2o` tag
/// EDGE_VEHICLE_KINEMATICS, line `EDGE_VEHICLE_KINEMATICS k k+1 u_s u_l u_w dT info(6)`.
///
/// Model: x_{k+1} = x_k + dT M(psi_k) (u + v), M(psi) = [[c, -s, 0], [s, c, 0], [0, 0, 1]],
/// with the measurement u = (speed [m/s], lateral speed [m/s], yaw rate [rad/s]) in the
/// platform frame of x_k and the time step dT [s] (a parameter of the edge). Error, in
/// the units of u (so the information is inv(Q) of the odometry noise):
///   e_12 = R(psi_k)^T (p_{k+1} - p_k) / dT - u_12,
///   e_3  = wrap(psi_{k+1} - psi_k - dT u_3) / dT.
/// e_3 wraps the heading change before dividing by dT (it is an angle then); it equals the
/// coursework's wrap(psi_{k+1} - psi_k) / dT - u_3 whenever |dT u_3| is small, and stays
/// continuous across +-pi. Analytic Jacobians (all divided by dT, dp = p_{k+1} - p_k):
///   J_k = [[-c, -s, -s dp_x + c dp_y], [s, -c, -c dp_x - s dp_y], [0, 0, -1]],
///   J_{k+1} = M(psi_k)^T.
class EdgeVehicleKinematics final
    : public BaseBinaryEdge<3, Eigen::Vector3d, VertexVehicle, VertexVehicle> {
 public:
  EdgeVehicleKinematics() { setMeasurement(Eigen::Vector3d::Zero()); }

  /// Time step dT [s] between the two states; default 0.1 (the DriveBot simulator's step).
  [[nodiscard]] double deltaT() const { return delta_t_; }
  /// Throws graphslam::Error unless dT is finite and positive.
  void setDeltaT(double delta_t);

  [[nodiscard]] ErrorVector evaluate(const Eigen::Vector3d& xk,
                                     const Eigen::Vector3d& xk1) const override;
  void linearizeOplus() override;

  /// The process model without noise: x_k + dT M(psi_k) u, heading wrapped.
  [[nodiscard]] static Eigen::Vector3d predict(const Eigen::Vector3d& xk, const Eigen::Vector3d& u,
                                               double delta_t);
  /// Sets the second vertex's estimate to predict(x_k, measurement(), deltaT()) — the
  /// prediction step of the DriveBot SLAM system (the coursework's edge.initialize()).
  /// The edge must be in a graph; throws graphslam::Error otherwise.
  void initializeSecond();

  [[nodiscard]] int parameterDataDimension() const override { return 1; }
  void getParameterData(double* data) const override { data[0] = delta_t_; }
  void setParameterData(const double* data) override { setDeltaT(data[0]); }

 private:
  double delta_t_ = 0.1;
};

}  // namespace graphslam::types_drivebot
