// SPDX-License-Identifier: MIT
// Run-time plugin registering the types of graphslam_types_slam2d (nothing when the program has
// the module already).
#include "graphslam/core/plugin.h"

#include "graphslam/types_slam2d/register.h"

GRAPHSLAM_PLUGIN_ENTRY(host) {
  if (!host.claimModule("types_slam2d")) return;
  graphslam::types_slam2d::registerTypes(*host.types);
}
