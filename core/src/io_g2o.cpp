// SPDX-License-Identifier: MIT
#include "graphslam/core/io_g2o.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <future>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "graphslam/core/error.h"
#include "graphslam/core/file_util.h"

namespace graphslam::io {

std::string Diagnostic::str() const { return file + ":" + std::to_string(line) + ": " + message; }

namespace {

/// A bad line; caught per line and turned into a Diagnostic.
struct LineError {
  std::string message;
};

/// The C locale's white space (std::isspace without the locale lookup per character).
constexpr bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/// Splits `line` at white space into `tokens` (cleared first; its storage is reused).
void tokenize(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    if (i >= line.size()) break;
    std::size_t j = i;
    while (j < line.size() && !isSpace(line[j])) ++j;
    tokens.push_back(line.substr(i, j - i));
    i = j;
  }
}

std::string quote(std::string_view token) { return "'" + std::string(token) + "'"; }

double parseDouble(std::string_view token, std::size_t index, std::string_view tag) {
  std::string_view t = token;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  double value = 0.0;
  auto res = std::from_chars(t.data(), t.data() + t.size(), value);
  if (res.ec != std::errc() || res.ptr != t.data() + t.size()) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is not a number"};
  }
  if (!std::isfinite(value)) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is not finite"};
  }
  return value;
}

VertexId parseId(std::string_view token, std::size_t index, std::string_view tag) {
  long long value = 0;
  auto res = std::from_chars(token.data(), token.data() + token.size(), value);
  if (res.ec != std::errc() || res.ptr != token.data() + token.size() ||
      value < std::numeric_limits<VertexId>::min() ||
      value > std::numeric_limits<VertexId>::max()) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is not a vertex id (an integer)"};
  }
  return static_cast<VertexId>(value);
}

class Reader {
 public:
  Reader(const std::string& name, const TypeRegistry& types, const LoadOptions& options)
      : name_(name), types_(types), options_(options) {}

  LoadResult run(std::istream& in) {
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
      ++line_no;
      std::string_view view(line);
      if (auto hash = view.find('#'); hash != std::string_view::npos) view = view.substr(0, hash);
      tokenize(view, tokens_);
      if (tokens_.empty()) continue;
      try {
        handleLine(tokens_, line_no);
      } catch (const LineError& err) {
        if (!report(line_no, err.message)) return std::move(result_);
      }
    }
    if (in.bad()) report(line_no, "read error");
    for (const auto& [line_of_fix, id] : fixes_) {
      Vertex* v = result_.graph.vertex(id);
      if (!v) {
        if (!report(line_of_fix,
                    "FIX: vertex " + std::to_string(id) + " is not defined in the file"))
          return std::move(result_);
        continue;
      }
      v->setFixed(true);
    }
    return std::move(result_);
  }

 private:
  /// Returns false when loading must stop.
  bool report(int line_no, std::string message) {
    result_.diagnostics.push_back({name_, line_no, std::move(message)});
    if (options_.strict) {
      result_.failed = true;
      return false;
    }
    ++result_.skipped_lines;
    return true;
  }

  void handleLine(const std::vector<std::string_view>& tokens, int line_no) {
    const std::string tag(tokens[0]);
    if (tag == "FIX") {
      if (tokens.size() < 2) throw LineError{"FIX expects at least one vertex id"};
      for (std::size_t i = 1; i < tokens.size(); ++i) {
        fixes_.emplace_back(line_no, parseId(tokens[i], i, tag));
      }
      return;
    }
    const TypeRegistry::Entry* entry = types_.find(tag);
    if (!entry) {
      throw LineError{"unknown tag " + quote(tag) +
                      " (graphslam list-types shows the known ones; --plugin loads more)"};
    }
    const std::size_t found = tokens.size() - 1;
    if (entry->kind == TypeRegistry::Kind::kVertex) {
      auto v = entry->make_vertex();
      const std::size_t est = static_cast<std::size_t>(v->estimateDataDimension());
      const std::size_t expected = 1 + est + static_cast<std::size_t>(v->parameterDataDimension());
      if (found != expected) throw LineError{countMessage(tag, expected, found)};
      const VertexId id = parseId(tokens[1], 1, tag);
      values_.resize(expected - 1);
      for (std::size_t i = 0; i + 1 < expected; ++i)
        values_[i] = parseDouble(tokens[i + 2], i + 2, tag);
      if (auto it = vertex_lines_.find(id); it != vertex_lines_.end()) {
        throw LineError{tag + ": duplicate vertex id " + std::to_string(id) +
                        " (first defined on line " + std::to_string(it->second) + ")"};
      }
      v->setId(id);
      v->setEstimateData(values_.data());
      setParameters(tag, [&] { v->setParameterData(values_.data() + est); });
      result_.graph.addVertex(std::move(v));
      vertex_lines_.emplace(id, line_no);
      return;
    }
    auto e = entry->make_edge();
    const int d = e->dimension();
    const std::size_t meas = static_cast<std::size_t>(e->measurementDataDimension()) +
                             static_cast<std::size_t>(e->parameterDataDimension());
    const std::size_t info = static_cast<std::size_t>(d * (d + 1) / 2);
    std::size_t num_ids = 0;
    if (e->arity() > 0) {
      num_ids = static_cast<std::size_t>(e->arity());
      if (found != num_ids + meas + info)
        throw LineError{countMessage(tag, num_ids + meas + info, found)};
    } else {
      if (found < 1 + meas + info) {
        throw LineError{tag + " expects at least " + std::to_string(1 + meas + info) +
                        " numbers after the tag (vertex ids, " + std::to_string(meas) +
                        " measurement and parameter values, " + std::to_string(info) +
                        " information values), found " + std::to_string(found)};
      }
      num_ids = found - meas - info;
    }
    std::vector<VertexId> ids(num_ids);  // moved into the edge
    for (std::size_t i = 0; i < num_ids; ++i) ids[i] = parseId(tokens[1 + i], 1 + i, tag);
    values_.resize(meas + info);
    for (std::size_t i = 0; i < meas + info; ++i) {
      values_[i] = parseDouble(tokens[1 + num_ids + i], 1 + num_ids + i, tag);
    }
    for (VertexId id : ids) {
      if (!result_.graph.hasVertex(id)) {
        throw LineError{tag + ": refers to vertex " + std::to_string(id) +
                        ", which is not defined before this line"};
      }
    }
    Eigen::MatrixXd& omega = omega_;  // storage reused from line to line
    omega.resize(d, d);
    std::size_t k = meas;
    for (int r = 0; r < d; ++r) {
      for (int c = r; c < d; ++c) {
        omega(r, c) = values_[k];
        omega(c, r) = values_[k];
        ++k;
      }
    }
    if (llt_.compute(omega).info() != Eigen::Success) {
      throw LineError{tag + ": information matrix is not positive definite"};
    }
    e->setVertexIds(std::move(ids));
    e->setMeasurementData(values_.data());
    setParameters(tag,
                  [&] { e->setParameterData(values_.data() + e->measurementDataDimension()); });
    e->setInformationData(omega.data());
    try {
      result_.graph.addEdge(std::move(e));
    } catch (const Error& err) {
      std::string msg = err.what();
      if (msg.rfind("addEdge: ", 0) == 0) msg = msg.substr(9);
      throw LineError{tag + ": " + msg};
    }
  }

  /// Runs `set` (a setParameterData call), turning a refused value into a line error.
  template <typename F>
  static void setParameters(const std::string& tag, F&& set) {
    try {
      set();
    } catch (const Error& err) {
      throw LineError{tag + ": " + err.what()};
    }
  }

  static std::string countMessage(const std::string& tag, std::size_t expected, std::size_t found) {
    return tag + " expects " + std::to_string(expected) + " numbers after the tag, found " +
           std::to_string(found);
  }

  std::string name_;
  const TypeRegistry& types_;
  LoadOptions options_;
  LoadResult result_;
  std::vector<double> values_;
  std::vector<std::string_view> tokens_;
  Eigen::MatrixXd omega_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  std::unordered_map<VertexId, int> vertex_lines_;
  std::vector<std::pair<int, VertexId>> fixes_;
};

/// Appends ' ' and the id to a line (no temporary string).
void appendId(std::string& line, VertexId id) {
  std::array<char, 24> buf{};
  buf[0] = ' ';
  auto res = std::to_chars(buf.data() + 1, buf.data() + buf.size(), id);
  line.append(buf.data(), res.ptr);
}

/// Appends the parameter values of a vertex or edge to its line.
template <typename T>
void appendParameters(std::string& line, const T& item, std::vector<double>& data) {
  data.resize(static_cast<std::size_t>(item.parameterDataDimension()));
  if (data.empty()) return;
  item.getParameterData(data.data());
  for (double x : data) appendDouble(line, x);
}

}  // namespace

LoadResult readG2o(std::istream& in, const std::string& name, const TypeRegistry& types,
                   const LoadOptions& options) {
  return Reader(name, types, options).run(in);
}

LoadResult loadG2o(const std::string& path, const TypeRegistry& types, const LoadOptions& options) {
  std::ifstream in(path);
  if (!in) {
    LoadResult result;
    result.failed = true;
    result.diagnostics.push_back({path, 0, "cannot open file"});
    return result;
  }
  return readG2o(in, path, types, options);
}

namespace {

/// Writes the lines of items [0, count) in order: batches of items are formatted by two
/// threads (each into its own buffer), then written. Formatting the numbers is most of
/// the work of writing a large graph (about 2 s for 1M poses); memory stays one batch.
/// `format(i, text)` appends item i's lines to text; an exception it throws reaches the
/// caller.
template <typename Format>
void writeLines(std::ostream& out, std::size_t count, const Format& format) {
  constexpr std::size_t kBatch = 1 << 15;  // items per thread and batch
  constexpr std::size_t kParallelFrom = 4096;
  std::string first, second;
  auto formatRange = [&format](std::size_t begin, std::size_t end, std::string& text) {
    text.clear();
    for (std::size_t i = begin; i < end; ++i) format(i, text);
  };
  for (std::size_t begin = 0; begin < count; begin += 2 * kBatch) {
    const std::size_t mid = std::min(count, begin + kBatch);
    const std::size_t end = std::min(count, mid + kBatch);
    if (end - begin < kParallelFrom) {
      formatRange(begin, end, first);
      second.clear();
    } else {
      auto other = std::async(std::launch::async, [&] { formatRange(mid, end, second); });
      formatRange(begin, mid, first);
      other.get();
    }
    out.write(first.data(), static_cast<std::streamsize>(first.size()));
    out.write(second.data(), static_cast<std::streamsize>(second.size()));
  }
}

}  // namespace

void writeG2o(std::ostream& out, const Graph& graph, const TypeRegistry& types) {
  std::vector<const Vertex*> vertices;
  vertices.reserve(graph.numVertices());
  for (const auto& [id, v] : graph.vertices()) vertices.push_back(v.get());
  // Per-thread scratch: the threads of writeLines format disjoint items.
  thread_local std::vector<double> data;
  writeLines(out, vertices.size(), [&](std::size_t i, std::string& line) {
    const Vertex& v = *vertices[i];
    const std::string* tag = types.tagOf(v);
    if (!tag)
      throw Error("cannot write vertex " + std::to_string(v.id()) + ": its type is not registered");
    data.resize(static_cast<std::size_t>(v.estimateDataDimension()));
    v.getEstimateData(data.data());
    line += *tag;
    appendId(line, v.id());
    for (double x : data) appendDouble(line, x);
    appendParameters(line, v, data);
    line += '\n';
  });
  for (const Vertex* v : vertices) {
    if (v->fixed()) out << "FIX " << v->id() << '\n';
  }
  const auto& edges = graph.edges();
  writeLines(out, edges.size(), [&](std::size_t i, std::string& line) {
    const Edge& e = *edges[i];
    const std::string* tag = types.tagOf(e);
    if (!tag)
      throw Error("cannot write an edge on vertex " + std::to_string(e.vertexId(0)) +
                  ": its type is not registered");
    line += *tag;
    for (VertexId id : e.vertexIds()) appendId(line, id);
    data.resize(static_cast<std::size_t>(e.measurementDataDimension()));
    e.getMeasurementData(data.data());
    for (double x : data) appendDouble(line, x);
    appendParameters(line, e, data);
    const int d = e.dimension();
    const double* info = e.informationData();
    for (int r = 0; r < d; ++r) {
      for (int c = r; c < d; ++c) appendDouble(line, info[r + c * d]);
    }
    line += '\n';
  });
}

void saveG2o(const std::string& path, const Graph& graph, const TypeRegistry& types) {
  writeFileAtomically(path, [&](std::ostream& out) { writeG2o(out, graph, types); });
}

}  // namespace graphslam::io
