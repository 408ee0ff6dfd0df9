// SPDX-License-Identifier: MIT
// graphslam info --plot-graph: the factor graph as a Graphviz picture.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>

#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::apps {

struct FactorGraphPlotOptions {
  /// Graphs with more vertices are refused: a picture of thousands of variables shows
  /// nothing, and Graphviz takes minutes to lay it out. 300 holds the first ~250 steps of a
  /// DriveBot run or a small pose graph.
  std::size_t max_vertices = 300;
  std::string title;
};

/// Writes the factor graph in Graphviz's dot language: a circle per vertex (label: id and
/// type; fixed vertices grey and double-circled), a small square per edge (coloured by type)
/// joined to the vertices it constrains, and the edge types' colours under the title.
void writeFactorGraphDot(std::ostream& out, const Graph& graph, const TypeRegistry& types,
                         const std::string& title);

/// Writes `out` (.dot: the dot source; .png, .svg or .pdf: drawn by Graphviz's `dot`, the
/// source beside it as OUT.dot). Throws UsageError for a graph over the size limit or an
/// unknown extension, Error when `dot` is missing (the .dot file is written first and the
/// message says how to draw it).
void plotFactorGraph(const std::string& out, const Graph& graph, const TypeRegistry& types,
                     const FactorGraphPlotOptions& options);

}  // namespace graphslam::apps
