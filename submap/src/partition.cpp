// SPDX-License-Identifier: MIT
#include "graphslam/submap/partition.h"

#include <algorithm>
#include <climits>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "graphslam/diagnostics/graph_checks.h"
#include "graphslam/support/error.h"
#include "node_bisection.h"

namespace graphslam::submap {
namespace {

/// The optimised vertices (non-fixed, with an active edge) in id order, their index by
/// address, and their adjacency (compressed rows). An edge of several vertices joins every
/// pair of them for node bisection (a separator then splits no edge), and its first
/// non-fixed vertex to the others for breadth-first orders (which keeps them together).
struct VertexGraph {
  std::vector<Vertex*> vertices;
  std::unordered_map<const Vertex*, int> index;
  std::vector<int> starts, neighbours;

  [[nodiscard]] int indexOf(const Vertex* v) const {
    const auto it = index.find(v);
    return it == index.end() ? -1 : it->second;
  }
};

/// The non-fixed vertices of `edge` as indices of `vg` (empty for an inactive edge).
void edgeVariables(const VertexGraph& vg, const Edge& edge, std::vector<int>& out) {
  out.clear();
  if (!edge.active()) return;
  for (std::size_t s = 0; s < edge.numVertices(); ++s) {
    const int k = vg.indexOf(edge.vertex(s));
    if (k >= 0) out.push_back(k);
  }
}

VertexGraph buildVertexGraph(const Graph& graph, bool all_pairs) {
  VertexGraph vg;
  for (const auto& [id, v] : graph.vertices()) {
    if (v->fixed()) continue;
    const auto& edges = v->edges();
    if (std::none_of(edges.begin(), edges.end(), [](const Edge* e) { return e->active(); })) {
      continue;
    }
    vg.index.emplace(v.get(), static_cast<int>(vg.vertices.size()));
    vg.vertices.push_back(v.get());
  }
  const std::size_t n = vg.vertices.size();
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> vars;
  for (const auto& e : graph.edges()) {
    edgeVariables(vg, *e, vars);
    for (std::size_t j = 0; j < (all_pairs ? vars.size() : 1); ++j) {
      for (std::size_t k = j + 1; k < vars.size(); ++k) {
        pairs.emplace_back(vars[j], vars[k]);
        pairs.emplace_back(vars[k], vars[j]);
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  vg.starts.assign(n + 1, 0);
  for (const auto& p : pairs) ++vg.starts[static_cast<std::size_t>(p.first) + 1];
  std::partial_sum(vg.starts.begin(), vg.starts.end(), vg.starts.begin());
  vg.neighbours.reserve(pairs.size());
  for (const auto& p : pairs) vg.neighbours.push_back(p.second);
  return vg;
}

/// Breadth-first order of `nodes` (vertices whose stamp equals `stamp`) from `start`,
/// continuing from the next unvisited node of `nodes` when a component is exhausted.
std::vector<int> bfsOrder(const VertexGraph& vg, const std::vector<int>& nodes, int start,
                          std::vector<int>& stamps, int stamp) {
  std::vector<int> order;
  order.reserve(nodes.size());
  const int visited = stamp + 1;
  auto visit = [&](int s) {
    stamps[static_cast<std::size_t>(s)] = visited;
    order.push_back(s);
    for (std::size_t head = order.size() - 1; head < order.size(); ++head) {
      const auto u = static_cast<std::size_t>(order[head]);
      for (int k = vg.starts[u]; k < vg.starts[u + 1]; ++k) {
        const int w = vg.neighbours[static_cast<std::size_t>(k)];
        if (stamps[static_cast<std::size_t>(w)] != stamp) continue;
        stamps[static_cast<std::size_t>(w)] = visited;
        order.push_back(w);
      }
    }
  };
  visit(start);
  for (int v : nodes) {
    if (stamps[static_cast<std::size_t>(v)] == stamp) visit(v);
  }
  for (int v : nodes) stamps[static_cast<std::size_t>(v)] = stamp;  // restore for the caller
  return order;
}

/// Part of every vertex: recursive bisection of breadth-first orders from a peripheral
/// vertex (the last one reached from an arbitrary start).
std::vector<int> bisect(const VertexGraph& vg, int num_parts) {
  const std::size_t n = vg.vertices.size();
  std::vector<int> part(n, 0), stamps(n, -1);
  struct Task {
    std::vector<int> nodes;
    int parts, first;
  };
  std::vector<Task> tasks;
  tasks.push_back({std::vector<int>(n), num_parts, 0});
  std::iota(tasks.back().nodes.begin(), tasks.back().nodes.end(), 0);
  int stamp = 0;
  while (!tasks.empty()) {
    Task t = std::move(tasks.back());
    tasks.pop_back();
    if (t.parts == 1 || t.nodes.empty()) {
      for (int v : t.nodes) part[static_cast<std::size_t>(v)] = t.first;
      continue;
    }
    stamp += 2;
    for (int v : t.nodes) stamps[static_cast<std::size_t>(v)] = stamp;
    const int far = bfsOrder(vg, t.nodes, t.nodes.front(), stamps, stamp).back();
    std::vector<int> order = bfsOrder(vg, t.nodes, far, stamps, stamp);
    const int left = t.parts / 2;
    const std::size_t cut =
        order.size() * static_cast<std::size_t>(left) / static_cast<std::size_t>(t.parts);
    std::vector<int> second(order.begin() + static_cast<std::ptrdiff_t>(cut), order.end());
    order.resize(cut);
    std::sort(order.begin(), order.end());
    std::sort(second.begin(), second.end());
    tasks.push_back({std::move(second), t.parts - left, t.first + left});
    tasks.push_back({std::move(order), left, t.first});
  }
  return part;
}

/// Adds separator vertices until they cover the edges that join parts. An edge of two
/// vertices in different parts is covered by the one with more such edges (the other
/// part's when equal), unless one of them already is in the separator; an edge of more
/// vertices puts its non-separator vertices outside the lowest part among them into the
/// separator. Afterwards the vertices of an edge outside the separator lie in one part.
/// (Node bisection leaves nothing to cover: this keeps the invariant whatever the split.)
void coverCutEdges(const Graph& graph, const VertexGraph& vg, const std::vector<int>& part,
                   std::vector<char>& is_separator) {
  std::vector<int> cut_degree(vg.vertices.size(), 0), vars;
  auto at = [](const std::vector<int>& v, int k) { return v[static_cast<std::size_t>(k)]; };
  for (const auto& e : graph.edges()) {
    edgeVariables(vg, *e, vars);
    if (vars.size() == 2 && at(part, vars[0]) != at(part, vars[1])) {
      ++cut_degree[static_cast<std::size_t>(vars[0])];
      ++cut_degree[static_cast<std::size_t>(vars[1])];
    } else if (vars.size() > 2) {
      int lowest = INT_MAX;
      for (int v : vars) {
        if (!is_separator[static_cast<std::size_t>(v)]) lowest = std::min(lowest, at(part, v));
      }
      for (int v : vars) {
        if (at(part, v) != lowest) is_separator[static_cast<std::size_t>(v)] = 1;
      }
    }
  }
  for (const auto& e : graph.edges()) {
    edgeVariables(vg, *e, vars);
    if (vars.size() != 2 || at(part, vars[0]) == at(part, vars[1])) continue;
    const int u = vars[0], v = vars[1];
    if (is_separator[static_cast<std::size_t>(u)] || is_separator[static_cast<std::size_t>(v)])
      continue;
    const bool take_u = at(cut_degree, u) != at(cut_degree, v)
                            ? at(cut_degree, u) > at(cut_degree, v)
                            : at(part, u) > at(part, v);
    is_separator[static_cast<std::size_t>(take_u ? u : v)] = 1;
  }
}

/// Checks that every group of interior vertices joined by a submap's edges reaches a
/// separator vertex, a fixed vertex or a unary edge; throws naming the first that does not.
void checkAnchors(const Partition& p, const VertexGraph& vg, const std::vector<int>& sep_index) {
  std::vector<int> parent(vg.vertices.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v) {
      v = parent[static_cast<std::size_t>(v)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    }
    return v;
  };
  std::vector<char> anchored(vg.vertices.size(), 0);
  std::vector<int> interior;
  for (const Submap& s : p.submaps) {
    for (const Edge* e : s.edges) {
      bool anchors = e->numVertices() == 1;
      interior.clear();
      for (std::size_t k = 0; k < e->numVertices(); ++k) {
        const int v = vg.indexOf(e->vertex(k));
        if (v < 0 || sep_index[static_cast<std::size_t>(v)] >= 0) {
          anchors = true;  // a fixed vertex or a separator vertex
        } else {
          interior.push_back(v);
        }
      }
      for (std::size_t k = 1; k < interior.size(); ++k) {
        const int a = find(interior[0]), b = find(interior[k]);
        if (a != b) {
          parent[static_cast<std::size_t>(b)] = a;
          anchored[static_cast<std::size_t>(a)] |= anchored[static_cast<std::size_t>(b)];
        }
      }
      if (anchors && !interior.empty()) anchored[static_cast<std::size_t>(find(interior[0]))] = 1;
    }
  }
  for (std::size_t k = 0; k < p.submaps.size(); ++k) {
    std::vector<VertexId> free_ids;
    int root = -1;
    for (const Vertex* v : p.submaps[k].interior) {
      const int r = find(vg.indexOf(v));
      if (anchored[static_cast<std::size_t>(r)]) continue;
      if (root < 0) root = r;
      if (r == root) free_ids.push_back(v->id());
    }
    if (root < 0) continue;
    throw Error("submap " + std::to_string(k) + " holds vertices that nothing anchors (" +
                formatIdRanges(free_ids, 20) +
                "): no separator vertex, fixed vertex or unary edge among their edges, so "
                "their gauge is free; fix a vertex of that component or let the solver fix "
                "the gauge (SubmapSolver::Options::fix_gauge)");
  }
}

}  // namespace

PartitionOptions::Method PartitionOptions::defaultMethod() {
  return detail::haveNodeBisection() ? Method::node_bisection : Method::breadth_first;
}

std::string Partition::describe() const {
  std::size_t largest = 0;
  int largest_separator = 0;
  for (const Submap& s : submaps) {
    largest = std::max(largest, s.interior.size());
    largest_separator = std::max(largest_separator, s.separator_dimension);
  }
  std::ostringstream out;
  out << submaps.size() << " submaps of " << num_variables << " vertices (largest interior "
      << largest << "), separator " << separators.size() << " vertices (dimension "
      << separator_offsets.back() << ", largest submap's " << largest_separator << ")";
  return out.str();
}

Partition partitionGraph(const Graph& graph, const PartitionOptions& options) {
  if (options.num_submaps < 1) {
    throw Error("submaps: the number of submaps must be at least 1, not " +
                std::to_string(options.num_submaps));
  }
  const bool by_nodes = options.method == PartitionOptions::Method::node_bisection;
  const VertexGraph vg = buildVertexGraph(graph, by_nodes);
  const std::size_t n = vg.vertices.size();
  if (n < static_cast<std::size_t>(options.num_submaps)) {
    throw Error("submaps: " + std::to_string(options.num_submaps) + " submaps for " +
                std::to_string(n) + " optimised vertices: use fewer submaps");
  }
  std::vector<int> part;
  std::vector<char> is_separator;
  if (by_nodes) {
    detail::NodeSplit split = detail::nodeBisection(vg.starts, vg.neighbours, options.num_submaps);
    part = std::move(split.part);
    is_separator = std::move(split.is_separator);
  } else {
    part = bisect(vg, options.num_submaps);
    is_separator.assign(n, 0);
  }
  coverCutEdges(graph, vg, part, is_separator);
  // An edge belongs to the part of its vertices outside the separator (one part: the cover
  // above), or to the lowest part among its vertices when all are separator vertices.
  std::vector<int> edge_part(graph.numEdges(), -1), vars;
  for (std::size_t e = 0; e < graph.numEdges(); ++e) {
    edgeVariables(vg, *graph.edges()[e], vars);
    if (vars.empty()) continue;
    int lowest = options.num_submaps, inner = -1;
    for (int v : vars) {
      lowest = std::min(lowest, part[static_cast<std::size_t>(v)]);
      if (!is_separator[static_cast<std::size_t>(v)]) inner = part[static_cast<std::size_t>(v)];
    }
    edge_part[e] = inner >= 0 ? inner : lowest;
  }
  Partition p;
  p.num_variables = n;
  p.submaps.resize(static_cast<std::size_t>(options.num_submaps));
  std::vector<int> sep_index(n, -1);
  p.separator_offsets.push_back(0);
  for (std::size_t v = 0; v < n; ++v) {
    Vertex* vertex = vg.vertices[v];
    p.dimension += vertex->dimension();
    if (is_separator[v]) {
      sep_index[v] = static_cast<int>(p.separators.size());
      p.separators.push_back(vertex);
      p.separator_offsets.push_back(p.separator_offsets.back() + vertex->dimension());
    } else {
      Submap& s = p.submaps[static_cast<std::size_t>(part[v])];
      s.interior.push_back(vertex);
      s.interior_dimension += vertex->dimension();
    }
  }
  for (std::size_t e = 0; e < graph.numEdges(); ++e) {
    if (edge_part[e] < 0) continue;
    Submap& s = p.submaps[static_cast<std::size_t>(edge_part[e])];
    s.edges.push_back(graph.edges()[e].get());
    edgeVariables(vg, *graph.edges()[e], vars);
    for (int v : vars) {
      if (sep_index[static_cast<std::size_t>(v)] >= 0) {
        s.separators.push_back(sep_index[static_cast<std::size_t>(v)]);
      }
    }
  }
  for (Submap& s : p.submaps) {
    std::sort(s.separators.begin(), s.separators.end());
    s.separators.erase(std::unique(s.separators.begin(), s.separators.end()), s.separators.end());
    for (int k : s.separators)
      s.separator_dimension += p.separators[static_cast<std::size_t>(k)]->dimension();
  }
  const double fraction = n == 0 ? 0.0 : static_cast<double>(p.separators.size()) / n;
  if (fraction > options.max_separator_fraction) {
    std::ostringstream msg;
    msg << "submaps: no good separator: " << p.describe() << "; the separator holds "
        << 100.0 * fraction << " % of the vertices, over the limit of "
        << 100.0 * options.max_separator_fraction << " % (the graph is too densely connected for "
        << options.num_submaps << " submaps): use fewer submaps or the direct path";
    throw Error(msg.str());
  }
  for (std::size_t k = 0; k < p.submaps.size(); ++k) {
    if (p.submaps[k].separator_dimension > options.max_submap_separator_dimension) {
      throw Error(
          "submaps: submap " + std::to_string(k) + " touches separator variables of " +
          std::to_string(p.submaps[k].separator_dimension) + " dimensions, over the limit of " +
          std::to_string(options.max_submap_separator_dimension) +
          " (its dense separator block would not fit): use more submaps or the direct path");
    }
  }
  checkAnchors(p, vg, sep_index);
  return p;
}

}  // namespace graphslam::submap
