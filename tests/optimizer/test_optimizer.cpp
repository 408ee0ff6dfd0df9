// SPDX-License-Identifier: MIT
// The optimizer: exact steps on every solver, gauge and anchors, threads, chord steps.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "../common/se2_graphs.h"
#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/graph.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/support/logging.h"
#include "graphslam/types_slam2d/se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"
#include "optimizer_test_graphs.h"

using namespace graphslam;
using test::addDisplacement;
using test::addPoint;
using test::allSolvers;
using test::EdgeDisplacement;
using test::mixedGraph;
using types_slam2d::SE2;
using types_slam2d::VertexSE2;
using types_slam2d::VertexXY;

namespace {

/// Absolute position of one point: e = p - z.
class EdgePointPrior final : public BaseUnaryEdge<2, Eigen::Vector2d, VertexXY> {
 public:
  ErrorVector evaluate(const Eigen::Vector2d& p) const override { return p - measurement(); }
};

class Optimizer_Batch : public ::testing::TestWithParam<std::string> {};

/// Two components: 0-1 anchored by the fixed vertex 0, 5-6 by nothing.
Graph twoComponents() {
  Graph g;
  addPoint(g, 0, {0, 0}).setFixed(true);
  addPoint(g, 1, {1, 0});
  addPoint(g, 5, {5, 0});
  addPoint(g, 6, {6, 0.5});
  addDisplacement<EdgeDisplacement>(g, 0, 1, {1, 0});
  addDisplacement<EdgeDisplacement>(g, 5, 6, {1, 0});  // floats: nothing anchors 5-6
  return g;
}

/// Optimises a simulated Manhattan graph (vertex 0 fixed) with `algorithm`, from the
/// simulator's estimates or from the global initial guess.
Summary optimizeSimulated(const simulation::ManhattanOptions& sim, Algorithm algorithm,
                          bool global_init) {
  auto solvers = allSolvers();
  Graph g = std::move(simulation::simulateManhattan(sim).graph);
  g.vertex(0)->setFixed(true);
  if (global_init) {
    auto init_solver = solvers.create("auto");
    EXPECT_TRUE(init::initializeGlobal(g, init_solver.get()).message.empty());
  }
  Optimizer::Options opt;
  opt.algorithm = algorithm;
  Optimizer optimizer(g, solvers, opt);
  return optimizer.optimize();
}

}  // namespace

/// A linear problem: GN must land on the exact least-squares solution in one step.
TEST_P(Optimizer_Batch, LinearProblemSolvedExactlyInOneStep) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.1);
  Graph g;
  const int n = 30;
  for (int i = 0; i < n; ++i) addPoint(g, i, {noise(rng) * 10, noise(rng) * 10});
  auto prior = std::make_unique<EdgePointPrior>();
  prior->setVertexIds({0});
  prior->setMeasurement({0, 0});
  g.addEdge(std::move(prior));
  for (int i = 0; i + 1 < n; ++i) {
    addDisplacement<EdgeDisplacement>(g, i, i + 1, {1 + noise(rng), noise(rng)}, 1.0 + i % 3);
  }
  for (int i = 0; i + 5 < n; i += 4)
    addDisplacement<EdgeDisplacement>(g, i, i + 5, {5 + noise(rng), noise(rng)}, 2.0);

  // Dense reference: stack the whitened linear system.
  const int dim = 2 * n;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(dim, dim);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(dim);
  for (const auto& e : g.edges()) {
    e->computeError();
    e->linearizeOplus();
    const Eigen::Map<const Eigen::Matrix2d> W(e->informationData());
    const Eigen::Map<const Eigen::Vector2d> err(e->errorData());
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      const int ci = 2 * e->vertexId(s);
      const Eigen::Map<const Eigen::Matrix2d> Ji(e->jacobianData(s));
      b.segment<2>(ci) += Ji.transpose() * W * err;
      for (std::size_t t = 0; t < e->numVertices(); ++t) {
        const Eigen::Map<const Eigen::Matrix2d> Jj(e->jacobianData(t));
        H.block<2, 2>(ci, 2 * e->vertexId(t)) += Ji.transpose() * W * Jj;
      }
    }
  }
  Eigen::VectorXd x0(dim);
  for (int i = 0; i < n; ++i)
    x0.segment<2>(2 * i) = static_cast<VertexXY*>(g.vertex(i))->estimate();
  const Eigen::VectorXd expected = x0 + H.ldlt().solve(-b);

  auto solvers = allSolvers();
  Optimizer::Options opt;
  opt.algorithm = Algorithm::kGaussNewton;
  opt.linear_solver = GetParam();
  opt.max_iterations = 5;
  Optimizer optimizer(g, solvers, opt);
  const Summary s = optimizer.optimize();
  EXPECT_EQ(s.status, TerminationStatus::kConverged) << s.message;
  EXPECT_LE(s.iterations, 2);
  EXPECT_TRUE(s.gauge_fixed.empty());  // the prior anchors the graph
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d got = static_cast<VertexXY*>(g.vertex(i))->estimate();
    EXPECT_NEAR((got - expected.segment<2>(2 * i)).norm(), 0.0, 1e-7) << "vertex " << i;
  }
}

/// A noise-free SE(2) pose graph from a perturbed start converges back to the truth.
TEST_P(Optimizer_Batch, NoiseFreePoseGraphRecoversTruth) {
  for (Algorithm algorithm : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt}) {
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0, 0.05);
    Graph g;
    std::vector<SE2> truth;
    const int n = 40;
    for (int i = 0; i < n; ++i) {
      truth.emplace_back(std::cos(i * 0.3) * 5, std::sin(i * 0.3) * 5, i * 0.3 + 1.57);
      auto v = std::make_unique<VertexSE2>();
      v->setId(i);
      v->setEstimate(i == 0 ? truth[0]
                            : SE2(truth[i].translation().x() + noise(rng),
                                  truth[i].translation().y() + noise(rng),
                                  truth[i].angle() + noise(rng)));
      g.addVertex(std::move(v));
    }
    auto link = [&](int i, int j) { test::addExactSE2Edge(g, truth, i, j); };
    for (int i = 0; i + 1 < n; ++i) link(i, i + 1);
    for (int i = 0; i + 21 < n; i += 3) link(i, i + 21);
    auto solvers = allSolvers();
    Optimizer::Options opt;
    opt.algorithm = algorithm;
    opt.linear_solver = GetParam();
    Optimizer optimizer(g, solvers, opt);
    const Summary s = optimizer.optimize();
    EXPECT_EQ(s.status, TerminationStatus::kConverged) << toString(algorithm) << ": " << s.message;
    EXPECT_LT(s.final_chi2, 1e-12);
    ASSERT_EQ(s.gauge_fixed, std::vector<VertexId>{0});
    EXPECT_FALSE(g.vertex(0)->fixed()) << "gauge fix must be undone after optimize()";
    for (int i = 0; i < n; ++i) {
      const SE2& got = static_cast<VertexSE2*>(g.vertex(i))->estimate();
      EXPECT_NEAR((got.translation() - truth[i].translation()).norm(), 0.0, 1e-7) << i;
      EXPECT_NEAR(types_slam2d::normalizeAngle(got.angle() - truth[i].angle()), 0.0, 1e-8) << i;
    }
    EXPECT_EQ(static_cast<int>(s.per_iteration.size()), s.iterations);
  }
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, Optimizer_Batch,
                         ::testing::Values("eigen-ldlt", "eigen-llt", "cholmod",
                                           "cholmod-simplicial"));

TEST(Optimizer_OptimizerDiagnostics, UnanchoredComponentIsAnchoredAtItsLowestId) {
  for (Algorithm algorithm : {Algorithm::kGaussNewton, Algorithm::kGaussNewtonFallback,
                              Algorithm::kLevenbergMarquardt, Algorithm::kDogleg}) {
    Graph g = twoComponents();
    auto solvers = allSolvers();
    Optimizer::Options opt;
    opt.algorithm = algorithm;
    opt.linear_solver = "cholmod";
    std::vector<std::string> logged;
    support::setLogSink([&](support::LogLevel, const std::string& m) { logged.push_back(m); });
    support::setLogLevel(support::LogLevel::kInfo);
    Optimizer optimizer(g, solvers, opt);
    const Summary s = optimizer.optimize();
    support::setLogLevel(support::LogLevel::kWarning);
    support::setLogSink(nullptr);
    SCOPED_TRACE(toString(algorithm));
    ASSERT_EQ(s.unanchored.size(), 1u);
    EXPECT_EQ(s.unanchored[0], (std::vector<VertexId>{5, 6}));
    EXPECT_EQ(s.gauge_fixed, (std::vector<VertexId>{5}));
    EXPECT_EQ(s.status, TerminationStatus::kConverged) << s.message;
    EXPECT_NEAR(s.final_chi2, 0.0, 1e-12);
    EXPECT_FALSE(g.vertex(5)->fixed());  // released after optimize()
    ASSERT_FALSE(logged.empty());
    EXPECT_NE(logged[0].find("fixing vertex 5"), std::string::npos) << logged[0];
  }
}

TEST(Optimizer_OptimizerDiagnostics, UnanchoredComponentFailureNamesVertexAndCause) {
  Graph g = twoComponents();
  auto solvers = allSolvers();
  Optimizer::Options opt;
  opt.algorithm = Algorithm::kGaussNewton;
  opt.linear_solver = "cholmod";
  opt.fix_gauge = false;
  std::vector<std::string> logged;
  support::setLogSink([&](support::LogLevel, const std::string& m) { logged.push_back(m); });
  Optimizer optimizer(g, solvers, opt);
  const Summary s = optimizer.optimize();
  support::setLogSink(nullptr);
  ASSERT_EQ(s.unanchored.size(), 1u);
  EXPECT_EQ(s.status, TerminationStatus::kNumericalFailure);
  EXPECT_NE(s.message.find("(at vertex 6)"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("component without an anchor"), std::string::npos) << s.message;
  ASSERT_FALSE(logged.empty());
  EXPECT_NE(logged[0].find("5 6"), std::string::npos) << logged[0];
}

TEST(Optimizer_OptimizerDiagnostics, CallbackAndRebuildAfterGraphChange) {
  Graph g;
  addPoint(g, 0, {0, 0}).setFixed(true);
  for (int i = 1; i < 5; ++i) {
    addPoint(g, i, {0, 0});
    addDisplacement<EdgeDisplacement>(g, i - 1, i, {1, 0});
  }
  auto solvers = allSolvers();
  Optimizer::Options opt;
  opt.linear_solver = "eigen-ldlt";
  int calls = 0;
  opt.callback = [&](const IterationStats&) { ++calls; };
  Optimizer optimizer(g, solvers, opt);
  Summary s = optimizer.optimize();
  EXPECT_EQ(calls, s.iterations);
  EXPECT_NEAR(static_cast<VertexXY*>(g.vertex(4))->estimate().x(), 4.0, 1e-6);
  // Grow the graph online and re-optimise with the same optimizer.
  addPoint(g, 5, {0, 0});
  addDisplacement<EdgeDisplacement>(g, 4, 5, {1, 0});
  s = optimizer.optimize();
  EXPECT_TRUE(s.succeeded());
  EXPECT_NEAR(static_cast<VertexXY*>(g.vertex(5))->estimate().x(), 5.0, 1e-6);
  g.removeVertex(5);
  s = optimizer.optimize();
  EXPECT_TRUE(s.succeeded());
  EXPECT_EQ(s.system_dimension, 8);
}

TEST(Optimizer_Batch, ThreadsGiveTheSameBits) {
  auto solvers = allSolvers();
  std::vector<std::vector<double>> chi2s;
  std::vector<std::vector<double>> states;
  for (int threads : {1, 2, 3}) {
    Graph g = mixedGraph();
    Optimizer::Options opt;
    opt.threads = threads;
    std::vector<double> chi2;
    opt.callback = [&](const IterationStats& st) { chi2.push_back(st.chi2); };
    Optimizer optimizer(g, solvers, opt);
    const Summary s = optimizer.optimize();
    ASSERT_TRUE(s.succeeded()) << s.report();
    EXPECT_GE(s.iterations, 3);
    chi2.push_back(s.final_chi2);
    chi2s.push_back(chi2);
    std::vector<double> state, buf;
    for (const auto& [id, v] : g.vertices()) {
      buf.resize(static_cast<std::size_t>(v->estimateDataDimension()));
      v->getEstimateData(buf.data());
      state.insert(state.end(), buf.begin(), buf.end());
    }
    states.push_back(state);
  }
  for (std::size_t k = 1; k < states.size(); ++k) {
    EXPECT_EQ(chi2s[k], chi2s[0]) << "thread count " << k + 1;  // bit for bit
    EXPECT_TRUE(states[k] == states[0]) << "thread count " << k + 1;
  }
}

// Near convergence the default algorithm reuses the last Gauss-Newton factorisation for
// one step (a chord step); it must end where plain Gauss-Newton ends, with fewer
// factorisations, and plain Gauss-Newton must factorise at every iteration.
TEST(Optimizer_Batch, ChordStepsSaveFactorisationsAndReachTheSameMinimum) {
  simulation::ManhattanOptions sim;
  sim.num_poses = 1500;
  const Summary fallback = optimizeSimulated(sim, Algorithm::kGaussNewtonFallback, false);
  const Summary gn = optimizeSimulated(sim, Algorithm::kGaussNewton, false);
  ASSERT_EQ(fallback.status, TerminationStatus::kConverged) << fallback.message;
  ASSERT_EQ(gn.status, TerminationStatus::kConverged) << gn.message;
  auto factorisations = [](const Summary& s) {
    int n = 0;
    for (const auto& it : s.per_iteration) n += it.factorizations;
    return n;
  };
  for (const auto& it : gn.per_iteration)
    EXPECT_GE(it.factorizations, 1) << "iteration " << it.iteration;
  EXPECT_EQ(fallback.per_iteration.back().factorizations, 0);  // the converging step was a chord
  EXPECT_LT(factorisations(fallback), factorisations(gn));
  EXPECT_NEAR(fallback.final_chi2, gn.final_chi2, 1e-8 * gn.final_chi2);
  std::printf("chi2 %.10g (default, %d factorisations) and %.10g (gn, %d)\n", fallback.final_chi2,
              factorisations(fallback), gn.final_chi2, factorisations(gn));
}

// Chord steps iterate conjugate gradients preconditioned with the last factorisation.
// Away from convergence one is taken when the last step agreed with its model and the
// factor is dense enough for a few iterations to cost less than a factorisation
// (nnz(L)/n >= 24); chord steps that reach their tolerance follow one another. On a
// simulated graph started at the global initial guess (what `graphslam optimize` does)
// one factorisation serves every step, and the optimizer ends where Gauss-Newton ends.
TEST(Optimizer_Batch, ChordStepsIterateConjugateGradientsOnTheLastFactorisation) {
  simulation::ManhattanOptions sim;
  sim.num_poses = 2000;
  sim.sigma_theta = 0.05;  // the first step lowers chi2 by 16 %
  const Summary fallback = optimizeSimulated(sim, Algorithm::kGaussNewtonFallback, true);
  const Summary gn = optimizeSimulated(sim, Algorithm::kGaussNewton, true);
  ASSERT_EQ(fallback.status, TerminationStatus::kConverged) << fallback.message;
  ASSERT_EQ(gn.status, TerminationStatus::kConverged) << gn.message;
  int factorisations = 0;
  int cg = 0;
  for (const auto& it : fallback.per_iteration) {
    std::printf("iteration %d: chi2 %.10g, %d factorisations, %d CG iterations\n", it.iteration,
                it.chi2, it.factorizations, static_cast<int>(it.strategy.value("cg_iterations")));
    factorisations += it.factorizations;
    cg += static_cast<int>(it.strategy.value("cg_iterations"));
    EXPECT_EQ(it.strategy.value("cg_iterations") > 0, it.factorizations == 0)
        << "iteration " << it.iteration;
  }
  EXPECT_EQ(factorisations, 1);
  EXPECT_GE(fallback.iterations, 3);
  // The first step lowered chi2 by far more than the near-convergence trigger (1e-4 of
  // it): the second is a chord step because the first agreed with its model.
  ASSERT_GE(fallback.per_iteration.size(), 2u);
  EXPECT_GT(fallback.initial_chi2 - fallback.per_iteration[0].chi2, 0.01 * fallback.initial_chi2);
  EXPECT_EQ(fallback.per_iteration[1].factorizations, 0);
  EXPECT_GT(cg, fallback.iterations - 1);  // some chord step took more than one iteration
  EXPECT_NEAR(fallback.final_chi2, gn.final_chi2, 1e-8 * gn.final_chi2);
  std::printf("chi2 %.10g -> %.10g (default) and %.10g (gn, %d iterations)\n",
              fallback.initial_chi2, fallback.final_chi2, gn.final_chi2, gn.iterations);
}
