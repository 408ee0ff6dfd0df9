// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/type_registry.h"

namespace graphslam::types_slam3d {

/// Registers g2o's 3D tags: VERTEX_SE3:QUAT, VERTEX_TRACKXYZ, PARAMS_SE3OFFSET,
/// EDGE_SE3:QUAT, EDGE_SE3_OFFSET, EDGE_SE3_PRIOR, EDGE_SE3_XYZ_PRIOR, EDGE_SE3_TRACKXYZ,
/// EDGE_POINTXYZ and EDGE_POINTXYZ_PRIOR.
void registerTypes(TypeRegistry& registry);

}  // namespace graphslam::types_slam3d
