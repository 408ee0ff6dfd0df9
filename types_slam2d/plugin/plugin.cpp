// SPDX-License-Identifier: MIT
// Run-time plugin registering the SE(2) pose and 2D point types of graphslam_types_slam2d.
#include "graphslam/core/plugin.h"
#include "graphslam/types_slam2d/register.h"

extern "C" GRAPHSLAM_PLUGIN_EXPORT void graphslam_plugin_register(
    graphslam::TypeRegistry& types, graphslam::SolverRegistry& /*solvers*/) {
  graphslam::types_slam2d::registerTypes(types);
}
