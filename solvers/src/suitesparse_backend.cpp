// SPDX-License-Identifier: MIT
// The SuiteSparse backend's exported table (suitesparse_backend.h).
#include "suitesparse_backend.h"

extern "C" __attribute__((visibility("default"))) const graphslam::solvers::suitesparse::Backend*
graphslam_solvers_suitesparse_backend() {
  namespace ss = graphslam::solvers::suitesparse;
  static const ss::Backend table{ss::makeCholmodSolver, ss::makeCholmodComplexSolver,
                                 ss::makeCsparseSolver, ss::makeUmfpackSolver,
                                 ss::makeSpqrSolver,    ss::metisBlocks,
                                 ss::makeOrderedFactor, ss::metisSeparator};
  return &table;
}
