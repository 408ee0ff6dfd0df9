// SPDX-License-Identifier: MIT
// Run-time plugin registering the types of graphslam_types_drivebot (nothing when the program has
// the module already).
#include "graphslam/core/plugin.h"

#include "graphslam/types_drivebot/register.h"

GRAPHSLAM_PLUGIN_ENTRY(host) {
  if (!host.claimModule("types_drivebot")) return;
  graphslam::types_drivebot::registerTypes(*host.types);
}
