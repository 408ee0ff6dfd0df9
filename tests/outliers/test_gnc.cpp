// SPDX-License-Identifier: MIT
// Graduated non-convexity (truncated least squares): the weight formula and mu schedule
// against hand values, and small simulated pose graphs with known wrong loop closures.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

#include "corrupted_graph.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/outliers/gnc.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/wrong_loop_closures.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

using namespace graphslam;
using namespace graphslam::outliers;

namespace {

TEST(Outliers_Gnc, Chi2ThresholdIsTheChiSquareQuantile) {
  // Tables: chi2_{3, 0.99} = 11.345, chi2_{2, 0.95} = 5.991, chi2_{1, 0.99} = 6.635.
  EXPECT_NEAR(chi2Threshold(3, 0.99), 11.3449, 1e-4);
  EXPECT_NEAR(chi2Threshold(2, 0.95), 5.9915, 1e-4);
  EXPECT_NEAR(chi2Threshold(1, 0.99), 6.6349, 1e-4);
  EXPECT_THROW((void)chi2Threshold(3, 1.0), Error);
  EXPECT_THROW((void)chi2Threshold(0, 0.5), Error);
}

TEST(Outliers_Gnc, TlsWeightMatchesHandValues) {
  const double c2 = 4.0, mu = 1.0;
  // Band: mu / (mu + 1) c2 = 2 < s < (mu + 1) / mu c2 = 8.
  EXPECT_EQ(tlsWeight(1.0, c2, mu), 1.0);
  EXPECT_EQ(tlsWeight(2.0, c2, mu), 1.0);
  EXPECT_EQ(tlsWeight(8.0, c2, mu), 0.0);
  EXPECT_EQ(tlsWeight(100.0, c2, mu), 0.0);
  // s = 4: sqrt(4 * 1 * 2 / 4) - 1 = sqrt(2) - 1.
  EXPECT_NEAR(tlsWeight(4.0, c2, mu), std::sqrt(2.0) - 1.0, 1e-15);
  // s = 3, mu = 2: band (8/3, 6); sqrt(4 * 2 * 3 / 3) - 2 = sqrt(8) - 2.
  EXPECT_NEAR(tlsWeight(3.0, c2, 2.0), std::sqrt(8.0) - 2.0, 1e-15);
  // Continuous at both ends of the band.
  EXPECT_NEAR(tlsWeight(2.0 + 1e-9, c2, mu), 1.0, 1e-8);
  EXPECT_NEAR(tlsWeight(8.0 - 1e-9, c2, mu), 0.0, 1e-8);
  // Large mu: a step at c2.
  EXPECT_EQ(tlsWeight(3.99, c2, 1e4), 1.0);
  EXPECT_EQ(tlsWeight(4.01, c2, 1e4), 0.0);
}

TEST(Outliers_Gnc, InitialMuIsRemarkFiveOverTheLargestResidual) {
  // mu_0 = c2 / (2 s_max - c2): s = 100, c2 = 10 -> 10 / 190.
  EXPECT_NEAR(initialMu({1.0, 100.0, 50.0}, {10.0, 10.0, 10.0}, 1e-6), 10.0 / 190.0, 1e-15);
  // Per-edge thresholds: the smallest ratio wins (20 / (2 * 30 - 20) = 0.5 vs 10 / 30).
  EXPECT_NEAR(initialMu({30.0, 20.0}, {20.0, 10.0}, 1e-6), 10.0 / 30.0, 1e-15);
  // Floored, and negative when every residual is within its threshold.
  EXPECT_EQ(initialMu({1e12}, {10.0}, 1e-6), 1e-6);
  EXPECT_LT(initialMu({1.0, 2.0}, {10.0, 10.0}, 1e-6), 0.0);
}

TEST(Outliers_Gnc, KnownInliersAreOdometryAndUnaryEdges) {
  simulation::ManhattanOptions sim;
  sim.num_poses = 30;
  auto s = simulation::simulateManhattan(sim);
  std::size_t known = 0;
  for (const auto& e : s.graph.edges()) {
    const bool odometry = std::abs(e->vertexId(0) - e->vertexId(1)) == 1;
    EXPECT_EQ(isOdometryOrUnary(*e), odometry);
    known += odometry ? 1 : 0;
  }
  EXPECT_EQ(known, 29u);
}

using test::Corrupted;

/// A simulated Manhattan world with `fraction` wrong loop closures, initialised from the
/// odometry only.
Corrupted makeCorrupted(int poses, double fraction, std::uint64_t seed) {
  Corrupted c = test::makeCorrupted(poses, fraction, 7, seed);
  (void)init::initializeGlobal(c.sim.graph, nullptr, isOdometryOrUnary);
  return c;
}

TEST(Outliers_Gnc, RejectsExactlyTheWrongLoopClosures) {
  for (double fraction : {0.1, 0.3}) {
    Corrupted c = makeCorrupted(400, fraction, 3);
    ASSERT_GT(c.wrong.size(), 3u);
    SolverRegistry solvers;
    solvers::registerSolvers(solvers);
    Graph& g = c.sim.graph;
    const std::size_t edges_before = g.numEdges();
    Summary reopt;
    // At 0.99 about 1 % of the right closures lie beyond the threshold by chance (their
    // noise is Gaussian); 0.9999 leaves none of them in this small world.
    GncOptions o;
    o.inlier_probability = 0.9999;
    const GncResult r = rejectOutliers(g, solvers, o, &reopt);
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_TRUE(r.converged);
    std::set<std::pair<VertexId, VertexId>> rejected;
    for (const auto& x : r.rejected) rejected.emplace(x.vertex_ids[0], x.vertex_ids[1]);
    EXPECT_EQ(rejected, c.wrong) << "fraction " << fraction;
    EXPECT_EQ(g.numEdges(), edges_before - c.wrong.size());
    EXPECT_TRUE(reopt.succeeded());
    // Every weight is decided, and the rejected edges' chi2 is far above the threshold.
    for (double w : r.weights) EXPECT_TRUE(w == 0.0 || w == 1.0) << w;
    for (const auto& x : r.rejected) EXPECT_GT(x.chi2, chi2Threshold(3, o.inlier_probability));
    // The inliers' optimum is the truth up to the noise.
    double worst = 0.0;
    for (int i = 0; i < 400; ++i) {
      const auto* v = static_cast<const types_slam2d::VertexSE2*>(g.vertex(i));
      const Eigen::Vector2d d =
          (c.sim.true_poses[0].inverse() * c.sim.true_poses[i]).translation() -
          (static_cast<const types_slam2d::VertexSE2*>(g.vertex(0))->estimate().inverse() *
           v->estimate())
              .translation();
      worst = std::max(worst, d.norm());
    }
    EXPECT_LT(worst, 1.0);
  }
}

TEST(Outliers_Gnc, KnownInliersAreNeverRejected) {
  Corrupted c = makeCorrupted(200, 0.2, 5);
  Graph& g = c.sim.graph;
  // Spoil one odometry edge badly: as a known inlier it must keep weight 1.
  auto* odo = dynamic_cast<types_slam2d::EdgeSE2*>(g.edges()[10].get());
  ASSERT_NE(odo, nullptr);
  ASSERT_TRUE(isOdometryOrUnary(*odo));
  odo->setMeasurement(types_slam2d::SE2(5.0, -3.0, 1.0));
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  const GncResult r = runGnc(g, solvers, GncOptions{});
  ASSERT_TRUE(r.ok) << r.message;
  for (std::size_t k = 0; k < g.numEdges(); ++k) {
    if (isOdometryOrUnary(*g.edges()[k])) {
      EXPECT_EQ(r.weights[k], 1.0) << k;
    }
  }
  for (const auto& x : r.rejected) EXPECT_FALSE(isOdometryOrUnary(*g.edges()[x.index]));
  // runGnc removes nothing and leaves no kernel behind.
  for (const auto& e : g.edges()) EXPECT_EQ(e->robustKernel(), nullptr);
}

TEST(Outliers_Gnc, MuGrowsByTheStepUntilWeightsAreBinary) {
  Corrupted c = makeCorrupted(200, 0.2, 9);
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  GncOptions o;
  std::vector<double> mus;
  std::vector<std::size_t> undecided;
  o.callback = [&](const GncIterationStats& s) {
    mus.push_back(s.mu);
    undecided.push_back(s.undecided);
  };
  const GncResult r = runGnc(c.sim.graph, solvers, o);
  ASSERT_TRUE(r.ok);
  ASSERT_EQ(mus.size(), static_cast<std::size_t>(r.iterations));
  ASSERT_GE(mus.size(), 2u);
  EXPECT_DOUBLE_EQ(mus.front(), r.initial_mu);
  for (std::size_t k = 1; k < mus.size(); ++k) EXPECT_DOUBLE_EQ(mus[k], mus[k - 1] * o.mu_step);
  EXPECT_EQ(undecided.back(), 0u);
  for (std::size_t k = 0; k + 1 < undecided.size(); ++k) EXPECT_GT(undecided[k], 0u);
  EXPECT_DOUBLE_EQ(r.final_mu, mus.back());
}

TEST(Outliers_Gnc, BadOptionsAreRefused) {
  GncOptions o;
  o.mu_step = 1.0;
  EXPECT_THROW(checkOptions(o), Error);
  o = GncOptions{};
  o.inlier_probability = 0.0;
  EXPECT_THROW(checkOptions(o), Error);
  o = GncOptions{};
  o.optimizer_iterations_per_step = 0;
  EXPECT_THROW(checkOptions(o), Error);
  EXPECT_NO_THROW(checkOptions(GncOptions{}));
}

}  // namespace
