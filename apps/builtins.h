// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/linear_solver.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::apps {

/// Registers every type module and solver this build has.
void registerBuiltins(TypeRegistry& types, SolverRegistry& solvers);

}  // namespace graphslam::apps
