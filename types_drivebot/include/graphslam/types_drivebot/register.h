// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/type_registry.h"

namespace graphslam::types_drivebot {

/// Registers the DriveBot types: VERTEX_VEHICLE, VERTEX_LANDMARK, EDGE_VEHICLE_KINEMATICS,
/// EDGE_GPS, EDGE_COMPASS, EDGE_LANDMARK_RANGE_BEARING and EDGE_VEHICLE_PRIOR.
void registerTypes(TypeRegistry& registry);

}  // namespace graphslam::types_drivebot
