// SPDX-License-Identifier: MIT
// Point edges with numeric Jacobians (on copies, g2o-style in place, multi-edge) and helpers to
// build graphs of them, shared by the core and optimizer tests.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <random>
#include <utility>

#include "graphslam/core/base_multi_edge.h"
#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/graph.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::test {

/// Linear displacement between two points: e = (b - a) - z. Numeric Jacobian (no
/// linearizeOplus), exercising the FixedEdge default on copies.
class EdgeDisplacement final
    : public BaseBinaryEdge<2, Eigen::Vector2d, types_slam2d::VertexXY, types_slam2d::VertexXY> {
 public:
  ErrorVector evaluate(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const override {
    return (b - a) - measurement();
  }
};

/// The same, written g2o style: overrides computeError() only.
class EdgeDisplacementG2oStyle final
    : public BaseBinaryEdge<2, Eigen::Vector2d, types_slam2d::VertexXY, types_slam2d::VertexXY> {
 public:
  void computeError() override {
    mutableError() = (vertexXi<1>().estimate() - vertexXi<0>().estimate()) - measurement();
  }
};

/// Dynamic arity: the centroid of any number of points equals z.
class EdgeCentroid final : public BaseMultiEdge<2, Eigen::Vector2d> {
 public:
  void computeError() override {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < numVertices(); ++i) {
      sum += static_cast<const types_slam2d::VertexXY*>(vertex(i))->estimate();
    }
    mutableError() = sum / static_cast<double>(numVertices()) - measurement();
  }
};

inline types_slam2d::VertexXY& addPoint(Graph& g, VertexId id, const Eigen::Vector2d& p) {
  auto v = std::make_unique<types_slam2d::VertexXY>();
  v->setId(id);
  v->setEstimate(p);
  return static_cast<types_slam2d::VertexXY&>(g.addVertex(std::move(v)));
}

template <typename E>
E& addDisplacement(Graph& g, VertexId a, VertexId b, const Eigen::Vector2d& z, double w = 1.0) {
  auto e = std::make_unique<E>();
  e->setVertexIds({a, b});
  e->setMeasurement(z);
  e->setInformation(Eigen::Matrix2d::Identity() * w);
  return static_cast<E&>(g.addEdge(std::move(e)));
}

}  // namespace graphslam::test
