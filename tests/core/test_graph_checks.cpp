// SPDX-License-Identifier: MIT
// checkConstraints (which vertices the edges cannot determine) and the optimizer's stop
// at an optimum it starts from.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "graphslam/core/graph_checks.h"
#include "graphslam/core/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using namespace graphslam::types_slam2d;
using namespace graphslam::simulation;

namespace {

template <typename V>
V& add(Graph& g, VertexId id, bool fixed = false) {
  auto v = std::make_unique<V>();
  v->setId(id);
  v->setFixed(fixed);
  return static_cast<V&>(g.addVertex(std::move(v)));
}

void odometry(Graph& g, VertexId a, VertexId b) {
  auto e = std::make_unique<EdgeSE2>();
  e->setVertexIds({a, b});
  e->setMeasurement(SE2(1, 0, 0));
  e->setInformation(Eigen::Matrix3d::Identity());
  g.addEdge(std::move(e));
}

void observation(Graph& g, VertexId pose, VertexId point) {
  auto e = std::make_unique<EdgeSE2XY>();
  e->setVertexIds({pose, point});
  e->setMeasurement(Eigen::Vector2d(1, 0));
  e->setInformation(Eigen::Matrix2d::Identity());
  g.addEdge(std::move(e));
}

}  // namespace

TEST(Core_GraphChecks, FindsUnanchoredIsolatedAndUnderMeasuredVertices) {
  Graph g;
  add<VertexSE2>(g, 0, true);
  add<VertexSE2>(g, 1);
  add<VertexSE2>(g, 2);
  odometry(g, 0, 1);
  odometry(g, 1, 2);  // 1, 2 anchored by the fixed 0
  add<VertexSE2>(g, 5);
  add<VertexSE2>(g, 6);
  add<VertexSE2>(g, 7);
  odometry(g, 5, 6);
  odometry(g, 6, 7);     // 5-7 float
  add<VertexSE2>(g, 8);  // no edge
  add<VertexXY>(g, 9, true);
  add<VertexSE2>(g, 10);
  observation(g, 10, 9);  // anchored, but 2 measured dimensions for 3 unknowns
  add<VertexXY>(g, 11);
  observation(g, 2, 11);  // a point seen once: 2 of 2, fine

  const ConstraintReport r = checkConstraints(g);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.without_edges, (std::vector<VertexId>{8}));
  ASSERT_EQ(r.unanchored.size(), 1u);
  EXPECT_EQ(r.unanchored[0], (std::vector<VertexId>{5, 6, 7}));
  EXPECT_EQ(r.too_few_measurements, (std::vector<VertexId>{10}));
  const std::string text = r.describe();
  EXPECT_NE(text.find("no edge at all: 8"), std::string::npos) << text;
  EXPECT_NE(text.find("can move freely together): 5-7"), std::string::npos) << text;
  EXPECT_NE(text.find("fewer measured dimensions than unknowns: 10"), std::string::npos) << text;

  g.removeVertex(8);
  g.removeVertex(10);
  odometry(g, 2, 5);
  EXPECT_TRUE(checkConstraints(g).ok()) << checkConstraints(g).describe();
}

TEST(Core_GraphChecks, IdRanges) {
  EXPECT_EQ(formatIdRanges({}), "");
  EXPECT_EQ(formatIdRanges({4}), "4");
  EXPECT_EQ(formatIdRanges({1, 2, 3, 4, 7, 9, 10}), "1-4, 7, 9-10");
  std::vector<VertexId> many;
  for (int i = 0; i < 100; i += 2) many.push_back(i);
  const std::string s = formatIdRanges(many, 5);
  EXPECT_EQ(s, "0, 2, 4, 6, 8, ... (50 in total)");
}

TEST(Core_OptimizerStop, RestartAtTheOptimumStopsAtOnce) {
  // Gauss-Newton (with LM fallback) restarted at its own optimum sees chi2 move only by
  // rounding; it must stop after one iteration, not count rounding as failed steps.
  ManhattanOptions sim;
  sim.num_poses = 400;
  sim.seed = 5;
  auto simulated = simulateManhattan(sim);
  Graph& g = simulated.graph;
  g.vertex(0)->setFixed(true);
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Optimizer optimizer(g, solvers);
  const Summary first = optimizer.optimize();
  ASSERT_TRUE(first.succeeded()) << first.report();
  for (int k = 0; k < 5; ++k) {
    const Summary again = optimizer.optimize();
    EXPECT_EQ(again.status, TerminationStatus::kConverged);
    EXPECT_LE(again.iterations, 2) << again.report();
  }
}
