// SPDX-License-Identifier: MIT
// Small pose graphs for the certify tests.
#pragma once

#include <memory>

#include "graphslam/core/graph.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/simulator3d.h"

namespace graphslam::test {

/// A simulated 2D Manhattan pose graph (odometry estimates).
inline Graph manhattan2d(int poses, std::uint32_t seed, double sigma_theta = 0.01) {
  simulation::ManhattanOptions o;
  o.num_poses = poses;
  o.seed = seed;
  o.sigma_theta = sigma_theta;
  return std::move(simulation::simulateManhattan(o).graph);
}

/// A simulated 3D pose graph (sphere or grid; odometry estimates).
inline Graph poseGraph3d(simulation::PoseGraph3dOptions::Shape shape, int poses, std::uint32_t seed,
                         double sigma_rotation = 0.01) {
  simulation::PoseGraph3dOptions o;
  o.shape = shape;
  o.num_poses = poses;
  o.seed = seed;
  o.sigma_rotation = sigma_rotation;
  return std::move(simulation::simulatePoseGraph3d(o).graph);
}

}  // namespace graphslam::test
