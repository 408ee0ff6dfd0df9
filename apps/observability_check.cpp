// SPDX-License-Identifier: MIT
#include "observability_check.h"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <unordered_set>

#include "graphslam/optimizer/marginals.h"
#include "graphslam/optimizer/optimizer.h"

namespace graphslam::apps {

namespace {

/// Undetermined vertices listed in full; the rest are counted.
constexpr std::size_t kListed = 20;
/// Ids named in the line on the vertices --drop-unobservable removed.
constexpr std::size_t kDroppedIdsShown = 10;
/// Rounds of --drop-unobservable: each removes at least one vertex, and a removal can only
/// leave its neighbours without edges; this bounds a pathological chain.
constexpr int kMaxDropRounds = 100;

ObservabilityReport check(LoadedInput& in, const TypeRegistry& types, int threads) {
  ObservabilityOptions options;
  options.types = &types;
  options.threads = threads;
  return checkObservability(in.graph, options);
}

/// The report's list with each vertex's edge lines.
std::string listWithLines(const ObservabilityReport& r, const LoadedInput& in) {
  return r.describeUndetermined(kListed, [&](const UndeterminedVertex& u) {
    const std::string lines = edgeLines(u.edges, in.edge_lines, in.graph.numEdges());
    if (lines.empty()) return lines;
    return std::string(u.edges.size() == 1 ? " [edge on " : " [edges on ") + lines + "]";
  });
}

/// Removes the undetermined vertices and their edges, keeping in.edge_lines in step;
/// returns the number of edges removed.
std::size_t drop(LoadedInput& in, const std::vector<VertexId>& ids) {
  Graph& graph = in.graph;
  std::unordered_set<const Edge*> gone;
  for (VertexId id : ids) {
    for (const Edge* e : graph.vertex(id)->edges()) gone.insert(e);
  }
  if (in.edge_lines.size() == graph.numEdges()) {
    std::vector<std::size_t> kept;
    kept.reserve(graph.numEdges() - gone.size());
    for (std::size_t k = 0; k < graph.numEdges(); ++k) {
      if (!gone.count(graph.edges()[k].get())) kept.push_back(in.edge_lines[k]);
    }
    in.edge_lines.swap(kept);
  }
  const std::size_t removed = graph.removeEdges([&](const Edge& e) { return gone.count(&e) != 0; });
  for (VertexId id : ids) graph.removeVertex(id);
  return removed;
}

std::string firstIds(const std::vector<VertexId>& ids) {
  std::string out;
  for (std::size_t k = 0; k < ids.size() && k < kDroppedIdsShown; ++k) {
    out += (k == 0 ? "" : ", ") + std::to_string(ids[k]);
  }
  if (ids.size() > kDroppedIdsShown) out += ", ...";
  return out;
}

}  // namespace

std::string edgeLines(const std::vector<std::size_t>& edges,
                      const std::vector<std::size_t>& edge_lines, std::size_t num_edges) {
  constexpr std::size_t kShown = 5;
  if (edges.empty() || edge_lines.size() != num_edges) return {};
  // Edges added after loading (a surrogate objective's) have no line.
  for (std::size_t k : edges) {
    if (k >= edge_lines.size()) return {};
  }
  std::string out = edges.size() == 1 ? "line " : "lines ";
  for (std::size_t k = 0; k < edges.size() && k < kShown; ++k) {
    out += (k == 0 ? "" : ", ") + std::to_string(edge_lines.at(edges[k]));
  }
  if (edges.size() > kShown) out += ", ... (" + std::to_string(edges.size()) + " edges)";
  return out;
}

std::string failedEdgeNote(std::ptrdiff_t failed_edge, const std::vector<std::size_t>& edge_lines,
                           std::size_t num_edges, const std::string& input) {
  if (failed_edge < 0) return {};
  const std::string line =
      edgeLines({static_cast<std::size_t>(failed_edge)}, edge_lines, num_edges);
  return line.empty() ? line : "that edge is on " + line + " of " + input + "\n";
}

bool checkBeforeSolving(LoadedInput& in, const TypeRegistry& types, bool drop_them, int threads,
                        bool quiet) {
  ObservabilityReport r = check(in, types, threads);
  bool dropped = false;
  for (int round = 0; !r.ok() && drop_them && round < kMaxDropRounds; ++round) {
    dropped = true;
    std::cout << listWithLines(r, in) << "\n";
    const std::vector<VertexId> ids = r.undeterminedIds();
    const std::size_t edges = drop(in, ids);
    std::printf("dropped %zu %s (%s) and %zu %s (--drop-unobservable)\n", ids.size(),
                ids.size() == 1 ? "vertex" : "vertices", firstIds(ids).c_str(), edges,
                edges == 1 ? "edge" : "edges");
    std::fflush(stdout);
    r = check(in, types, threads);
  }
  if (!r.ok()) {
    std::cerr << (in.path.empty() ? std::string("graph") : in.path) << ": " << listWithLines(r, in)
              << "\nnot optimising: --drop-unobservable removes these vertices and their edges\n";
    return false;
  }
  if (dropped && in.graph.numEdges() == 0) {
    std::cerr << (in.path.empty() ? std::string("graph") : in.path)
              << ": nothing is left to optimise after --drop-unobservable (no edge "
                 "remains): not writing a result\n";
    return false;
  }
  if (!quiet && !r.unanchored.empty()) std::cout << r.describeUnanchored() << "\n";
  return true;
}

bool checkFiniteTerms(LoadedInput& in, const std::string& output) {
  const NonFiniteEdge bad = findNonFiniteEdge(in.graph);
  if (bad.index < 0) return true;
  std::cerr << "optimisation failed: numerical failure (initial chi2 is not finite: "
            << bad.description << ")\n"
            << failedEdgeNote(bad.index, in.edge_lines, in.graph.numEdges(), in.path);
  if (!output.empty()) std::cerr << "not writing " << output << "\n";
  return false;
}

bool checkUndampedAtResult(LoadedInput& in, const Summary& summary, const SolverRegistry& solvers) {
  if (!summary.succeeded()) return true;
  for (const IterationStats& it : summary.per_iteration) {
    if (it.undamped) return true;  // H factorised undamped: it was positive definite there
  }
  MarginalCovariance::Options options;
  options.solvers = &solvers;
  MarginalCovariance marginals(options);
  const MarginalSummary check = marginals.compute(in.graph, {});
  if (check.ok()) return true;
  std::cerr << (in.path.empty() ? std::string("graph") : in.path) << ": "
            << toString(summary.status) << " by " << toString(summary.algorithm)
            << ", but H is singular at the result (the damping hid it): " << check.message << "\n";
  for (VertexId id : check.bad_vertices) {
    const Vertex* v = in.graph.vertex(id);
    if (v == nullptr) continue;
    std::vector<std::size_t> edges;
    for (std::size_t k = 0; k < in.graph.numEdges(); ++k) {
      const VertexIdView ids = in.graph.edges()[k]->vertexIds();
      if (std::find(ids.begin(), ids.end(), id) != ids.end()) edges.push_back(k);
    }
    const std::string lines = edgeLines(edges, in.edge_lines, in.graph.numEdges());
    if (!lines.empty()) std::cerr << "vertex " << id << ": edges on " << lines << "\n";
  }
  std::cerr << "its estimate is arbitrary along the undetermined directions; not writing "
               "outputs (--drop-unobservable does not find joint degeneracies: remove or "
               "constrain the vertices named)\n";
  return false;
}

void printObservability(LoadedInput& in, const TypeRegistry& types) {
  const ObservabilityReport r = check(in, types, 1);
  if (r.ok()) {
    std::printf("observability: every non-fixed vertex is determined by its edges\n");
  } else {
    std::printf("observability: %s\n", listWithLines(r, in).c_str());
  }
  if (!r.unanchored.empty()) std::printf("%s\n", r.describeUnanchored().c_str());
}

}  // namespace graphslam::apps
