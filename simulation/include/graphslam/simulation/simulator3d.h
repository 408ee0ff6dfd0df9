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
  /// 3D points (VERTEX_TRACKXYZ, ids after the poses), drawn uniformly in the poses'
  /// bounding box grown by point_range; each is seen (EDGE_SE3_TRACKXYZ through one
  /// PARAMS_SE3OFFSET sensor at the pose, id 0) from every pose within point_range, with
  /// noise sigma_point per axis. A point seen from fewer than min_observations poses is
  /// drawn again (up to max_point_draws times each, then the simulation fails).
  int num_points = 0;
  double point_range = 15.0;
  double sigma_point = 0.05;
  int min_observations = 2;
  int max_point_draws = 1000;
};

/// The graph (estimates: the odometry composed from the first pose, which is at its true
/// pose; each point from its first observation; nothing fixed), the true poses (ids
/// 0..N-1), the true points (ids N..N+M-1) and the counts of loop closures and point
/// observations.
struct SimulatedGraph3d {
  Graph graph;
  std::vector<geometry::SE3> true_poses;
  std::vector<Eigen::Vector3d> true_points;
  std::size_t num_loop_closures = 0;
  std::size_t num_point_observations = 0;
};

/// Deterministic for a given seed (std::mt19937).
[[nodiscard]] SimulatedGraph3d simulatePoseGraph3d(const PoseGraph3dOptions& options);

}  // namespace graphslam::simulation
