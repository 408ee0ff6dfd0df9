// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/io/coursework_npz.h"

namespace graphslam::eval {

using io::PointGroundTruth;

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

}  // namespace graphslam::eval
