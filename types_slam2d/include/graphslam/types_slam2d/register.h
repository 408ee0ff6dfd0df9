// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/type_registry.h"

namespace graphslam::types_slam2d {

/// Registers VERTEX_SE2, VERTEX_XY, EDGE_SE2, EDGE_SE2_XY, EDGE_PRIOR_SE2 and the
/// point-robot types EDGE_POINTXY, EDGE_PRIOR_XY, EDGE_XY_BEARING_RANGE.
void registerTypes(TypeRegistry& registry);

}  // namespace graphslam::types_slam2d
