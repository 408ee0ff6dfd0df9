// SPDX-License-Identifier: MIT
// Built when graphslam is configured without SuiteSparse.
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"

namespace graphslam::solvers {

bool haveSuiteSparse() { return false; }

void registerSuiteSparseSolvers(SolverRegistry& /*registry*/, const SolverOptions& /*options*/) {
  throw RegistryError(
      "graphslam was built without SuiteSparse: the cholmod, csparse, umfpack and spqr solvers "
      "are not available (install libsuitesparse-dev and reconfigure)");
}

}  // namespace graphslam::solvers
