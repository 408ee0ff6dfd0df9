// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "graphslam/init/initial_guess.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam2d/edge_pointxy.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using namespace graphslam::types_slam2d;

// Edges the global initialisation does not use (custom types, say) are named in its report
// instead of being passed over in silence.
TEST(Init_InitialGuess, SaysWhichEdgesTakeNoPart) {
  Graph g;
  for (int id : {0, 1}) {
    auto v = std::make_unique<VertexSE2>();
    v->setId(id);
    g.addVertex(std::move(v));
  }
  for (int id : {10, 11}) {
    auto v = std::make_unique<VertexXY>();
    v->setId(id);
    g.addVertex(std::move(v));
  }
  auto odometry = std::make_unique<EdgeSE2>();
  odometry->setVertexIds({0, 1});
  odometry->setMeasurement(SE2(1.0, 0.0, 0.5));
  g.addEdge(std::move(odometry));
  auto between = std::make_unique<EdgePointXY>();
  between->setVertexIds({10, 11});
  between->setMeasurement(Eigen::Vector2d(1.0, 1.0));
  g.addEdge(std::move(between));
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  const init::InitialGuessReport r = init::initializeGraph(g, solvers, "auto");
  EXPECT_EQ(r.poses, 1u);
  ASSERT_EQ(r.lines.size(), 2u);
  EXPECT_NE(r.lines[1].find("1 edge (graphslam::types_slam2d::EdgePointXY) takes no part in the "
                            "initial guess"),
            std::string::npos)
      << r.lines[1];
}
