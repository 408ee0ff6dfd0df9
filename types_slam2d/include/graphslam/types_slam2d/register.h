// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/type_registry.h"

namespace graphslam::types_slam2d {

/// Registers VERTEX_SE2, VERTEX_XY, EDGE_SE2, EDGE_SE2_XY and EDGE_PRIOR_SE2.
void registerTypes(TypeRegistry& registry);

}  // namespace graphslam::types_slam2d
