// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "graphslam/core/graph.h"

namespace graphslam::homework {

/// True 2D positions of some vertices of a graph, split into the robot's trajectory (in
/// order) and landmarks.
struct PointGroundTruth {
  std::vector<VertexId> pose_ids;
  std::vector<Eigen::Vector2d> poses;
  std::vector<VertexId> landmark_ids;
  std::vector<Eigen::Vector2d> landmarks;
  [[nodiscard]] bool empty() const { return pose_ids.empty() && landmark_ids.empty(); }
};

/// Euclidean position errors |estimate - truth| over a set of vertices (metres).
struct PositionErrorStats {
  std::size_t count = 0;  ///< vertices compared
  double rmse = 0.0;
  double mean = 0.0;
  double max = 0.0;
};

struct GroundTruthErrors {
  PositionErrorStats poses;
  PositionErrorStats landmarks;
};

/// The position of a VertexXY (its estimate) or of a VertexSE2 (its translation);
/// false for other vertex types.
[[nodiscard]] bool vertexPosition(const Vertex& v, Eigen::Vector2d& position);

/// Errors of the graph's current estimates against `truth`. Ids missing from the graph or
/// of a vertex type without a position are not counted.
[[nodiscard]] GroundTruthErrors positionErrors(const Graph& graph, const PointGroundTruth& truth);

}  // namespace graphslam::homework
