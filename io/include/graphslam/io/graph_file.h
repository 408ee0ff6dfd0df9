// SPDX-License-Identifier: MIT
// Graphs read from and written to files through the format registry: every graph format
// (.g2o, TORO, iSAM, the CMU homework's .npz, the relative-pose matrix) is read and written
// the same way, from a path, standard input ("-"), a pipe or a FIFO (read once).
//
//   io::FormatRegistry formats;  io::registerFormats(formats);
//   io::ReadContext context;  context.types = &types;
//   io::GraphFile in = io::readGraph("intel.g2o", formats, context);  // throws InputError
//   io::writeGraph("out.g2o", in.graph, formats, {&types});
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/io/coursework_npz.h"
#include "graphslam/io/format_registry.h"

namespace graphslam::io {

/// A graph read from a file, with what came with it.
struct GraphFile {
  Graph graph;
  std::string path;                ///< the input's name (a path, or "standard input")
  std::string format;              ///< the registry name of its format ("g2o", "toro", ...)
  std::string description;         ///< one line on what was read (for the user)
  std::vector<std::string> notes;  ///< further lines worth printing (model choice, repairs)
  PointGroundTruth ground_truth;   ///< empty unless the file has one (.npz)
  /// The file line of each edge, in graph edge order (.g2o and formats translated to .g2o
  /// text); empty for other formats.
  std::vector<std::size_t> edge_lines;
  /// The file line of each vertex a line defines (id, line), in file order (.g2o and
  /// formats translated to .g2o text); empty for other formats.
  std::vector<std::pair<VertexId, std::size_t>> vertex_lines;
  /// The file's estimates are a deliberate initial guess that a default initialisation
  /// must keep (.npz: the homework's); false for pose-graph files.
  bool keep_initial_guess = false;
  /// Vertices created from edges (no line of the file defines them; default estimates).
  std::size_t created_vertices = 0;
  /// Information matrices repaired (LoadOptions::information).
  std::size_t repaired_information = 0;
};

/// A graph format reads a GraphFile and writes a Graph.
template <>
struct Written<GraphFile> {
  using type = Graph;
};

/// Reads the graph at `path` ("-": standard input) in `format` ("auto": the registry's
/// detection, by extension and content). Throws graphslam::InputError holding every
/// diagnostic (`FILE:LINE: ...`), and for an empty graph (no vertex and no edge: an empty
/// file, only comments) "FILE: the graph is empty".
[[nodiscard]] GraphFile readGraph(const std::string& path, const FormatRegistry& formats,
                                  const ReadContext& context, const std::string& format = "auto");

/// The same from an opened source (a program that looked at its head, or read it from
/// memory).
[[nodiscard]] GraphFile readGraph(Source& source, const FormatRegistry& formats,
                                  const ReadContext& context, const std::string& format = "auto");

/// Writes `graph` to `path` in `format` ("auto": by the path's extension, .g2o when no format
/// claims it... and refused when a non-graph format claims it, e.g. .tum). Regular files are
/// replaced atomically; character devices, FIFOs and "-" (standard output) are written in
/// place. Throws graphslam::Error naming the path.
void writeGraph(const std::string& path, const Graph& graph, const FormatRegistry& formats,
                const WriteContext& context, const std::string& format = "auto");

/// "created N vertices from edges (...)" for a graph with created vertices, else empty.
[[nodiscard]] std::string createdVerticesNote(const GraphFile& in);

}  // namespace graphslam::io
