// SPDX-License-Identifier: MIT
// Graphs and registries shared by the optimizer tests.
#pragma once

#include <random>
#include <utility>

#include "../common/point_edges.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/solvers/register.h"

namespace graphslam::test {

inline SolverRegistry allSolvers() {
  SolverRegistry s;
  solvers::registerSolvers(s);
  return s;
}

/// A graph mixing every way of linearising: an SE(2) pose graph (analytic Jacobians) and
/// points with numeric Jacobians on copies, in place (g2o style) and of a multi-edge.
inline Graph mixedGraph() {
  simulation::ManhattanOptions sim;
  sim.num_poses = 1500;
  Graph g = std::move(simulation::simulateManhattan(sim).graph);
  g.vertex(0)->setFixed(true);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.1);
  const VertexId p0 = 100000;
  const int points = 1200;
  for (int i = 0; i < points; ++i) addPoint(g, p0 + i, {noise(rng), noise(rng)});
  g.vertex(p0)->setFixed(true);
  for (int i = 1; i < points; ++i) {
    const Eigen::Vector2d z(1.0 + noise(rng), noise(rng));
    if (i % 2) {
      addDisplacement<EdgeDisplacement>(g, p0 + i - 1, p0 + i, z);
    } else {
      addDisplacement<EdgeDisplacementG2oStyle>(g, p0 + i - 1, p0 + i, z);
    }
    if (i % 7 == 0) {
      auto c = std::make_unique<EdgeCentroid>();
      c->setVertexIds({p0 + i - 2, p0 + i - 1, p0 + i});
      c->setMeasurement(Eigen::Vector2d(i - 1.0 + noise(rng), noise(rng)));
      g.addEdge(std::move(c));
    }
  }
  return g;
}

}  // namespace graphslam::test
