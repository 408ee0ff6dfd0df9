// SPDX-License-Identifier: MIT
// graphslam.optimize's options and result (optimize.cpp runs it as `graphslam optimize`
// does; optimize_result.cpp binds the result).
#pragma once

#include <string>
#include <vector>

#include "common.h"
#include "graphslam/optimizer/optimizer.h"

namespace graphslam::python {

/// An edge that outlier rejection removed.
struct RejectedEdgeInfo {
  std::size_t index = 0;        ///< in the graph's edges before the removal
  std::vector<VertexId> vertex_ids;
  double chi2 = 0.0;            ///< at the end of the GNC
  std::size_t line = 0;         ///< its line in the file (0: none)
};

/// What graphslam.optimize returns.
struct OptimizeResult {
  Summary summary;
  bool ok = false;                ///< the estimate is usable (converged or iterations used up)
  bool stopped = false;           ///< the callback stopped the run
  std::string status;             ///< converged, max_iterations, stopped, no_progress, ...
  std::string message;
  std::vector<std::string> initialization;  ///< what the initial guess did, line by line
  std::vector<RejectedEdgeInfo> rejected;   ///< outlier rejection's removed edges
  std::vector<VertexId> dropped;            ///< drop_unobservable's removed vertices
  std::size_t robust_edges = 0;
  double seconds = 0.0;  ///< the whole call: initial guess, checks, GNC, optimisation
};

void bindOptimizeResult(py::module_& m);

}  // namespace graphslam::python
