// SPDX-License-Identifier: MIT
#include "suitesparse.h"

#include "graphslam/solvers/register.h"
#include "ordering.h"

namespace graphslam::solvers {

bool haveSuiteSparse() { return true; }

void registerSuiteSparseSolvers(SolverRegistry& registry) {
  const auto orderings = detail::availableOrderings();
  const auto nf = SystemForm::kNormalEquations;
  registry.registerSolver(
      "cholmod", "CHOLMOD supernodal Cholesky on H (ordering on the block graph)", nf, orderings,
      [](const LinearSolverOptions& o) { return makeCholmodSolver(true, o.ordering); });
  registry.registerSolver(
      "cholmod-simplicial", "CHOLMOD simplicial Cholesky on H (ordering on the block graph)", nf,
      orderings, [](const LinearSolverOptions& o) { return makeCholmodSolver(false, o.ordering); });
  registry.registerSolver(
      "csparse", "CXSparse up-looking Cholesky on H", nf, orderings,
      [](const LinearSolverOptions& o) { return makeCsparseSolver(o.ordering); });
  registry.registerSolver(
      "umfpack", "UMFPACK LU of H (both triangles; the ordering is its column pre-order)", nf,
      orderings, [](const LinearSolverOptions& o) { return makeUmfpackSolver(o.ordering); });
  // SPQR orders the scalar columns of J itself.
  registry.registerSolver("spqr",
                          "SuiteSparseQR on the whitened Jacobian J (SPQR's own column ordering)",
                          SystemForm::kJacobian,
                          {Ordering::kColamd, Ordering::kNatural, Ordering::kAmd, Ordering::kMetis},
                          [](const LinearSolverOptions& o) { return makeSpqrSolver(o.ordering); });
}

}  // namespace graphslam::solvers
