// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/type_registry.h"

namespace graphslam::types_slam2d {

/// Registers g2o's slam2d types — VERTEX_SE2, VERTEX_XY, PARAMS_SE2OFFSET, EDGE_SE2,
/// EDGE_SE2_XY, EDGE_PRIOR_SE2, EDGE_PRIOR_SE2_XY, EDGE_SE2_OFFSET, EDGE_SE2_POINTXY_OFFSET,
/// EDGE_BEARING_SE2_XY, EDGE_SE2_XY_CALIB, EDGE_SE2_TWOPOINTSXY, EDGE_SE2_LOTSOFXY,
/// EDGE_POINTXY, EDGE_PRIOR_XY — and the point-robot EDGE_XY_BEARING_RANGE.
void registerTypes(TypeRegistry& registry);

}  // namespace graphslam::types_slam2d
