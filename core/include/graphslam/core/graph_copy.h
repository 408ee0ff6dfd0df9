// SPDX-License-Identifier: MIT
#pragma once

#include <memory>

#include "graphslam/core/edge.h"
#include "graphslam/core/graph.h"
#include "graphslam/core/parameter.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/core/vertex.h"

namespace graphslam::incremental {

/// Copies of graph objects made through the TypeRegistry (createVertex / createEdge /
/// createParameter of the object's tag, tagOf), so any registered type, plugins' included,
/// is copied. Each throws graphslam::Error naming the object when its type is not
/// registered, and passes on the exceptions of the types' set...Data.

/// A new vertex of the same type: id, estimate, parameter data and fixed flag.
[[nodiscard]] std::unique_ptr<Vertex> copyVertex(const Vertex& vertex, const TypeRegistry& types);

/// A new edge of the same type, not in any graph: vertex ids, parameter ids, measurement,
/// parameter data, information and robust kernel (the same kernel object, shared).
[[nodiscard]] std::unique_ptr<Edge> copyEdge(const Edge& edge, const TypeRegistry& types);

/// A new parameter of the same type: id and values.
[[nodiscard]] std::unique_ptr<Parameter> copyParameter(const Parameter& parameter,
                                                       const TypeRegistry& types);

/// A copy of `graph`: its parameters, vertices (estimates as they are now) and edges in the
/// same order, with their active flags.
[[nodiscard]] Graph copyGraph(const Graph& graph, const TypeRegistry& types);

}  // namespace graphslam::incremental
