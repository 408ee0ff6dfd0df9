// SPDX-License-Identifier: MIT
// The arrays a page holds, built from a graph: private to the view module.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "graphslam/view/scene.h"

namespace graphslam::view {

/// Bits of an edge's flags in the page.
enum EdgeFlag : std::uint8_t {
  kFlagInactive = 1,      ///< left out of the optimisation (Graph::setEdgeActive)
  kFlagDownweighted = 2,  ///< robust weight below Options::downweight_below
  kFlagRobust = 4,        ///< has a robust kernel
  kFlagRemoved = 8,       ///< removed from the graph as an outlier (Scene::addRejectedEdge)
};

struct Scene::Data {
  int dim = 2;
  std::vector<std::string> vertex_tags;  ///< distinct tags, indexed by vtag
  std::vector<VertexKind> tag_kinds;     ///< per vertex tag
  std::vector<std::int32_t> vid;         ///< per vertex, in graph vertex order
  std::vector<std::uint8_t> vtag, vfixed;
  std::vector<std::int32_t> vline;  ///< file line, 0 unknown
  std::vector<std::string> edge_tags;
  std::vector<std::uint32_t> ea, eb;  ///< vertex indices (eb == ea for a unary edge)
  std::vector<std::uint8_t> ekind, etag, eflag;
  std::vector<float> echi2, eweight;
  std::vector<std::int32_t> eline;
  /// Error dimension and error vector (concatenated) of each graph edge at the current
  /// estimate; empty above Options::max_error_edges.
  std::vector<std::uint8_t> edim;
  std::vector<float> eerr;
  /// Further segments of edges on more than two vertices: (edge, vertex index) pairs, drawn
  /// from the edge's first vertex.
  std::vector<std::uint32_t> xedge, xvertex;
  /// Positions (dim per vertex) and per-edge chi2 of each frame; the last is the current.
  std::vector<std::vector<float>> frame_pos, frame_chi2;
  std::vector<std::string> frame_labels;
  std::vector<double> frame_objective;
  bool has_initial = false;
  std::vector<float> truth_pos, ape;  ///< empty without ground truth; NaN where none
  std::vector<std::string> notes;     ///< said in the panel (generic types, ...)
};

/// Index of `tag` in `tags`, added when new (throws Error beyond 255 tags).
[[nodiscard]] std::uint8_t tagIndex(std::vector<std::string>& tags, const std::string& tag);
/// The tag of `v` ("(unregistered)" when the registry does not know its type).
[[nodiscard]] std::string vertexTag(const TypeRegistry& types, const Vertex& v);
/// How a vertex of `tag` is drawn.
[[nodiscard]] VertexKind kindOfTag(const std::string& tag);
/// 3 when a vertex of the graph is a 3D type (VERTEX_SE3:QUAT, VERTEX_TRACKXYZ), else 2.
[[nodiscard]] int graphDimension(const Graph& graph, const TypeRegistry& types);
/// Throws InputError naming (up to 10) vertices whose estimate data is not finite.
void checkFinite(const Graph& graph);
/// Fills the vertex and edge arrays (not the frames) of `d`.
void buildStructure(Graph& graph, const TypeRegistry& types, Scene::Data& d);
/// The positions (first dim values of each vertex's estimate data) of `snapshot`.
[[nodiscard]] std::vector<float> positionsOf(const std::vector<double>& snapshot,
                                             const Graph& graph, int dim);
/// Every edge's chi2 at the graph's current estimate (computes the errors).
[[nodiscard]] std::vector<float> edgeChi2(Graph& graph);
/// The estimates of `snapshot` put into `graph`; throws Error when it does not fit.
void restoreEstimates(Graph& graph, const Snapshot& snapshot);

/// Base64 (RFC 4648, with padding) of `bytes` bytes.
[[nodiscard]] std::string base64(const void* data, std::size_t bytes);
/// `text` as a JSON string literal that is safe inside an HTML <script> element.
[[nodiscard]] std::string jsonString(const std::string& text);
/// The page's JSON data object.
[[nodiscard]] std::string dataJson(const Scene::Data& d, const std::string& title,
                                   const std::string& source, const Options& options,
                                   const std::string& extra);

}  // namespace graphslam::view
