// SPDX-License-Identifier: MIT
// Graduated non-convexity over the global initialisation, the TLS cost, and the rejection
// from a global start that chooses between the initialisation's and the nonlinear GNC's.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "corrupted_graph.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/outliers/robust_init.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"

using namespace graphslam;
using namespace graphslam::outliers;

namespace {

using test::Corrupted;

/// A simulated pose graph with wrong loop closures and every estimate zeroed (as an
/// edges-only file would be).
Corrupted makeCorrupted(int poses, double fraction) {
  Corrupted c = test::makeCorrupted(poses, fraction, 11, 5);
  for (const auto& [id, v] : c.sim.graph.vertices()) {
    static_cast<types_slam2d::VertexSE2&>(*v).setEstimate(types_slam2d::SE2());
  }
  return c;
}

std::set<std::pair<VertexId, VertexId>> rejectedPairs(const GncResult& r) {
  std::set<std::pair<VertexId, VertexId>> out;
  for (const auto& x : r.rejected) out.emplace(x.vertex_ids[0], x.vertex_ids[1]);
  return out;
}

GncOptions strictOptions() {
  GncOptions o;
  o.inlier_probability = 0.9999;  // no right closure beyond its threshold by chance
  return o;
}

}  // namespace

TEST(Outliers_RobustInit, WeightedInitialisationWithZeroWeightsIsTheFilteredOne) {
  Corrupted a = makeCorrupted(300, 0.2);
  Corrupted b = makeCorrupted(300, 0.2);
  (void)init::initializeGlobal(a.sim.graph, nullptr, isOdometryOrUnary);
  (void)init::initializeGlobalWeighted(
      b.sim.graph, nullptr, [](const Edge& e) { return isOdometryOrUnary(e) ? 1.0 : 0.0; });
  for (const auto& [id, v] : a.sim.graph.vertices()) {
    const auto& pa = static_cast<const types_slam2d::VertexSE2&>(*v).estimate();
    const auto& pb =
        static_cast<const types_slam2d::VertexSE2*>(b.sim.graph.vertex(id))->estimate();
    EXPECT_EQ(pa.translation(), pb.translation()) << id;
    EXPECT_EQ(pa.angle(), pb.angle()) << id;
  }
}

TEST(Outliers_RobustInit, ClassifiesTheWrongLoopClosuresFromZeroEstimates) {
  for (double fraction : {0.1, 0.3}) {
    Corrupted c = makeCorrupted(400, fraction);
    ASSERT_GT(c.wrong.size(), 5u);
    const RobustInitReport r = robustInitialization(c.sim.graph, nullptr, strictOptions());
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_TRUE(r.converged);
    EXPECT_EQ(r.zero_weight, c.wrong.size()) << fraction;
    const GncResult by_init = rejectionFromInitialization(c.sim.graph, r, strictOptions());
    EXPECT_EQ(rejectedPairs(by_init), c.wrong) << fraction;
  }
}

TEST(Outliers_RobustInit, TlsCostCountsCandidatesUpToTheirThreshold) {
  Corrupted c = makeCorrupted(200, 0.2);
  (void)init::initializeGlobal(c.sim.graph, nullptr, isOdometryOrUnary);
  GncOptions o;
  double expected = 0.0;
  (void)c.sim.graph.chi2();
  for (const auto& e : c.sim.graph.edges()) {
    expected += isOdometryOrUnary(*e) ? e->chi2() : std::min(e->chi2(), chi2Threshold(3, 0.99));
  }
  EXPECT_DOUBLE_EQ(tlsCost(c.sim.graph, o), expected);
  EXPECT_LT(expected, c.sim.graph.chi2());  // the wrong closures are capped
}

TEST(Outliers_RobustInit, GlobalStartRejectsExactlyTheWrongClosuresAndChoosesTheLowerCost) {
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  for (bool verify : {false, true}) {
    Corrupted c = makeCorrupted(400, 0.2);
    GncOptions o = strictOptions();
    o.verify = verify;
    GlobalStartReport report;
    const GncResult r = rejectFromGlobalStart(c.sim.graph, solvers, nullptr, o, &report);
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_EQ(rejectedPairs(r), c.wrong) << verify;
    EXPECT_EQ(report.cost_by_gnc >= 0.0, verify);
    if (verify) {
      EXPECT_EQ(report.chose_gnc,
                report.cost_by_gnc < report.cost_by_initialization -
                                         o.verify_margin * chi2Threshold(3, o.inlier_probability));
    }
    // The estimate left in the graph is the chosen answer's: its TLS cost.
    const double chosen = report.chose_gnc ? report.cost_by_gnc : report.cost_by_initialization;
    EXPECT_NEAR(tlsCost(c.sim.graph, o), chosen, 1e-9 * chosen);
  }
}
