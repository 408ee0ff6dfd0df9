// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: the SuiteSparse backend (CHOLMOD, CXSparse, UMFPACK, SPQR
// and METIS through CHOLMOD), built as a library of its own, libgraphslam_solvers_suitesparse,
// that the solvers library loads on first use (suitesparse_loader.cpp): CHOLMOD brings the
// BLAS and LAPACK and their start-up, which a program that never factorises with them should
// not pay. The backend exports one table of its factories.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/ordered_factor.h"
#include "ordering.h"

namespace graphslam::solvers::suitesparse {

// The backend's own definitions (suitesparse.h has the solvers library's entry points,
// which reach these through the table).
std::unique_ptr<detail::OrderedSolver> makeCholmodSolver(bool supernodal, Ordering ordering,
                                                         bool prepermuted_lower,
                                                         const CholmodOptions& options);
std::unique_ptr<detail::OrderedSolver> makeCholmodComplexSolver(bool supernodal, Ordering ordering,
                                                                bool prepermuted_lower,
                                                                const CholmodOptions& options);
std::unique_ptr<LinearSolver> makeCsparseSolver(Ordering ordering,
                                                std::shared_ptr<OrderingCache> cache);
std::unique_ptr<LinearSolver> makeUmfpackSolver(Ordering ordering,
                                                std::shared_ptr<OrderingCache> cache);
std::unique_ptr<LinearSolver> makeSpqrSolver(Ordering ordering);
std::vector<int> metisBlocks(const detail::BlockGraph& g);
std::unique_ptr<OrderedFactor> makeOrderedFactor();
std::vector<int> metisSeparator(const std::vector<int>& column_starts,
                                const std::vector<int>& rows);
/// A CHOLMOD status (cholmod_common::status, also SuiteSparseQR's) in words.
std::string cholmodStatusText(int status);

/// The table the backend library exports.
struct Backend {
  decltype(&makeCholmodSolver) cholmod;
  decltype(&makeCholmodComplexSolver) cholmod_complex;
  decltype(&makeCsparseSolver) csparse;
  decltype(&makeUmfpackSolver) umfpack;
  decltype(&makeSpqrSolver) spqr;
  decltype(&metisBlocks) metis;
  decltype(&makeOrderedFactor) ordered_factor;
  decltype(&metisSeparator) metis_separator;
};

}  // namespace graphslam::solvers::suitesparse

/// The backend library's one exported entry (by name, through dlopen).
extern "C" const graphslam::solvers::suitesparse::Backend* graphslam_solvers_suitesparse_backend();
