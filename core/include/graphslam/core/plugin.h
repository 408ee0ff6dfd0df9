// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/core/type_registry.h"

/// The one symbol a plugin exports (a shared library built against graphslam::core):
///   extern "C" GRAPHSLAM_PLUGIN_EXPORT void graphslam_plugin_register(
///       graphslam::TypeRegistry& types, graphslam::SolverRegistry& solvers);
#define GRAPHSLAM_PLUGIN_EXPORT __attribute__((visibility("default")))
#define GRAPHSLAM_PLUGIN_ENTRY "graphslam_plugin_register"

namespace graphslam {

using PluginRegisterFunction = void(TypeRegistry&, SolverRegistry&);

/// A loaded plugin library. Keep it alive for as long as any object created through the
/// types or solvers it registered exists (destroy graphs before plugins).
class Plugin {
 public:
  /// Loads the shared library at `path` and calls its registration entry with the given
  /// registries. Throws graphslam::Error naming the path when the library cannot be
  /// loaded, lacks the entry, or its registration fails.
  static std::unique_ptr<Plugin> load(const std::string& path, TypeRegistry& types,
                                      SolverRegistry& solvers);
  ~Plugin();
  Plugin(const Plugin&) = delete;
  Plugin& operator=(const Plugin&) = delete;

  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  struct Impl;
  Plugin(std::string path, std::unique_ptr<Impl> impl);
  std::string path_;
  std::unique_ptr<Impl> impl_;
};

/// The environment variable naming further plugin folders (separated by ':').
inline constexpr const char* kPluginPathVariable = "GRAPHSLAM_PLUGIN_PATH";

/// The plugin files of `directories`, in the order of the folders and by file name within
/// each: every regular file whose name starts with "lib" and ends in ".so". A folder that
/// does not exist is skipped (an empty list is not an error).
[[nodiscard]] std::vector<std::string> findPluginFiles(const std::vector<std::string>& directories);

/// The folders of GRAPHSLAM_PLUGIN_PATH, in order (empty entries skipped; none when unset).
[[nodiscard]] std::vector<std::string> pluginPathFromEnvironment();

/// Loads every file of `paths` in order (Plugin::load); throws on the first that fails,
/// and when two plugins register the same name (the message names both files). The
/// registries hold code of the plugins: destroy them, and every graph and solver made
/// through them, before the plugins (declare the plugins first).
[[nodiscard]] std::vector<std::unique_ptr<Plugin>> loadPlugins(
    const std::vector<std::string>& paths, TypeRegistry& types, SolverRegistry& solvers);

}  // namespace graphslam
