// SPDX-License-Identifier: MIT
#include "view_output.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "graphslam/optimizer/marginals.h"
#include "graphslam/support/error.h"

namespace graphslam::apps {

void declareViewOptions(po::options_description& desc, std::string& page, std::string& covariance) {
  desc.add_options()("view", po::value(&page),
                     "write a self-contained web page to explore the result here (one HTML file, "
                     "opens offline: docs/VIEW.md)")(
      "view-covariance", po::value(&covariance),
      "with --view: draw the 3-sigma marginal covariance of these vertices (ids separated "
      "by commas)");
}

std::vector<VertexId> parseIdList(const std::string& text, const std::string& option) {
  std::vector<VertexId> ids;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, comma - at);
    VertexId id = 0;
    const auto r = std::from_chars(item.data(), item.data() + item.size(), id);
    if (item.empty() || r.ec != std::errc() || r.ptr != item.data() + item.size()) {
      throw UsageError("--" + option + ": '" + item +
                       "' is not a vertex id (ids separated by commas)");
    }
    ids.push_back(id);
    at = comma + 1;
  }
  return ids;
}

ViewRecorder::ViewRecorder(std::string page, const view::Options& options)
    : page_(std::move(page)), options_(options) {}

void ViewRecorder::captureInitial(const Graph& graph, const std::string& label) {
  if (on()) initial_ = view::captureEstimates(graph, label, std::nan(""));
}

void ViewRecorder::captureEdgeTags(const Graph& graph, const TypeRegistry& types) {
  if (!on()) return;
  edge_tags_.clear();
  for (const auto& e : graph.edges()) {
    const std::string* tag = types.tagOf(*e);
    edge_tags_.push_back(tag ? *tag : std::string("(unregistered)"));
  }
}

void ViewRecorder::record(Optimizer::Options& options, const Graph& graph) {
  if (!on()) return;
  std::size_t doubles = 0;
  for (const auto& [id, v] : graph.vertices())
    doubles += static_cast<std::size_t>(v->estimateDataDimension());
  // Snapshots hold doubles; the page's frames floats of the positions only.
  const std::size_t keep = std::max<std::size_t>(
      2, std::min(options_.max_frames,
                  2 * options_.max_frame_bytes / std::max<std::size_t>(8 * doubles, 1)));
  auto previous = options.callback;
  options.callback = [this, previous, &graph, keep](const IterationStats& s) {
    if (previous) previous(s);
    if (seen_++ % stride_ != 0) return;
    frames_.push_back(
        view::captureEstimates(graph, "iteration " + std::to_string(s.iteration), s.chi2));
    if (frames_.size() <= keep) return;
    std::vector<view::Snapshot> kept;  // every other one, the first kept
    for (std::size_t i = 0; i < frames_.size(); i += 2) kept.push_back(std::move(frames_[i]));
    frames_.swap(kept);
    stride_ *= 2;
  };
}

std::vector<std::pair<std::string, std::string>> optimizerSummaryLines(const Summary& summary) {
  char chi2[96];
  std::snprintf(chi2, sizeof chi2, "%.6g -> %.6g", summary.initial_chi2, summary.final_chi2);
  char time[32];
  std::snprintf(time, sizeof time, "%.3f s", summary.total_time);
  return {{"status",
           toString(summary.status) + (summary.message.empty() ? "" : ": " + summary.message)},
          {"algorithm", std::string(toString(summary.algorithm)) + ", " +
                            std::to_string(summary.iterations) + " iterations"},
          {"solver", summary.linear_solver},
          {"chi2", chi2},
          {"time", time}};
}

void checkVertexIds(const Graph& graph, const std::vector<VertexId>& ids,
                    const std::string& option) {
  for (VertexId id : ids) {
    if (!graph.hasVertex(id)) {
      throw UsageError("--" + option + ": the graph has no vertex " + std::to_string(id));
    }
  }
}

void addCovariances(view::Scene& scene, Graph& graph, const Registries& reg,
                    const std::vector<VertexId>& ids, const std::string& option) {
  if (ids.empty()) return;
  checkVertexIds(graph, ids, option);
  MarginalCovariance::Options options;
  options.solvers = &reg.solvers;
  MarginalCovariance marginals(options);
  const MarginalSummary summary = marginals.compute(graph, ids);
  if (!summary.ok()) throw Error("marginal covariances for the page failed: " + summary.message);
  for (VertexId id : ids) scene.addCovariance(id, marginals.block(id));
}

/// The ground truth of a .npz file (positions of poses and landmarks) and each vertex's
/// position error, for the page.
void addPointTruth(view::Scene& scene, const Graph& graph, const io::PointGroundTruth& truth) {
  if (truth.empty()) return;
  std::map<VertexId, Eigen::Vector3d> where;
  std::map<VertexId, double> error;
  auto add = [&](const std::vector<VertexId>& ids, const std::vector<Eigen::Vector2d>& at) {
    for (std::size_t i = 0; i < ids.size() && i < at.size(); ++i) {
      const Vertex* v = graph.vertex(ids[i]);
      if (!v || v->estimateDataDimension() < 2) continue;
      std::vector<double> x(static_cast<std::size_t>(v->estimateDataDimension()));
      v->getEstimateData(x.data());
      where[ids[i]] = Eigen::Vector3d(at[i].x(), at[i].y(), 0.0);
      error[ids[i]] = (Eigen::Vector2d(x[0], x[1]) - at[i]).norm();
    }
  };
  add(truth.pose_ids, truth.poses);
  add(truth.landmark_ids, truth.landmarks);
  scene.setGroundTruth(where, error);
}

void ViewRecorder::write(const std::string& staged, Graph& graph, const Registries& reg,
                         const io::GraphFile& in,
                         const std::vector<std::pair<std::string, std::string>>& summary,
                         const outliers::GncResult* gnc,
                         const std::vector<VertexId>& covariance_ids) {
  view::Options options = options_;
  if (options.title.empty()) options.title = std::filesystem::path(in.path).filename().string();
  view::Scene scene(graph, reg.types, options);
  std::vector<std::size_t> lines = in.edge_lines;
  if (gnc && !gnc->rejected.empty()) {
    std::set<std::size_t> gone;
    for (const auto& r : gnc->rejected) {
      gone.insert(r.index);
      const std::string tag = r.index < edge_tags_.size() ? edge_tags_[r.index] : "(rejected)";
      scene.addRejectedEdge(r.vertex_ids, tag, r.chi2,
                            r.index < in.edge_lines.size() ? in.edge_lines[r.index] : 0);
    }
    lines.clear();
    for (std::size_t k = 0; k < in.edge_lines.size(); ++k) {
      if (!gone.count(k)) lines.push_back(in.edge_lines[k]);
    }
  }
  scene.setSourceLines(in.path, in.vertex_lines, lines);
  if (!initial_.data.empty()) scene.setInitial(initial_);
  for (auto& f : frames_) scene.addIteration(f);
  for (const auto& [k, v] : summary) scene.addSummary(k, v);
  addCovariances(scene, graph, reg, covariance_ids, "view-covariance");
  addPointTruth(scene, graph, in.ground_truth);
  scene.writePage(staged);
}

void writeGraphView(const std::string& staged, Graph& graph, const Registries& reg,
                    const std::string& title,
                    const std::vector<std::pair<std::string, std::string>>& summary,
                    const std::vector<std::pair<VertexId, std::size_t>>& vertex_lines,
                    const std::string& source) {
  view::Options options;
  options.title = title;
  view::Scene scene(graph, reg.types, options);
  scene.setSourceLines(source, vertex_lines, {});
  for (const auto& [k, v] : summary) scene.addSummary(k, v);
  scene.writePage(staged);
}

void writeTrajectoryView(const std::string& staged, const io::Trajectory& reference,
                         const io::Trajectory& estimate, const std::vector<double>& ape,
                         const Registries& reg, const std::string& title,
                         const std::vector<std::pair<std::string, std::string>>& summary) {
  bool planar = true;
  for (const auto& p : estimate.poses()) {
    planar =
        planar && std::abs(p.translation().z()) < 1e-9 && std::abs(p.linear()(2, 2) - 1) < 1e-9;
  }
  for (const auto& p : reference.poses()) planar = planar && std::abs(p.translation().z()) < 1e-9;
  Graph graph;
  std::map<VertexId, Eigen::Vector3d> truth;
  std::map<VertexId, double> errors;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const Eigen::Isometry3d& p = estimate.poses()[i];
    auto v = reg.types.createVertex(planar ? "VERTEX_SE2" : "VERTEX_SE3:QUAT");
    v->setId(static_cast<VertexId>(i));
    const Eigen::Quaterniond q(p.linear());
    const Eigen::Vector3d t = p.translation();
    const double se2[3] = {t.x(), t.y(), std::atan2(p.linear()(1, 0), p.linear()(0, 0))};
    const double se3[7] = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    v->setEstimateData(planar ? se2 : se3);
    graph.addVertex(std::move(v));
    if (i < reference.size()) truth[static_cast<VertexId>(i)] = reference.poses()[i].translation();
    if (i < ape.size()) errors[static_cast<VertexId>(i)] = ape[i];
  }
  view::Options options;
  options.title = title;
  view::Scene scene(graph, reg.types, options);
  scene.setGroundTruth(truth, errors);
  for (const auto& [k, v] : summary) scene.addSummary(k, v);
  scene.writePage(staged);
}

}  // namespace graphslam::apps
