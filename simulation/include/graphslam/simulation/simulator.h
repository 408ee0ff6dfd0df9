// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/types_slam2d/se2.h"

namespace graphslam::simulation {

/// Parameters of a synthetic Manhattan-world run: a robot steps one grid unit per pose
/// through a square world, turning by +-90 degrees at random; revisiting a cell seen at
/// least `min_loop_gap` poses earlier yields a loop-closure edge.
struct ManhattanOptions {
  int num_poses = 1000;
  std::uint32_t seed = 42;
  /// Side of the square world in grid units; 0 picks about sqrt(num_poses) / 2.
  int world_size = 0;
  double turn_probability = 0.3;
  int min_loop_gap = 10;
  /// Probability that a revisit actually produces a loop closure.
  double loop_probability = 0.8;
  /// Standard deviations of odometry and loop-closure noise (metres, radians).
  double sigma_xy = 0.05;
  double sigma_theta = 0.01;
  /// Landmarks (0 for a pure pose graph), observed as EDGE_SE2_XY within `landmark_range`.
  int num_landmarks = 0;
  double landmark_range = 2.0;
  double sigma_landmark = 0.05;
};

/// A simulated graph with its ground truth. Poses have ids 0..N-1, landmarks N..N+L-1.
/// Vertex estimates are the dead-reckoned odometry (landmarks from their first sighting);
/// nothing is fixed.
struct SimulatedGraph {
  Graph graph;
  std::vector<types_slam2d::SE2> true_poses;
  std::vector<Eigen::Vector2d> true_landmarks;
  std::size_t num_loop_closures = 0;
  std::size_t num_observations = 0;
};

/// Deterministic for a given seed (std::mt19937).
[[nodiscard]] SimulatedGraph simulateManhattan(const ManhattanOptions& options);

/// Roughly what simulateManhattan(options) makes, before making it: the expected number of
/// landmark observations (each pose sees the landmarks within landmark_range, spread over
/// the world) and the memory the graph takes (measured: about 1.2 kB per pose and 0.26 kB
/// per observation; 200k poses 227 MB, 1000 poses with 200k landmarks 2.5 GB).
struct ManhattanSize {
  double observations = 0.0;
  double bytes = 0.0;
};
[[nodiscard]] ManhattanSize estimateSize(const ManhattanOptions& options);

}  // namespace graphslam::simulation
