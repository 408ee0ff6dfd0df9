// SPDX-License-Identifier: MIT
// graphslam optimize's robust-kernel options, and graphslam list-kernels.
#pragma once

#include <boost/program_options.hpp>
#include <string>
#include <vector>

#include "cli_common.h"
#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::apps {

struct RobustOptions {
  std::string kernel;  ///< NAME[:WIDTH]; empty: no kernel
  std::string edges;   ///< all (when empty), loop-closures or an edge tag
};

/// Adds --robust-kernel and --robust-edges.
void declareRobustOptions(boost::program_options::options_description& desc, RobustOptions& o);

/// Checks the options against the registered kernels and edge tags; UsageError (exit 2)
/// naming the known ones when they are wrong.
void checkRobustOptions(const RobustOptions& o, const Registries& reg);

/// Gives the selected edges of `graph` the kernel and says so on stdout (nothing without
/// --robust-kernel).
void applyRobustOptions(const RobustOptions& o, Graph& graph, const Registries& reg);

/// graphslam list-kernels [--plugin LIB]...
int cmdListKernels(const std::vector<std::string>& args);

}  // namespace graphslam::apps
