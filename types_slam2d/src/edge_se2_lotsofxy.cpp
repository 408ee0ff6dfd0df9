// SPDX-License-Identifier: MIT
#include "graphslam/types_slam2d/edge_se2_lotsofxy.h"

#include <cassert>

#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"
#include "se2_jacobians.h"

namespace graphslam::types_slam2d {

namespace {
const SE2& poseOf(const Edge& e) { return static_cast<const VertexSE2*>(e.vertex(0))->estimate(); }
const Eigen::Vector2d& pointOf(const Edge& e, std::size_t slot) {
  return static_cast<const VertexXY*>(e.vertex(slot))->estimate();
}
}  // namespace

void EdgeSE2LotsOfXY::resizeForVertices(std::size_t num_vertices) {
  if (num_vertices < 2) {
    throw Error("EdgeSE2LotsOfXY takes a pose and at least one point, " +
                std::to_string(num_vertices) + " vertices given");
  }
  const int rows = 2 * (static_cast<int>(num_vertices) - 1);
  setErrorDimension(rows);
  mutableMeasurement().setZero(rows);
}

void EdgeSE2LotsOfXY::computeError() {
  assert(measurement().size() == dimension() && "measurement of 2 values per point");
  const SE2& x = poseOf(*this);
  for (std::size_t i = 1; i < numVertices(); ++i) {
    const Eigen::Index row = 2 * static_cast<Eigen::Index>(i - 1);
    mutableError().segment<2>(row) =
        x.inverseTimes(pointOf(*this, i)) - measurement().segment<2>(row);
  }
}

void EdgeSE2LotsOfXY::linearizeOplus() {
  const SE2& x = poseOf(*this);
  JacobianType& j_pose = jacobian(0);  // sizes every slot's block
  Eigen::Matrix<double, 2, 3> j_x;
  Eigen::Matrix2d j_l;
  for (std::size_t i = 1; i < numVertices(); ++i) {
    const Eigen::Index row = 2 * static_cast<Eigen::Index>(i - 1);
    detail::pointInPoseJacobians(x, pointOf(*this, i), j_x, j_l);
    j_pose.middleRows<2>(row) = j_x;
    JacobianType& j_point = jacobian(i);
    j_point.setZero();
    j_point.middleRows<2>(row) = j_l;
  }
}

bool EdgeSE2LotsOfXY::acceptsVertex(std::size_t slot, const Vertex& v) const {
  return slot == 0 ? dynamic_cast<const VertexSE2*>(&v) != nullptr
                   : dynamic_cast<const VertexXY*>(&v) != nullptr;
}

std::string EdgeSE2LotsOfXY::expectedVertexType(std::size_t slot) const {
  return typeName(slot == 0 ? typeid(VertexSE2) : typeid(VertexXY));
}

}  // namespace graphslam::types_slam2d
