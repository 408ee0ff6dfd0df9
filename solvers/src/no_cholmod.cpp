// SPDX-License-Identifier: MIT
// Built instead of cholmod_solver.cpp when graphslam is configured without CHOLMOD.
#include "graphslam/core/error.h"
#include "graphslam/solvers/register.h"

namespace graphslam::solvers {

bool haveCholmod() { return false; }

void registerCholmodSolvers(SolverRegistry& /*registry*/) {
  throw RegistryError(
      "graphslam was built without CHOLMOD (install libsuitesparse-dev and "
      "reconfigure with GRAPHSLAM_WITH_CHOLMOD=ON)");
}

}  // namespace graphslam::solvers
