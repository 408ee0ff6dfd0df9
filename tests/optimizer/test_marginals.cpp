// SPDX-License-Identifier: MIT
// Marginal covariances against a dense inverse of H built independently from the edges'
// Jacobians.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <map>
#include <memory>
#include <random>

#include "../common/hessian_reference.h"
#include "graphslam/optimizer/marginals.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_drivebot/edge_compass.h"
#include "graphslam/types_drivebot/edge_gps.h"
#include "graphslam/types_drivebot/edge_landmark_range_bearing.h"
#include "graphslam/types_drivebot/edge_vehicle_kinematics.h"
#include "graphslam/types_drivebot/edge_vehicle_prior.h"
#include "graphslam/types_drivebot/vertex_landmark.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

using namespace graphslam;

namespace {

/// Marginals ordered by the solvers module's block AMD (registered in a SolverRegistry).
MarginalCovariance::Options amdOrdered(bool fix_gauge = true) {
  static const SolverRegistry registry = [] {
    SolverRegistry r;
    solvers::registerSolvers(r);
    return r;
  }();
  MarginalCovariance::Options o;
  o.fix_gauge = fix_gauge;
  o.solvers = &registry;
  return o;
}

/// Dense inverse of the independently assembled H.
struct DenseReference {
  std::map<VertexId, int> column;
  Eigen::MatrixXd cov;

  explicit DenseReference(Graph& g) {
    const test::HessianReference ref(g);
    column = ref.column;
    cov = Eigen::MatrixXd(ref.h).inverse();
  }

  Eigen::MatrixXd block(const Graph& g, VertexId a, VertexId b) const {
    const int da = g.vertex(a)->dimension();
    const int db = g.vertex(b)->dimension();
    if (!column.count(a) || !column.count(b)) return Eigen::MatrixXd::Zero(da, db);
    return cov.block(column.at(a), column.at(b), da, db);
  }
};

void expectClose(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want, double scale,
                 const std::string& what) {
  ASSERT_EQ(got.rows(), want.rows()) << what;
  ASSERT_EQ(got.cols(), want.cols()) << what;
  EXPECT_LE((got - want).cwiseAbs().maxCoeff(), 1e-9 * scale) << what << "\ngot\n"
                                                              << got << "\nwant\n"
                                                              << want;
}

/// Small Manhattan world with landmarks, loop closures and two fixed vertices.
Graph slam2dGraph(int poses, int landmarks, unsigned seed) {
  simulation::ManhattanOptions sim;
  sim.num_poses = poses;
  sim.num_landmarks = landmarks;
  sim.seed = seed;
  auto result = simulation::simulateManhattan(sim);
  return std::move(result.graph);
}

using namespace graphslam::types_drivebot;

/// DriveBot graph: vehicle chain (kinematics), GPS every 5 steps, compass every 3,
/// range-bearing observations of 4 landmarks, a prior on the first state.
Graph drivebotGraph(bool fix_first) {
  Graph g;
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 0.05);
  const double dt = 0.1;
  Eigen::Vector3d x(0, 0, 3.0);
  const std::vector<Eigen::Vector2d> landmarks = {{5, 3}, {-4, 6}, {2, -7}, {12, 1}};
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    auto l = std::make_unique<VertexLandmark>();
    l->setId(100 + static_cast<int>(i));
    l->setEstimate(landmarks[i] + Eigen::Vector2d(noise(rng), noise(rng)));
    g.addVertex(std::move(l));
  }
  for (int k = 0; k < 40; ++k) {
    auto v = std::make_unique<VertexVehicle>();
    v->setId(k);
    v->setTime(k * dt);
    v->setEstimate(x + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    if (k == 0 && fix_first) v->setFixed(true);
    g.addVertex(std::move(v));
    if (k == 0) {
      auto p = std::make_unique<EdgeVehiclePrior>();
      p->setVertexIds({0});
      p->setMeasurement(x);
      p->setInformation(Eigen::Vector3d(100, 100, 400).asDiagonal());
      g.addEdge(std::move(p));
    } else {
      auto e = std::make_unique<EdgeVehicleKinematics>();
      e->setVertexIds({k - 1, k});
      e->setDeltaT(dt);
      e->setMeasurement({6, 0, 0.5});
      e->setInformation(Eigen::Vector3d(25, 100, 3282.8).asDiagonal());
      g.addEdge(std::move(e));
    }
    if (k % 5 == 0) {
      auto e = std::make_unique<EdgeGps>();
      e->setVertexIds({k});
      e->setMeasurement(x.head<2>() + Eigen::Vector2d(10, -20));
      g.addEdge(std::move(e));
    }
    if (k % 3 == 0) {
      auto e = std::make_unique<EdgeCompass>();
      e->setVertexIds({k});
      e->setOffset(0.75 * 3.14159265358979);
      e->setMeasurement(wrapAngle(x[2] + 0.75 * 3.14159265358979));
      e->setInformation(Eigen::Matrix<double, 1, 1>(131.3));
      g.addEdge(std::move(e));
    }
    for (std::size_t i = 0; i < landmarks.size(); ++i) {
      if ((k + static_cast<int>(i)) % 4 != 0) continue;
      const Eigen::Vector2d d = landmarks[i] - x.head<2>();
      auto e = std::make_unique<EdgeLandmarkRangeBearing>();
      e->setVertexIds({k, 100 + static_cast<int>(i)});
      e->setMeasurement({d.norm(), wrapAngle(std::atan2(d.y(), d.x()) - x[2])});
      e->setInformation(Eigen::Vector2d(100, 3282.8).asDiagonal());
      g.addEdge(std::move(e));
    }
    x = EdgeVehicleKinematics::predict(x, {6, 0, 0.5}, dt);
  }
  return g;
}

MarginalSummary checkAllBlocksAndSomeCrossBlocks(
    Graph& g, const std::vector<std::pair<VertexId, VertexId>>& pairs) {
  std::vector<VertexId> ids;  // unobserved landmarks of the simulation have no covariance
  for (const auto& [id, v] : g.vertices()) {
    if (v->fixed() || !v->edges().empty()) ids.push_back(id);
  }
  for (const auto& [a, b] : pairs) {
    EXPECT_FALSE(g.vertex(a)->edges().empty()) << a;
    EXPECT_FALSE(g.vertex(b)->edges().empty()) << b;
  }
  MarginalCovariance marginals(amdOrdered());
  const MarginalSummary summary = marginals.compute(g, ids, pairs);
  EXPECT_TRUE(summary.ok()) << summary.report();
  if (!summary.ok()) return summary;
  const DenseReference ref(g);
  const double scale = std::max(1.0, ref.cov.cwiseAbs().maxCoeff());
  for (VertexId id : ids) {
    expectClose(marginals.block(id), ref.block(g, id, id), scale, "block " + std::to_string(id));
  }
  for (const auto& [a, b] : pairs) {
    const std::string what = "cross " + std::to_string(a) + "," + std::to_string(b);
    expectClose(marginals.crossBlock(a, b), ref.block(g, a, b), scale, what);
    expectClose(marginals.crossBlock(b, a), ref.block(g, b, a), scale, what + " (transposed)");
  }
  return summary;
}

TEST(Optimizer_Marginals, Slam2dPoseGraphWithLandmarksMatchesDenseInverse) {
  for (unsigned seed : {1u, 2u, 3u}) {
    Graph g = slam2dGraph(60, 12, seed);
    g.vertex(0)->setFixed(true);
    g.vertex(31)->setFixed(true);  // a fixed vertex in the middle of the chain too
    // Neighbours, far-apart poses (outside L's pattern), pose-landmark, fixed partners.
    checkAllBlocksAndSomeCrossBlocks(
        g, {{1, 2}, {5, 50}, {3, 58}, {10, 60}, {61, 65}, {0, 7}, {31, 44}, {59, 2}});
  }
}

TEST(Optimizer_Marginals, DriveBotGraphMatchesDenseInverse) {
  for (bool fix_first : {false, true}) {
    Graph g = drivebotGraph(fix_first);
    checkAllBlocksAndSomeCrossBlocks(g,
                                     {{0, 1}, {3, 39}, {100, 101}, {5, 102}, {20, 103}, {0, 100}});
  }
}

TEST(Optimizer_Marginals, SubsetOfVerticesGivesTheSameBlocks) {
  Graph g = slam2dGraph(80, 10, 4);
  MarginalCovariance all(amdOrdered());
  ASSERT_TRUE(all.computeAll(g).ok());
  for (VertexId id : {1, 17, 42, 79, 85}) {
    MarginalCovariance one(amdOrdered());
    const MarginalSummary s = one.compute(g, {id});
    ASSERT_TRUE(s.ok()) << s.report();
    EXPECT_LE((one.block(id) - all.block(id)).cwiseAbs().maxCoeff(), 1e-12) << id;
    // Only the elimination-tree path of the vertex is computed.
    EXPECT_LT(s.inverse_entries, all.computeAll(g).inverse_entries) << id;
    EXPECT_THROW((void)one.block(id == 1 ? 2 : 1), Error);
  }
}

TEST(Optimizer_Marginals, NaturalOrderWithoutARegistryGivesTheSameBlocks) {
  // Without a registry of orderings H is factorised in the id order: more fill, the same
  // covariances to rounding.
  Graph g = slam2dGraph(80, 10, 4);
  MarginalCovariance amd(amdOrdered());
  MarginalCovariance natural;
  const MarginalSummary sa = amd.computeAll(g);
  const MarginalSummary sn = natural.computeAll(g);
  ASSERT_TRUE(sa.ok() && sn.ok());
  EXPECT_LT(sa.factor_nonzeros, sn.factor_nonzeros);
  for (const auto& [id, block] : amd.blocks()) {
    EXPECT_LE((natural.block(id) - block).cwiseAbs().maxCoeff(),
              1e-9 * std::max(1.0, block.cwiseAbs().maxCoeff()))
        << id;
  }
}

TEST(Optimizer_Marginals, GaugeIsFixedAtTheLowestIdWhenNothingAnchorsTheGraph) {
  Graph g = slam2dGraph(30, 0, 5);
  ASSERT_FALSE(g.vertex(0)->fixed());
  MarginalCovariance marginals(amdOrdered());
  const MarginalSummary s = marginals.computeAll(g);
  ASSERT_TRUE(s.ok()) << s.report();
  ASSERT_EQ(s.gauge_fixed, std::vector<VertexId>{0});
  EXPECT_FALSE(g.vertex(0)->fixed()) << "the gauge vertex must be released";
  EXPECT_EQ(marginals.block(0), Eigen::MatrixXd::Zero(3, 3));
  g.vertex(0)->setFixed(true);
  const DenseReference ref(g);
  for (VertexId id = 1; id < 30; ++id) {
    expectClose(marginals.block(id), ref.block(g, id, id), 1.0, std::to_string(id));
  }

  MarginalCovariance no_gauge(amdOrdered(false));
  g.vertex(0)->setFixed(false);
  const MarginalSummary bad = no_gauge.computeAll(g);
  EXPECT_EQ(bad.status, MarginalStatus::kSingular);
  EXPECT_NE(bad.message.find("no anchor"), std::string::npos) << bad.message;
  EXPECT_FALSE(bad.bad_vertices.empty());
}

TEST(Optimizer_Marginals, ErrorsNameTheVertices) {
  Graph g = drivebotGraph(true);
  // A vehicle state without edges.
  auto lonely = std::make_unique<VertexVehicle>();
  lonely->setId(500);
  g.addVertex(std::move(lonely));
  MarginalCovariance marginals(amdOrdered());
  MarginalSummary s = marginals.compute(g, {3, 500});
  EXPECT_EQ(s.status, MarginalStatus::kUnconstrained);
  EXPECT_EQ(s.bad_vertices, std::vector<VertexId>{500});
  EXPECT_NE(s.message.find("500"), std::string::npos) << s.message;
  EXPECT_THROW((void)marginals.block(3), Error);
  EXPECT_THROW((void)marginals.compute(g, {12345}), Error);

  // A state whose heading nothing determines: GPS at the platform origin only.
  auto v = std::make_unique<VertexVehicle>();
  v->setId(600);
  g.addVertex(std::move(v));
  auto gps = std::make_unique<EdgeGps>();
  gps->setVertexIds({600});
  gps->setOffset(Eigen::Vector2d::Zero());
  g.addEdge(std::move(gps));
  s = marginals.compute(g, {3, 600});
  EXPECT_EQ(s.status, MarginalStatus::kSingular);
  EXPECT_EQ(s.bad_vertices, std::vector<VertexId>{600});
  EXPECT_NE(s.message.find("vertex 600"), std::string::npos) << s.message;

  // Adding a compass determines it: the structure is rebuilt and the result is right.
  auto compass = std::make_unique<EdgeCompass>();
  compass->setVertexIds({600});
  g.addEdge(std::move(compass));
  s = marginals.compute(g, {3, 600});
  ASSERT_TRUE(s.ok()) << s.report();
  const DenseReference ref(g);
  expectClose(marginals.block(600), ref.block(g, 600, 600), 1.0, "600");
  expectClose(marginals.block(3), ref.block(g, 3, 3), 1.0, "3");
}

TEST(Optimizer_Marginals, OptimizerIsUnaffectedByMarginalsInBetween) {
  // The marginals rebuild their own structure with the gauge vertex free; the optimizer
  // keeps its structure (built with the gauge vertex fixed) and its own columns.
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Graph a = slam2dGraph(100, 5, 6);
  Graph b = slam2dGraph(100, 5, 6);
  Optimizer::Options options;
  options.max_iterations = 2;
  Optimizer oa(a, solvers, options);
  Optimizer ob(b, solvers, options);
  (void)oa.optimize();
  (void)ob.optimize();
  a.vertex(0)->setFixed(true);  // different fixed set in the marginals: indices shift
  MarginalCovariance m(amdOrdered());
  ASSERT_TRUE(m.computeAll(a).ok());
  a.vertex(0)->setFixed(false);
  const Summary sa = oa.optimize();
  const Summary sb = ob.optimize();
  EXPECT_EQ(sa.final_chi2, sb.final_chi2);
  std::vector<double> xa, xb;
  for (const auto& [id, v] : a.vertices()) {
    xa.resize(static_cast<std::size_t>(v->estimateDataDimension()));
    xb.resize(xa.size());
    v->getEstimateData(xa.data());
    b.vertex(id)->getEstimateData(xb.data());
    EXPECT_EQ(xa, xb) << "vertex " << id;
  }
}

TEST(Optimizer_Marginals, GrowingGraphReusesAndRebuildsTheStructure) {
  Graph g = drivebotGraph(true);
  MarginalCovariance m(amdOrdered());
  ASSERT_TRUE(m.computeAll(g).ok());
  ASSERT_TRUE(m.computeAll(g).ok());  // unchanged structure
  // Grow by one state and a kinematics edge.
  auto v = std::make_unique<VertexVehicle>();
  v->setId(40);
  g.addVertex(std::move(v));
  auto e = std::make_unique<EdgeVehicleKinematics>();
  e->setVertexIds({39, 40});
  e->setMeasurement({6, 0, 0.5});
  auto& edge = static_cast<EdgeVehicleKinematics&>(g.addEdge(std::move(e)));
  edge.initializeSecond();
  ASSERT_TRUE(m.computeAll(g).ok());
  const DenseReference ref(g);
  for (const auto& [id, block] : m.blocks()) {
    expectClose(block, ref.block(g, id, id), 1.0, std::to_string(id));
  }
  // The last state is less certain than the one before it (no GPS, only prediction).
  EXPECT_GT(m.block(40).trace(), m.block(39).trace());
}

}  // namespace

namespace {

TEST(Optimizer_Marginals, OneObjectServesTwoGraphs) {
  Graph a = slam2dGraph(40, 0, 7);
  Graph b = slam2dGraph(40, 0, 8);  // same sizes and versions, different edges
  MarginalCovariance m(amdOrdered());
  ASSERT_TRUE(m.computeAll(a).ok());
  ASSERT_TRUE(m.computeAll(b).ok());
  b.vertex(0)->setFixed(true);
  const DenseReference ref(b);
  for (VertexId id = 1; id < 40; ++id) {
    expectClose(m.block(id), ref.block(b, id, id), 1.0, std::to_string(id));
  }
}

}  // namespace
