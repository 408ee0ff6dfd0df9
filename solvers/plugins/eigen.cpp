// SPDX-License-Identifier: MIT
// Run-time plugin registering the solvers built on Eigen alone (eigen-ldlt, eigen-llt, eigen-qr, dense-ldlt, dense-pinv, pcg, block-llt, ...)
// from the shared library graphslam_solvers.
#include "graphslam/core/plugin.h"
#include "graphslam/solvers/register.h"

extern "C" GRAPHSLAM_PLUGIN_EXPORT void graphslam_plugin_register(
    graphslam::TypeRegistry& /*types*/, graphslam::SolverRegistry& solvers) {
  graphslam::solvers::registerEigenSolvers(solvers);
}
