// SPDX-License-Identifier: MIT
// The replay protocol (incremental/replay.h) through the IncrementalOptimizer: where poses
// and landmarks start, gaps, rank-deficient first observations, failures, 3D graphs with
// parameters, and the estimates against batch solves of the same graph.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <set>
#include <sstream>

#include "../common/test_util.h"
#include "graphslam/core/graph_copy.h"
#include "graphslam/incremental/replay.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/io/g2o.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/robust/kernels.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/simulator3d.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"
#include "graphslam/types_slam3d/register.h"

using namespace graphslam;
using incremental::ReplayOptions;
using incremental::ReplayResult;

namespace {

struct Registries {
  TypeRegistry types;
  SolverRegistry solvers;
  Registries() {
    types_slam2d::registerTypes(types);
    types_slam3d::registerTypes(types);
    solvers::registerSolvers(solvers);
  }
};

Graph readText(const std::string& text, const TypeRegistry& types) {
  std::istringstream in(text);
  io::LoadResult r = io::readG2o(in, "test.g2o", types);
  if (!r.ok()) throw Error(r.diagnostics.at(0).str());
  return std::move(r.graph);
}

Eigen::Vector3d pose(const Graph& g, VertexId id) {
  const auto& e = static_cast<const types_slam2d::VertexSE2*>(g.vertex(id))->estimate();
  return {e.translation().x(), e.translation().y(), e.angle()};
}

Eigen::Vector2d point(const Graph& g, VertexId id) {
  return static_cast<const types_slam2d::VertexXY*>(g.vertex(id))->estimate();
}

/// The batch optimum of `source` as the tool reaches it: global initial guess, then the
/// optimizer's defaults, on a copy.
double batchOptimum(const Graph& source, const Registries& reg) {
  Graph copy = incremental::copyGraph(source, reg.types);
  const auto solver = reg.solvers.create("auto");
  (void)init::initializeGlobal(copy, solver.get());
  Optimizer optimizer(copy, reg.solvers);
  const Summary s = optimizer.optimize();
  EXPECT_TRUE(s.succeeded()) << s.message;
  return s.final_cost;
}

/// A seeded Manhattan world with landmarks (EDGE_SE2_XY), dead-reckoned estimates.
simulation::SimulatedGraph simulateLandmarkGraph(int poses, int landmarks, std::uint32_t seed) {
  simulation::ManhattanOptions sim;
  sim.num_poses = poses;
  sim.num_landmarks = landmarks;
  sim.seed = seed;
  return simulation::simulateManhattan(sim);
}

/// A seeded 3D grid of poses with points seen through a PARAMS_SE3OFFSET sensor.
simulation::SimulatedGraph3d simulateGrid3d(int poses, int points, std::uint32_t seed) {
  simulation::PoseGraph3dOptions sim;
  sim.shape = simulation::PoseGraph3dOptions::Shape::kGrid;
  sim.num_poses = poses;
  sim.num_points = points;
  sim.seed = seed;
  return simulation::simulatePoseGraph3d(sim);
}

constexpr const char* kInfo3 = " 100 0 0 100 0 100\n";

/// The relinearisation threshold of the comparisons with the batch optimizer. At 1e-2 the
/// estimates between updates are further from the batch solution than 1e-6 relative in
/// chi2 (intel: up to 7.7e-6, poses up to 8.2e-4 apart, at the steps drawn below), and at
/// the default (iSAM2's 0.1) the replay of intel ends 8.2e-4 above the batch optimum; at
/// 1e-3 both agree to 1e-6, which is what these tests hold the replay and optimizer to
/// (refine() closes the gap from any threshold: IntelRefineClosesTheGap).
constexpr double kCheckedThreshold = 1e-3;

ReplayOptions checkedOptions() {
  ReplayOptions options;
  options.optimizer.relinearize_threshold = kCheckedThreshold;
  return options;
}

/// Replays `source` (relinearisation threshold kCheckedThreshold) and, at `count` steps
/// drawn with `seed`, compares the estimates with a batch solve of the same graph (a copy
/// of the replayed graph at that step): chi2 within 1e-6 relative, every estimate entry
/// within `tolerance`.
void expectAgreementAtRandomSteps(const Graph& source, const Registries& reg, unsigned seed,
                                  int count, double tolerance) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::size_t> pick(1, source.numVertices() / 2);
  std::set<std::size_t> steps;
  while (static_cast<int>(steps.size()) < count) steps.insert(pick(random));
  ReplayOptions options = checkedOptions();
  std::size_t checked = 0;
  options.after_step = [&](std::size_t step, const incremental::ReplayStep&, const Graph& g) {
    if (!steps.count(step)) return;
    const auto c = incremental::compareWithBatch(g, reg.types, reg.solvers);
    ASSERT_TRUE(c.ok()) << "step " << step << ": " << c.summary.message;
    EXPECT_LE(std::abs(c.relative_gap), 1e-6)
        << "step " << step << ": chi2 " << c.chi2 << " batch " << c.batch_chi2;
    EXPECT_LE(c.max_difference, tolerance) << "step " << step << ": vertex " << c.worst_vertex;
    ++checked;
  };
  Graph target;
  const ReplayResult r = incremental::replayGraph(source, reg.types, target, options);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(checked, static_cast<std::size_t>(std::count_if(
                         steps.begin(), steps.end(), [&](auto s) { return s < r.steps.size(); })));
}

TEST(Incremental_Replay, PosesAreComposedFromTheCurrentEstimateAndTheOdometry) {
  Registries reg;
  // File estimates far off: the replay must not use them (but for the first pose).
  const Graph source = readText(std::string("VERTEX_SE2 0 1 2 0.5\nVERTEX_SE2 1 50 50 3\n") +
                                    "VERTEX_SE2 2 -9 7 -2\nEDGE_SE2 0 1 1 0 0.5" + kInfo3 +
                                    "EDGE_SE2 2 1 -1 0 -0.25" + kInfo3,
                                reg.types);
  ReplayOptions options;
  options.record_chi2 = true;
  std::vector<Eigen::Vector3d> after;
  options.after_step = [&](std::size_t step, const incremental::ReplayStep& s, const Graph& g) {
    after.push_back(pose(g, s.pose));
    EXPECT_EQ(g.numVertices(), step + 1);
  };
  Graph target;
  const ReplayResult r = incremental::replayGraph(source, reg.types, target, options);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.pose_tag, "VERTEX_SE2");
  ASSERT_EQ(r.steps.size(), 3u);
  EXPECT_EQ(r.gaps, 0);
  EXPECT_EQ(r.initialised_from_file, 0);
  // 0 -> 1: (1, 0, 0.5) in the frame of (1, 2, 0.5); the edge 2 -> 1 read backwards.
  const Eigen::Vector3d p1(1 + std::cos(0.5), 2 + std::sin(0.5), 1.0);
  const Eigen::Vector3d p2 = p1 + Eigen::Vector3d(std::cos(1.25), std::sin(1.25), 0.25);
  EXPECT_LT((after[0] - Eigen::Vector3d(1, 2, 0.5)).norm(), 1e-9);
  EXPECT_LT((after[1] - p1).norm(), 1e-9) << after[1].transpose();
  EXPECT_LT((after[2] - p2).norm(), 1e-9) << after[2].transpose();
  for (const auto& s : r.steps) EXPECT_LT(s.chi2, 1e-16);
  EXPECT_EQ(r.steps[1].new_edges, 1);
  EXPECT_EQ(r.steps[2].pose, 2);
}

TEST(Incremental_Replay, LandmarksArePlacedByTheirFirstObservation) {
  Registries reg;
  // Landmark 5 (between the pose ids) first seen from pose 1, then from 2; its file
  // estimate is far off.
  const Graph source =
      readText(std::string("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\nVERTEX_XY 5 100 100\n") +
                   "VERTEX_SE2 7 0 0 0\nEDGE_SE2 0 1 1 0 1.5707963267948966" + kInfo3 +
                   "EDGE_SE2_XY 1 5 2 0 100 0 100\nEDGE_SE2 1 7 1 0 0" + kInfo3 +
                   "EDGE_SE2_XY 7 5 1 0 100 0 100\n",
               reg.types);
  ReplayOptions options;
  std::vector<Eigen::Vector2d> landmark;
  options.after_step = [&](std::size_t, const incremental::ReplayStep&, const Graph& g) {
    if (g.hasVertex(5)) landmark.push_back(point(g, 5));
  };
  Graph target;
  const ReplayResult r = incremental::replayGraph(source, reg.types, target, options);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.num_landmarks, 1u);
  ASSERT_EQ(r.steps.size(), 3u);
  EXPECT_EQ(r.steps[1].new_landmarks, 1);
  EXPECT_EQ(r.steps[1].new_edges, 2);
  EXPECT_EQ(r.steps[2].pose, 7);
  ASSERT_EQ(landmark.size(), 2u);
  // Pose 1 is (1, 0, pi/2): 2 m ahead of it is (1, 2).
  EXPECT_LT((landmark[0] - Eigen::Vector2d(1, 2)).norm(), 1e-9) << landmark[0].transpose();
  EXPECT_LT((landmark[1] - Eigen::Vector2d(1, 2)).norm(), 1e-9);
  EXPECT_EQ(r.initialised_from_file, 0);
  EXPECT_LT(r.final_chi2, 1e-16);
}

TEST(Incremental_Replay, GapKeepsTheFileEstimate) {
  Registries reg;
  // No edge 1 -> 2: pose 2 starts at the file's estimate, then its edge from 0 moves it.
  const Graph source =
      readText(std::string("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 9 9 0\n") +
                   "VERTEX_SE2 2 2.5 0.5 0.1\nVERTEX_SE2 3 0 0 0\n" + "EDGE_SE2 0 1 1 0 0" +
                   kInfo3 + "EDGE_SE2 0 2 2 0 0" + kInfo3 + "EDGE_SE2 2 3 1 0 0" + kInfo3,
               reg.types);
  Graph target;
  const ReplayResult r = incremental::replayGraph(source, reg.types, target);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.gaps, 1);
  EXPECT_LT((pose(target, 2) - Eigen::Vector3d(2, 0, 0)).norm(), 1e-6);
  EXPECT_LT((pose(target, 3) - Eigen::Vector3d(3, 0, 0)).norm(), 1e-6);
}

TEST(Incremental_Replay, RankDeficientFirstObservationTakesTheFileEstimate) {
  Registries reg;
  // Landmark 3 is first seen by bearing only (no range: the file's estimate is kept and
  // counted); its prior, which has no pose endpoint, comes in the same step. (Pose 0 is
  // fixed: a unary edge means the optimizer fixes no vertex for the gauge.)
  const Graph source = readText(std::string("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\n") +
                                    "VERTEX_XY 3 1.5 1.5\nEDGE_SE2 0 1 1 0 0" + kInfo3 +
                                    "EDGE_BEARING_SE2_XY 0 3 0.7853981633974483 100\n" +
                                    "EDGE_PRIOR_XY 3 1 1 1 0 1\nFIX 0\n",
                                reg.types);
  Graph target;
  std::vector<std::size_t> vertices;
  ReplayOptions options;
  options.after_step = [&](std::size_t, const incremental::ReplayStep&, const Graph& g) {
    vertices.push_back(g.numVertices());
  };
  const ReplayResult r = incremental::replayGraph(source, reg.types, target, options);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.initialised_from_file, 1);
  EXPECT_EQ(vertices, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(r.steps[0].new_edges, 2);
  EXPECT_LT((point(target, 3) - Eigen::Vector2d(1, 1)).norm(), 1e-6);
}

TEST(Incremental_Replay, FailingUpdateStopsAndNamesTheVertex) {
  Registries reg;
  // A landmark seen once by bearing: nothing determines its range, the update fails.
  const Graph source = readText(std::string("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\n") +
                                    "VERTEX_XY 3 1 1\nVERTEX_SE2 4 0 0 0\nEDGE_SE2 0 1 1 0 0" +
                                    kInfo3 + "EDGE_BEARING_SE2_XY 1 3 1.5707963267948966 100\n" +
                                    "EDGE_SE2 1 4 1 0 0" + kInfo3,
                                reg.types);
  Graph target;
  const ReplayResult r = incremental::replayGraph(source, reg.types, target);
  EXPECT_FALSE(r.ok);
  ASSERT_EQ(r.steps.size(), 2u);
  EXPECT_NE(r.error.find("step 1 (pose 1): "), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("3"), std::string::npos) << r.error;
  EXPECT_EQ(r.initialised_from_file, 1);
}

TEST(Incremental_Replay, TargetMustBeEmpty) {
  Registries reg;
  const Graph source = readText("VERTEX_SE2 0 0 0 0\n", reg.types);
  Graph target = incremental::copyGraph(source, reg.types);
  EXPECT_THROW_MSG((void)incremental::replayGraph(source, reg.types, target), Error,
                   "must be empty");
}

TEST(Incremental_Replay, LandmarkGraphEndsAtTheBatchOptimum) {
  Registries reg;
  const auto simulated = simulateLandmarkGraph(300, 40, 11);
  Graph target;
  const ReplayResult r =
      incremental::replayGraph(simulated.graph, reg.types, target, checkedOptions());
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.steps.size(), 300u);
  EXPECT_EQ(r.initialised_from_file, 0);
  EXPECT_EQ(target.numEdges(), simulated.graph.numEdges());
  const double optimum = batchOptimum(simulated.graph, reg);
  EXPECT_LE(std::abs(r.final_chi2 - optimum), 1e-6 * optimum)
      << "incremental " << r.final_chi2 << ", batch " << optimum;
  EXPECT_TRUE(std::isnan(r.refined_chi2));  // no refine() unless asked
}

TEST(Incremental_Replay, Graph3dWithParametersAndPoints) {
  Registries reg;
  const auto simulated = simulateGrid3d(80, 15, 5);
  ASSERT_FALSE(simulated.graph.parameters().empty());
  Graph target;
  const ReplayResult r =
      incremental::replayGraph(simulated.graph, reg.types, target, checkedOptions());
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.pose_tag, "VERTEX_SE3:QUAT");
  EXPECT_EQ(r.steps.size(), 80u);
  EXPECT_EQ(r.initialised_from_file, 0);
  EXPECT_EQ(target.parameters().size(), simulated.graph.parameters().size());
  const auto c = incremental::compareWithBatch(target, reg.types, reg.solvers);
  ASSERT_TRUE(c.ok()) << c.summary.message;
  EXPECT_LE(std::abs(c.relative_gap), 1e-6) << c.chi2 << " vs " << c.batch_chi2;
}

TEST(Incremental_Replay, RandomStepsAgreeWithBatchSolves) {
  Registries reg;
  const auto simulated = simulateLandmarkGraph(400, 30, 3);
  // Landmarks seen from two or three poses move with the poses' stale linearisation
  // points: they agree to the relinearisation threshold (measured: 1.6e-4 m at 1e-3,
  // 1.4e-5 at 1e-4); the poses of the intel test below to 1e-4.
  expectAgreementAtRandomSteps(simulated.graph, reg, 2024, 8, kCheckedThreshold);
}

/// intel.g2o loaded, or null (the test is skipped) when the dataset is absent.
std::unique_ptr<Graph> loadIntel(const Registries& reg) {
  const std::string path = test::dataDir() + "/intel.g2o";
  if (!test::fileExists(path)) return nullptr;
  io::LoadResult loaded = io::loadG2o(path, reg.types);
  if (!loaded.ok()) throw Error(loaded.diagnostics.at(0).str());
  return std::make_unique<Graph>(std::move(loaded.graph));
}

#define GRAPHSLAM_SKIP_WITHOUT(graph) \
  if (!(graph))                       \
  GTEST_SKIP() << "dataset intel.g2o not found in " << test::dataDir() << " (set GRAPHSLAM_DATA)"

TEST(Incremental_Replay, IntelEndsAtTheBatchOptimum) {
  Registries reg;
  const auto intel = loadIntel(reg);
  GRAPHSLAM_SKIP_WITHOUT(intel);
  Graph target;
  const ReplayResult r = incremental::replayGraph(*intel, reg.types, target, checkedOptions());
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.steps.size(), 1728u);
  const double optimum = batchOptimum(*intel, reg);
  EXPECT_LE(std::abs(r.final_chi2 - optimum), 1e-6 * optimum)
      << "incremental " << r.final_chi2 << ", batch " << optimum;
}

TEST(Incremental_Replay, IntelRefineClosesTheGap) {
  Registries reg;
  const auto intel = loadIntel(reg);
  GRAPHSLAM_SKIP_WITHOUT(intel);
  Graph target;
  ReplayOptions options;  // the optimizer's default threshold
  options.refine_threshold = 1e-6;
  const ReplayResult r = incremental::replayGraph(*intel, reg.types, target, options);
  ASSERT_TRUE(r.ok) << r.error;
  const double optimum = batchOptimum(*intel, reg);
  EXPECT_LE(std::abs(r.refined_chi2 - optimum), 1e-10 * optimum)
      << "refined " << r.refined_chi2 << ", batch " << optimum << " (before refine " << r.final_chi2
      << ")";
  EXPECT_GT(r.refine_stats.passes, 0);
}

TEST(Incremental_Replay, IntelRandomStepsAgreeWithBatchSolves) {
  Registries reg;
  const auto intel = loadIntel(reg);
  GRAPHSLAM_SKIP_WITHOUT(intel);
  expectAgreementAtRandomSteps(*intel, reg, 38, 6, 1e-4);
}

TEST(Incremental_GraphCopy, CopiesEveryPartThroughTheRegistry) {
  Registries reg;
  auto simulated = simulateGrid3d(30, 5, 42);
  Graph& source = simulated.graph;
  source.vertex(0)->setFixed(true);
  auto kernel = std::make_shared<robust::CauchyKernel>(2.0);
  source.edges().front()->setRobustKernel(kernel);
  source.setEdgeActive(*source.edges().back(), false);
  const Graph copy = incremental::copyGraph(source, reg.types);
  // Written alike, but for the last bits of quaternions (normalised again on reading).
  std::ostringstream a, b;
  io::writeG2o(a, source, reg.types);
  io::writeG2o(b, copy, reg.types);
  std::istringstream ta(a.str()), tb(b.str());
  std::string x, y;
  std::size_t tokens = 0;
  while (ta >> x) {
    ASSERT_TRUE(tb >> y);
    ++tokens;
    if (x == y) continue;
    ASSERT_NEAR(std::stod(x), std::stod(y), 1e-15 * std::max(1.0, std::abs(std::stod(x))))
        << "token " << tokens;
  }
  EXPECT_FALSE(tb >> y);
  EXPECT_EQ(copy.edges().front()->robustKernel(), kernel.get());
  EXPECT_FALSE(copy.edges().back()->active());
  EXPECT_TRUE(copy.vertex(0)->fixed());
  EXPECT_EQ(copy.parameters().size(), source.parameters().size());
}

}  // namespace
