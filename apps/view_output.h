// SPDX-License-Identifier: MIT
// The tool's pages (view module): `graphslam view` and --view PAGE.html of optimize,
// incremental, eval and drivebot.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "cli_common.h"
#include "graphslam/io/graph_file.h"
#include "graphslam/io/trajectory.h"
#include "graphslam/outliers/gnc.h"
#include "graphslam/view/scene.h"

namespace graphslam::apps {

/// Declares --view PAGE.html and --view-covariance IDS into `desc`.
void declareViewOptions(po::options_description& desc, std::string& page, std::string& covariance);

/// The vertex ids of a --view-covariance / --covariance list ("3,17,40"); throws UsageError.
[[nodiscard]] std::vector<VertexId> parseIdList(const std::string& text, const std::string& option);

/// Throws UsageError naming `option` and the first of `ids` that `graph` does not have.
void checkVertexIds(const Graph& graph, const std::vector<VertexId>& ids,
                    const std::string& option);

/// Records what a page shows of an optimisation: the estimate it starts from and every
/// iteration's (thinned evenly, doubling its stride, once more than the page keeps).
class ViewRecorder {
 public:
  ViewRecorder(std::string page, const view::Options& options = {});
  [[nodiscard]] bool on() const { return !page_.empty(); }
  [[nodiscard]] const std::string& page() const { return page_; }
  /// The estimate of `graph` now, as the page's initial estimate.
  void captureInitial(const Graph& graph, const std::string& label);
  /// Makes `options.callback` also record `graph`'s estimate after every iteration.
  void record(Optimizer::Options& options, const Graph& graph);
  /// The tags of `graph`'s edges now (before outlier rejection removes some).
  void captureEdgeTags(const Graph& graph, const TypeRegistry& types);

  /// Writes the page for `graph` to `staged`: the recorded estimates, the source lines of
  /// `in` (edge lines before `gnc` removed its rejected edges, which are drawn as such), the
  /// covariances of `covariance_ids` and the `summary` lines. Throws Error.
  void write(const std::string& staged, Graph& graph, const Registries& reg,
             const io::GraphFile& in,
             const std::vector<std::pair<std::string, std::string>>& summary,
             const outliers::GncResult* gnc, const std::vector<VertexId>& covariance_ids);

 private:
  std::string page_;
  view::Options options_;
  view::Snapshot initial_;
  std::vector<view::Snapshot> frames_;
  std::size_t stride_ = 1, seen_ = 0;
  std::vector<std::string> edge_tags_;
};

/// The summary lines of an optimisation for a page: status, algorithm, solver, chi2, time.
[[nodiscard]] std::vector<std::pair<std::string, std::string>> optimizerSummaryLines(
    const Summary& summary);

/// Adds the marginal covariances of `ids` (computed at `graph`'s estimate) to `scene`;
/// throws Error naming the vertices when they cannot be computed.
void addCovariances(view::Scene& scene, Graph& graph, const Registries& reg,
                    const std::vector<VertexId>& ids, const std::string& option);

/// A page of `graph` as it is (incremental and drivebot --view): `title`, the `summary`
/// lines and, when known, the file line of each vertex.
void writeGraphView(const std::string& staged, Graph& graph, const Registries& reg,
                    const std::string& title,
                    const std::vector<std::pair<std::string, std::string>>& summary,
                    const std::vector<std::pair<VertexId, std::size_t>>& vertex_lines = {},
                    const std::string& source = {});

/// eval --view: the estimate (aligned as evaluated) coloured by its APE per pose, over the
/// reference, written to `staged`.
void writeTrajectoryView(const std::string& staged, const io::Trajectory& reference,
                         const io::Trajectory& estimate, const std::vector<double>& ape,
                         const Registries& reg, const std::string& title,
                         const std::vector<std::pair<std::string, std::string>>& summary);

}  // namespace graphslam::apps
