// SPDX-License-Identifier: MIT
// Run-time plugin registering the DriveBot vehicle, landmark and sensor types of
// graphslam_types_drivebot.
#include "graphslam/core/plugin.h"
#include "graphslam/types_drivebot/register.h"

extern "C" GRAPHSLAM_PLUGIN_EXPORT void graphslam_plugin_register(
    graphslam::TypeRegistry& types, graphslam::SolverRegistry& /*solvers*/) {
  graphslam::types_drivebot::registerTypes(types);
}
