// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/geometry/se3.h"

namespace graphslam::simulation {

/// Parameters of a synthetic SE(3) pose graph (VERTEX_SE3:QUAT, EDGE_SE3:QUAT).
struct PoseGraph3dOptions {
  enum class Shape {
    /// Rings of poses on a sphere (as sphere2500): odometry along each ring and on to the
    /// next; loop closures between a pose and the one below it on the previous ring.
    kSphere,
    /// A snake through a cubic lattice (as SE-Sync's grid): odometry one cell per pose;
    /// loop closures to lattice neighbours visited earlier.
    kGrid,
  };
  Shape shape = Shape::kSphere;
  int num_poses = 2500;
  std::uint32_t seed = 42;
  /// Sphere radius or lattice spacing (metres).
  double scale = 10.0;
  /// Probability that a candidate pair becomes a loop closure.
  double loop_probability = 1.0;
  /// Standard deviations of the measurement noise: translation (metres) and rotation
  /// (radians, about each axis); the information is their inverse squares, the rotation
  /// rows scaled for g2o's quaternion error (about half the angle).
  double sigma_translation = 0.05;
  double sigma_rotation = 0.01;
};

/// The graph (estimates: the odometry composed from the first pose, which is at its true
/// pose; nothing fixed), the true poses (ids 0..N-1) and the count of loop closures.
struct SimulatedGraph3d {
  Graph graph;
  std::vector<geometry::SE3> true_poses;
  std::size_t num_loop_closures = 0;
};

/// Deterministic for a given seed (std::mt19937).
[[nodiscard]] SimulatedGraph3d simulatePoseGraph3d(const PoseGraph3dOptions& options);

}  // namespace graphslam::simulation
