// SPDX-License-Identifier: MIT
// Run-time plugin registering the robust kernels of graphslam_robust.
#include "graphslam/core/plugin.h"

#include "graphslam/robust/register.h"

extern "C" GRAPHSLAM_PLUGIN_EXPORT void graphslam_plugin_register(
    graphslam::TypeRegistry& types, graphslam::SolverRegistry& /*solvers*/) {
  graphslam::robust::registerKernels(types);
}
