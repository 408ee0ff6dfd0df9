// SPDX-License-Identifier: MIT
#include "objective_options.h"

#include <cstdio>

#include "cli_common.h"

namespace graphslam::apps {

void checkObjective(const std::string& objective) {
  if (objective != "g2o" && objective != "chordal") {
    throw UsageError("--objective must be g2o or chordal, not '" + objective + "'");
  }
}

std::unique_ptr<init::ChordalObjective> applyObjective(const std::string& objective, Graph& graph) {
  if (objective != "chordal") return nullptr;
  auto switched = std::make_unique<init::ChordalObjective>(graph);
  std::printf("objective: chordal (SE-Sync's), %zu relative-pose edges switched\n",
              switched->switched());
  if (switched->skipped() > 0) {
    std::printf("  %zu edges kept in g2o's cost: their information gives no positive weight\n",
                switched->skipped());
  }
  return switched;
}

void finishObjective(init::ChordalObjective* objective, Graph& graph) {
  if (!objective) return;
  std::printf("SE-Sync's f: %.10g\n", objective->value());
  objective->restore();
  std::printf("chi2 in g2o's cost at this estimate: %.10g\n", graph.chi2());
}

}  // namespace graphslam::apps
