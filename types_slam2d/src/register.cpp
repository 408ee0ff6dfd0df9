// SPDX-License-Identifier: MIT
#include "graphslam/types_slam2d/register.h"

#include "graphslam/types_slam2d/edge_bearing_se2_xy.h"
#include "graphslam/types_slam2d/edge_pointxy.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_prior_se2_xy.h"
#include "graphslam/types_slam2d/edge_prior_xy.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_lotsofxy.h"
#include "graphslam/types_slam2d/edge_se2_offset.h"
#include "graphslam/types_slam2d/edge_se2_pointxy_offset.h"
#include "graphslam/types_slam2d/edge_se2_twopointsxy.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/edge_se2_xy_calib.h"
#include "graphslam/types_slam2d/edge_xy_bearing_range.h"
#include "graphslam/types_slam2d/parameter_se2_offset.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::types_slam2d {

void registerTypes(TypeRegistry& registry) {
  registry.registerVertex<VertexSE2>("VERTEX_SE2");
  registry.registerVertex<VertexXY>("VERTEX_XY");
  registry.registerParameter<ParameterSE2Offset>("PARAMS_SE2OFFSET");
  registry.registerEdge<EdgeSE2>("EDGE_SE2");
  registry.registerEdge<EdgeSE2XY>("EDGE_SE2_XY");
  registry.registerEdge<EdgePriorSE2>("EDGE_PRIOR_SE2");
  registry.registerEdge<EdgePriorSE2XY>("EDGE_PRIOR_SE2_XY");
  registry.registerEdge<EdgeSE2Offset>("EDGE_SE2_OFFSET");
  registry.registerEdge<EdgeSE2PointXYOffset>("EDGE_SE2_POINTXY_OFFSET");
  registry.registerEdge<EdgeBearingSE2XY>("EDGE_BEARING_SE2_XY");
  registry.registerEdge<EdgeSE2XYCalib>("EDGE_SE2_XY_CALIB");
  registry.registerEdge<EdgeSE2TwoPointsXY>("EDGE_SE2_TWOPOINTSXY");
  registry.registerEdge<EdgeSE2LotsOfXY>("EDGE_SE2_LOTSOFXY");
  registry.registerEdge<EdgePointXY>("EDGE_POINTXY");
  registry.registerEdge<EdgePriorXY>("EDGE_PRIOR_XY");
  registry.registerEdge<EdgeXYBearingRange>("EDGE_XY_BEARING_RANGE");
}

}  // namespace graphslam::types_slam2d
