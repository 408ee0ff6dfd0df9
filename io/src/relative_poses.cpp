// SPDX-License-Identifier: MIT
#include "graphslam/io/relative_poses.h"

#include <memory>

#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::io {

using namespace graphslam::types_slam2d;

Graph poseGraphFromRelativePoses(const Eigen::Matrix3Xd& relative,
                                 const RelativePoseGraphOptions& options) {
  const int columns = static_cast<int>(relative.cols());
  const int odometry = options.last_column_closes_loop ? columns - 1 : columns;
  if (odometry < 1) throw Error("poseGraphFromRelativePoses: needs at least two relative poses");
  Graph graph;
  SE2 pose;
  for (int i = 0; i <= odometry; ++i) {
    auto v = std::make_unique<VertexSE2>();
    v->setId(i);
    v->setEstimate(pose);
    graph.addVertex(std::move(v));
    if (i < odometry) pose = pose * SE2::fromVector(relative.col(i));
  }
  auto add_edge = [&](int from, int to, const Eigen::Vector3d& z) {
    auto e = std::make_unique<EdgeSE2>();
    e->setVertexIds({from, to});
    e->setMeasurement(SE2::fromVector(z));
    e->setInformation(options.information);
    graph.addEdge(std::move(e));
  };
  for (int i = 0; i < odometry; ++i) add_edge(i, i + 1, relative.col(i));
  if (options.last_column_closes_loop) add_edge(odometry, 0, relative.col(columns - 1));
  return graph;
}

}  // namespace graphslam::io
