// SPDX-License-Identifier: MIT
// Type look-ups by tag for the graph bindings: the C++ type behind a registered tag (so a
// bulk read compares types, not tags, per vertex) and the tag of an object.
#pragma once

#include <memory>
#include <string>
#include <vector>
#include <typeindex>

#include "common.h"

namespace graphslam::python {

/// What a registered vertex or edge tag makes.
struct TagType {
  std::type_index type = std::type_index(typeid(void));
  int data_dimension = 0;       ///< estimate (vertex) or measurement (edge) numbers
  int parameter_dimension = 0;  ///< line parameters (timestamp, time step)
  int arity = 0;                ///< edges: vertices (-1: per instance)
  int dimension = 0;            ///< edges: error dimension; vertices: tangent dimension
};

/// The vertex type of `tag`; throws graphslam::RegistryError for a tag that is not a
/// registered vertex tag.
const TagType& vertexTagType(const std::string& tag);
/// The same for edge tags.
const TagType& edgeTagType(const std::string& tag);
/// The tag of a vertex / edge, "?" when its type is not registered.
std::string tagOf(const Vertex& v);
std::string tagOf(const Edge& e);

/// The registered vertex tags that slot `slot` of `edge` accepts ("VERTEX_XY"), for messages.
std::string expectedTag(const Edge& edge, std::size_t slot);
/// A new vertex of `tag` (estimate and parameters checked; None: the type's default).
std::unique_ptr<Vertex> makeVertex(const std::string& tag, std::int64_t id, const py::handle& estimate,
                                   bool fixed, const py::handle& parameters);
/// A new edge of `tag` with its ids, measurement, information (None: identity) and
/// parameters set, every value checked (ValueError); not yet in a graph.
std::unique_ptr<Edge> makeEdge(const std::string& tag, const std::vector<VertexId>& ids,
                               const py::handle& measurement, const py::handle& information,
                               const std::vector<int>& parameter_ids, const py::handle& parameters);
/// Vertex ids from a 1-D array or list.
std::vector<VertexId> vertexIdList(const py::handle& obj, const std::string& what);

}  // namespace graphslam::python
