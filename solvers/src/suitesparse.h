// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: factories of the SuiteSparse backends. They load the
// backend library on first use (suitesparse_loader.cpp) and throw graphslam::Error when it
// cannot be loaded.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/solvers/options.h"
#include "ordering.h"

namespace graphslam::solvers {

/// CHOLMOD Cholesky of H given as its upper triangle, in any order. With
/// `prepermuted_lower`, H is given as its lower triangle, already in its fill-reducing and
/// postordered order, and analyzeOrdered() takes the identity order only: CHOLMOD then
/// factorises the given arrays without copying them (ordering() is only a label).
std::unique_ptr<detail::OrderedSolver> makeCholmodSolver(bool supernodal, Ordering ordering,
                                                         bool prepermuted_lower,
                                                         const CholmodOptions& options);
/// CHOLMOD on a Hermitian matrix: values, right-hand side and solution interleaved
/// complex (two doubles each); the structure counts complex entries and unknowns.
std::unique_ptr<detail::OrderedSolver> makeCholmodComplexSolver(bool supernodal, Ordering ordering,
                                                                bool prepermuted_lower,
                                                                const CholmodOptions& options);
/// `cache`: the block orderings the solver's analysis looks up (null: none).
std::unique_ptr<LinearSolver> makeCsparseSolver(Ordering ordering,
                                                std::shared_ptr<OrderingCache> cache);
std::unique_ptr<LinearSolver> makeUmfpackSolver(Ordering ordering,
                                                std::shared_ptr<OrderingCache> cache);
std::unique_ptr<LinearSolver> makeSpqrSolver(Ordering ordering);
/// METIS nested dissection of a block graph (through CHOLMOD).
std::vector<int> metisBlockOrdering(const detail::BlockGraph& g);

}  // namespace graphslam::solvers
