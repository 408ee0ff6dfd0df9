// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/linear_solver.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::apps {

/// Registers every type module and solver this build has. The solvers share one cache of
/// block orderings: the global initial guess and the optimizer order one pose graph.
void registerBuiltins(TypeRegistry& types, SolverRegistry& solvers);

/// The tool's process-wide settings, made once at start-up (the library makes none by
/// itself): SuiteSparse's allocations faulted in on two threads, CHOLMOD's OpenMP loops
/// serial, and freed huge-page arrays kept for the next optimisation.
void configureProcess();

}  // namespace graphslam::apps
