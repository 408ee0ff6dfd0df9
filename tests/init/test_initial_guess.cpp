// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "graphslam/init/global_se2.h"
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

namespace {
/// A loop of `n` poses on a circle with noise-free odometry and a closure from every
/// fourth pose to the one 9 poses back, every estimate at the origin.
Graph noiseFreeLoop(int n, std::vector<SE2>& truth) {
  Graph g;
  truth.clear();
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    truth.emplace_back(10.0 * std::cos(a), 10.0 * std::sin(a), a + M_PI / 2);
    auto v = std::make_unique<VertexSE2>();
    v->setId(i);
    v->setFixed(i == 0);
    v->setEstimate(i == 0 ? truth[0] : SE2());
    g.addVertex(std::move(v));
  }
  const auto link = [&](int a, int b) {
    auto e = std::make_unique<EdgeSE2>();
    e->setVertexIds({a, b});
    e->setMeasurement(truth[a].inverse() * truth[b]);
    Eigen::Matrix3d info = Eigen::Matrix3d::Identity();
    info(2, 2) = 4.0;
    e->setInformation(info);
    g.addEdge(std::move(e));
  };
  for (int i = 1; i < n; ++i) link(i - 1, i);
  for (int i = 12; i < n; i += 4) link(i - 9, i);
  return g;
}
}  // namespace

// Both steps (orientations, then positions in the same pattern's system, laid out once)
// recover noise-free poses exactly, with Eigen's LDL^T and with the tool's default solver;
// the report counts the solver's analysis (its ordering) within the seconds.
TEST(Init_InitialGuess, NoiseFreeLoopIsRecoveredAndTheAnalysisIsReported) {
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  for (const bool with_solver : {false, true}) {
    SCOPED_TRACE(with_solver ? "auto" : "eigen ldlt");
    std::vector<SE2> truth;
    Graph g = noiseFreeLoop(400, truth);
    const auto solver = solvers.create("auto");
    const init::InitializationReport r =
        init::initializeGlobal(g, with_solver ? solver.get() : nullptr);
    ASSERT_TRUE(r.message.empty()) << r.message;
    EXPECT_EQ(r.poses, 399u);
    if (with_solver) {
      EXPECT_GT(r.analysis_seconds, 0.0);
      EXPECT_LE(r.analysis_seconds, r.seconds);
    } else {
      EXPECT_EQ(r.analysis_seconds, 0.0);
    }
    double worst = 0.0;
    for (int i = 0; i < 400; ++i) {
      const SE2 d = truth[i].inverse() * static_cast<VertexSE2*>(g.vertex(i))->estimate();
      worst = std::max(worst, d.log().cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst, 1e-9);
  }
}
