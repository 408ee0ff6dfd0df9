// SPDX-License-Identifier: MIT
// The solvers library as a plugin (libgraphslam_solvers_plugin.so).
#include "graphslam/core/plugin.h"
#include "graphslam/solvers/register.h"

extern "C" GRAPHSLAM_PLUGIN_EXPORT void graphslam_plugin_register(
    graphslam::TypeRegistry& /*types*/, graphslam::SolverRegistry& solvers) {
  graphslam::solvers::registerSolvers(solvers);
}
