// SPDX-License-Identifier: MIT
#include "builtins.h"

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

#include "graphslam/core/error.h"
#include "graphslam/core/large_array.h"
#include "graphslam/solvers/process.h"

#ifndef GRAPHSLAM_TOOL_PLUGINS
#include "graphslam/robust/register.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_drivebot/register.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"
#endif

namespace graphslam::apps {

namespace {

namespace fs = std::filesystem;

#ifdef GRAPHSLAM_TOOL_PLUGINS
/// The tool's own plugin folder: next to an installed tool, else in the build tree.
std::string ownPluginDirectory() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec)
    throw Error("cannot find the graphslam tool's own path (/proc/self/exe): " + ec.message());
  const fs::path candidates[] = {exe.parent_path() / GRAPHSLAM_INSTALLED_PLUGINS_FROM_TOOL,
                                 exe.parent_path() / GRAPHSLAM_BUILD_PLUGINS_FROM_TOOL};
  for (const auto& dir : candidates) {
    if (fs::is_directory(dir, ec)) return dir.lexically_normal().string();
  }
  throw Error("the graphslam tool's plugin folder is missing (looked in " +
              candidates[0].lexically_normal().string() + " and " +
              candidates[1].lexically_normal().string() +
              "): it holds every type and solver; reinstall or rebuild");
}
#endif

}  // namespace

std::vector<std::string> pluginDirectories() {
  std::vector<std::string> dirs;
#ifdef GRAPHSLAM_TOOL_PLUGINS
  dirs.push_back(ownPluginDirectory());
#endif
  for (auto& dir : pluginPathFromEnvironment()) dirs.push_back(std::move(dir));
  return dirs;
}

std::vector<std::unique_ptr<Plugin>> loadTypesAndSolvers(TypeRegistry& types,
                                                         SolverRegistry& solvers,
                                                         const std::vector<std::string>& extra) {
#ifndef GRAPHSLAM_TOOL_PLUGINS
  types.setOrigin("types_slam2d");
  types_slam2d::registerTypes(types);
  types.setOrigin("types_slam3d");
  types_slam3d::registerTypes(types);
  types.setOrigin("types_drivebot");
  types_drivebot::registerTypes(types);
  types.setOrigin("robust");
  robust::registerKernels(types);
  types.setOrigin("");
  solvers.setOrigin("solvers");
  // One cache of block orderings: the global initial guess and the optimizer order one
  // pose graph.
  solvers::SolverOptions options;
  options.ordering_cache = std::make_shared<solvers::OrderingCache>();
  solvers::registerSolvers(solvers, options);
  solvers.setOrigin("");
#endif
  std::vector<std::string> files = findPluginFiles(pluginDirectories());
  files.insert(files.end(), extra.begin(), extra.end());
  return loadPlugins(files, types, solvers);
}

void exitOutOfMemory(const std::string& command) {
  std::cout.flush();
  std::cerr << "graphslam " << command
            << ": out of memory: the work needs more memory than this process may use\n";
  std::cerr.flush();
  std::_Exit(1);
}

void oneBlasThreadUnlessSet() {
  if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr) (void)solvers::setBlasThreads(1);
}

void configureProcess() {
  // Under a file size limit (ulimit -f) a write past it fails with EFBIG, reported with the
  // file's name and the staged outputs removed, instead of SIGXFSZ ending the process.
  std::signal(SIGXFSZ, SIG_IGN);
  solvers::installCholmodPrefaultingAllocator();
  solvers::serializeCholmodOpenMp();
  setLargeArrayRetention(LargeArrayRetention{});
}

}  // namespace graphslam::apps
