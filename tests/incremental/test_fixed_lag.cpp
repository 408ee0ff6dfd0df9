// SPDX-License-Identifier: MIT
// Fixed-lag smoothing and checkpoints of IncrementalOptimizer: the marginalisation prior's
// Jacobian, marginalising at the optimum, the window's bounds and refusals, landmarks
// leaving with their last observer, and checkpoints resumed bit for bit or refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <random>

#include "graphslam/core/jacobian_check.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/incremental/incremental_optimizer.h"
#include "graphslam/incremental/linear_prior_edge.h"
#include "graphslam/incremental/replay.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"
#include "graphslam/types_slam3d/register.h"
#include "graphslam/types_slam3d/vertex_se3.h"

namespace graphslam {
namespace {

using incremental::IncrementalOptimizer;
using incremental::LinearPriorEdge;
using types_slam2d::SE2;

TypeRegistry& types() {
  static TypeRegistry t = [] {
    TypeRegistry r;
    types_slam2d::registerTypes(r);
    types_slam3d::registerTypes(r);
    return r;
  }();
  return t;
}

// A prior on (SE2, XY, SE3) with a random Jacobian and offset, its vertices away from the
// linearisation point: analytic against numeric Jacobians.
TEST(Incremental_LinearPrior, JacobianMatchesNumeric) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    Graph g;
    auto a = std::make_unique<types_slam2d::VertexSE2>();
    a->setId(1);
    a->setEstimate(SE2(n(rng), n(rng), 3.0 * n(rng)));
    auto b = std::make_unique<types_slam2d::VertexXY>();
    b->setId(2);
    b->setEstimate(Eigen::Vector2d(n(rng), n(rng)));
    auto c = std::make_unique<types_slam3d::VertexSE3>();
    c->setId(3);
    c->setEstimate(geometry::SE3(geometry::SO3::exp(Eigen::Vector3d(n(rng), n(rng), n(rng))),
                                 Eigen::Vector3d(n(rng), n(rng), n(rng))));
    std::vector<double> x_lin;
    for (Vertex* v : {static_cast<Vertex*>(a.get()), static_cast<Vertex*>(b.get()),
                      static_cast<Vertex*>(c.get())}) {
      std::vector<double> d(static_cast<std::size_t>(v->estimateDataDimension()));
      v->getEstimateData(d.data());
      x_lin.insert(x_lin.end(), d.begin(), d.end());
    }
    g.addVertex(std::move(a));
    g.addVertex(std::move(b));
    g.addVertex(std::move(c));
    // Move the vertices away from the linearisation point.
    for (VertexId id : {1, 2, 3}) {
      std::vector<double> step(static_cast<std::size_t>(g.vertex(id)->dimension()));
      for (double& s : step) s = 0.3 * n(rng);
      g.vertex(id)->oplus(step.data());
    }
    const Eigen::MatrixXd j = Eigen::MatrixXd::Random(7, 11);
    const Eigen::VectorXd r = Eigen::VectorXd::Random(7);
    auto prior = std::make_unique<LinearPriorEdge>(std::vector<int>{3, 2, 6}, j, r, x_lin);
    prior->setVertexIds({1, 2, 3});
    Edge& e = g.addEdge(std::move(prior));
    EXPECT_EQ(checkJacobians(e, g, 1e-6), "") << "trial " << trial;
  }
}

// At the linearisation point the prior's error is the offset.
TEST(Incremental_LinearPrior, ErrorIsTheOffsetAtTheLinearisationPoint) {
  Graph g;
  auto a = std::make_unique<types_slam2d::VertexSE2>();
  a->setId(0);
  a->setEstimate(SE2(1, 2, 3.1));
  g.addVertex(std::move(a));
  auto prior =
      std::make_unique<LinearPriorEdge>(std::vector<int>{3}, Eigen::Matrix3d::Identity(),
                                        Eigen::Vector3d(1, 2, 3), std::vector<double>{1, 2, 3.1});
  prior->setVertexIds({0});
  Edge& e = g.addEdge(std::move(prior));
  e.computeError();
  EXPECT_EQ(Eigen::Map<const Eigen::Vector3d>(e.errorData()), Eigen::Vector3d(1, 2, 3));
}

// Poses around a square, odometry and a loop closure to the pose `back` steps before.
class Drive {
 public:
  Drive(int back, unsigned seed) : back_(back), rng_(seed) {}
  void addStep(IncrementalOptimizer& inc, int k) {
    std::normal_distribution<double> noise(0.0, 0.02);
    const SE2 truth_k = truth(k);
    auto v = std::make_unique<types_slam2d::VertexSE2>();
    v->setId(k);
    if (k == 0) {
      v->setEstimate(truth_k);
      inc.addVertex(std::move(v));
      inc.addState(k, k);
      return;
    }
    const SE2 odo = truth(k - 1).inverse() * truth_k * SE2(noise(rng_), noise(rng_), noise(rng_));
    const auto& prev = static_cast<const types_slam2d::VertexSE2&>(*inc.graph().vertex(k - 1));
    v->setEstimate(prev.estimate() * odo);
    inc.addVertex(std::move(v));
    inc.addState(k, k);
    addEdge(inc, k - 1, k, odo);
    if (k >= back_) {
      addEdge(inc, k - back_, k,
              truth(k - back_).inverse() * truth_k * SE2(noise(rng_), noise(rng_), noise(rng_)));
    }
  }
  static SE2 truth(int k) {
    const double heading = (k / 8) * M_PI / 2;
    const Eigen::Vector2d corner[4] = {{0, 0}, {8, 0}, {8, 8}, {0, 8}};
    const Eigen::Vector2d p =
        corner[(k / 8) % 4] + (k % 8) * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    return SE2(p.x(), p.y(), heading);
  }

 private:
  static void addEdge(IncrementalOptimizer& inc, int i, int j, const SE2& z) {
    auto e = std::make_unique<types_slam2d::EdgeSE2>();
    e->setVertexIds({i, j});
    e->setMeasurement(z);
    e->setInformation(Eigen::Matrix3d::Identity() * 100.0);
    inc.addEdge(std::move(e));
  }
  int back_;
  std::mt19937 rng_;
};

// Marginalising at the optimum keeps it (the reduced problem's gradient is zero there) and
// keeps the marginal covariance of what stays (the Schur complement is exact for the
// linearised problem), the gauge pose among the marginalised.
TEST(Incremental_Window, MarginalisingAtTheOptimumKeepsEstimatesAndCovariances) {
  Graph graph;
  incremental::Options options;
  options.relinearize_threshold = 1e-4;
  IncrementalOptimizer inc(graph, options);
  Drive drive(32, 5);
  for (int k = 0; k < 64; ++k) {
    drive.addStep(inc, k);
    ASSERT_TRUE(inc.update()) << inc.failure().message;
  }
  ASSERT_TRUE(inc.refine(1e-12));
  const Eigen::MatrixXd cov = inc.marginalCovariance(50);
  std::vector<double> before(static_cast<std::size_t>(3 * 64));
  for (int k = 0; k < 64; ++k) graph.vertex(k)->getEstimateData(before.data() + 3 * k);
  const auto gone = inc.marginalize({0, 1, 2, 3, 4, 5, 6, 7, 8, 9});
  EXPECT_EQ(gone.size(), 10u);
  EXPECT_FALSE(graph.hasVertex(3));
  EXPECT_TRUE(inc.isMarginalized(3));
  ASSERT_TRUE(inc.update()) << inc.failure().message;
  ASSERT_TRUE(inc.refine(1e-12));
  for (int k = 10; k < 64; ++k) {
    double now[3];
    graph.vertex(k)->getEstimateData(now);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(now[c], before[3 * k + c], 1e-8) << "pose " << k;
  }
  EXPECT_LT((inc.marginalCovariance(50) - cov).norm(), 1e-9 * cov.norm());
  EXPECT_EQ(inc.marginalizedCount(), 10u);
}

// The window keeps N states; an edge to a marginalised pose is refused naming it.
TEST(Incremental_Window, KeepsNStatesAndRefusesEdgesToMarginalisedOnes) {
  Graph graph;
  incremental::Options options;
  options.window.states = 10;
  std::vector<VertexId> written;
  options.window.on_marginalised = [&](const Vertex& v, const incremental::WindowState* s) {
    ASSERT_NE(s, nullptr);
    written.push_back(v.id());
  };
  IncrementalOptimizer inc(graph, options);
  Drive drive(1000, 5);
  for (int k = 0; k < 40; ++k) {
    drive.addStep(inc, k);
    ASSERT_TRUE(inc.update()) << inc.failure().message;
    EXPECT_LE(inc.windowStates().size(), 10u);
  }
  EXPECT_EQ(written.size(), 30u);
  EXPECT_EQ(written.front(), 0);
  EXPECT_EQ(written.back(), 29);
  EXPECT_EQ(graph.numVertices(), 10u);
  auto e = std::make_unique<types_slam2d::EdgeSE2>();
  e->setVertexIds({5, 39});
  try {
    inc.addEdge(std::move(e));
    FAIL() << "an edge to a marginalised vertex was accepted";
  } catch (const InputError& x) {
    EXPECT_NE(std::string(x.what()).find("vertex 5 refused"), std::string::npos) << x.what();
  }
}

// By time: states older than the newest stamp minus the window leave.
TEST(Incremental_Window, BySecondsAndByPolicy) {
  Graph graph;
  incremental::Options options;
  options.window.seconds = 5.0;
  std::size_t policy_calls = 0;
  options.window.policy = [&](const std::vector<incremental::WindowState>& w) {
    ++policy_calls;
    std::vector<VertexId> out;
    for (const auto& s : w) {
      if (s.id % 2 == 1 && s.id + 2 < w.back().id) out.push_back(s.id);  // drop odd keyframes
    }
    return out;
  };
  IncrementalOptimizer inc(graph, options);
  Drive drive(1000, 5);
  for (int k = 0; k < 30; ++k) {
    drive.addStep(inc, k);
    ASSERT_TRUE(inc.update()) << inc.failure().message;
  }
  EXPECT_EQ(policy_calls, 30u);
  for (const auto& s : inc.windowStates()) {
    EXPECT_GE(s.stamp, 29.0 - 5.0);
    EXPECT_TRUE(s.id % 2 == 0 || s.id + 2 >= 29) << s.id;
  }
}

// Landmarks leave with the last pose that sees them; the window's vertices stay bounded.
TEST(Incremental_Window, LandmarksLeaveWithTheirLastObserver) {
  simulation::ManhattanOptions sim;
  sim.num_poses = 300;
  sim.num_landmarks = 40;
  sim.seed = 9;
  const auto world = simulation::simulateManhattan(sim);
  incremental::ReplayOptions options;
  options.optimizer.window.states = 20;
  std::size_t most = 0;
  options.after_step = [&](std::size_t, const incremental::ReplayStep&, const Graph& g) {
    most = std::max(most, g.numVertices());
    // Every landmark in the graph is seen (a measurement, not the prior) by a pose in it.
    for (const auto& [id, v] : g.vertices()) {
      if (v->dimension() != 2) continue;
      bool seen = false;
      for (const Edge* e : v->edges()) {
        if (dynamic_cast<const LinearPriorEdge*>(e)) continue;
        for (VertexId o : e->vertexIds()) seen = seen || (o != id && g.hasVertex(o));
      }
      EXPECT_TRUE(seen) << "landmark " << id;
    }
  };
  Graph target;
  const auto r = incremental::replayGraph(world.graph, types(), target, options);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_GT(r.marginalized, 280u);
  EXPECT_LT(most, 20u + 40u);
}

// 300 poses without loop closures among 15 landmarks, each seen again after its observers
// have left a window of 20.
simulation::SimulatedGraph revisitedLandmarks() {
  simulation::ManhattanOptions sim;
  sim.num_poses = 300;
  sim.num_landmarks = 15;
  sim.seed = 9;
  sim.loop_probability = 0.0;
  return simulation::simulateManhattan(sim);
}

// With reinitialize_landmarks a landmark seen again after it left is added anew: no
// observation is refused, and the window still holds only landmarks its poses see.
TEST(Incremental_Window, ReinitialisedLandmarksAreNotRefused) {
  const auto world = revisitedLandmarks();
  incremental::ReplayOptions options;
  options.optimizer.window.states = 20;
  Graph refused_graph;
  const auto refused = incremental::replayGraph(world.graph, types(), refused_graph, options);
  ASSERT_TRUE(refused.ok) << refused.error;
  EXPECT_GT(refused.refused_edges, 0u);
  options.optimizer.window.reinitialize_landmarks = true;
  Graph target;
  const auto r = incremental::replayGraph(world.graph, types(), target, options);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.refused_edges, 0u);
  EXPECT_GT(r.marginalized, refused.marginalized);
}

// Landmark id -> estimate, of the 2D landmarks in g.
std::map<VertexId, Eigen::Vector2d> landmarkEstimates(const Graph& g) {
  std::map<VertexId, Eigen::Vector2d> out;
  for (const auto& [id, v] : g.vertices()) {
    if (const auto* xy = dynamic_cast<const types_slam2d::VertexXY*>(v.get())) {
      out[id] = xy->estimate();
    }
  }
  return out;
}

// RMS distance of a's landmarks from b's (those in both).
double landmarkRms(const Graph& a, const Graph& b) {
  const auto la = landmarkEstimates(a), lb = landmarkEstimates(b);
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& [id, p] : la) {
    if (!lb.count(id)) continue;
    sum += (p - lb.at(id)).squaredNorm();
    ++n;
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : std::nan("");
}

// With keep_landmarks only poses leave: every landmark stays to the end, none of its
// observations is refused, and the map ends closer to the full history's than when
// landmarks seen again start anew (those lose what the window knew of them).
TEST(Incremental_Window, KeptLandmarksStayAndKeepTheirHistory) {
  const auto world = revisitedLandmarks();
  incremental::ReplayOptions options;
  Graph full;
  ASSERT_TRUE(incremental::replayGraph(world.graph, types(), full, options).ok);
  options.optimizer.window.states = 20;
  options.optimizer.window.reinitialize_landmarks = true;
  Graph reinitialised;
  ASSERT_TRUE(incremental::replayGraph(world.graph, types(), reinitialised, options).ok);
  options.optimizer.window.reinitialize_landmarks = false;
  options.optimizer.window.keep_landmarks = true;
  Graph kept;
  const auto r = incremental::replayGraph(world.graph, types(), kept, options);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.refused_edges, 0u);
  EXPECT_EQ(landmarkEstimates(kept).size(), landmarkEstimates(full).size());
  EXPECT_EQ(r.marginalized, 300u - r.window_vertices + landmarkEstimates(kept).size());
  const double kept_rms = landmarkRms(kept, full),
               reinitialised_rms = landmarkRms(reinitialised, full);
  EXPECT_LT(kept_rms, 0.5 * reinitialised_rms) << kept_rms << " against " << reinitialised_rms;
  // Both exclude each other.
  incremental::Options both;
  both.window.states = 20;
  both.window.keep_landmarks = both.window.reinitialize_landmarks = true;
  Graph g;
  EXPECT_THROW(IncrementalOptimizer(g, both), Error);
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<double> estimates(const Graph& g) {
  std::vector<double> out;
  for (const auto& [id, v] : g.vertices()) {
    std::vector<double> d(static_cast<std::size_t>(v->estimateDataDimension()));
    v->getEstimateData(d.data());
    out.push_back(static_cast<double>(id));
    out.insert(out.end(), d.begin(), d.end());
  }
  return out;
}

// A checkpointed run and the same run resumed from its checkpoint end bit for bit equal;
// with and without a window.
TEST(Incremental_Checkpoint, ResumedRunIsBitIdentical) {
  for (std::size_t window : {std::size_t{0}, std::size_t{40}}) {
    const std::string path =
        ::testing::TempDir() + "/fixed_lag_" + std::to_string(window) + ".ckpt";
    incremental::Options options;
    options.window.states = window;
    Graph graph;
    IncrementalOptimizer inc(graph, options);
    Drive drive(32, 8);
    for (int k = 0; k < 100; ++k) {
      drive.addStep(inc, k);
      ASSERT_TRUE(inc.update()) << inc.failure().message;
      if (k == 45) inc.saveCheckpoint(path, types(), "step 46");
    }
    Graph scratch;
    IncrementalOptimizer skip(scratch, options);
    Drive again(32, 8);
    for (int k = 0; k < 46; ++k) {
      again.addStep(skip, k);
      ASSERT_TRUE(skip.update());
    }
    Graph resumed_graph;
    IncrementalOptimizer resumed(resumed_graph, options);
    EXPECT_EQ(resumed.loadCheckpoint(path, types()), "step 46");
    for (int k = 46; k < 100; ++k) {
      again.addStep(resumed, k);
      ASSERT_TRUE(resumed.update()) << resumed.failure().message;
    }
    EXPECT_EQ(estimates(resumed_graph), estimates(graph)) << "window " << window;
    EXPECT_EQ(resumed.marginalizedCount(), inc.marginalizedCount());
  }
}

std::string refusal(const std::string& path, const incremental::Options& options = {}) {
  Graph g;
  IncrementalOptimizer inc(g, options);
  try {
    (void)inc.loadCheckpoint(path, types());
  } catch (const InputError& e) {
    EXPECT_EQ(g.numVertices(), 0u);
    return e.what();
  }
  return "accepted";
}

TEST(Incremental_Checkpoint, CorruptTruncatedForeignAndOtherOptionsAreRefused) {
  const std::string dir = ::testing::TempDir();
  const std::string good = dir + "/good.ckpt";
  {
    incremental::Options options;
    options.window.states = 20;
    Graph graph;
    IncrementalOptimizer inc(graph, options);
    Drive drive(32, 8);
    for (int k = 0; k < 30; ++k) {
      drive.addStep(inc, k);
      ASSERT_TRUE(inc.update());
    }
    inc.saveCheckpoint(good, types());
  }
  const std::string bytes = readAll(good);
  const auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(dir + "/" + name, std::ios::binary) << content;
    return dir + "/" + name;
  };
  incremental::Options same;
  same.window.states = 20;
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  EXPECT_NE(refusal(write("flipped.ckpt", flipped), same).find("checksum mismatch"),
            std::string::npos);
  EXPECT_NE(refusal(write("cut.ckpt", bytes.substr(0, bytes.size() - 100)), same).find("truncated"),
            std::string::npos);
  EXPECT_NE(refusal(write("header.ckpt", bytes.substr(0, 20)), same).find("truncated"),
            std::string::npos);
  EXPECT_NE(refusal(write("foreign.ckpt", "VERTEX_SE2 0 0 0 0\n"), same)
                .find("not a graphslam checkpoint"),
            std::string::npos);
  std::string future = bytes;
  future[20] = 9;  // the version's low byte (little-endian)
  EXPECT_NE(refusal(write("future.ckpt", future), same).find("format version 9"),
            std::string::npos);
  EXPECT_NE(refusal(good).find("window states 20, this optimizer has 0"), std::string::npos)
      << refusal(good);
  EXPECT_NE(refusal(good, same).find("accepted"), std::string::npos);
  EXPECT_NE(refusal(dir + "/missing.ckpt", same).find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace graphslam
