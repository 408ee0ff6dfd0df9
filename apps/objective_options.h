// SPDX-License-Identifier: MIT
// optimize --objective: g2o's chi2 (the default) or SE-Sync's chordal objective.
#pragma once

#include <memory>
#include <string>

#include "graphslam/core/graph.h"
#include "graphslam/init/chordal_objective.h"

namespace graphslam::apps {

/// Checks an --objective value (g2o|chordal); throws UsageError otherwise.
void checkObjective(const std::string& objective);

/// For chordal: switches the graph's relative-pose edges to SE-Sync's terms and says how
/// many; null for g2o (nothing to switch).
[[nodiscard]] std::unique_ptr<init::ChordalObjective> applyObjective(const std::string& objective,
                                                                     Graph& graph);

/// After optimising: prints SE-Sync's f, restores the original edges (so the graph can be
/// written) and prints chi2 in g2o's cost there. Nothing for a null objective.
void finishObjective(init::ChordalObjective* objective, Graph& graph);

}  // namespace graphslam::apps
