// SPDX-License-Identifier: MIT
// Built when graphslam is configured without SuiteSparse.
#include "graphslam/solvers/ordered_factor.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"

namespace graphslam::solvers {

bool haveSuiteSparse() { return false; }

void registerSuiteSparseSolvers(SolverRegistry& /*registry*/, const SolverOptions& /*options*/) {
  throw RegistryError(
      "graphslam was built without SuiteSparse: the cholmod, csparse, umfpack and spqr solvers "
      "are not available (install libsuitesparse-dev and reconfigure)");
}

std::unique_ptr<OrderedFactor> makeOrderedSupernodalFactor() {
  throw Error("graphslam was built without SuiteSparse: no supernodal factorisation (CHOLMOD)");
}

std::vector<int> metisVertexSeparator(const std::vector<int>& /*column_starts*/,
                                      const std::vector<int>& /*rows*/) {
  throw Error("graphslam was built without SuiteSparse: no METIS vertex separator (CHOLMOD)");
}

}  // namespace graphslam::solvers
