// SPDX-License-Identifier: MIT
// What the DriveBot test suites share.
#pragma once

#include "graphslam/core/linear_solver.h"
#include "graphslam/solvers/register.h"

namespace graphslam::drivebot_test {

/// Every registered linear solver, made once.
inline const SolverRegistry& allSolvers() {
  static const SolverRegistry registry = [] {
    SolverRegistry r;
    solvers::registerSolvers(r);
    return r;
  }();
  return registry;
}

}  // namespace graphslam::drivebot_test
