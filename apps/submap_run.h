// SPDX-License-Identifier: MIT
// graphslam optimize --submaps K: the submap solver in place of the direct path.
#pragma once

#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/optimizer/optimizer.h"

namespace graphslam::apps {

/// Optimises `graph` by `submaps` submaps (the separator system solved by the solver
/// `options.linear_solver` names, or for "auto" by cholmod when `solvers` has it) with the
/// iteration limits, tolerances and
/// threads of `options`, printing a line per iteration (unless `quiet`: chi2, gradient
/// norm, separator size, time) and the summary; adds the --stats lines to `csv` (the
/// optimizer's columns, the submap figures in the strategy column). Returns the summary in
/// the optimizer's form for the outputs. Throws graphslam::Error for a partition it refuses.
Summary runSubmapSolver(Graph& graph, const SolverRegistry& solvers, int submaps,
                        const Optimizer::Options& options, bool quiet,
                        std::vector<std::string>& csv);

}  // namespace graphslam::apps
