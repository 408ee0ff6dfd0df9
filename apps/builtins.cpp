// SPDX-License-Identifier: MIT
#include "builtins.h"

#include <memory>

#include "graphslam/core/large_array.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/process.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_drivebot/register.h"
#include "graphslam/types_slam2d/register.h"

namespace graphslam::apps {

void registerBuiltins(TypeRegistry& types, SolverRegistry& solvers) {
  types_slam2d::registerTypes(types);
  types_drivebot::registerTypes(types);
  solvers.setOrigin("solvers");
  solvers::SolverOptions options;
  options.ordering_cache = std::make_shared<solvers::OrderingCache>();
  solvers::registerSolvers(solvers, options);
  solvers.setOrigin("");
}

void configureProcess() {
  solvers::installCholmodPrefaultingAllocator();
  solvers::serializeCholmodOpenMp();
  setLargeArrayRetention(LargeArrayRetention{});
}

}  // namespace graphslam::apps
