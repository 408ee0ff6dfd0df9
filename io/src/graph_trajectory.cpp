// SPDX-License-Identifier: MIT
#include "graphslam/io/trajectory.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam3d/vertex_se3.h"

namespace graphslam::io {

Trajectory trajectoryFromGraph(const Graph& graph) {
  Trajectory out;
  for (const auto& [id, v] : graph.vertices()) {
    if (const auto* pose = dynamic_cast<const types_slam2d::VertexSE2*>(v.get())) {
      const types_slam2d::SE2& x = pose->estimate();
      out.append(static_cast<double>(id),
                 se2ToIsometry3(x.translation().x(), x.translation().y(), x.angle()));
    } else if (const auto* pose3 = dynamic_cast<const types_slam3d::VertexSE3*>(v.get())) {
      out.append(static_cast<double>(id), pose3->estimate().isometry());
    }
  }
  return out;
}

}  // namespace graphslam::io
