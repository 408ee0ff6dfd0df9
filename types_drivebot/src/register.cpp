// SPDX-License-Identifier: MIT
#include "graphslam/types_drivebot/register.h"

namespace graphslam::types_drivebot {

void registerTypes(TypeRegistry& /*registry*/) {}

}  // namespace graphslam::types_drivebot
