// SPDX-License-Identifier: MIT
#include "graphslam/homework/pose_graph_io.h"

#include <map>
#include <memory>
#include <optional>

#include "graphslam/core/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam3d/vertex_se3.h"

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
    } else if (const auto* pose3 = dynamic_cast<const types_slam3d::VertexSE3*>(v.get())) {
      out.append(static_cast<double>(id), pose3->estimate().isometry());
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

// The poses are the VERTEX_SE2 vertices in id order (landmarks and other vertices between
// them are skipped); each is composed from the one before by an EDGE_SE2 joining the two, in
// either direction (the first such edge).
Trajectory deadReckonGraph(const Graph& graph) {
  std::vector<VertexId> ids;
  std::map<VertexId, std::size_t> position;
  for (const auto& [id, v] : graph.vertices()) {
    if (!dynamic_cast<const VertexSE2*>(v.get())) continue;
    position.emplace(id, ids.size());
    ids.push_back(id);
  }
  if (ids.empty()) throw Error("dead reckoning: the graph has no VERTEX_SE2");
  std::vector<std::optional<SE2>> step(ids.size());  // step[k]: from pose k - 1 to pose k
  for (const auto& e : graph.edges()) {
    const auto* se2 = dynamic_cast<const EdgeSE2*>(e.get());
    if (!se2) continue;
    const auto a = position.find(se2->vertexId(0));
    const auto b = position.find(se2->vertexId(1));
    if (a == position.end() || b == position.end()) continue;
    if (b->second == a->second + 1 && !step[b->second]) step[b->second] = se2->measurement();
    if (a->second == b->second + 1 && !step[a->second]) {
      step[a->second] = se2->measurement().inverse();
    }
  }
  SE2 pose = static_cast<const VertexSE2*>(graph.vertex(ids.front()))->estimate();
  Trajectory out;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    if (k > 0) {
      if (!step[k]) {
        throw Error("dead reckoning: no EDGE_SE2 joins the consecutive poses " +
                    std::to_string(ids[k - 1]) + " and " + std::to_string(ids[k]));
      }
      pose = pose * *step[k];
    }
    out.append(static_cast<double>(ids[k]),
               se2ToIsometry3(pose.translation().x(), pose.translation().y(), pose.angle()));
  }
  return out;
}

}  // namespace graphslam::homework
