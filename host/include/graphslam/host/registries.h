// SPDX-License-Identifier: MIT
// Everything a program that reads, optimises and writes graphs registers, in one object:
// the registries of types, solvers, robust kernels and file formats, filled with the
// library's modules (registerBuiltins) and with plugins (loadPlugins). The graphslam tool
// and the Python package both start from it; a program may equally call the modules'
// register functions itself.
//
//   host::Registries reg;
//   host::registerBuiltins(reg);
//   host::loadPlugins(reg, {"libmy_types.so"});  // GRAPHSLAM_PLUGIN_PATH's folders first
#pragma once

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/core/plugin.h"
#include "graphslam/core/robust_kernel.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/io/format_registry.h"
#include "graphslam/solvers/cost_model.h"

namespace graphslam::host {

/// The registries and the plugins behind their entries.
struct Registries {
  // Declared first so they are destroyed last: the registries hold factories whose code lives
  // in the plugins, and graphs built from them are destroyed before these.
  std::vector<std::unique_ptr<Plugin>> plugins;
  std::set<std::string> modules;  ///< modules registered so far (PluginHost::claimModule)
  TypeRegistry types;
  SolverRegistry solvers;
  KernelRegistry kernels;
  io::FormatRegistry formats;

  Registries() = default;
  Registries(const Registries&) = delete;
  Registries& operator=(const Registries&) = delete;

  /// The view of these registries a plugin's entry receives.
  [[nodiscard]] PluginHost pluginHost();
};

/// The environment variable naming a calibration file of the auto solver's cost model
/// (`graphslam calibrate -o FILE`); unset: the built-in model.
inline constexpr const char* kCalibrationVariable = "GRAPHSLAM_CALIBRATION";

/// The cost model of GRAPHSLAM_CALIBRATION's file, or null when the variable is unset.
/// Throws graphslam::InputError naming the file when it cannot be read or used.
[[nodiscard]] std::shared_ptr<const solvers::CostModel> calibrationFromEnvironment();

/// Registers the library's modules: the types of types_slam2d, types_slam3d and
/// types_drivebot, the robust kernels, every solver of this build (sharing one cache of
/// block orderings; auto with the cost model of GRAPHSLAM_CALIBRATION when set), and the
/// formats of io and drivebot. Each module once: calling it again,
/// or loading a module's plugin afterwards, registers nothing more.
void registerBuiltins(Registries& registries);

/// Loads the plugins of GRAPHSLAM_PLUGIN_PATH's folders, then the files of `extra`, each file
/// once (by identity). Throws graphslam::Error naming the file that fails to load, was built
/// for another plugin ABI, or registers a name that is already taken (naming both files).
void loadPlugins(Registries& registries, const std::vector<std::string>& extra = {});

}  // namespace graphslam::host
