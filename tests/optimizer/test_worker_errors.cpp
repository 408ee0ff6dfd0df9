// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <memory>

#include "../common/point_edges.h"
#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/graph.h"
#include "graphslam/optimizer/linear_system.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using namespace graphslam::test;
using types_slam2d::VertexXY;

namespace {
/// A type that forgot both hooks.
class EdgeBroken final : public BaseUnaryEdge<2, Eigen::Vector2d, VertexXY> {};
}  // namespace

TEST(Optimizer_LinearSystem, MissingHooksAreReportedFromWorkerThreads) {
  // An edge that throws in a worker thread reaches the caller as the same exception.
  Graph g;
  for (int i = 0; i < 3000; ++i) {
    addPoint(g, i, {0, 0});
    auto e = std::make_unique<EdgeBroken>();
    e->setVertexIds({i});
    g.addEdge(std::move(e));
  }
  LinearSystem system;
  system.setThreads(3);
  system.update(g);
  EXPECT_THROW((void)system.computeChi2(g), Error);
}
