// SPDX-License-Identifier: MIT
#include "graphslam/init/dead_reckoning.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::init {

using namespace graphslam::types_slam2d;
using io::se2ToIsometry3;
using io::Trajectory;

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

}  // namespace graphslam::init
