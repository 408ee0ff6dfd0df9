// SPDX-License-Identifier: MIT
// Run-time plugins: shared libraries that add types, solvers, robust kernels or file formats
// to a program's registries. A plugin exports one entry, declared with GRAPHSLAM_PLUGIN_ENTRY:
//
//   #include "graphslam/core/plugin.h"
//   GRAPHSLAM_PLUGIN_ENTRY(host) {
//     if (!host.claimModule("my_types")) return;  // loaded twice: nothing to do
//     my_types::registerTypes(*host.types);
//   }
//
// The entry's symbol name carries the plugin ABI version (graphslam_plugin_register_abi2), so
// a plugin built against another version of this header is refused by name before any of its
// code runs, with a message naming both versions.
#pragma once

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/core/robust_kernel.h"
#include "graphslam/core/type_registry.h"

namespace graphslam {

namespace io {
class FormatRegistry;
}  // namespace io

/// The plugin ABI: bumped whenever PluginHost's layout or a registry's class changes in a
/// way that a plugin built against the old header would misread. A plugin built for another
/// ABI is refused (Plugin::load).
#define GRAPHSLAM_PLUGIN_ABI 3
inline constexpr std::uint32_t kPluginAbiVersion = GRAPHSLAM_PLUGIN_ABI;

/// What a program hands to a plugin's entry: the ABI it was built with and its registries.
/// Fields are only ever added at the end (`size` tells a plugin which exist); a change to
/// an existing one bumps kPluginAbiVersion.
struct PluginHost {
  std::uint32_t abi_version = kPluginAbiVersion;
  std::uint32_t size = sizeof(PluginHost);
  TypeRegistry* types = nullptr;          ///< vertex, edge and parameter tags
  SolverRegistry* solvers = nullptr;      ///< linear solvers and orderings
  KernelRegistry* kernels = nullptr;      ///< robust kernels
  io::FormatRegistry* formats = nullptr;  ///< file formats (graphslam/io/format_registry.h)
  /// Names of the modules registered so far (claimModule); owned by the program.
  std::set<std::string>* modules = nullptr;

  /// Records that `module` registers into these registries now; false when it already has
  /// (the module was built in, or another file carried it): the caller then registers
  /// nothing. Lets a module's plugin be loaded into a program that has the module built in.
  bool claimModule(const std::string& module) const {
    return modules == nullptr || modules->insert(module).second;
  }
  /// Sets the origin label of every registry's next registrations ("" to clear).
  void setOrigin(const std::string& origin) const;
};

/// A plugin's entry: `GRAPHSLAM_PLUGIN_ENTRY(host) { ... }` defines it (extern "C", exported,
/// named after the ABI version). Registration errors are reported by throwing.
#define GRAPHSLAM_PLUGIN_ENTRY(host)                                               \
  extern "C" __attribute__((visibility("default"))) void GRAPHSLAM_PLUGIN_SYMBOL_( \
      graphslam_plugin_register_abi, GRAPHSLAM_PLUGIN_ABI)(const graphslam::PluginHost& host)
#define GRAPHSLAM_PLUGIN_SYMBOL_(prefix, abi) GRAPHSLAM_PLUGIN_PASTE_(prefix, abi)
#define GRAPHSLAM_PLUGIN_PASTE_(prefix, abi) prefix##abi

/// The symbol GRAPHSLAM_PLUGIN_ENTRY defines for `abi` (the loader looks it up by name).
[[nodiscard]] std::string pluginEntrySymbol(std::uint32_t abi);

using PluginEntryFunction = void(const PluginHost&);

/// A loaded plugin library. Keep it alive for as long as any object created through what
/// it registered exists (destroy graphs and registries before plugins).
class Plugin {
 public:
  /// Loads the shared library at `path` and calls its entry with `host`. Throws
  /// graphslam::Error naming the path when the library cannot be loaded, has no entry,
  /// was built for another plugin ABI (naming both versions), or its registration throws
  /// (any exception, std or not).
  static std::unique_ptr<Plugin> load(const std::string& path, const PluginHost& host);
  ~Plugin();
  Plugin(const Plugin&) = delete;
  Plugin& operator=(const Plugin&) = delete;

  [[nodiscard]] const std::string& path() const { return path_; }
  /// The file's identity (device and inode): two paths of one file load it once.
  [[nodiscard]] const std::string& identity() const { return identity_; }

 private:
  Plugin(std::string path, std::string identity, void* handle);
  std::string path_;
  std::string identity_;
  void* handle_ = nullptr;
};

/// The environment variable naming further plugin folders (separated by ':').
inline constexpr const char* kPluginPathVariable = "GRAPHSLAM_PLUGIN_PATH";

/// The plugin files of `directories`, in the order of the folders and by file name within
/// each: every regular file whose name starts with "lib" and ends in ".so". A folder that
/// does not exist is skipped (an empty list is not an error).
[[nodiscard]] std::vector<std::string> findPluginFiles(const std::vector<std::string>& directories);

/// The folders of GRAPHSLAM_PLUGIN_PATH, in order (empty entries skipped; none when unset).
[[nodiscard]] std::vector<std::string> pluginPathFromEnvironment();

/// Loads every file of `paths` in order into `plugins` (Plugin::load), skipping a file
/// already loaded (the same file by another path, or named twice); throws on the first that
/// fails, and when two plugins register the same name (the message names both files).
/// Plugins hold the code behind the registries' entries: destroy the registries, and every
/// graph and solver made through them, before `plugins`.
void loadPlugins(const std::vector<std::string>& paths, const PluginHost& host,
                 std::vector<std::unique_ptr<Plugin>>& plugins);

}  // namespace graphslam
