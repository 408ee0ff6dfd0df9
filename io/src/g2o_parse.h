// SPDX-License-Identifier: MIT
// Private to graphslam::core: the .g2o reader's line parser. A line becomes its vertex,
// edge, parameter or FIX ids with every check that needs no graph (tokens, numbers, the
// type's own refusals, the information matrix), so that chunks of lines can be parsed on
// several threads and added to the graph in file order (io_g2o.cpp).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <exception>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "graphslam/core/type_registry.h"
#include "graphslam/io/g2o.h"

namespace graphslam::io::detail {

/// One parsed line: what reading it needs no graph for (tokens, numbers, the new vertex or
/// edge object and its own checks), so that lines can be parsed on several threads.
struct ParsedLine {
  int line = 0;                          ///< 1-based, within its chunk
  std::unique_ptr<Vertex> vertex;        ///< a vertex line
  std::unique_ptr<Edge> edge;            ///< an edge line
  std::unique_ptr<Parameter> parameter;  ///< a parameter line
  std::vector<VertexId> fix;             ///< a FIX line
  const std::string* tag = nullptr;      ///< a vertex or edge line's tag (the registry's string)
  std::string error;                     ///< a bad line: why
  bool bad = false;
  bool fatal = false;       ///< a bad line that ends the reading, lenient or not (too long)
  bool indefinite = false;  ///< an edge whose information is not positive definite (refused)
  bool repaired = false;    ///< ... that was repaired
};

/// A run of whole lines of the input and, once parsed, its lines.
struct Chunk {
  std::string text;
  std::vector<ParsedLine> lines;
  int line_count = 0;
  std::exception_ptr failure;  ///< an exception other than a bad line, rethrown in order
  bool parsed = false;
};

/// Parses chunks; one per thread (its scratch storage is reused from line to line).
class LineParser {
 public:
  LineParser(const TypeRegistry& types, const io::LoadOptions& options)
      : types_(types), options_(options) {}

  /// Fills chunk.lines and chunk.line_count from chunk.text.
  void parse(Chunk& chunk);

 private:
  void parseLine(const std::vector<std::string_view>& tokens, ParsedLine& out);
  /// An edge line: `TAG id... [|| count] parameter-id... measurement... information...`
  /// (the count only in g2o's separated layout, Edge::separatedCount).
  void parseEdge(const std::vector<std::string_view>& tokens, const TypeRegistry::Entry& entry,
                 ParsedLine& out);
  /// The vertex ids of a line in g2o's separated layout: the tokens before "||", set on
  /// `e` (which sizes it), and the count after it, checked. Returns the index of the
  /// token after the count.
  static std::size_t readSeparatedIds(const std::vector<std::string_view>& tokens,
                                      const std::string& tag, Edge& e);
  /// Sets the `count` ids after the tag on `e`; a count the type refuses is a bad line.
  static void setVertexIds(Edge& e, const std::vector<std::string_view>& tokens, std::size_t count,
                           const std::string& tag);

  const TypeRegistry& types_;
  const io::LoadOptions& options_;
  std::vector<double> values_;
  std::vector<std::string_view> tokens_;
  Eigen::MatrixXd omega_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace graphslam::io::detail
