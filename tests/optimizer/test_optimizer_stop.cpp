// SPDX-License-Identifier: MIT
// What the optimizer says when it stops: at its own optimum, and on a numerical failure.
#include <gtest/gtest.h>

#include <vector>

#include "../common/range_bearing_edges.h"
#include "../common/small_se2_graphs.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/solvers/register.h"

using namespace graphslam;
using namespace graphslam::test;
using namespace graphslam::simulation;

TEST(Optimizer_Stop, RestartAtTheOptimumStopsAtOnce) {
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

// The optimizer's numerical failure names the vertex and the vertices its edges join it to,
// and returns both (its edges as indices into graph.edges()).
TEST(Optimizer_Diagnostics, FailureNamesTheVertexAndItsEdges) {
  Graph g = threePoses();
  point(g, 10, 4, 0);  // on the x axis from pose 1: the range sees x only, exactly
  observe<test::EdgeRangeSE2XY>(g, 1, 10);
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Optimizer::Options options;
  options.algorithm = Algorithm::kGaussNewton;
  options.linear_solver = "cholmod";
  Optimizer optimizer(g, solvers, options);
  const Summary s = optimizer.optimize();
  ASSERT_EQ(s.status, TerminationStatus::kNumericalFailure);
  EXPECT_NE(s.message.find("(at vertex 10); its edge joins it to vertex 1"), std::string::npos)
      << s.message;
  EXPECT_EQ(s.failed_vertex, 10);
  EXPECT_EQ(s.failed_vertex_edges, (std::vector<std::size_t>{2}));
}
