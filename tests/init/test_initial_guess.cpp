// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "graphslam/init/global_se2.h"
#include "graphslam/init/initial_guess.h"
#include "graphslam/solvers/cost_model.h"
#include "graphslam/solvers/options.h"
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

namespace {
/// A linear solver whose analysis fails, as one that runs out of memory does.
class FailingSolver final : public LinearSolver {
 public:
  [[nodiscard]] std::string name() const override { return "failing"; }
  LinearSolverResult analyze(const SparseStructure& /*structure*/) override {
    return LinearSolverResult::failure(LinearSolverStatus::kFailure, "out of memory (test)");
  }
};
}  // namespace

// A system the solver cannot solve is said with the solver's reason, the estimates kept;
// it is never reported as a graph with nothing to initialise.
TEST(Init_InitialGuess, AFailedSystemIsSaidWithTheSolversReason) {
  SolverRegistry solvers;
  solvers.registerSolver("failing", "always fails",
                         [] { return std::make_unique<FailingSolver>(); });
  std::vector<SE2> truth;
  Graph g = noiseFreeLoop(50, truth);
  const init::InitialGuessReport r = init::initializeGraph(g, solvers, "failing");
  EXPECT_EQ(r.poses, 0u);
  ASSERT_EQ(r.lines.size(), 1u);
  EXPECT_EQ(r.lines[0],
            "orientation system not solved (failing's analysis failed: out of memory (test)): "
            "initial estimates kept");
  EXPECT_EQ(static_cast<VertexSE2*>(g.vertex(7))->estimate().translation().norm(), 0.0);
  const auto solver = solvers.create("failing");
  const init::InitializationReport direct = init::initializeGlobal(g, solver.get());
  EXPECT_TRUE(direct.failed);
}

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

// On a graph large enough for CHOLMOD (here a cost model that always sends the systems
// there), the orientations take the complex path and the positions the scalar one on the
// same analysis (one solver, CHOLMOD's factor switching from complex to real values, both
// position components in one solve): the estimates are those of Eigen's LDL^T on the same
// systems, the noise making every system differ from the other.
TEST(Init_InitialGuess, ComplexAndScalarPathsOnOneAnalysisGiveTheSameEstimates) {
  solvers::SolverOptions options;
  auto model = std::make_shared<solvers::CostModel>(solvers::CostModel::builtIn());
  model->cholmod_supernodal = solvers::CostLine{0.0, 0.0, 1e-15};
  options.auto_solver.cost_model = model;
  SolverRegistry solvers;
  solvers::registerSolvers(solvers, options);
  if (!solvers.contains("cholmod")) GTEST_SKIP() << "the complex path needs CHOLMOD";
  std::vector<SE2> truth;
  const int n = 3000;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  auto noisy = [&] {
    Graph g = noiseFreeLoop(n, truth);
    for (const auto& e : g.edges()) {
      auto* se2 = static_cast<EdgeSE2*>(e.get());
      const SE2 z = se2->measurement();
      se2->setMeasurement(SE2(z.translation().x() + noise(rng), z.translation().y() + noise(rng),
                              z.angle() + noise(rng)));
    }
    return g;
  };
  rng.seed(7);
  Graph reference = noisy();
  rng.seed(7);
  Graph g = noisy();
  const init::InitializationReport by_ldlt = init::initializeGlobal(reference, nullptr);
  ASSERT_TRUE(by_ldlt.message.empty()) << by_ldlt.message;
  const auto solver = solvers.create("auto");
  const init::InitializationReport r = init::initializeGlobal(g, solver.get());
  ASSERT_TRUE(r.message.empty()) << r.message;
  EXPECT_EQ(r.poses, static_cast<std::size_t>(n - 1));
  EXPECT_GT(r.analysis_seconds, 0.0);
  double worst = 0.0, moved = 0.0;
  for (int i = 1; i < n; ++i) {
    const SE2 a = static_cast<VertexSE2*>(reference.vertex(i))->estimate();
    const SE2 b = static_cast<VertexSE2*>(g.vertex(i))->estimate();
    worst = std::max(worst, (a.inverse() * b).log().cwiseAbs().maxCoeff());
    moved = std::max(moved, (truth[i].inverse() * b).log().cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-8);
  EXPECT_GT(moved, 1e-3);  // the noise moved the estimates: the systems are not trivial
}
