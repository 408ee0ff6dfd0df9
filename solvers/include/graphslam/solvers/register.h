// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/linear_solver.h"

namespace graphslam::solvers {

/// Registers "eigen-ldlt" and "eigen-llt" (Eigen simplicial Cholesky, block AMD ordering).
void registerEigenSolvers(SolverRegistry& registry);

/// Registers "cholmod" (supernodal) and "cholmod-simplicial". Throws RegistryError when
/// graphslam was built without CHOLMOD.
void registerCholmodSolvers(SolverRegistry& registry);

/// Whether this build has CHOLMOD.
[[nodiscard]] bool haveCholmod();

/// Registers every solver this build has.
void registerSolvers(SolverRegistry& registry);

}  // namespace graphslam::solvers
