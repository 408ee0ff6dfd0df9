// SPDX-License-Identifier: MIT
// Run-time plugin registering the SE(3) pose, 3D point and offset types of
// graphslam_types_slam3d.
#include "graphslam/core/plugin.h"

#include "graphslam/types_slam3d/register.h"

extern "C" GRAPHSLAM_PLUGIN_EXPORT void graphslam_plugin_register(
    graphslam::TypeRegistry& types, graphslam::SolverRegistry& /*solvers*/) {
  graphslam::types_slam3d::registerTypes(types);
}
