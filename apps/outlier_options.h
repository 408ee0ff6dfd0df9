// SPDX-License-Identifier: MIT
// graphslam optimize --reject-outliers: the options, the initial guess from the known
// inliers, the GNC run with its output, and the --outliers file.
#pragma once

#include <boost/program_options.hpp>
#include <cstddef>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/outliers/gnc.h"
#include "graphslam/outliers/robust_init.h"
#include "input.h"

namespace graphslam::apps {

/// The outlier-rejection options of graphslam optimize.
struct OutlierCliOptions {
  bool reject = false;        ///< --reject-outliers
  std::string outliers_file;  ///< --outliers FILE
  /// --gnc-init robust (true): with a global initialisation, outliers::rejectFromGlobalStart
  /// places the graph and rejects; known-inliers: the initialisation from the odometry and
  /// priors only, then outliers::runGnc.
  bool robust_init = true;
  std::string init_choice = "robust";  ///< --gnc-init as given
  bool global_start = false;           ///< set by initializeFromKnownInliers
  outliers::GncOptions gnc;
};

/// Adds --reject-outliers, --outliers and the GNC's tuning options to `desc`.
void declareOutlierOptions(boost::program_options::options_description& desc, OutlierCliOptions& o);

/// Checks the values after parsing (UsageError on a bad one).
void checkOutlierOptions(const boost::program_options::variables_map& vm, OutlierCliOptions& o);

/// The initial guess with --reject-outliers: as applyInitialGuess, but a global
/// initialisation uses the known inliers only (odometry and priors), which the wrong loop
/// closures cannot spoil. Prints one line on what was done.
void initializeFromKnownInliers(const LoadedInput& in, Graph& graph, std::string init,
                                const SolverRegistry& solvers, OutlierCliOptions& o);

/// Runs the GNC with `optimizer` options for its steps, prints its progress (unless quiet)
/// and its outcome, and removes the rejected edges from `graph`. Returns false (after
/// printing why) when a GNC step failed.
bool rejectOutliersForOptimize(Graph& graph, const SolverRegistry& solvers,
                               const Optimizer::Options& optimizer, OutlierCliOptions& o,
                               bool quiet, outliers::GncResult& result);

/// Writes the --outliers file: one line per rejected edge, `LINE ID... CHI2` (LINE: its
/// line in the input file, 0 when unknown; CHI2: at the end of the GNC), atomically.
/// `shown`: the name the "wrote" line gives (default `path`).
void writeOutliersFile(const std::string& path, const outliers::GncResult& result,
                       const std::vector<std::size_t>& edge_lines, const std::string& shown = {});

}  // namespace graphslam::apps
