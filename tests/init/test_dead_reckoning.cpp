// SPDX-License-Identifier: MIT
// Dead reckoning over the odometry chain of a graph whose poses are not numbered 0, 1, 2...
#include <gtest/gtest.h>

#include <memory>

#include "../common/test_util.h"
#include "graphslam/init/dead_reckoning.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using types_slam2d::SE2;

namespace {

void addPose(Graph& g, VertexId id, const SE2& estimate) {
  auto v = std::make_unique<types_slam2d::VertexSE2>();
  v->setId(id);
  v->setEstimate(estimate);
  g.addVertex(std::move(v));
}

void addOdometry(Graph& g, VertexId a, VertexId b, const SE2& z) {
  auto e = std::make_unique<types_slam2d::EdgeSE2>();
  e->setVertexIds({a, b});
  e->setMeasurement(z);
  g.addEdge(std::move(e));
}

/// Poses 0, 2, 5 with landmarks 1 and 3 between them; the odometry 5 -> 2 is reversed.
Graph interleaved(bool with_second_odometry) {
  Graph g;
  addPose(g, 0, SE2(1, 2, 0.5));
  addPose(g, 2, SE2());
  addPose(g, 5, SE2());
  for (VertexId id : {1, 3}) {
    auto l = std::make_unique<types_slam2d::VertexXY>();
    l->setId(id);
    g.addVertex(std::move(l));
    auto obs = std::make_unique<types_slam2d::EdgeSE2XY>();
    obs->setVertexIds({0, id});
    g.addEdge(std::move(obs));
  }
  addOdometry(g, 0, 5, SE2(9, 9, 1));  // a loop closure: not on the chain
  addOdometry(g, 0, 2, SE2(1, 0, 0.25));
  if (with_second_odometry) addOdometry(g, 5, 2, SE2(0.5, -1, -0.75));
  return g;
}

}  // namespace

TEST(Init_DeadReckoning, FollowsThePosesAndSkipsLandmarks) {
  const io::Trajectory t = init::deadReckonGraph(interleaved(true));
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t.timestamps(), (std::vector<double>{0, 2, 5}));
  const SE2 p0(1, 2, 0.5);
  const SE2 p2 = p0 * SE2(1, 0, 0.25);
  const SE2 p5 = p2 * SE2(0.5, -1, -0.75).inverse();
  EXPECT_NEAR(t.position(1).x(), p2.translation().x(), 1e-12);
  EXPECT_NEAR(t.position(1).y(), p2.translation().y(), 1e-12);
  EXPECT_NEAR(t.position(2).x(), p5.translation().x(), 1e-12);
  EXPECT_NEAR(t.position(2).y(), p5.translation().y(), 1e-12);
}

TEST(Init_DeadReckoning, MissingLinkNamesTheTwoPoses) {
  EXPECT_THROW_MSG((void)init::deadReckonGraph(interleaved(false)), Error,
                   "no EDGE_SE2 joins the consecutive poses 2 and 5");
}
