// SPDX-License-Identifier: MIT
#include "builtins.h"

#include "graphslam/solvers/register.h"
#include "graphslam/types_drivebot/register.h"
#include "graphslam/types_slam2d/register.h"

namespace graphslam::apps {

void registerBuiltins(TypeRegistry& types, SolverRegistry& solvers) {
  types_slam2d::registerTypes(types);
  types_drivebot::registerTypes(types);
  solvers.setOrigin("solvers");
  solvers::registerSolvers(solvers);
  solvers.setOrigin("");
}

}  // namespace graphslam::apps
