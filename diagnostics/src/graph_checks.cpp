// SPDX-License-Identifier: MIT
#include "graphslam/diagnostics/graph_checks.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>

#include "id_index.h"

namespace graphslam {

std::string formatIdRanges(const std::vector<VertexId>& ids, std::size_t max_ids) {
  std::string out;
  std::size_t shown = 0;
  for (std::size_t i = 0; i < ids.size() && shown < max_ids;) {
    std::size_t j = i;
    while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
    if (!out.empty()) out += ", ";
    out += std::to_string(ids[i]);
    if (j > i) out += "-" + std::to_string(ids[j]);
    shown += (j > i) ? 2 : 1;
    i = j + 1;
    if (shown >= max_ids && i < ids.size()) {
      out += ", ... (" + std::to_string(ids.size()) + " in total)";
    }
  }
  return out;
}

std::string ConstraintReport::describe(std::size_t max_ids) const {
  std::string out;
  auto line = [&](const std::string& text) {
    if (!out.empty()) out += "\n";
    out += text;
  };
  if (!without_edges.empty()) {
    line(std::to_string(without_edges.size()) +
         " non-fixed vertices have no edge at all: " + formatIdRanges(without_edges, max_ids));
  }
  for (const auto& group : unanchored) {
    line(std::to_string(group.size()) +
         " vertices are connected to no fixed vertex and no prior (they can move freely "
         "together): " +
         formatIdRanges(group, max_ids));
  }
  if (!too_few_measurements.empty()) {
    line(std::to_string(too_few_measurements.size()) +
         " vertices have fewer measured dimensions than unknowns: " +
         formatIdRanges(too_few_measurements, max_ids));
  }
  return out;
}

ConstraintReport checkConstraints(const Graph& graph) {
  ConstraintReport report;
  // Index the non-fixed vertices that have edges.
  detail::IdIndex index(graph);
  std::vector<VertexId> ids;
  std::vector<int> dimension;
  for (const auto& [id, v] : graph.vertices()) {
    if (v->fixed()) continue;
    if (v->edges().empty()) {
      report.without_edges.push_back(id);
      continue;
    }
    index.add(id, static_cast<int>(ids.size()));
    ids.push_back(id);
    dimension.push_back(v->dimension());
  }
  std::vector<int> parent(ids.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<char> anchored(ids.size(), 0);
  std::vector<int> measured(ids.size(), 0);
  for (const auto& e : graph.edges()) {
    int first = -1;
    bool touches_fixed = false;
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      const Vertex* v = e->vertex(s);
      if (v->fixed()) {
        touches_fixed = true;
        continue;
      }
      const int k = index.at(v->id());
      measured[k] += e->dimension();
      if (first < 0) {
        first = k;
      } else {
        const int a = find(first), b = find(k);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
    if (first >= 0 && (touches_fixed || e->numVertices() == 1)) anchored[first] = 1;
  }
  std::vector<char> root_anchored(ids.size(), 0);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    if (anchored[k]) root_anchored[find(static_cast<int>(k))] = 1;
  }
  std::vector<int> group_of_root(ids.size(), -1);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    if (measured[k] < dimension[k]) report.too_few_measurements.push_back(ids[k]);
    const int root = find(static_cast<int>(k));
    if (root_anchored[root]) continue;
    int& group = group_of_root[static_cast<std::size_t>(root)];
    if (group < 0) {
      group = static_cast<int>(report.unanchored.size());
      report.unanchored.emplace_back();
    }
    report.unanchored[static_cast<std::size_t>(group)].push_back(ids[k]);
  }
  return report;
}

}  // namespace graphslam
