// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: factories of the backends the registry and the composite
// solvers (auto, isotropic) make, each with its tuning.
#pragma once

#include <memory>

#include "common.h"
#include "graphslam/solvers/options.h"

namespace graphslam::solvers {

/// Largest vertex dimension of a structure.
[[nodiscard]] int maxBlockSize(const SparseStructure& s);

std::unique_ptr<detail::OrderedSolver> makeEigenLdlt();
std::unique_ptr<detail::OrderedSolver> makeBlockCholesky(Ordering ordering,
                                                         const BlockCholeskyOptions& options);
/// The isotropic (H = H_s (x) I_d) and conformal (Hermitian 2x2 blocks) paths; `options`
/// for their own tuning and their inner CHOLMOD and block-llt factorisations.
std::unique_ptr<detail::OrderedSolver> makeIsotropicSolver(Ordering ordering,
                                                           const SolverOptions& options);
std::unique_ptr<detail::OrderedSolver> makeConformalSolver(Ordering ordering,
                                                           const SolverOptions& options);
/// Both paths on one analysis (vertices of dimension 2): each factorisation takes the
/// isotropic path when its values allow, else the conformal one.
std::unique_ptr<detail::OrderedSolver> makeTwoWayIsotropicSolver(Ordering ordering,
                                                                 const SolverOptions& options);
std::unique_ptr<detail::OrderedSolver> makeEnvelopeSolver(Ordering ordering);
std::unique_ptr<LinearSolver> makePcgSolver();

namespace detail {
/// `solver` with the registry's shared cache of block orderings (options.ordering_cache,
/// may be null).
template <typename Solver>
std::unique_ptr<Solver> withOrderingCache(std::unique_ptr<Solver> solver,
                                          const SolverOptions& options) {
  solver->setOrderingCache(options.ordering_cache);
  return solver;
}
}  // namespace detail

}  // namespace graphslam::solvers
