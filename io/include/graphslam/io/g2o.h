// SPDX-License-Identifier: MIT
#pragma once

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/diagnostics/information.h"

namespace graphslam::io {

/// One problem found in an input file.
struct Diagnostic {
  std::string file;
  int line = 0;
  std::string message;
  /// `FILE:LINE: message`, or `FILE: message` for the file as a whole (line 0).
  [[nodiscard]] std::string str() const;
};

struct LoadOptions {
  /// Strict (default): the first bad line makes the load fail. Lenient: bad lines are
  /// reported, skipped and counted.
  bool strict = true;
  /// Threads parsing the text (the calling one included). Lines are added to the graph in
  /// file order whatever the count, so the result is the same; with more than one, the
  /// registered types' factories and set...Data functions run on several threads at once
  /// (on different objects).
  int threads = 1;
  /// Bytes read at a time; a chunk of whole lines is parsed by one thread. The default
  /// (4 MiB) keeps two threads busy on the benchmark files with a small read-ahead window
  /// (2 chunks per thread); tests set it small to put line ends on chunk boundaries.
  std::size_t chunk_bytes = std::size_t{1} << 22;
  /// Longest line accepted, in bytes (without its line end). A longer line ends the load
  /// with an error naming it, in lenient mode too, after at most this plus chunk_bytes of
  /// it were read (a multi-gigabyte line is never held whole). The default (1 MiB) is
  /// thousands of times the longest line of the shared datasets (313 bytes, a 3D edge).
  std::size_t max_line_bytes = std::size_t{1} << 20;
  /// Edges whose information matrix is not positive definite: refused (default; strict
  /// mode counts every such line to the end of the file, lists the first kListedLines and
  /// a summary, and fails; lenient mode skips each like any bad line) or repaired
  /// (repairInformation) and counted in LoadResult::repaired_information.
  InformationRepair information = InformationRepair::kRefuse;
  /// kNearestPd's eigenvalue floor, relative to the largest eigenvalue magnitude.
  double nearest_pd_floor = 1e-6;
  /// Refused information matrices listed line by line before the summary.
  static constexpr std::size_t kListedLines = 5;
  /// Off (default): an edge that refers to a vertex no line has defined before it is an
  /// error. On: such a vertex is created from the edge, of the registered vertex type its
  /// slot accepts (Edge::acceptsVertex; when several do, the first in tag order), with the
  /// type's default estimate (identity pose, zero point), and counted in
  /// LoadResult::created_vertices. This reads files that hold only edges (SE-Sync's, the
  /// KITTI pose graphs); their estimates are then the caller's business (a global
  /// initialisation; dead reckoning from the default estimate). A vertex that an edge refers
  /// to before its own line defines it stays an error (as g2o, which drops such edges with
  /// "Unable to find vertices for edge"), reported at the edge's line when the vertex line
  /// comes; in lenient mode that vertex line is skipped and the created vertex stays.
  bool create_missing_vertices = false;
};

struct LoadResult {
  Graph graph;
  std::vector<Diagnostic> diagnostics;
  std::size_t skipped_lines = 0;
  /// Lines read (a last line without a line end counts): every line up to the end of the
  /// input, or up to the line that stopped a strict load.
  std::size_t lines = 0;
  /// The 1-based file line of each edge of `graph`, in graph edge order (edges are added
  /// in file order for every thread count), so `edge_lines[k]` is the line of
  /// `graph.edges()[k]` as loaded.
  std::vector<std::size_t> edge_lines;
  /// The 1-based file line of each vertex a line defines (id, line), in file order; filled
  /// when the load finishes (vertices created from edges have none).
  std::vector<std::pair<VertexId, std::size_t>> vertex_lines;
  /// Edges whose information matrix was not positive definite and was repaired
  /// (LoadOptions::information), or refused.
  std::size_t repaired_information = 0;
  std::size_t refused_information = 0;
  /// Vertices created from edges (LoadOptions::create_missing_vertices).
  std::size_t created_vertices = 0;
  bool failed = false;  ///< strict mode met an error; `graph` holds what was read before it
  [[nodiscard]] bool ok() const { return !failed; }
};

/// Reads a `.g2o` file through `types`: one element per line, `TAG values...`, `FIX id...`,
/// `#` comments. A vertex line is `TAG id estimate... parameters...`, an edge line
/// `TAG ids... parameter-ids... measurement... parameters... information-upper-triangle...`
/// (parameters: see Vertex::parameterDataDimension and Edge::parameterDataDimension;
/// parameter ids: Edge::numParameters; most types have neither; a type sized by its vertex
/// count ends its ids with `|| count`, Edge::separatedCount), a parameter line
/// `TAG id values...` (Parameter). Checks: unknown tag, wrong number of tokens, non-numbers,
/// NaN/Inf, duplicate vertex id, edge to an undefined vertex (unless
/// LoadOptions::create_missing_vertices), vertex of the wrong type, information matrix not
/// positive definite, a parameter the type refuses. Never throws for bad data; a file that cannot
/// be opened is reported as a diagnostic with line 0 and the system's reason.
[[nodiscard]] LoadResult loadG2o(const std::string& path, const TypeRegistry& types,
                                 const LoadOptions& options = {});
/// Same, from a stream; `name` is used in diagnostics.
[[nodiscard]] LoadResult readG2o(std::istream& in, const std::string& name,
                                 const TypeRegistry& types, const LoadOptions& options = {});

/// Writes parameters and vertices (by id), `FIX` lines, then edges (in graph order). Numbers are
/// written with the shortest representation that reads back exactly. Throws graphslam::Error when
/// a vertex or edge type is not registered.
void writeG2o(std::ostream& out, const Graph& graph, const TypeRegistry& types);
/// writeG2o to `path`, atomically (temporary file + rename).
void saveG2o(const std::string& path, const Graph& graph, const TypeRegistry& types);

}  // namespace graphslam::io
