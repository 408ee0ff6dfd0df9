// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "graphslam/core/edge.h"
#include "graphslam/core/vertex.h"

namespace graphslam {

/// Owns the vertices and edges of a factor graph. Vertices and edges may be added and
/// removed at any time (online use); removing a vertex removes its edges. Edges refer to
/// vertices by id and are resolved to non-owning pointers on insertion.
class Graph {
 public:
  Graph() = default;
  Graph(Graph&&) noexcept = default;
  Graph& operator=(Graph&&) noexcept = default;
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;
  ~Graph();

  /// Takes ownership. Throws graphslam::Error on a null vertex or a duplicate id.
  Vertex& addVertex(std::unique_ptr<Vertex> vertex);
  /// Takes ownership. Throws graphslam::Error when a vertex id is unset or unknown, a
  /// vertex appears twice, or a vertex has the wrong type for its slot.
  Edge& addEdge(std::unique_ptr<Edge> edge);

  /// Removes the vertex and every edge incident to it. Returns false if the id is unknown.
  bool removeVertex(VertexId id);
  /// Returns false if the edge is not in this graph.
  bool removeEdge(const Edge* edge);
  /// Includes the edge in the optimisation or leaves it out (Edge::active). Throws
  /// graphslam::Error when the edge is not in this graph.
  void setEdgeActive(Edge& edge, bool active);
  /// Removes every edge for which `pred` is true; returns how many.
  std::size_t removeEdges(const std::function<bool(const Edge&)>& pred);
  void clear();

  [[nodiscard]] Vertex* vertex(VertexId id);
  [[nodiscard]] const Vertex* vertex(VertexId id) const;
  [[nodiscard]] bool hasVertex(VertexId id) const { return vertices_.count(id) != 0; }

  /// Vertices by increasing id.
  [[nodiscard]] const std::map<VertexId, std::unique_ptr<Vertex>>& vertices() const {
    return vertices_;
  }
  /// Edges in insertion order.
  [[nodiscard]] const std::vector<std::unique_ptr<Edge>>& edges() const { return edges_; }
  [[nodiscard]] std::size_t numVertices() const { return vertices_.size(); }
  [[nodiscard]] std::size_t numEdges() const { return edges_.size(); }

  /// Changes whenever a vertex or edge is added or removed; an optimizer rebuilds its
  /// sparsity structure when this changes.
  [[nodiscard]] std::uint64_t structureVersion() const { return version_; }

  /// Sum of chi2 over the active edges after recomputing the errors of all edges.
  [[nodiscard]] double chi2();

 private:
  std::map<VertexId, std::unique_ptr<Vertex>> vertices_;
  std::vector<std::unique_ptr<Edge>> edges_;
  std::uint64_t version_ = 0;
};

}  // namespace graphslam
