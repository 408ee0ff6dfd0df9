// SPDX-License-Identifier: MIT
#include <cmath>
#include <string>

#include "graphslam/support/error.h"
#include "graphslam/types_drivebot/edge_compass.h"
#include "graphslam/types_drivebot/edge_gps.h"
#include "graphslam/types_drivebot/edge_landmark_range_bearing.h"
#include "graphslam/types_drivebot/edge_vehicle_kinematics.h"
#include "graphslam/types_drivebot/vertex_landmark.h"

namespace graphslam::types_drivebot {

namespace {
/// Typed writable vertex of an edge in a graph, or an error naming the edge's purpose.
template <typename V>
V& vertexToInitialize(Vertex* v, const char* what) {
  if (!v) throw Error(std::string(what) + ": the edge is not in a graph yet");
  return static_cast<V&>(*v);  // the graph checked the slot's type on insertion
}
}  // namespace

// ---------------------------------------------------------------------------------------
// EdgeVehicleKinematics

void EdgeVehicleKinematics::setDeltaT(double delta_t) {
  if (!(std::isfinite(delta_t) && delta_t > 0.0)) {
    throw Error("vehicle kinematics: time step dT must be positive and finite, got " +
                std::to_string(delta_t));
  }
  delta_t_ = delta_t;
}

EdgeVehicleKinematics::ErrorVector EdgeVehicleKinematics::evaluate(
    const Eigen::Vector3d& xk, const Eigen::Vector3d& xk1) const {
  const double c = std::cos(xk[2]);
  const double s = std::sin(xk[2]);
  const double dx = xk1[0] - xk[0];
  const double dy = xk1[1] - xk[1];
  const Eigen::Vector3d& u = measurement();
  ErrorVector e;
  e[0] = (c * dx + s * dy) / delta_t_ - u[0];
  e[1] = (-s * dx + c * dy) / delta_t_ - u[1];
  e[2] = wrapAngle(xk1[2] - xk[2] - delta_t_ * u[2]) / delta_t_;
  return e;
}

void EdgeVehicleKinematics::linearizeOplus() {
  const Eigen::Vector3d& xk = vertexXi<0>().estimate();
  const Eigen::Vector3d& xk1 = vertexXi<1>().estimate();
  const double c = std::cos(xk[2]);
  const double s = std::sin(xk[2]);
  const double dx = xk1[0] - xk[0];
  const double dy = xk1[1] - xk[1];
  const double k = 1.0 / delta_t_;
  jacobian<0>() << -c * k, -s * k, (-s * dx + c * dy) * k,  //
      s * k, -c * k, (-c * dx - s * dy) * k,                //
      0.0, 0.0, -k;
  jacobian<1>() << c * k, s * k, 0.0,  //
      -s * k, c * k, 0.0,              //
      0.0, 0.0, k;
}

Eigen::Vector3d EdgeVehicleKinematics::predict(const Eigen::Vector3d& xk, const Eigen::Vector3d& u,
                                               double delta_t) {
  const double c = std::cos(xk[2]);
  const double s = std::sin(xk[2]);
  return {xk[0] + delta_t * (c * u[0] - s * u[1]), xk[1] + delta_t * (s * u[0] + c * u[1]),
          wrapAngle(xk[2] + delta_t * u[2])};
}

void EdgeVehicleKinematics::initializeSecond() {
  auto& next = vertexToInitialize<VertexVehicle>(mutableVertex(1), "initializeSecond");
  next.setEstimate(predict(vertexXi<0>().estimate(), measurement(), delta_t_));
}

// ---------------------------------------------------------------------------------------
// EdgeGps

EdgeGps::ErrorVector EdgeGps::evaluate(const Eigen::Vector3d& x) const {
  const double c = std::cos(x[2]);
  const double s = std::sin(x[2]);
  return {x[0] + c * offset_.x() - s * offset_.y() - measurement().x(),
          x[1] + s * offset_.x() + c * offset_.y() - measurement().y()};
}

void EdgeGps::linearizeOplus() {
  const double psi = vertexXi<0>().estimate()[2];
  const double c = std::cos(psi);
  const double s = std::sin(psi);
  jacobian<0>() << 1.0, 0.0, -s * offset_.x() - c * offset_.y(),  //
      0.0, 1.0, c * offset_.x() - s * offset_.y();
}

// ---------------------------------------------------------------------------------------
// EdgeCompass

void EdgeCompass::setParameterData(const double* data) {
  if (data[1] != 0.0 && data[1] != 1.0) {
    throw Error("compass: the wrap flag must be 0 or 1, got " + std::to_string(data[1]));
  }
  offset_ = data[0];
  wrap_error_ = data[1] == 1.0;
}

// ---------------------------------------------------------------------------------------
// EdgeLandmarkRangeBearing

EdgeLandmarkRangeBearing::ErrorVector EdgeLandmarkRangeBearing::evaluate(
    const Eigen::Vector3d& x, const Eigen::Vector2d& l) const {
  const Eigen::Vector2d d = l - x.head<2>();
  return {d.norm() - measurement()[0],
          wrapAngle(std::atan2(d.y(), d.x()) - x[2] - measurement()[1])};
}

void EdgeLandmarkRangeBearing::linearizeOplus() {
  const Eigen::Vector3d& x = vertexXi<0>().estimate();
  const Eigen::Vector2d d = vertexXi<1>().estimate() - x.head<2>();
  const double r2 = d.squaredNorm();
  if (r2 == 0.0) {
    jacobian<0>().setZero();
    jacobian<1>().setZero();
    return;
  }
  const double r = std::sqrt(r2);
  jacobian<0>() << -d.x() / r, -d.y() / r, 0.0,  //
      d.y() / r2, -d.x() / r2, -1.0;
  jacobian<1>() << d.x() / r, d.y() / r,  //
      -d.y() / r2, d.x() / r2;
}

Eigen::Vector2d EdgeLandmarkRangeBearing::landmarkFrom(const Eigen::Vector3d& x,
                                                       const Eigen::Vector2d& z) {
  const double a = z[1] + x[2];
  return {x[0] + z[0] * std::cos(a), x[1] + z[0] * std::sin(a)};
}

void EdgeLandmarkRangeBearing::initializeLandmark() {
  auto& landmark = vertexToInitialize<VertexLandmark>(mutableVertex(1), "initializeLandmark");
  landmark.setEstimate(landmarkFrom(vertexXi<0>().estimate(), measurement()));
}

}  // namespace graphslam::types_drivebot
