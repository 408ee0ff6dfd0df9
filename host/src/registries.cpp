// SPDX-License-Identifier: MIT
#include "graphslam/host/registries.h"

#include <cerrno>
#include <cstdlib>
#include <fstream>

#include "graphslam/drivebot/scenario.h"
#include "graphslam/io/register.h"
#include "graphslam/robust/register.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "graphslam/types_drivebot/register.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

namespace graphslam::host {

PluginHost Registries::pluginHost() {
  PluginHost host;
  host.types = &types;
  host.solvers = &solvers;
  host.kernels = &kernels;
  host.formats = &formats;
  host.modules = &modules;
  return host;
}

std::shared_ptr<const solvers::CostModel> calibrationFromEnvironment() {
  const char* path = std::getenv(kCalibrationVariable);
  if (!path || !*path) return nullptr;
  std::ifstream in(path);
  if (!in)
    throw InputError(support::cannotOpenMessage(path, errno) + " (" + kCalibrationVariable + ")");
  return std::make_shared<const solvers::CostModel>(solvers::CostModel::read(in, path));
}

void registerBuiltins(Registries& registries) {
  const PluginHost host = registries.pluginHost();
  const auto once = [&](const char* module, const auto& register_module) {
    if (!host.claimModule(module)) return;
    host.setOrigin(module);
    register_module();
    host.setOrigin("");
  };
  once("types_slam2d", [&] { types_slam2d::registerTypes(registries.types); });
  once("types_slam3d", [&] { types_slam3d::registerTypes(registries.types); });
  once("types_drivebot", [&] { types_drivebot::registerTypes(registries.types); });
  once("robust", [&] { robust::registerKernels(registries.kernels); });
  once("solvers", [&] {
    // One cache of block orderings: the global initial guess and the optimizer order one
    // pose graph once.
    solvers::SolverOptions options;
    options.ordering_cache = std::make_shared<solvers::OrderingCache>();
    options.auto_solver.cost_model = calibrationFromEnvironment();
    solvers::registerSolvers(registries.solvers, options);
  });
  once("io", [&] { io::registerFormats(registries.formats); });
  once("drivebot", [&] { drivebot::registerFormats(registries.formats); });
}

void loadPlugins(Registries& registries, const std::vector<std::string>& extra) {
  std::vector<std::string> files = findPluginFiles(pluginPathFromEnvironment());
  files.insert(files.end(), extra.begin(), extra.end());
  graphslam::loadPlugins(files, registries.pluginHost(), registries.plugins);
}

}  // namespace graphslam::host
