// SPDX-License-Identifier: MIT
// Small SE(2) graphs built by hand (poses, points, odometry, observations), shared by the
// diagnostics and optimizer tests.
#pragma once

#include <memory>

#include "graphslam/core/graph.h"
#include "graphslam/diagnostics/observability.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::test {

using namespace graphslam::types_slam2d;

template <typename V>
V& add(Graph& g, VertexId id, bool fixed = false) {
  auto v = std::make_unique<V>();
  v->setId(id);
  v->setFixed(fixed);
  return static_cast<V&>(g.addVertex(std::move(v)));
}

inline void odometry(Graph& g, VertexId a, VertexId b) {
  auto e = std::make_unique<EdgeSE2>();
  e->setVertexIds({a, b});
  e->setMeasurement(SE2(1, 0, 0));
  e->setInformation(Eigen::Matrix3d::Identity());
  g.addEdge(std::move(e));
}

inline void observation(Graph& g, VertexId pose, VertexId point) {
  auto e = std::make_unique<EdgeSE2XY>();
  e->setVertexIds({pose, point});
  e->setMeasurement(Eigen::Vector2d(1, 0));
  e->setInformation(Eigen::Matrix2d::Identity());
  g.addEdge(std::move(e));
}

inline void pose(Graph& g, VertexId id, double x, double y, bool fixed = false) {
  add<VertexSE2>(g, id, fixed).setEstimate(SE2(x, y, 0));
}

inline void point(Graph& g, VertexId id, double x, double y) {
  add<VertexXY>(g, id).setEstimate(Eigen::Vector2d(x, y));
}

template <typename E>
inline void observe(Graph& g, VertexId from, VertexId landmark) {
  auto e = std::make_unique<E>();
  e->setVertexIds({from, landmark});
  g.addEdge(std::move(e));
}

/// Poses 0 (fixed), 1, 2 at (0, 0), (1, 0), (2, 0) along the x axis, joined by odometry.
inline Graph threePoses() {
  Graph g;
  pose(g, 0, 0, 0, true);
  pose(g, 1, 1, 0);
  pose(g, 2, 2, 0);
  odometry(g, 0, 1);
  odometry(g, 1, 2);
  return g;
}

inline const UndeterminedVertex* find(const ObservabilityReport& r, VertexId id) {
  for (const auto& u : r.undetermined) {
    if (u.id == id) return &u;
  }
  return nullptr;
}

}  // namespace graphslam::test
