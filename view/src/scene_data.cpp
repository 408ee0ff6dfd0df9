// SPDX-License-Identifier: MIT
#include "scene_data.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <unordered_map>

#include "graphslam/core/edge.h"
#include "graphslam/support/error.h"

namespace graphslam::view {

namespace {

/// Odometry joins poses next to each other in id order (landmark ids between them do not
/// count: some files number poses and landmarks with one counter); `rank` is a vertex's
/// place among the poses.
EdgeKind kindOfEdge(const Edge& e, const std::vector<VertexKind>& kinds_by_index,
                    const std::unordered_map<const Vertex*, std::uint32_t>& index,
                    const std::vector<std::int64_t>& rank) {
  if (e.numVertices() == 1) return EdgeKind::kPrior;
  bool point = false, generic = false;
  for (std::size_t s = 0; s < e.numVertices(); ++s) {
    const VertexKind k = kinds_by_index[index.at(e.vertex(s))];
    point = point || k == VertexKind::kPoint;
    generic = generic || k == VertexKind::kGeneric;
  }
  if (generic) return EdgeKind::kOther;
  if (point) return EdgeKind::kLandmark;
  if (e.numVertices() == 2 &&
      std::abs(rank[index.at(e.vertex(0))] - rank[index.at(e.vertex(1))]) == 1) {
    return EdgeKind::kOdometry;
  }
  return EdgeKind::kLoopClosure;
}

}  // namespace

std::uint8_t tagIndex(std::vector<std::string>& tags, const std::string& tag) {
  const auto it = std::find(tags.begin(), tags.end(), tag);
  if (it != tags.end()) return static_cast<std::uint8_t>(it - tags.begin());
  if (tags.size() >= 255) throw Error("graphslam view: more than 255 vertex or edge tags");
  tags.push_back(tag);
  return static_cast<std::uint8_t>(tags.size() - 1);
}

std::string vertexTag(const TypeRegistry& types, const Vertex& v) {
  const std::string* tag = types.tagOf(v);
  return tag ? *tag : std::string("(unregistered)");
}

VertexKind kindOfTag(const std::string& tag) {
  if (tag == "VERTEX_SE2" || tag == "VERTEX_SE3:QUAT" || tag == "VERTEX_VEHICLE") {
    return VertexKind::kPose;
  }
  if (tag == "VERTEX_XY" || tag == "VERTEX_TRACKXYZ" || tag == "VERTEX_LANDMARK") {
    return VertexKind::kPoint;
  }
  return VertexKind::kGeneric;
}

int graphDimension(const Graph& graph, const TypeRegistry& types) {
  for (const auto& [id, v] : graph.vertices()) {
    const std::string* tag = types.tagOf(*v);
    if (tag && (*tag == "VERTEX_SE3:QUAT" || *tag == "VERTEX_TRACKXYZ")) return 3;
  }
  return 2;
}

void checkFinite(const Graph& graph) {
  std::vector<double> data;
  std::string ids;
  std::size_t bad = 0;
  for (const auto& [id, v] : graph.vertices()) {
    data.resize(static_cast<std::size_t>(v->estimateDataDimension()));
    v->getEstimateData(data.data());
    if (std::all_of(data.begin(), data.end(), [](double x) { return std::isfinite(x); })) continue;
    if (++bad <= 10) ids += (bad == 1 ? "" : ", ") + std::to_string(id);
  }
  if (bad == 0) return;
  throw InputError("graphslam view: the estimate of " + std::to_string(bad) +
                   (bad == 1 ? " vertex is" : " vertices are") + " not finite (NaN or infinite): " +
                   ids + (bad > 10 ? ", ..." : "") + "; no page written");
}

void buildStructure(Graph& graph, const TypeRegistry& types, Scene::Data& d) {
  std::unordered_map<const Vertex*, std::uint32_t> index;
  index.reserve(graph.numVertices());
  std::vector<VertexKind> kinds;
  std::map<std::string, std::size_t> generic;
  for (const auto& [id, v] : graph.vertices()) {
    const std::string tag = vertexTag(types, *v);
    const std::uint8_t t = tagIndex(d.vertex_tags, tag);
    if (d.tag_kinds.size() < d.vertex_tags.size()) d.tag_kinds.push_back(kindOfTag(tag));
    index.emplace(v.get(), static_cast<std::uint32_t>(d.vid.size()));
    kinds.push_back(d.tag_kinds[t]);
    if (kinds.back() == VertexKind::kGeneric) ++generic[tag];
    d.vid.push_back(id);
    d.vtag.push_back(t);
    d.vfixed.push_back(v->fixed() ? 1 : 0);
  }
  std::vector<std::int64_t> rank(kinds.size(), 0);
  std::int64_t poses = 0;
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    if (kinds[i] == VertexKind::kPose) rank[i] = poses++;
  }
  for (const auto& [tag, n] : generic) {
    d.notes.push_back("unknown vertex type " + tag + " (" + std::to_string(n) +
                      "): drawn as generic vertices from its first estimate values");
  }
  const std::size_t m = graph.numEdges();
  d.ea.reserve(m);
  d.eb.reserve(m);
  for (std::size_t k = 0; k < m; ++k) {
    const Edge& e = *graph.edges()[k];
    const std::string* tag = types.tagOf(e);
    d.etag.push_back(tagIndex(d.edge_tags, tag ? *tag : std::string("(unregistered)")));
    const std::uint32_t a = index.at(e.vertex(0));
    d.ea.push_back(a);
    d.eb.push_back(e.numVertices() > 1 ? index.at(e.vertex(1)) : a);
    for (std::size_t s = 2; s < e.numVertices(); ++s) {
      d.xedge.push_back(static_cast<std::uint32_t>(k));
      d.xvertex.push_back(index.at(e.vertex(s)));
    }
    d.ekind.push_back(static_cast<std::uint8_t>(kindOfEdge(e, kinds, index, rank)));
    std::uint8_t flag = e.active() ? 0 : kFlagInactive;
    if (e.robustKernel()) flag |= kFlagRobust;
    d.eflag.push_back(flag);
  }
}

std::vector<float> positionsOf(const std::vector<double>& snapshot, const Graph& graph, int dim) {
  std::vector<float> pos(graph.numVertices() * static_cast<std::size_t>(dim), 0.0f);
  std::size_t at = 0, i = 0;
  for (const auto& [id, v] : graph.vertices()) {
    const int n = v->estimateDataDimension();
    for (int c = 0; c < std::min(n, dim); ++c) {
      pos[i * static_cast<std::size_t>(dim) + static_cast<std::size_t>(c)] =
          static_cast<float>(snapshot[at + static_cast<std::size_t>(c)]);
    }
    at += static_cast<std::size_t>(n);
    ++i;
  }
  return pos;
}

std::vector<float> edgeChi2(Graph& graph) {
  std::vector<float> chi2;
  chi2.reserve(graph.numEdges());
  for (const auto& e : graph.edges()) {
    e->computeError();
    chi2.push_back(static_cast<float>(e->chi2()));
  }
  return chi2;
}

void restoreEstimates(Graph& graph, const Snapshot& snapshot) {
  std::size_t at = 0;
  for (const auto& [id, v] : graph.vertices()) {
    const auto n = static_cast<std::size_t>(v->estimateDataDimension());
    if (at + n > snapshot.data.size()) {
      throw Error("graphslam view: the snapshot '" + snapshot.label + "' does not fit the graph");
    }
    v->setEstimateData(snapshot.data.data() + at);
    at += n;
  }
  if (at != snapshot.data.size()) {
    throw Error("graphslam view: the snapshot '" + snapshot.label + "' does not fit the graph");
  }
}

}  // namespace graphslam::view
