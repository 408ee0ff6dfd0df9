// SPDX-License-Identifier: MIT
// A simulated Manhattan world with seeded wrong loop closures, for the outlier tests.
#pragma once

#include <cstdint>
#include <set>
#include <utility>

#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/wrong_loop_closures.h"

namespace graphslam::test {

struct Corrupted {
  simulation::SimulatedGraph sim;
  std::set<std::pair<VertexId, VertexId>> wrong;  ///< vertex pairs of the wrong closures
};

/// `poses` poses of the world of `world_seed` (estimates: its odometry), then `fraction`
/// wrong loop closures drawn with `wrong_seed`.
inline Corrupted makeCorrupted(int poses, double fraction, std::uint32_t world_seed,
                               std::uint64_t wrong_seed) {
  simulation::ManhattanOptions o;
  o.num_poses = poses;
  o.seed = world_seed;
  Corrupted c{simulation::simulateManhattan(o), {}};
  simulation::WrongLoopClosureOptions w;
  w.fraction = fraction;
  w.seed = wrong_seed;
  for (std::size_t k : simulation::addWrongLoopClosures(c.sim.graph, w).edge_indices) {
    const Edge& e = *c.sim.graph.edges()[k];
    c.wrong.emplace(e.vertexId(0), e.vertexId(1));
  }
  return c;
}

}  // namespace graphslam::test
