// SPDX-License-Identifier: MIT
// IncrementalOptimizer against the batch Optimizer on the same graphs: estimates and chi2 after
// updates, marginal covariances, failures, edge removal, direct graph changes, 3D.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "graphslam/core/graph_copy.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/incremental/incremental_optimizer.h"
#include "graphslam/optimizer/marginals.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam2d/edge_bearing_se2_xy.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"
#include "graphslam/types_slam3d/edges.h"
#include "graphslam/types_slam3d/register.h"
#include "graphslam/types_slam3d/vertex_se3.h"

namespace graphslam {
namespace {

using incremental::IncrementalOptimizer;
using types_slam2d::SE2;
using types_slam3d::SE3;

struct Registries {
  Registries() {
    types_slam2d::registerTypes(types);
    types_slam3d::registerTypes(types);
    solvers::registerSolvers(solvers);
  }
  TypeRegistry types;
  SolverRegistry solvers;
};

Registries& registries() {
  static Registries r;
  return r;
}

double batchChi2(const Graph& g, Graph* optimised = nullptr) {
  Graph copy = incremental::copyGraph(g, registries().types);
  Optimizer opt(copy, registries().solvers);
  const Summary s = opt.optimize();
  EXPECT_TRUE(s.succeeded()) << s.message;
  const double chi2 = opt.chi2();
  if (optimised != nullptr) *optimised = std::move(copy);
  return chi2;
}

// A robot driving `laps` times around a square of `side` poses, with noisy odometry and a
// loop closure to the pose one lap before; poses are added one by one.
class SquareLaps {
 public:
  SquareLaps(int side, int laps, unsigned seed) : side_(side), rng_(seed) {
    const int n = 4 * side * laps;
    for (int k = 0; k < n; ++k) {
      const double heading = (k / side) * M_PI / 2;
      const int along = k % side;
      const Eigen::Vector2d corner[4] = {{0, 0}, {side, 0}, {side, side}, {0, side}};
      const Eigen::Vector2d dir(std::cos(heading), std::sin(heading));
      const Eigen::Vector2d p = corner[(k / side) % 4] + along * dir;
      truth_.emplace_back(p.x(), p.y(), heading);
    }
  }
  [[nodiscard]] int size() const { return static_cast<int>(truth_.size()); }

  // Adds pose k (composed from the current estimate of k-1 and the odometry) and its edges.
  void addStep(IncrementalOptimizer& inc, int k) {
    std::normal_distribution<double> noise(0.0, 0.02);
    auto v = std::make_unique<types_slam2d::VertexSE2>();
    v->setId(k);
    if (k == 0) {
      v->setEstimate(truth_[0]);
      inc.addVertex(std::move(v));
      return;
    }
    const SE2 odo =
        truth_[k - 1].inverse() * truth_[k] * SE2(noise(rng_), noise(rng_), noise(rng_));
    const auto& prev = static_cast<const types_slam2d::VertexSE2&>(*inc.graph().vertex(k - 1));
    v->setEstimate(prev.estimate() * odo);
    inc.addVertex(std::move(v));
    addEdge(inc, k - 1, k, odo);
    const int back = 4 * side_;
    if (k >= back) {
      addEdge(inc, k - back, k,
              truth_[k - back].inverse() * truth_[k] * SE2(noise(rng_), noise(rng_), noise(rng_)));
    }
  }

 private:
  static void addEdge(IncrementalOptimizer& inc, int i, int j, const SE2& z) {
    auto e = std::make_unique<types_slam2d::EdgeSE2>();
    e->setVertexIds({i, j});
    e->setMeasurement(z);
    e->setInformation(Eigen::Matrix3d::Identity() * 100.0);
    inc.addEdge(std::move(e));
  }

  int side_;
  std::mt19937 rng_;
  std::vector<SE2> truth_;
};

// Replays SquareLaps and compares with batch solves at random steps: chi2 within
// `chi2_tolerance` (relative) and positions within `position_tolerance`.
void expectBatchAgreement(const incremental::Options& options, double chi2_tolerance,
                          double position_tolerance) {
  Graph graph;
  IncrementalOptimizer inc(graph, options);
  SquareLaps laps(8, 4, 7);
  std::mt19937 pick(11);
  int checked = 0;
  for (int k = 0; k < laps.size(); ++k) {
    laps.addStep(inc, k);
    ASSERT_TRUE(inc.update()) << inc.failure().message;
    if (k < 2 || pick() % 8 != 0) continue;
    Graph batch;
    const double expected = batchChi2(graph, &batch);
    EXPECT_NEAR(inc.chi2(), expected, chi2_tolerance * expected + 1e-9) << "step " << k;
    for (const auto& [id, v] : batch.vertices()) {
      const auto& a = static_cast<const types_slam2d::VertexSE2&>(*v).estimate();
      const auto& b = static_cast<const types_slam2d::VertexSE2&>(*graph.vertex(id)).estimate();
      EXPECT_LT((a.translation() - b.translation()).norm(), position_tolerance)
          << "step " << k << " pose " << id;
      EXPECT_LT(std::abs(types_slam2d::normalizeAngle(a.angle() - b.angle())), position_tolerance);
    }
    ++checked;
  }
  EXPECT_GT(checked, 5);
  EXPECT_TRUE(graph.vertex(0)->fixed()) << "the gauge: the first pose is fixed";
  // refine() brings the last estimates to the batch optimum.
  ASSERT_TRUE(inc.refine(1e-9));
  const double expected = batchChi2(graph);
  EXPECT_NEAR(inc.chi2(), expected, 1e-9 * expected);
}

TEST(Incremental, GrowingPoseGraphMatchesBatchAtRandomSteps) {
  // The default relinearisation threshold (0.1): estimates within a few hundredths of the
  // optimum's.
  expectBatchAgreement(incremental::Options{}, 5e-2, 3e-2);
}

TEST(Incremental, RelinearisationThreshold001MatchesBatchCloser) {
  incremental::Options options;
  options.relinearize_threshold = 1e-2;
  expectBatchAgreement(options, 1e-4, 1e-3);
}

TEST(Incremental, TighterRelinearisationThresholdMatchesBatchCloser) {
  incremental::Options options;
  options.relinearize_threshold = 1e-3;
  expectBatchAgreement(options, 1e-6, 1e-4);
}

// Every supernode of the elimination tree in one front (the test graphs' fronts are below
// the default's 48 rows, so this is where supernodal elimination is checked).
TEST(Incremental, ChainsInOneFrontMatchBatchToo) {
  incremental::Options options;
  options.relinearize_threshold = 1e-3;
  options.chain_min_front_rows = 1;
  expectBatchAgreement(options, 1e-6, 1e-4);
}

// A step that would change by less than the back-substitution threshold keeps its old value
// (so that such changes cannot add up unseen): an edge that agrees with the current
// estimates moves the solution of the re-eliminated vertices only a little, and no estimate
// changes.
TEST(Incremental, StepsChangingLessThanTheThresholdKeepTheirValue) {
  Graph graph;
  IncrementalOptimizer inc(graph);
  SquareLaps laps(6, 2, 5);
  for (int k = 0; k < laps.size(); ++k) {
    laps.addStep(inc, k);
    ASSERT_TRUE(inc.update());
  }
  const int n = laps.size();
  const auto pose = [&graph](int k) {
    return static_cast<const types_slam2d::VertexSE2&>(*graph.vertex(k)).estimate();
  };
  std::vector<Eigen::Vector3d> before;
  for (int k = 0; k < n; ++k) before.push_back(pose(k).toVector());
  auto e = std::make_unique<types_slam2d::EdgeSE2>();
  e->setVertexIds({n - 3, n - 1});
  e->setMeasurement(pose(n - 3).inverse() * pose(n - 1));
  e->setInformation(Eigen::Matrix3d::Identity());
  inc.addEdge(std::move(e));
  ASSERT_TRUE(inc.update());
  EXPECT_GE(inc.lastStats().eliminated_columns, 3);
  for (int k = 0; k < n; ++k) EXPECT_EQ(pose(k).toVector(), before[k]) << "vertex " << k;
}

TEST(Incremental, RelinearisationSkipStillEndsAtTheOptimumAfterRefine) {
  incremental::Options options;
  options.relinearize_skip = 10;
  // Between checks the new edges are solved at old linearisation points: centimetres here.
  expectBatchAgreement(options, 1.0, 5e-2);
}

// A chain of SE2 poses along x with odometry edges, built through an IncrementalOptimizer.
class ChainOnX {
 public:
  explicit ChainOnX(const incremental::Options& options) : inc(graph, options) {}
  void addPose(int id, double x) {
    auto v = std::make_unique<types_slam2d::VertexSE2>();
    v->setId(id);
    v->setEstimate(SE2(x, 0.0, 0.0));
    inc.addVertex(std::move(v));
  }
  void addOdometry(int from, double dx) {
    auto e = std::make_unique<types_slam2d::EdgeSE2>();
    e->setVertexIds({from, from + 1});
    e->setMeasurement(SE2(dx, 0.0, 0.0));
    e->setInformation(Eigen::Matrix3d::Identity());
    inc.addEdge(std::move(e));
  }
  // Poses 0 and 1 (update 0), then pose 2 placed at 2.0 with odometry of 1.5 (update 1,
  // which moves it by 0.5, above the default threshold).
  [[nodiscard]] bool startWithAJump() {
    addPose(0, 0.0);
    addPose(1, 1.0);
    addOdometry(0, 1.0);
    if (!inc.update()) return false;
    addPose(2, 2.0);
    addOdometry(1, 1.5);
    return inc.update();
  }
  // Pose `id` at x with odometry that agrees with the estimates (pose id - 1 is at x - 1).
  [[nodiscard]] bool addAgreeingPose(int id, double x) {
    addPose(id, x);
    addOdometry(id - 1, 1.0);
    return inc.update();
  }
  Graph graph;
  IncrementalOptimizer inc;
};

TEST(Incremental, RelinearisationSkipChecksTheStepsOfTheUpdatesBetween) {
  // Relinearisation checked at every third update. Update 1 (no check) moves pose 2 by
  // 0.5 > the threshold; updates 2 and 3 add edges that agree with the estimates, so pose 2's
  // step does not change again. The check of update 3 must still relinearise it: afterwards
  // refine() at the threshold has nothing left to do.
  incremental::Options options;
  options.relinearize_skip = 3;
  ChainOnX chain(options);
  ASSERT_TRUE(chain.startWithAJump());  // update 1 does not check: pose 2 not relinearised
  EXPECT_EQ(chain.inc.lastStats().relinearized_vertices, 0);
  ASSERT_TRUE(chain.addAgreeingPose(3, 3.5));  // update 2
  ASSERT_TRUE(chain.addAgreeingPose(4, 4.5));  // update 3: checks
  EXPECT_GE(chain.inc.lastStats().relinearized_vertices, 1);
  ASSERT_TRUE(chain.inc.refine(options.relinearize_threshold));
  EXPECT_EQ(chain.inc.lastStats().relinearized_vertices, 0);
  const auto& last = static_cast<const types_slam2d::VertexSE2&>(*chain.graph.vertex(4));
  EXPECT_NEAR(last.estimate().translation().x(), 4.5, 1e-9);
}

TEST(Incremental, OnePassPerUpdateRelinearisesAtTheStartOfTheNext) {
  // One solve per update (iSAM2's scheme): update 1 moves pose 2 by 0.5 > the threshold and
  // cannot relinearise it; update 2 must, before its solve (its new edge agrees with the
  // estimates, so nothing else would). Afterwards refine() at the threshold has nothing to do.
  incremental::Options options;
  options.max_passes = 1;
  ChainOnX chain(options);
  ASSERT_TRUE(chain.startWithAJump());  // update 1: pose 2 moves to 2.5
  EXPECT_EQ(chain.inc.lastStats().relinearized_vertices, 0);
  EXPECT_EQ(chain.inc.lastStats().passes, 1);
  EXPECT_TRUE(chain.inc.lastStats().pass_limit_reached);
  ASSERT_TRUE(chain.addAgreeingPose(3, 3.5));  // update 2
  EXPECT_GE(chain.inc.lastStats().relinearized_vertices, 1);
  EXPECT_EQ(chain.inc.lastStats().passes, 1);
  ASSERT_TRUE(chain.inc.refine(options.relinearize_threshold));
  EXPECT_EQ(chain.inc.lastStats().relinearized_vertices, 0);
}

TEST(Incremental, OnePassPerUpdateStillEndsAtTheOptimumAfterRefine) {
  incremental::Options options;
  options.max_passes = 1;
  expectBatchAgreement(options, 5e-2, 3e-2);
}

TEST(Incremental, UpdateAfterOdometryOnlyTouchesFewColumns) {
  Graph graph;
  IncrementalOptimizer inc(graph);
  SquareLaps laps(10, 1, 3);  // one lap: no loop closure
  for (int k = 0; k < laps.size(); ++k) {
    laps.addStep(inc, k);
    ASSERT_TRUE(inc.update());
    if (k > 5) {
      EXPECT_LE(inc.lastStats().eliminated_columns, 3) << "step " << k;
    }
  }
}

TEST(Incremental, MarginalCovarianceMatchesBatch) {
  Graph graph;
  incremental::Options options;
  options.relinearize_threshold = 1e-3;
  IncrementalOptimizer inc(graph, options);
  SquareLaps laps(6, 2, 5);
  for (int k = 0; k < laps.size(); ++k) {
    laps.addStep(inc, k);
    ASSERT_TRUE(inc.update());
  }
  MarginalCovariance marginals;
  const VertexId last = laps.size() - 1;
  ASSERT_TRUE(marginals.compute(graph, {last, 7}).ok());
  for (VertexId id : {last, VertexId{7}}) {
    const Eigen::MatrixXd expected = marginals.block(id);
    const Eigen::MatrixXd got = inc.marginalCovariance(id);
    // The incremental factor is linearised at points within the relinearisation threshold
    // (1e-3) of the estimates the batch computation linearises at.
    EXPECT_LT((got - expected).norm(), 2e-3 * expected.norm()) << "vertex " << id;
  }
  EXPECT_THROW((void)inc.marginalCovariance(0), Error);  // the fixed gauge vertex
}

// `options`: with chain_min_front_rows 1 the landmark is eliminated in one front with other
// vertices, and the failing member of that front is found.
void expectUndeterminedVertexFailsNamingIt(const incremental::Options& options) {
  Graph graph;
  IncrementalOptimizer inc(graph, options);
  SquareLaps laps(5, 1, 1);
  for (int k = 0; k < 6; ++k) laps.addStep(inc, k);
  ASSERT_TRUE(inc.update());
  const double before = inc.chi2();
  auto l = std::make_unique<types_slam2d::VertexXY>();
  l->setId(100);
  l->setEstimate(Eigen::Vector2d(3, 4));
  inc.addVertex(std::move(l));
  auto b = std::make_unique<types_slam2d::EdgeBearingSE2XY>();
  b->setVertexIds({5, 100});
  b->setMeasurement(0.3);
  inc.addEdge(std::move(b));
  EXPECT_FALSE(inc.update());
  EXPECT_EQ(inc.failure().vertex, 100);
  EXPECT_NE(inc.failure().message.find("vertex 100"), std::string::npos);
  EXPECT_EQ(static_cast<const types_slam2d::VertexXY&>(*graph.vertex(100)).estimate(),
            Eigen::Vector2d(3, 4));
  // A second bearing from another pose determines it.
  auto b2 = std::make_unique<types_slam2d::EdgeBearingSE2XY>();
  b2->setVertexIds({0, 100});
  b2->setMeasurement(0.9);
  inc.addEdge(std::move(b2));
  EXPECT_TRUE(inc.update()) << inc.failure().message;
  EXPECT_TRUE(inc.lastStats().rebuilt);
  EXPECT_GE(inc.chi2(), 0.0);
  EXPECT_GT(before, -1.0);
}

TEST(Incremental, UndeterminedVertexFailsNamingItAndKeepsEstimates) {
  expectUndeterminedVertexFailsNamingIt({});
  incremental::Options one_front;
  one_front.chain_min_front_rows = 1;
  expectUndeterminedVertexFailsNamingIt(one_front);
}

TEST(Incremental, RemovedEdgeAndDirectChangesRebuild) {
  Graph graph;
  // Every step solved exactly, so that each rebuilt factor ends at the optimum (with the
  // default fraction a step within 1e-3 of the old one keeps the old).
  incremental::Options options;
  options.backsubstitution_fraction = 0.0;
  IncrementalOptimizer inc(graph, options);
  SquareLaps laps(6, 3, 9);
  for (int k = 0; k < laps.size(); ++k) {
    laps.addStep(inc, k);
    ASSERT_TRUE(inc.update());
  }
  const Edge* closure = graph.edges().back().get();
  ASSERT_TRUE(inc.removeEdge(closure));
  ASSERT_TRUE(inc.update());
  EXPECT_EQ(inc.lastStats().removed_edges, 1);
  EXPECT_NEAR(inc.chi2(), batchChi2(graph), 1e-6 * batchChi2(graph));
  // An edge added to the graph directly, not through the optimizer.
  auto e = std::make_unique<types_slam2d::EdgeSE2>();
  e->setVertexIds({2, 30});
  e->setMeasurement(SE2(1.0, 0.5, 0.1));
  graph.addEdge(std::move(e));
  ASSERT_TRUE(inc.update());
  EXPECT_TRUE(inc.lastStats().rebuilt);
  EXPECT_NEAR(inc.chi2(), batchChi2(graph), 1e-6 * batchChi2(graph));
}

TEST(Incremental, Se3PoseGraphMatchesBatch) {
  Graph graph;
  incremental::Options options;
  options.relinearize_threshold = 1e-2;
  IncrementalOptimizer inc(graph, options);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<SE3> truth;
  const int n = 60;
  for (int k = 0; k < n; ++k) {
    Eigen::Matrix<double, 6, 1> xi;
    xi << 1.0, 0.0, 0.1, 0.0, 0.05, 2 * M_PI / 20;
    truth.push_back(k == 0 ? SE3() : truth.back() * SE3::exp(xi));
  }
  const auto noisy = [&](const SE3& z) {
    Eigen::Matrix<double, 6, 1> d;
    for (int i = 0; i < 6; ++i) d[i] = noise(rng);
    return z * SE3::exp(d);
  };
  for (int k = 0; k < n; ++k) {
    auto v = std::make_unique<types_slam3d::VertexSE3>();
    v->setId(k);
    SE3 odo;
    if (k > 0) {
      odo = noisy(truth[k - 1].inverse() * truth[k]);
      v->setEstimate(static_cast<const types_slam3d::VertexSE3&>(*graph.vertex(k - 1)).estimate() *
                     odo);
    }
    inc.addVertex(std::move(v));
    std::vector<std::pair<int, SE3>> edges;
    if (k > 0) edges.emplace_back(k - 1, odo);
    if (k >= 20) edges.emplace_back(k - 20, noisy(truth[k - 20].inverse() * truth[k]));
    for (const auto& [i, z] : edges) {
      auto e = std::make_unique<types_slam3d::EdgeSE3>();
      e->setVertexIds({i, k});
      e->setMeasurement(z);
      e->setInformation(Eigen::Matrix<double, 6, 6>::Identity() * 50.0);
      inc.addEdge(std::move(e));
    }
    ASSERT_TRUE(inc.update()) << inc.failure().message;
    if (k % 15 == 14) {
      const double expected = batchChi2(graph);
      EXPECT_NEAR(inc.chi2(), expected, 1e-4 * expected + 1e-9) << "step " << k;
    }
  }
}

// One new vertex alone in the re-eliminated part, which is all to go last (the ordering's
// constraint sets must stay below their count: a replay of garage crashed on it).
TEST(Incremental, SingleVertexUnderAPrior) {
  Graph graph;
  IncrementalOptimizer inc(graph);
  auto v = std::make_unique<types_slam2d::VertexSE2>();
  v->setId(0);
  inc.addVertex(std::move(v));
  auto prior = registries().types.createEdge("EDGE_PRIOR_SE2");
  prior->setVertexIds({0});
  const double z[3] = {1.0, 2.0, 0.5};
  prior->setMeasurementData(z);
  inc.addEdge(std::move(prior));
  ASSERT_TRUE(inc.update()) << inc.failure().message;
  EXPECT_NEAR(inc.chi2(), 0.0, 1e-20);
  EXPECT_EQ(inc.factorColumns(), 1u);
}

TEST(Incremental, OptionsOutOfRangeThrow) {
  Graph graph;
  incremental::Options o;
  o.relinearize_threshold = -1.0;
  EXPECT_THROW(IncrementalOptimizer(graph, o), Error);
  o = {};
  o.max_passes = 0;
  EXPECT_THROW(IncrementalOptimizer(graph, o), Error);
  o = {};
  o.refine_max_passes = 0;
  EXPECT_THROW(IncrementalOptimizer(graph, o), Error);
  o = {};
  o.backsubstitution_fraction = std::nan("");
  EXPECT_THROW(IncrementalOptimizer(graph, o), Error);
  o = {};
  o.relinearize_skip = 0;
  EXPECT_THROW(IncrementalOptimizer(graph, o), Error);
  o = {};
  o.chain_min_front_rows = 0;
  EXPECT_THROW(IncrementalOptimizer(graph, o), Error);
  IncrementalOptimizer inc(graph);
  EXPECT_THROW((void)inc.refine(), Error) << "refine before update";
  EXPECT_THROW((void)inc.refine(-1.0), Error);
}

}  // namespace
}  // namespace graphslam
