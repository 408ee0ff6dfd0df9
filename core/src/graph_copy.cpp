// SPDX-License-Identifier: MIT
#include "graphslam/core/graph_copy.h"

#include <string>
#include <vector>

#include "graphslam/support/error.h"

namespace graphslam::incremental {

namespace {

template <typename Object>
const std::string& tagOrThrow(const Object& object, const TypeRegistry& types,
                              const std::string& what) {
  const std::string* tag = types.tagOf(object);
  if (!tag) {
    throw Error("cannot copy " + what + ": its type (" + typeName(typeid(object)) +
                ") is not registered");
  }
  return *tag;
}

/// The line parameters (Vertex / Edge::getParameterData) of `from` into `to`.
template <typename Object>
void copyParameterData(const Object& from, Object& to) {
  std::vector<double> data(static_cast<std::size_t>(from.parameterDataDimension()));
  if (data.empty()) return;
  from.getParameterData(data.data());
  to.setParameterData(data.data());
}

}  // namespace

std::unique_ptr<Vertex> copyVertex(const Vertex& vertex, const TypeRegistry& types) {
  auto copy =
      types.createVertex(tagOrThrow(vertex, types, "vertex " + std::to_string(vertex.id())));
  copy->setId(vertex.id());
  std::vector<double> data(static_cast<std::size_t>(vertex.estimateDataDimension()));
  vertex.getEstimateData(data.data());
  copy->setEstimateData(data.data());
  copyParameterData(vertex, *copy);
  copy->setFixed(vertex.fixed());
  return copy;
}

std::unique_ptr<Edge> copyEdge(const Edge& edge, const TypeRegistry& types) {
  std::string what = "an edge of vertices";
  for (VertexId id : edge.vertexIds()) what += " " + std::to_string(id);
  auto copy = types.createEdge(tagOrThrow(edge, types, what));
  copy->setVertexIds(edge.vertexIds());  // first: it sizes edges of dynamic arity
  for (int k = 0; k < edge.numParameters(); ++k) {
    copy->setParameterId(static_cast<std::size_t>(k),
                         edge.parameterId(static_cast<std::size_t>(k)));
  }
  std::vector<double> data(static_cast<std::size_t>(edge.measurementDataDimension()));
  edge.getMeasurementData(data.data());
  copy->setMeasurementData(data.data());
  copyParameterData(edge, *copy);
  copy->setInformationData(edge.informationData());
  copy->setRobustKernel(edge.sharedRobustKernel());
  return copy;
}

std::unique_ptr<Parameter> copyParameter(const Parameter& parameter, const TypeRegistry& types) {
  auto copy = types.createParameter(
      tagOrThrow(parameter, types, "parameter " + std::to_string(parameter.id())));
  copy->setId(parameter.id());
  std::vector<double> data(static_cast<std::size_t>(parameter.dataDimension()));
  parameter.getData(data.data());
  copy->setData(data.data());
  return copy;
}

Graph copyGraph(const Graph& graph, const TypeRegistry& types) {
  Graph copy;
  for (const auto& [id, p] : graph.parameters()) copy.addParameter(copyParameter(*p, types));
  for (const auto& [id, v] : graph.vertices()) copy.addVertex(copyVertex(*v, types));
  for (const auto& e : graph.edges()) {
    Edge& added = copy.addEdge(copyEdge(*e, types));
    if (!e->active()) copy.setEdgeActive(added, false);
  }
  return copy;
}

}  // namespace graphslam::incremental
