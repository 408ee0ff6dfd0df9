// SPDX-License-Identifier: MIT
#include "graphslam/view/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "graphslam/core/edge.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "scene_data.h"
#include "web_assets.inc"

namespace graphslam::view {

Snapshot captureEstimates(const Graph& graph, std::string label, double chi2) {
  Snapshot s;
  s.label = std::move(label);
  s.chi2 = chi2;
  std::size_t total = 0;
  for (const auto& [id, v] : graph.vertices()) {
    total += static_cast<std::size_t>(v->estimateDataDimension());
  }
  s.data.resize(total);
  std::size_t at = 0;
  for (const auto& [id, v] : graph.vertices()) {
    v->getEstimateData(s.data.data() + at);
    at += static_cast<std::size_t>(v->estimateDataDimension());
  }
  return s;
}

Scene::Scene(Graph& graph, const TypeRegistry& types, Options options)
    : graph_(graph), types_(types), options_(std::move(options)) {
  if (graph.numVertices() == 0) {
    throw InputError("graphslam view: the graph has no vertices: nothing to draw");
  }
}

void Scene::setSourceLines(std::string path,
                           const std::vector<std::pair<VertexId, std::size_t>>& vertex_lines,
                           const std::vector<std::size_t>& edge_lines) {
  source_ = std::move(path);
  vertex_lines_.clear();
  for (const auto& [id, line] : vertex_lines) vertex_lines_[id] = line;
  edge_lines_ = edge_lines;
}

void Scene::setInitial(Snapshot initial) { initial_ = std::move(initial); }

void Scene::addIteration(Snapshot frame) { frames_.push_back(std::move(frame)); }

void Scene::setGroundTruth(const std::map<VertexId, Eigen::Vector3d>& truth,
                           const std::map<VertexId, double>& ape) {
  truth_ = truth;
  ape_ = ape;
}

void Scene::addCovariance(VertexId id, const Eigen::MatrixXd& block) {
  if (!graph_.hasVertex(id)) {
    throw Error("graphslam view: covariance of vertex " + std::to_string(id) +
                ", which the graph does not have");
  }
  covariances_[id] = block;
}

void Scene::addRejectedEdge(const std::vector<VertexId>& ids, const std::string& tag, double chi2,
                            std::size_t line) {
  for (VertexId id : ids) {
    if (!graph_.hasVertex(id)) {
      throw Error("graphslam view: rejected edge " + tag + " on vertex " + std::to_string(id) +
                  ", which the graph does not have");
    }
  }
  if (ids.empty()) throw Error("graphslam view: rejected edge " + tag + " without vertices");
  rejected_.push_back({ids, tag, chi2, line});
}

void Scene::addSummary(std::string key, std::string value) {
  summary_.emplace_back(std::move(key), std::move(value));
}

std::string Scene::html() {
  checkFinite(graph_);
  Data d;
  d.dim = graphDimension(graph_, types_);
  buildStructure(graph_, types_, d);
  d.vline.assign(d.vid.size(), 0);
  for (std::size_t i = 0; i < d.vid.size(); ++i) {
    const auto it = vertex_lines_.find(d.vid[i]);
    if (it != vertex_lines_.end()) d.vline[i] = static_cast<std::int32_t>(it->second);
  }
  const bool lines = edge_lines_.size() == graph_.numEdges();
  for (std::size_t k = 0; k < graph_.numEdges(); ++k) {
    d.eline.push_back(lines ? static_cast<std::int32_t>(edge_lines_[k]) : 0);
  }
  // The current estimate, last frame; its robust weights mark the down-weighted edges.
  const Snapshot current =
      captureEstimates(graph_, "optimised", std::numeric_limits<double>::quiet_NaN());
  std::vector<float> chi2_now = edgeChi2(graph_);
  for (std::size_t k = 0; k < graph_.numEdges(); ++k) {
    const Edge& e = *graph_.edges()[k];
    const double w = e.robustWeight();
    d.eweight.push_back(static_cast<float>(w));
    if (e.robustKernel() && w < options_.downweight_below) d.eflag[k] |= kFlagDownweighted;
    if (graph_.numEdges() <= options_.max_error_edges) {
      d.edim.push_back(static_cast<std::uint8_t>(std::min(e.dimension(), 255)));
      for (int r = 0; r < d.edim.back(); ++r)
        d.eerr.push_back(static_cast<float>(e.errorData()[r]));
    }
  }
  addRejectedArrays(d);
  addFrames(d, current, chi2_now);
  addTruth(d);
  std::string extra = covarianceJson(d);
  extra += ",\"summary\":[";
  for (std::size_t i = 0; i < summary_.size(); ++i) {
    extra += (i ? "[" : "[") + jsonString(summary_[i].first) + "," +
             jsonString(summary_[i].second) + (i + 1 < summary_.size() ? "]," : "]");
  }
  extra += "]";
  const std::string title = options_.title.empty() ? std::string("graph") : options_.title;
  std::string page;
  page.reserve(1 << 16);
  page += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>";
  for (const char c : title)
    page += c == '<' ? std::string("&lt;") : c == '&' ? std::string("&amp;") : std::string(1, c);
  page += " - graphslam view</title>\n<style>\n";
  page += kViewerStyle;
  page += "</style></head>\n<body>\n<script type=\"application/json\" id=\"graph-data\">";
  page += dataJson(d, title, source_, options_, extra);
  page += "</script>\n<script>\n\"use strict\";\n";
  for (const char* script : kViewerScripts) page += script;
  page += "</script>\n</body></html>\n";
  return page;
}

void Scene::writePage(const std::string& path) {
  const std::string page = html();
  support::writeFileAtomically(path, [&](std::ostream& out) { out << page; });
}

}  // namespace graphslam::view
