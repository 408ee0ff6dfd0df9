// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "graphslam/core/edge.h"
#include "graphslam/core/parameter.h"
#include "graphslam/core/vertex.h"

namespace graphslam {

/// Owns the vertices, edges and parameters of a factor graph. Vertices and edges may be added and
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
  /// vertex appears twice, a vertex has the wrong type for its slot, or a parameter the
  /// edge refers to is not in the graph or has the wrong type.
  Edge& addEdge(std::unique_ptr<Edge> edge);

  /// Takes ownership. Throws graphslam::Error on a null parameter or a duplicate id.
  /// Parameters stay until clear(): edges added later refer to them by id (Edge::parameterId),
  /// resolved by addEdge, which throws when one is missing or has the wrong type.
  Parameter& addParameter(std::unique_ptr<Parameter> parameter);
  [[nodiscard]] const Parameter* parameter(ParameterId id) const;
  /// Parameters by increasing id.
  [[nodiscard]] const std::map<ParameterId, std::unique_ptr<Parameter>>& parameters() const {
    return parameters_;
  }

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
  void resolveParameters(Edge& edge) const;

  // Declared first: destroyed after the edges that point to them.
  std::map<ParameterId, std::unique_ptr<Parameter>> parameters_;
  std::map<VertexId, std::unique_ptr<Vertex>> vertices_;
  std::vector<std::unique_ptr<Edge>> edges_;
  std::uint64_t version_ = 0;
};

}  // namespace graphslam
