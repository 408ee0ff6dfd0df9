// SPDX-License-Identifier: MIT
// Run-time plugin registering every solver and ordering of graphslam_solvers (nothing when
// the program has the module already).
#include "graphslam/core/plugin.h"

#include <memory>

#include "graphslam/solvers/options.h"
#include "graphslam/solvers/register.h"

GRAPHSLAM_PLUGIN_ENTRY(host) {
  if (!host.claimModule("solvers")) return;
  // The solvers made through these registrations share one cache of block orderings, held
  // by the registry's entries: the global initial guess and the optimizer of one program
  // order the same pose graph once.
  graphslam::solvers::SolverOptions options;
  options.ordering_cache = std::make_shared<graphslam::solvers::OrderingCache>();
  graphslam::solvers::registerSolvers(*host.solvers, options);
}
