// SPDX-License-Identifier: MIT
// Run-time plugin registering the SuiteSparse solvers (cholmod, cholmod-simplicial, csparse, umfpack, spqr)
// from the shared library graphslam_solvers.
#include "graphslam/core/plugin.h"
#include "graphslam/solvers/register.h"

extern "C" GRAPHSLAM_PLUGIN_EXPORT void graphslam_plugin_register(
    graphslam::TypeRegistry& /*types*/, graphslam::SolverRegistry& solvers) {
  graphslam::solvers::registerSuiteSparseSolvers(solvers);
}
