// SPDX-License-Identifier: MIT
#include "suitesparse.h"

#include "factories.h"
#include "graphslam/solvers/register.h"
#include "ordering.h"

namespace graphslam::solvers {

bool haveSuiteSparse() { return true; }

void registerSuiteSparseSolvers(SolverRegistry& registry, const SolverOptions& options) {
  const auto orderings = detail::availableOrderings();
  const auto nf = SystemForm::kNormalEquations;
  registry.registerSolver(
      "cholmod", "CHOLMOD supernodal Cholesky on H (ordering on the block graph)", nf, orderings,
      [options](const LinearSolverOptions& o) {
        return detail::withOrderingCache(
            makeCholmodSolver(true, o.ordering, false, options.cholmod), options);
      });
  registry.registerSolver(
      "cholmod-simplicial", "CHOLMOD simplicial Cholesky on H (ordering on the block graph)", nf,
      orderings, [options](const LinearSolverOptions& o) {
        return detail::withOrderingCache(
            makeCholmodSolver(false, o.ordering, false, options.cholmod), options);
      });
  registry.registerSolver(
      "csparse", "CXSparse up-looking Cholesky on H", nf, orderings,
      [options](const LinearSolverOptions& o) {
        return makeCsparseSolver(o.ordering, options.ordering_cache);
      });
  registry.registerSolver(
      "umfpack", "UMFPACK LU of H (both triangles; the ordering is its column pre-order)", nf,
      orderings, [options](const LinearSolverOptions& o) {
        return makeUmfpackSolver(o.ordering, options.ordering_cache);
      });
  // SPQR orders the scalar columns of J itself.
  registry.registerSolver("spqr",
                          "SuiteSparseQR on the whitened Jacobian J (SPQR's own column ordering)",
                          SystemForm::kJacobian,
                          {Ordering::kColamd, Ordering::kNatural, Ordering::kAmd, Ordering::kMetis},
                          [](const LinearSolverOptions& o) { return makeSpqrSolver(o.ordering); });
}

}  // namespace graphslam::solvers
