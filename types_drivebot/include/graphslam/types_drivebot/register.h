// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/type_registry.h"

namespace graphslam::types_drivebot {

/// Registers the DriveBot types. None exist yet (they come with the DriveBot issue), so
/// this registers nothing.
void registerTypes(TypeRegistry& registry);

}  // namespace graphslam::types_drivebot
