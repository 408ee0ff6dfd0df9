// SPDX-License-Identifier: MIT
#include "graphslam/homework/pose_graph_io.h"

#include <map>
#include <memory>

#include "graphslam/core/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::homework {

using namespace graphslam::types_slam2d;
using namespace graphslam::eval;

Trajectory trajectoryFromGraph(const Graph& graph) {
  Trajectory out;
  for (const auto& [id, v] : graph.vertices()) {
    if (const auto* pose = dynamic_cast<const VertexSE2*>(v.get())) {
      const SE2& x = pose->estimate();
      out.append(static_cast<double>(id),
                 se2ToIsometry3(x.translation().x(), x.translation().y(), x.angle()));
    }
  }
  return out;
}

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

Trajectory deadReckonGraph(const Graph& graph) {
  std::map<VertexId, const EdgeSE2*> next;
  for (const auto& e : graph.edges()) {
    if (const auto* se2 = dynamic_cast<const EdgeSE2*>(e.get())) {
      if (se2->vertexId(1) == se2->vertexId(0) + 1) next.emplace(se2->vertexId(0), se2);
    }
  }
  std::vector<VertexId> ids;
  for (const auto& [id, v] : graph.vertices()) {
    if (dynamic_cast<const VertexSE2*>(v.get())) ids.push_back(id);
  }
  if (ids.empty()) throw Error("dead reckoning: the graph has no VERTEX_SE2");
  SE2 pose = static_cast<const VertexSE2*>(graph.vertex(ids.front()))->estimate();
  Trajectory out;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const VertexId id = ids[k];
    if (k > 0) {
      auto it = next.find(ids[k - 1]);
      if (it == next.end() || id != ids[k - 1] + 1) {
        throw Error("dead reckoning: no EDGE_SE2 from pose " + std::to_string(ids[k - 1]) + " to " +
                    std::to_string(ids[k - 1] + 1));
      }
      pose = pose * it->second->measurement();
    }
    out.append(static_cast<double>(id),
               se2ToIsometry3(pose.translation().x(), pose.translation().y(), pose.angle()));
  }
  return out;
}

}  // namespace graphslam::homework
