// SPDX-License-Identifier: MIT
// Run-time plugin registering the SuiteSparse solvers (cholmod, cholmod-simplicial, csparse, umfpack, spqr)
// from the shared library graphslam_solvers.
#include <memory>

#include "graphslam/core/plugin.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/register.h"

extern "C" GRAPHSLAM_PLUGIN_EXPORT void graphslam_plugin_register(
    graphslam::TypeRegistry& /*types*/, graphslam::SolverRegistry& solvers) {
  // The solvers made through these registrations share one cache of block orderings, held
  // by the registry's entries: the global initial guess and the optimizer of one program
  // order the same pose graph once.
  graphslam::solvers::SolverOptions options;
  options.ordering_cache = std::make_shared<graphslam::solvers::OrderingCache>();
  graphslam::solvers::registerSuiteSparseSolvers(solvers, options);
}
