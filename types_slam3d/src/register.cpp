// SPDX-License-Identifier: MIT
#include "graphslam/types_slam3d/register.h"

#include "graphslam/types_slam3d/edges.h"

namespace graphslam::types_slam3d {

void registerTypes(TypeRegistry& registry) {
  registry.registerVertex<VertexSE3>("VERTEX_SE3:QUAT");
  registry.registerVertex<VertexPointXYZ>("VERTEX_TRACKXYZ");
  registry.registerParameter<ParameterSE3Offset>("PARAMS_SE3OFFSET");
  registry.registerEdge<EdgeSE3>("EDGE_SE3:QUAT");
  registry.registerEdge<EdgeSE3Offset>("EDGE_SE3_OFFSET");
  registry.registerEdge<EdgeSE3Prior>("EDGE_SE3_PRIOR");
  registry.registerEdge<EdgeSE3XYZPrior>("EDGE_SE3_XYZ_PRIOR");
  registry.registerEdge<EdgeSE3PointXYZ>("EDGE_SE3_TRACKXYZ");
  registry.registerEdge<EdgePointXYZ>("EDGE_POINTXYZ");
  registry.registerEdge<EdgeXYZPrior>("EDGE_POINTXYZ_PRIOR");
}

}  // namespace graphslam::types_slam3d
