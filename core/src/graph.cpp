// SPDX-License-Identifier: MIT
#include "graphslam/core/graph.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "graphslam/support/error.h"

namespace graphslam {

void Edge::resizeVertices(std::size_t n) {
  if (num_vertices_ > kInlineVertices) {
    delete[] heap_ids_;
    delete[] heap_vertices_;
  }
  num_vertices_ = 0;
  if (n > kInlineVertices) {
    heap_ids_ = new VertexId[n];
    heap_vertices_ = new Vertex*[n];
  }
  num_vertices_ = static_cast<std::uint32_t>(n);
  std::fill(ids(), ids() + n, -1);
  std::fill(vertices(), vertices() + n, nullptr);
}

void Edge::setVertexIds(std::vector<VertexId> ids) {
  if (arity_ > 0 && static_cast<int>(ids.size()) != arity_) {
    throw Error("edge takes " + std::to_string(arity_) + " vertices, " +
                std::to_string(ids.size()) + " given");
  }
  if (in_graph_) throw Error("vertex ids of an edge cannot change once it is in a graph");
  if (ids.size() != num_vertices_) {
    resizeForVertices(ids.size());
    resizeVertices(ids.size());
  }
  std::copy(ids.begin(), ids.end(), this->ids());
}

void Edge::setDimension(int dimension) {
  if (in_graph_) throw Error("the dimension of an edge cannot change once it is in a graph");
  dimension_ = dimension;
}

void Edge::setVertexId(std::size_t slot, VertexId id) {
  if (slot >= num_vertices_) {
    throw Error("edge slot " + std::to_string(slot) + " out of range (edge has " +
                std::to_string(num_vertices_) + " slots)");
  }
  if (in_graph_) throw Error("vertex ids of an edge cannot change once it is in a graph");
  ids()[slot] = id;
}

VertexId Edge::vertexId(std::size_t slot) const {
  if (slot >= num_vertices_) {
    throw std::out_of_range("edge slot " + std::to_string(slot) + " out of range (edge has " +
                            std::to_string(num_vertices_) + " slots)");
  }
  return ids()[slot];
}

ParameterId Edge::parameterId(std::size_t slot) const {
  if (slot >= static_cast<std::size_t>(numParameters())) {
    throw std::out_of_range("edge parameter slot " + std::to_string(slot) +
                            " out of range (the type has " + std::to_string(numParameters()) + ")");
  }
  return parameterSlots()[slot].id;
}

void Edge::setParameterId(std::size_t slot, ParameterId id) {
  if (slot >= static_cast<std::size_t>(numParameters())) {
    throw Error("edge parameter slot " + std::to_string(slot) + " out of range (the type has " +
                std::to_string(numParameters()) + ")");
  }
  if (in_graph_) throw Error("parameter ids of an edge cannot change once it is in a graph");
  parameterSlots()[slot].id = id;
}

const Parameter* Edge::parameter(std::size_t slot) const {
  if (slot >= static_cast<std::size_t>(numParameters())) return nullptr;
  return parameterSlots()[slot].parameter;
}

bool Edge::allVerticesFixed() const {
  if (!in_graph_) return true;
  return std::all_of(vertices(), vertices() + num_vertices_,
                     [](const Vertex* v) { return v->fixed(); });
}

void Edge::numericJacobianInPlace(std::size_t slot, double* jacobian) {
  if (!in_graph_ || slot >= num_vertices_) {
    throw std::out_of_range("numeric Jacobian: edge slot " + std::to_string(slot) +
                            " has no vertex");
  }
  Vertex* v = vertices()[slot];
  const int d = dimension();
  std::vector<double> delta(static_cast<std::size_t>(v->dimension()), 0.0);
  std::vector<double> plus(static_cast<std::size_t>(d));
  for (int k = 0; k < v->dimension(); ++k) {
    v->push();
    delta[k] = kNumericJacobianStep;
    v->oplus(delta.data());
    computeError();
    std::copy(errorData(), errorData() + d, plus.begin());
    v->pop();
    v->push();
    delta[k] = -kNumericJacobianStep;
    v->oplus(delta.data());
    computeError();
    const double* minus = errorData();
    for (int r = 0; r < d; ++r) {
      jacobian[r + k * d] = (plus[r] - minus[r]) / (2.0 * kNumericJacobianStep);
    }
    v->pop();
    delta[k] = 0.0;
  }
}

Graph::~Graph() = default;

Vertex& Graph::addVertex(std::unique_ptr<Vertex> vertex) {
  if (!vertex) throw Error("addVertex: null vertex");
  const VertexId id = vertex->id();
  auto [it, inserted] = vertices_.emplace(id, std::move(vertex));
  if (!inserted) throw Error("addVertex: duplicate vertex id " + std::to_string(id));
  ++version_;
  return *it->second;
}

Edge& Graph::addEdge(std::unique_ptr<Edge> edge) {
  if (!edge) throw Error("addEdge: null edge");
  const auto& ids = edge->vertexIds();
  if (ids.empty()) throw Error("addEdge: edge has no vertices");
  // Resolved straight into the edge: a refused edge is destroyed with the exception.
  Vertex** resolved = edge->vertices();
  for (std::size_t slot = 0; slot < ids.size(); ++slot) {
    const VertexId id = ids[slot];
    auto it = vertices_.find(id);
    if (it == vertices_.end()) {
      throw Error("addEdge: edge refers to vertex " + std::to_string(id) +
                  ", which is not in the graph");
    }
    if (std::find(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(slot), id) !=
        ids.begin() + static_cast<std::ptrdiff_t>(slot)) {
      throw Error("addEdge: vertex " + std::to_string(id) + " appears twice in one edge");
    }
    if (!edge->acceptsVertex(slot, *it->second)) {
      throw Error("addEdge: vertex " + std::to_string(id) + " has the wrong type for slot " +
                  std::to_string(slot) + " (expected " + edge->expectedVertexType(slot) + ")");
    }
    resolved[slot] = it->second.get();
  }
  resolveParameters(*edge);
  edge->in_graph_ = true;
  Edge* raw = edge.get();
  for (std::size_t slot = 0; slot < ids.size(); ++slot) resolved[slot]->edges_.push_back(raw);
  edges_.push_back(std::move(edge));
  ++version_;
  return *raw;
}

void Graph::resolveParameters(Edge& edge) const {
  const int n = edge.numParameters();
  Edge::ParameterSlot* slots = edge.parameterSlots();
  for (int slot = 0; slot < n; ++slot) {
    const ParameterId id = slots[slot].id;
    auto it = parameters_.find(id);
    if (it == parameters_.end()) {
      throw Error("addEdge: edge refers to parameter " + std::to_string(id) +
                  ", which is not in the graph");
    }
    if (!edge.acceptsParameter(static_cast<std::size_t>(slot), *it->second)) {
      throw Error("addEdge: parameter " + std::to_string(id) +
                  " has the wrong type for parameter slot " + std::to_string(slot));
    }
  }
  for (int slot = 0; slot < n; ++slot) slots[slot].parameter = parameters_.at(slots[slot].id).get();
}

Parameter& Graph::addParameter(std::unique_ptr<Parameter> parameter) {
  if (!parameter) throw Error("addParameter: null parameter");
  const ParameterId id = parameter->id();
  auto [it, inserted] = parameters_.emplace(id, std::move(parameter));
  if (!inserted) throw Error("addParameter: duplicate parameter id " + std::to_string(id));
  return *it->second;
}

const Parameter* Graph::parameter(ParameterId id) const {
  auto it = parameters_.find(id);
  return it == parameters_.end() ? nullptr : it->second.get();
}

bool Graph::removeVertex(VertexId id) {
  auto it = vertices_.find(id);
  if (it == vertices_.end()) return false;
  const std::vector<Edge*> incident = it->second->edges();
  if (!incident.empty()) {
    removeEdges([&incident](const Edge& e) {
      return std::find(incident.begin(), incident.end(), &e) != incident.end();
    });
  }
  vertices_.erase(it);
  ++version_;
  return true;
}

void Graph::setEdgeActive(Edge& edge, bool active) {
  const Vertex* v = edge.in_graph_ && edge.numVertices() > 0 ? edge.vertex(0) : nullptr;
  const bool mine = v && vertex(v->id()) == v &&
                    std::find(v->edges().begin(), v->edges().end(), &edge) != v->edges().end();
  if (!mine) throw Error("setEdgeActive: the edge is not in this graph");
  if (edge.active_ == active) return;
  edge.active_ = active;
  ++version_;
}

bool Graph::removeEdge(const Edge* edge) {
  return removeEdges([edge](const Edge& e) { return &e == edge; }) != 0;
}

std::size_t Graph::removeEdges(const std::function<bool(const Edge&)>& pred) {
  std::size_t removed = 0;
  auto keep_end = std::stable_partition(
      edges_.begin(), edges_.end(), [&pred](const std::unique_ptr<Edge>& e) { return !pred(*e); });
  for (auto it = keep_end; it != edges_.end(); ++it) {
    Edge* e = it->get();
    for (std::size_t slot = 0; slot < e->numVertices(); ++slot) {
      Vertex* v = e->vertices()[slot];
      auto& inc = v->edges_;
      inc.erase(std::remove(inc.begin(), inc.end(), e), inc.end());
    }
    ++removed;
  }
  edges_.erase(keep_end, edges_.end());
  if (removed) ++version_;
  return removed;
}

void Graph::clear() {
  edges_.clear();
  vertices_.clear();
  parameters_.clear();
  ++version_;
}

Vertex* Graph::vertex(VertexId id) {
  auto it = vertices_.find(id);
  return it == vertices_.end() ? nullptr : it->second.get();
}

const Vertex* Graph::vertex(VertexId id) const {
  auto it = vertices_.find(id);
  return it == vertices_.end() ? nullptr : it->second.get();
}

double Graph::chi2() {
  double sum = 0.0;
  for (auto& e : edges_) {
    e->computeError();
    if (e->active()) sum += e->chi2();
  }
  return sum;
}

}  // namespace graphslam
