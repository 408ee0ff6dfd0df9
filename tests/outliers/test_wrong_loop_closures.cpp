// SPDX-License-Identifier: MIT
// The seeded generator of wrong loop closures (simulation::addWrongLoopClosures).
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/wrong_loop_closures.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_se2.h"

using namespace graphslam;
using namespace graphslam::simulation;

namespace {

SimulatedGraph world() {
  ManhattanOptions o;
  o.num_poses = 300;
  return simulateManhattan(o);
}

TEST(Simulation_WrongLoopClosures, FractionCountsLoopClosuresAndEdgesLookReal) {
  SimulatedGraph s = world();
  const std::size_t before = s.graph.numEdges();
  std::set<std::pair<VertexId, VertexId>> joined;
  for (const auto& e : s.graph.edges()) {
    joined.emplace(std::min(e->vertexId(0), e->vertexId(1)),
                   std::max(e->vertexId(0), e->vertexId(1)));
  }
  WrongLoopClosureOptions o;
  o.fraction = 0.2;
  const auto added = addWrongLoopClosures(s.graph, o);
  EXPECT_EQ(added.loop_closures, s.num_loop_closures);
  EXPECT_EQ(added.requested,
            static_cast<std::size_t>(std::llround(0.2 * static_cast<double>(s.num_loop_closures))));
  ASSERT_EQ(added.edge_indices.size(), added.requested);
  ASSERT_EQ(s.graph.numEdges(), before + added.requested);
  for (std::size_t k = 0; k < added.edge_indices.size(); ++k) {
    EXPECT_EQ(added.edge_indices[k], before + k);  // appended in order
    const auto* e = dynamic_cast<const types_slam2d::EdgeSE2*>(s.graph.edges()[before + k].get());
    ASSERT_NE(e, nullptr);
    const VertexId a = std::min(e->vertexId(0), e->vertexId(1));
    const VertexId b = std::max(e->vertexId(0), e->vertexId(1));
    EXPECT_GT(b - a, 1);
    EXPECT_TRUE(joined.emplace(a, b).second) << "pair " << a << " " << b << " already joined";
    // The simulator's loop-closure information.
    EXPECT_DOUBLE_EQ(e->information()(0, 0), 1.0 / (0.05 * 0.05));
    EXPECT_LE(std::abs(e->measurement().angle()), M_PI);
  }
}

TEST(Simulation_WrongLoopClosures, SameSeedSameEdgesOtherSeedOthers) {
  auto pairs = [](std::uint64_t seed) {
    SimulatedGraph s = world();
    WrongLoopClosureOptions o;
    o.count = 25;
    o.seed = seed;
    const auto added = addWrongLoopClosures(s.graph, o);
    std::vector<std::array<double, 5>> out;
    for (std::size_t k : added.edge_indices) {
      const auto* e = static_cast<const types_slam2d::EdgeSE2*>(s.graph.edges()[k].get());
      out.push_back({double(e->vertexId(0)), double(e->vertexId(1)),
                     e->measurement().translation().x(), e->measurement().translation().y(),
                     e->measurement().angle()});
    }
    return out;
  };
  const auto a = pairs(11);
  EXPECT_EQ(a.size(), 25u);
  EXPECT_EQ(a, pairs(11));
  EXPECT_NE(a, pairs(12));
}

TEST(Simulation_WrongLoopClosures, NoPoseGraphIsAnError) {
  Graph g;
  EXPECT_THROW((void)addWrongLoopClosures(g, WrongLoopClosureOptions{}), Error);
}

}  // namespace

TEST(Simulation_Size, EstimateIsCloseToWhatTheSimulatorMakes) {
  simulation::ManhattanOptions o;
  o.num_poses = 2000;
  o.num_landmarks = 3000;
  const simulation::ManhattanSize size = simulation::estimateSize(o);
  const auto sim = simulation::simulateManhattan(o);
  const double made = static_cast<double>(sim.num_observations);
  EXPECT_GT(size.observations, 0.7 * made);
  EXPECT_LT(size.observations, 1.3 * made);
  EXPECT_NEAR(size.bytes, 1200.0 * 2000 + 260.0 * size.observations, 1.0);
  o.num_landmarks = 0;
  EXPECT_EQ(simulation::estimateSize(o).observations, 0.0);
}
