// SPDX-License-Identifier: MIT
// Writing .g2o files: the lines of vertices, FIX and edges through the type registry.
#include <algorithm>
#include <array>
#include <charconv>
#include <future>
#include <ostream>
#include <string>
#include <vector>

#include "graphslam/io/g2o.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"

namespace graphslam::io {

namespace {

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
  for (double x : data) support::appendDouble(line, x);
}

/// Writes the lines of items [0, count) in order: batches of items are formatted by two
/// threads (each into its own buffer), then written. Formatting the numbers is most of
/// the work of writing a large graph; memory stays one batch.
/// `format(i, text, scratch)` appends item i's lines to text (`scratch`: a vector of the
/// formatting thread's own, for the item's numbers); an exception it throws reaches the
/// caller.
template <typename Format>
void writeLines(std::ostream& out, std::size_t count, const Format& format) {
  constexpr std::size_t kBatch = 1 << 15;  // items per thread and batch
  constexpr std::size_t kParallelFrom = 4096;
  std::string first, second;
  auto formatRange = [&format](std::size_t begin, std::size_t end, std::string& text) {
    text.clear();
    std::vector<double> scratch;
    for (std::size_t i = begin; i < end; ++i) format(i, text, scratch);
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
  std::vector<double> data;
  for (const auto& [id, p] : graph.parameters()) {
    const std::string* tag = types.tagOf(*p);
    if (!tag)
      throw Error("cannot write parameter " + std::to_string(id) + ": its type is not registered");
    std::string line = *tag;
    appendId(line, id);
    data.resize(static_cast<std::size_t>(p->dataDimension()));
    p->getData(data.data());
    for (double x : data) support::appendDouble(line, x);
    line += '\n';
    out.write(line.data(), static_cast<std::streamsize>(line.size()));
  }
  writeLines(out, vertices.size(),
             [&](std::size_t i, std::string& line, std::vector<double>& data) {
               const Vertex& v = *vertices[i];
               const std::string* tag = types.tagOf(v);
               if (!tag)
                 throw Error("cannot write vertex " + std::to_string(v.id()) +
                             ": its type is not registered");
               data.resize(static_cast<std::size_t>(v.estimateDataDimension()));
               v.getEstimateData(data.data());
               line += *tag;
               appendId(line, v.id());
               for (double x : data) support::appendDouble(line, x);
               appendParameters(line, v, data);
               line += '\n';
             });
  for (const Vertex* v : vertices) {
    if (v->fixed()) out << "FIX " << v->id() << '\n';
  }
  const auto& edges = graph.edges();
  writeLines(out, edges.size(), [&](std::size_t i, std::string& line, std::vector<double>& data) {
    const Edge& e = *edges[i];
    const std::string* tag = types.tagOf(e);
    if (!tag)
      throw Error("cannot write an edge on vertex " + std::to_string(e.vertexId(0)) +
                  ": its type is not registered");
    line += *tag;
    for (VertexId id : e.vertexIds()) appendId(line, id);
    if (const int count = e.separatedCount(e.numVertices()); count >= 0) {
      line += " ||";
      appendId(line, count);
    }
    for (int k = 0; k < e.numParameters(); ++k)
      appendId(line, e.parameterId(static_cast<std::size_t>(k)));
    data.resize(static_cast<std::size_t>(e.measurementDataDimension()));
    e.getMeasurementData(data.data());
    for (double x : data) support::appendDouble(line, x);
    appendParameters(line, e, data);
    const int d = e.dimension();
    const double* info = e.informationData();
    for (int r = 0; r < d; ++r) {
      for (int c = r; c < d; ++c) support::appendDouble(line, info[r + c * d]);
    }
    line += '\n';
  });
}

void saveG2o(const std::string& path, const Graph& graph, const TypeRegistry& types) {
  support::writeFileAtomically(path, [&](std::ostream& out) { writeG2o(out, graph, types); });
}

}  // namespace graphslam::io
