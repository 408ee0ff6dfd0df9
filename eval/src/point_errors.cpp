// SPDX-License-Identifier: MIT
#include "graphslam/eval/point_errors.h"

#include <algorithm>
#include <cmath>

#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::eval {

using namespace graphslam::types_slam2d;

namespace {
PositionErrorStats errorStats(const Graph& graph, const std::vector<VertexId>& ids,
                              const std::vector<Eigen::Vector2d>& truth) {
  PositionErrorStats s;
  double sum = 0.0, sum_sq = 0.0;
  for (std::size_t k = 0; k < ids.size() && k < truth.size(); ++k) {
    const Vertex* v = graph.vertex(ids[k]);
    Eigen::Vector2d p;
    if (!v || !vertexPosition(*v, p)) continue;
    const double e = (p - truth[k]).norm();
    ++s.count;
    sum += e;
    sum_sq += e * e;
    s.max = std::max(s.max, e);
  }
  if (s.count) {
    s.mean = sum / static_cast<double>(s.count);
    s.rmse = std::sqrt(sum_sq / static_cast<double>(s.count));
  }
  return s;
}
}  // namespace

bool vertexPosition(const Vertex& v, Eigen::Vector2d& position) {
  if (const auto* xy = dynamic_cast<const VertexXY*>(&v)) {
    position = xy->estimate();
    return true;
  }
  if (const auto* se2 = dynamic_cast<const VertexSE2*>(&v)) {
    position = se2->estimate().translation();
    return true;
  }
  return false;
}

GroundTruthErrors positionErrors(const Graph& graph, const PointGroundTruth& truth) {
  return {errorStats(graph, truth.pose_ids, truth.poses),
          errorStats(graph, truth.landmark_ids, truth.landmarks)};
}

}  // namespace graphslam::eval
