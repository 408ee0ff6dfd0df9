// SPDX-License-Identifier: MIT
// Run-time plugin registering the types of graphslam_types_slam3d (nothing when the program has
// the module already).
#include "graphslam/core/plugin.h"

#include "graphslam/types_slam3d/register.h"

GRAPHSLAM_PLUGIN_ENTRY(host) {
  if (!host.claimModule("types_slam3d")) return;
  graphslam::types_slam3d::registerTypes(*host.types);
}
