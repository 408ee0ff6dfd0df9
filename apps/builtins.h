// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/core/plugin.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::apps {

/// The folders the tool discovers plugins in, in load order: its own plugin folder (in an
/// install tree <prefix>/<libdir>/graphslam/plugins, in the build tree build/plugins,
/// found from where the running tool is), then the folders of GRAPHSLAM_PLUGIN_PATH.
/// Throws graphslam::Error when the tool's own folder is missing (a shared build needs it
/// for every type and solver).
[[nodiscard]] std::vector<std::string> pluginDirectories();

/// Fills the registries: the plugins of pluginDirectories(), then `extra` (--plugin), in
/// order. A static build has no plugin modules: its types and solvers are registered
/// directly, then the plugins of GRAPHSLAM_PLUGIN_PATH and `extra` are loaded. Throws
/// graphslam::Error naming the file when a plugin fails to load or registers a name that
/// is already registered (naming both files).
[[nodiscard]] std::vector<std::unique_ptr<Plugin>> loadTypesAndSolvers(
    TypeRegistry& types, SolverRegistry& solvers, const std::vector<std::string>& extra);

/// The tool's process-wide settings, made once at start-up (the library makes none by
/// itself): SuiteSparse's allocations faulted in on two threads, CHOLMOD's OpenMP loops
/// serial, freed huge-page arrays kept for the next optimisation, and SIGXFSZ ignored (a
/// write past a file size limit then fails with EFBIG and is reported).
void configureProcess();

/// For the commands that run the incremental optimizer: BLAS on one thread unless
/// OPENBLAS_NUM_THREADS says otherwise. Its fronts are small for BLAS's threads: on two cores
/// they doubled the CPU time of sphere2500's replay and did not shorten it.
void oneBlasThreadUnlessSet();

/// Reports "graphslam COMMAND: out of memory ..." and ends the process with exit code 1
/// without the libraries' shutdown: after an allocation failure OpenBLAS's can wait forever
/// for a worker thread.
[[noreturn]] void exitOutOfMemory(const std::string& command);

}  // namespace graphslam::apps
