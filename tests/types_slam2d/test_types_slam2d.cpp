// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <sstream>

#include "../common/edge_type_checks.h"
#include "../common/se2_graphs.h"
#include "edge_factories.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/io/g2o.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;
using namespace graphslam::types_slam2d;
using namespace graphslam::init;
using namespace graphslam::simulation;
using namespace slam2d_test;

namespace {

template <typename E>
class TypesSlam2d_Edge : public ::testing::Test {};
using EdgeTypes =
    ::testing::Types<EdgeSE2, EdgeSE2XY, EdgePriorSE2, EdgePointXY, EdgeXYBearingRange, EdgePriorXY,
                     EdgeSE2Offset, EdgeSE2PointXYOffset, EdgeBearingSE2XY, EdgeSE2XYCalib,
                     EdgePriorSE2XY, EdgeSE2TwoPointsXY, EdgeSE2LotsOfXY>;
TYPED_TEST_SUITE(TypesSlam2d_Edge, EdgeTypes, ::testing::internal::DefaultNameGenerator);

TYPED_TEST(TypesSlam2d_Edge, AnalyticJacobianMatchesNumeric) {
  graphslam::test::expectAnalyticJacobians<TypeParam>(EdgeFactory<TypeParam>::make, 1234, 500);
}

TYPED_TEST(TypesSlam2d_Edge, WriteReadRoundTripIsExact) {
  TypeRegistry types;
  registerTypes(types);
  std::mt19937 rng(7);
  Graph g;
  EdgeFactory<TypeParam>::make(g, rng);
  graphslam::test::expectExactRoundTrip(g, types);
}

TEST(TypesSlam2d_SE2, GroupAxioms) {
  std::mt19937 rng(5);
  for (int i = 0; i < 100; ++i) {
    const SE2 a = randomPose(rng), b = randomPose(rng), c = randomPose(rng);
    const SE2 ident = a * a.inverse();
    EXPECT_NEAR(ident.translation().norm(), 0.0, 1e-12);
    EXPECT_NEAR(ident.angle(), 0.0, 1e-12);
    EXPECT_TRUE(((a * b) * c).matrix().isApprox((a * (b * c)).matrix(), 1e-12));
    EXPECT_TRUE((a * b).matrix().isApprox(a.matrix() * b.matrix(), 1e-12));
    EXPECT_GE(a.angle(), -kPi);
    EXPECT_LT(a.angle(), kPi);
  }
}

TEST(TypesSlam2d_SE2, NormalizeAngle) {
  EXPECT_NEAR(normalizeAngle(3 * kPi), -kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(-3 * kPi / 2), kPi / 2, 1e-12);
  EXPECT_NEAR(normalizeAngle(0.5), 0.5, 0);
  EXPECT_NEAR(normalizeAngle(2 * kPi + 0.25), 0.25, 1e-12);
}

TEST(TypesSlam2d_EdgeSE2, ErrorFollowsG2oConvention) {
  // Z^-1 (Xi^-1 Xj) for a hand-computed case.
  Graph g;
  auto a = std::make_unique<VertexSE2>();
  a->setId(0);
  a->setEstimate(SE2(1, 2, kPi / 2));
  auto b = std::make_unique<VertexSE2>();
  b->setId(1);
  b->setEstimate(SE2(1, 5, kPi));
  g.addVertex(std::move(a));
  g.addVertex(std::move(b));
  auto e = std::make_unique<EdgeSE2>();
  e->setVertexIds({0, 1});
  e->setMeasurement(SE2(3, 0, kPi / 2));  // exact: b is 3 m ahead of a, turned by 90 deg
  auto& edge = static_cast<EdgeSE2&>(g.addEdge(std::move(e)));
  edge.computeError();
  EXPECT_NEAR(edge.error().norm(), 0.0, 1e-12);
  // 1 m further than measured along a's x axis, expressed in the measurement's frame
  // (rotated by 90 degrees): e_t = R_z^T (1, 0) = (0, -1).
  edge.setMeasurement(SE2(2, 0, kPi / 2));
  edge.computeError();
  EXPECT_NEAR(edge.error()[0], 0.0, 1e-12);
  EXPECT_NEAR(edge.error()[1], -1.0, 1e-12);
  EXPECT_NEAR(edge.error()[2], 0.0, 1e-12);
}

TEST(TypesSlam2d_EdgePointXY, ErrorIsDisplacementMinusMeasurement) {
  Graph g;
  auto& e = pointEdge<EdgePointXY>(g, {1, 2}, {4, -1}, {2.5, -3});
  EXPECT_NEAR(e.error()[0], 0.5, 1e-15);
  EXPECT_NEAR(e.error()[1], 0.0, 1e-15);
}

TEST(TypesSlam2d_EdgeXYBearingRange, ErrorWrapsAsTheHomework) {
  // The homework's warp2pi(a) = a - 2 pi floor((a + pi) / (2 pi)).
  auto warp2pi = [](double a) { return a - 2 * kPi * std::floor((a + kPi) / (2 * kPi)); };
  Graph g;
  // Landmark straight behind the robot (bearing pi); the measurement -3.2386 is unwrapped,
  // like the smallest bearing in 2d_nonlinear.npz.
  auto& e = pointEdge<EdgeXYBearingRange>(g, {1, 1}, {-2, 1}, {-3.2386, 2.5});
  EXPECT_NEAR(e.error()[0], warp2pi(kPi - -3.2386), 1e-12);
  EXPECT_NEAR(e.error()[0], 3.2386 - kPi, 1e-12);  // pi + 3.2386 wrapped
  EXPECT_NEAR(e.error()[1], 0.5, 1e-15);
  for (double a : {-7.0, -3.5, -kPi, -1.0, 0.0, 2.0, kPi - 1e-9, 4.0, 9.5}) {
    EXPECT_NEAR(normalizeAngle(a), warp2pi(a), 1e-12) << a;
  }
}

TEST(TypesSlam2d_EdgeXYBearingRange, JacobianIsTheHomeworksHl) {
  // H_l = [[dy/q, -dx/q, -dy/q, dx/q], [-dx/d, -dy/d, dx/d, dy/d]] for the prediction h;
  // our error is h - z, so its Jacobian is H_l.
  Graph g;
  auto& e = pointEdge<EdgeXYBearingRange>(g, {0.5, -1}, {2.5, 0.5}, {0.6, 2.4});
  e.linearizeOplus();
  const double dx = 2, dy = 1.5, q = dx * dx + dy * dy, d = std::sqrt(q);
  Eigen::Matrix<double, 2, 4> expected;
  expected << dy / q, -dx / q, -dy / q, dx / q, -dx / d, -dy / d, dx / d, dy / d;
  EXPECT_TRUE(e.jacobian<0>().isApprox(expected.leftCols<2>(), 1e-14));
  EXPECT_TRUE(e.jacobian<1>().isApprox(expected.rightCols<2>(), 1e-14));
}

TEST(TypesSlam2d_Register, AllTagsRegistered) {
  TypeRegistry types;
  registerTypes(types);
  for (const char* tag :
       {"VERTEX_SE2", "VERTEX_XY", "PARAMS_SE2OFFSET", "EDGE_SE2", "EDGE_SE2_XY", "EDGE_PRIOR_SE2",
        "EDGE_PRIOR_SE2_XY", "EDGE_SE2_OFFSET", "EDGE_SE2_POINTXY_OFFSET", "EDGE_BEARING_SE2_XY",
        "EDGE_SE2_XY_CALIB", "EDGE_SE2_TWOPOINTSXY", "EDGE_SE2_LOTSOFXY", "EDGE_POINTXY",
        "EDGE_PRIOR_XY", "EDGE_XY_BEARING_RANGE"}) {
    EXPECT_TRUE(types.contains(tag)) << tag;
  }
  EXPECT_THROW(registerTypes(types), RegistryError);  // duplicates are refused
}

}  // namespace

namespace {

/// A noise-free graph with all estimates zero but pose 0 (as an edges-only file gives);
/// angles wrap several times around. Poses 0..59 with ids i * id_step, landmark
/// 100 * id_step.
struct NoiseFreeGraph {
  Graph g;
  std::vector<SE2> truth;
  Eigen::Vector2d landmark{1.0, -2.0};
  static constexpr int kPoses = 60;
  int id_step;

  [[nodiscard]] int id(int i) const { return i * id_step; }

  explicit NoiseFreeGraph(int step = 1) : id_step(step) {
    for (int i = 0; i < kPoses; ++i) {
      truth.emplace_back(3 * std::cos(0.5 * i), 3 * std::sin(0.5 * i), 0.5 * i + 1.0);
      auto v = std::make_unique<VertexSE2>();
      v->setId(id(i));
      if (i == 0) v->setEstimate(truth[0]);
      g.addVertex(std::move(v));
    }
    auto link = [&](int i, int j) {
      auto e = std::make_unique<EdgeSE2>();
      e->setVertexIds({id(i), id(j)});
      e->setMeasurement(truth[i].inverse() * truth[j]);
      g.addEdge(std::move(e));
    };
    for (int i = 0; i + 1 < kPoses; ++i) link(i, i + 1);
    for (int i = 0; i + 13 < kPoses; i += 5) link(i, i + 13);
    auto lm = std::make_unique<VertexXY>();
    lm->setId(id(100));
    g.addVertex(std::move(lm));
    for (int i = 0; i < kPoses; i += 7) {
      auto e = std::make_unique<EdgeSE2XY>();
      e->setVertexIds({id(i), id(100)});
      e->setMeasurement(truth[i].rotation().transpose() * (landmark - truth[i].translation()));
      g.addEdge(std::move(e));
    }
  }

  void expectExact(const InitializationReport& report) {
    ASSERT_TRUE(report.message.empty()) << report.message;
    EXPECT_EQ(report.poses, static_cast<std::size_t>(kPoses - 1));  // pose 0 holds the gauge
    EXPECT_EQ(report.landmarks, 1u);
    for (int i = 0; i < kPoses; ++i) {
      const SE2& got = static_cast<VertexSE2*>(g.vertex(id(i)))->estimate();
      EXPECT_NEAR((got.translation() - truth[i].translation()).norm(), 0.0, 1e-9) << i;
      EXPECT_NEAR(normalizeAngle(got.angle() - truth[i].angle()), 0.0, 1e-12) << i;
    }
    EXPECT_NEAR((static_cast<VertexXY*>(g.vertex(id(100)))->estimate() - landmark).norm(), 0.0,
                1e-9);
    EXPECT_LT(g.chi2(), 1e-16);
  }
};

TEST(TypesSlam2d_Initialization, NoiseFreeGraphFromZeroEstimatesIsExact) {
  NoiseFreeGraph f;
  f.expectExact(initializeGlobal(f.g));
}

TEST(TypesSlam2d_Initialization, SparseIdsGiveTheSameGuess) {
  // Ids spread far apart (poses are then looked up by hashing, not through a table over
  // the id range).
  NoiseFreeGraph f(1000003);
  f.expectExact(initializeGlobal(f.g));
}

TEST(TypesSlam2d_Initialization, EverySolverOfTheNormalEquationsGivesTheSameGuess) {
  // The orientation system has diagonal blocks w I and rotation blocks off the diagonal:
  // its structural zeros must reach the solvers as complete blocks (block-llt reads a
  // block with one stride per vertex).
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  for (const auto* entry : registry.entries()) {
    for (Ordering ordering : entry->orderings) {
      LinearSolverOptions options;
      options.ordering = ordering;
      const auto solver = registry.create(entry->name, options);
      if (solver->form() == SystemForm::kJacobian) continue;
      // The orientation system's rotation blocks are not multiples of I.
      if (entry->name == "isotropic") continue;
      SCOPED_TRACE(entry->name + ":" + toString(ordering));
      NoiseFreeGraph f;
      f.expectExact(initializeGlobal(f.g, solver.get()));
    }
  }
}

// Odometry and landmark observations only (no loop closure, like victoria_park): the
// orientations of odometry alone are the dead-reckoned ones, which drift; the landmarks,
// seen from poses far apart along the path, must correct them.
TEST(TypesSlam2d_Initialization, LandmarksCorrectTheOrientationsOfOdometry) {
  ManhattanOptions o;
  o.num_poses = 1000;
  o.num_landmarks = 40;
  o.loop_probability = 0.0;
  o.sigma_theta = 0.02;
  auto sim = simulateManhattan(o);
  Graph& g = sim.graph;
  ASSERT_EQ(sim.num_loop_closures, 0u);
  ASSERT_GT(sim.num_observations, 0u);
  g.vertex(0)->setFixed(true);
  static_cast<VertexSE2*>(g.vertex(0))->setEstimate(sim.true_poses[0]);
  auto heading_rms = [&] {
    double sum = 0.0;
    for (int i = 0; i < o.num_poses; ++i) {
      const double d = normalizeAngle(static_cast<VertexSE2*>(g.vertex(i))->estimate().angle() -
                                      sim.true_poses[i].angle());
      sum += d * d;
    }
    return std::sqrt(sum / o.num_poses);
  };
  const double dead_reckoning = heading_rms();
  const double chi2_before = g.chi2();
  const InitializationReport r = initializeGlobal(g);
  ASSERT_TRUE(r.message.empty()) << r.message;
  const double initialised = heading_rms();
  std::printf("heading rms: dead reckoning %.4f rad, initialised %.4f rad; chi2 %.6g -> %.6g\n",
              dead_reckoning, initialised, chi2_before, g.chi2());
  EXPECT_GT(dead_reckoning, 0.1);
  EXPECT_LT(initialised, 0.25 * dead_reckoning);  // 0.061 against 0.40 rad
}

TEST(TypesSlam2d_Simulator, SeededAndConsistentWithTruth) {
  ManhattanOptions o;
  o.num_poses = 300;
  o.num_landmarks = 20;
  auto a = simulateManhattan(o);
  const auto b = simulateManhattan(o);
  EXPECT_EQ(a.graph.numEdges(), b.graph.numEdges());
  EXPECT_GT(a.num_loop_closures, 0u);
  EXPECT_GT(a.num_observations, 0u);
  EXPECT_EQ(a.graph.numVertices(), 320u);
  for (int i = 0; i < o.num_poses; ++i) {
    EXPECT_EQ(static_cast<const VertexSE2*>(a.graph.vertex(i))->estimate().toVector(),
              static_cast<const VertexSE2*>(b.graph.vertex(i))->estimate().toVector());
  }
  o.seed = 43;
  const auto c = simulateManhattan(o);
  EXPECT_NE(static_cast<const VertexSE2*>(c.graph.vertex(299))->estimate().toVector(),
            static_cast<const VertexSE2*>(a.graph.vertex(299))->estimate().toVector());
  // chi2 at the ground truth is about the number of measurement dimensions.
  Graph& g = a.graph;
  for (int i = 0; i < o.num_poses; ++i)
    static_cast<VertexSE2*>(g.vertex(i))->setEstimate(a.true_poses[i]);
  for (int k = 0; k < o.num_landmarks; ++k) {
    if (auto* v = g.vertex(o.num_poses + k))
      static_cast<VertexXY*>(v)->setEstimate(a.true_landmarks[k]);
  }
  std::size_t dims = 0;
  for (const auto& e : g.edges()) dims += static_cast<std::size_t>(e->dimension());
  EXPECT_NEAR(g.chi2() / static_cast<double>(dims), 1.0, 0.15);
}

}  // namespace
