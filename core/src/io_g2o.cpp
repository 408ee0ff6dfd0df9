// SPDX-License-Identifier: MIT
#include "graphslam/core/io_g2o.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <fstream>
#include <future>
#include <memory>
#include <mutex>
#include <sstream>
#include <string_view>
#include <thread>
#include <unordered_map>

#include "graphslam/core/error.h"
#include "graphslam/core/internal/file_util.h"

namespace graphslam::io {

std::string Diagnostic::str() const {
  return line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message;
}

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

/// `token` in quotes for a message: bytes that would not show (control characters,
/// non-ASCII: binary or UTF-16 input, a byte-order mark) as \xHH, and at most
/// kQuotedBytes of it.
std::string quote(std::string_view token) {
  constexpr std::size_t kQuotedBytes = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kQuotedBytes; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      constexpr char kHex[] = "0123456789ABCDEF";
      out += {'\\', 'x', kHex[c >> 4], kHex[c & 15]};
    }
  }
  out += token.size() > kQuotedBytes ? "'..." : "'";
  if (token.substr(0, 3) == "\xEF\xBB\xBF") {
    out += " (a UTF-8 byte-order mark: save the file without one)";
  }
  return out;
}

double parseDouble(std::string_view token, std::size_t index, std::string_view tag) {
  std::string_view t = token;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  double value = 0.0;
  auto res = std::from_chars(t.data(), t.data() + t.size(), value);
  if (res.ec == std::errc::result_out_of_range && res.ptr == t.data() + t.size()) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is out of the range of a double"};
  }
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

/// An id (`what`: "vertex id" or "parameter id"; both are ints).
VertexId parseId(std::string_view token, std::size_t index, std::string_view tag,
                 const char* what = "vertex id") {
  long long value = 0;
  auto res = std::from_chars(token.data(), token.data() + token.size(), value);
  const bool whole = res.ptr == token.data() + token.size();
  if (whole && (res.ec == std::errc::result_out_of_range ||
                (res.ec == std::errc() && (value < std::numeric_limits<VertexId>::min() ||
                                           value > std::numeric_limits<VertexId>::max())))) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is out of the range of " + what + "s (" +
                    std::to_string(std::numeric_limits<VertexId>::min()) + " to " +
                    std::to_string(std::numeric_limits<VertexId>::max()) + ")"};
  }
  if (res.ec != std::errc() || !whole) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is not a " + what + " (an integer)"};
  }
  return static_cast<VertexId>(value);
}

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
  LineParser(const TypeRegistry& types, const LoadOptions& options)
      : types_(types), options_(options) {}

  void parse(Chunk& chunk) {
    chunk.lines.clear();
    const std::string_view text(chunk.text);
    int line_no = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
      std::size_t end = text.find('\n', pos);
      if (end == std::string_view::npos) end = text.size();
      std::string_view view = text.substr(pos, end - pos);
      pos = end + 1;
      ++line_no;
      if (auto hash = view.find('#'); hash != std::string_view::npos) view = view.substr(0, hash);
      tokenize(view, tokens_);
      if (tokens_.empty()) continue;
      ParsedLine& out = chunk.lines.emplace_back();
      out.line = line_no;
      try {
        parseLine(tokens_, out);
      } catch (const LineError& err) {
        out = ParsedLine{};
        out.line = line_no;
        out.bad = true;
        out.error = err.message;
      }
    }
    chunk.line_count = line_no;
  }

 private:
  void parseLine(const std::vector<std::string_view>& tokens, ParsedLine& out) {
    const std::string tag(tokens[0]);
    if (tag == "FIX") {
      if (tokens.size() < 2) throw LineError{"FIX expects at least one vertex id"};
      for (std::size_t i = 1; i < tokens.size(); ++i) out.fix.push_back(parseId(tokens[i], i, tag));
      return;
    }
    const TypeRegistry::Entry* entry = types_.find(tag);
    if (!entry) {
      throw LineError{"unknown tag " + quote(tag) +
                      " (graphslam list-types shows the known ones; --plugin loads more)"};
    }
    const std::size_t found = tokens.size() - 1;
    if (entry->kind == TypeRegistry::Kind::kParameter) {
      auto p = entry->make_parameter();
      const std::size_t expected = 1 + static_cast<std::size_t>(p->dataDimension());
      if (found != expected) throw LineError{countMessage(tag, expected, found)};
      p->setId(parseId(tokens[1], 1, tag, "parameter id"));
      values_.resize(expected - 1);
      for (std::size_t i = 0; i + 1 < expected; ++i)
        values_[i] = parseDouble(tokens[i + 2], i + 2, tag);
      out.error = refusal(tag, [&] { p->setData(values_.data()); });
      out.parameter = std::move(p);
      out.tag = &entry->tag;
      return;
    }
    if (entry->kind == TypeRegistry::Kind::kVertex) {
      auto v = entry->make_vertex();
      const std::size_t est = static_cast<std::size_t>(v->estimateDataDimension());
      const std::size_t expected = 1 + est + static_cast<std::size_t>(v->parameterDataDimension());
      if (found != expected) throw LineError{countMessage(tag, expected, found)};
      const VertexId id = parseId(tokens[1], 1, tag);
      values_.resize(expected - 1);
      for (std::size_t i = 0; i + 1 < expected; ++i)
        values_[i] = parseDouble(tokens[i + 2], i + 2, tag);
      v->setId(id);
      v->setEstimateData(values_.data());
      // Reported after the duplicate-id check (at commit), as a serial reader would.
      out.error = refusal(tag, [&] { v->setParameterData(values_.data() + est); });
      out.vertex = std::move(v);
      out.tag = &entry->tag;
      return;
    }
    parseEdge(tokens, *entry, out);
  }

  /// An edge line: `TAG id... [|| count] parameter-id... measurement... information...`
  /// (the count only in g2o's separated layout, Edge::separatedCount).
  void parseEdge(const std::vector<std::string_view>& tokens, const TypeRegistry::Entry& entry,
                 ParsedLine& out) {
    const std::string& tag = entry.tag;
    auto e = entry.make_edge();
    const std::size_t found = tokens.size() - 1;
    // In the separated layout the ids come first: they size the edge.
    const bool separated = e->arity() < 0 && e->separatedCount(0) >= 0;
    const std::size_t first = separated ? readSeparatedIds(tokens, tag, *e) : 1;
    const int d = e->dimension();
    const std::size_t meas = static_cast<std::size_t>(e->measurementDataDimension()) +
                             static_cast<std::size_t>(e->parameterDataDimension());
    const std::size_t info = static_cast<std::size_t>(d * (d + 1) / 2);
    // Parameter ids follow the vertex ids (g2o's layout).
    const std::size_t num_params = static_cast<std::size_t>(e->numParameters());
    const std::size_t rest = num_params + meas + info;
    std::size_t num_ids = 0;
    if (separated) {
      if (found != first - 1 + rest) throw LineError{countMessage(tag, first - 1 + rest, found)};
    } else if (e->arity() > 0) {
      num_ids = static_cast<std::size_t>(e->arity());
      if (found != num_ids + rest) throw LineError{countMessage(tag, num_ids + rest, found)};
    } else {
      if (found < 1 + rest) {
        throw LineError{tag + " expects at least " + std::to_string(1 + rest) +
                        " numbers after the tag (vertex ids, " +
                        (num_params ? std::to_string(num_params) + " parameter ids, " : "") +
                        std::to_string(meas) + " measurement and parameter values, " +
                        std::to_string(info) + " information values), found " +
                        std::to_string(found)};
      }
      num_ids = found - rest;
    }
    if (!separated) setVertexIds(*e, tokens, num_ids, tag);
    const std::size_t first_param = separated ? first : 1 + num_ids;
    for (std::size_t i = 0; i < num_params; ++i) {
      const std::size_t at = first_param + i;
      e->setParameterId(i, parseId(tokens[at], at, tag, "parameter id"));
    }
    values_.resize(meas + info);
    const std::size_t first_value = first_param + num_params;
    for (std::size_t i = 0; i < meas + info; ++i) {
      values_[i] = parseDouble(tokens[first_value + i], first_value + i, tag);
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
    // Checked after the edge's vertices are known to be defined (at commit), in this
    // order: the information matrix, then the parameters.
    if (llt_.compute(omega).info() != Eigen::Success) {
      out.repaired = repairInformation(omega, options_.information, options_.nearest_pd_floor) &&
                     llt_.compute(omega).info() == Eigen::Success;
      out.indefinite = !out.repaired;
    }
    if (out.indefinite) {
      out.error = tag + ": information matrix is not positive definite";
    } else {
      e->setMeasurementData(values_.data());
      out.error = refusal(
          tag, [&] { e->setParameterData(values_.data() + e->measurementDataDimension()); });
      e->setInformationData(omega.data());
    }
    out.edge = std::move(e);
    out.tag = &entry.tag;
  }

  /// The vertex ids of a line in g2o's separated layout (Edge::separatedCount): the tokens
  /// before "||", set on `e` (which sizes it), and the count after it, checked. Returns the
  /// index of the token after the count.
  static std::size_t readSeparatedIds(const std::vector<std::string_view>& tokens,
                                      const std::string& tag, Edge& e) {
    std::size_t sep = 1;
    while (sep < tokens.size() && tokens[sep] != "||") ++sep;
    if (sep == 1 || sep + 1 >= tokens.size()) {
      throw LineError{tag + " expects its vertex ids to be followed by '||' and a count"};
    }
    setVertexIds(e, tokens, sep - 1, tag);
    const int expected = e.separatedCount(sep - 1);
    if (parseId(tokens[sep + 1], sep + 1, tag, "count") != expected) {
      throw LineError{tag + ": the count " + quote(tokens[sep + 1]) + " after '||' does not " +
                      "match its " + std::to_string(sep - 1) + " vertex ids (" +
                      std::to_string(expected) + " expected)"};
    }
    return sep + 2;
  }

  /// Sets the `count` ids after the tag on `e`; a count the type refuses is a bad line.
  static void setVertexIds(Edge& e, const std::vector<std::string_view>& tokens, std::size_t count,
                           const std::string& tag) {
    std::vector<VertexId> ids(count);  // moved into the edge
    for (std::size_t i = 0; i < count; ++i) ids[i] = parseId(tokens[1 + i], 1 + i, tag);
    try {
      e.setVertexIds(std::move(ids));
    } catch (const Error& err) {
      throw LineError{tag + ": " + err.what()};
    }
  }

  /// Runs `set` (a setParameterData call); the message when the type refuses the value,
  /// else empty.
  template <typename F>
  static std::string refusal(const std::string& tag, F&& set) {
    try {
      set();
    } catch (const Error& err) {
      return tag + ": " + err.what();
    }
    return {};
  }

  static std::string countMessage(const std::string& tag, std::size_t expected, std::size_t found) {
    return tag + " expects " + std::to_string(expected) + " numbers after the tag, found " +
           std::to_string(found);
  }

  const TypeRegistry& types_;
  const LoadOptions& options_;
  std::vector<double> values_;
  std::vector<std::string_view> tokens_;
  Eigen::MatrixXd omega_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

/// Reads the input in chunks of whole lines. Chunks are parsed on up to `threads` threads
/// (the calling one included) and added to the graph in file order by the calling thread,
/// so the graph and the diagnostics do not depend on the thread count.
class Reader {
 public:
  Reader(const std::string& name, const TypeRegistry& types, const LoadOptions& options)
      : name_(name), types_(types), options_(options) {}

  LoadResult run(std::istream& in) {
    const int threads = std::max(1, options_.threads);
    const std::size_t chunk_bytes = std::max<std::size_t>(1, options_.chunk_bytes);
    LineParser own(types_, options_);
    std::deque<std::unique_ptr<Chunk>> window;  // read, not yet added; in file order
    std::string carry;                          // a line begun in the last chunk read
    bool eof = false;
    Workers workers(types_, options_);
    const std::size_t max_window = 2 * static_cast<std::size_t>(threads);
    int line_base = 0;
    while (true) {
      while (!eof && window.size() < max_window) {
        auto chunk = readChunk(in, chunk_bytes, carry, eof);
        if (!chunk) break;
        if (threads > 1 && (window.size() > 0 || !eof)) workers.start(threads - 1);
        workers.push(*chunk);
        window.push_back(std::move(chunk));
      }
      if (window.empty()) break;
      Chunk& front = *window.front();
      workers.waitFor(front, own);
      if (front.failure) std::rethrow_exception(front.failure);
      for (ParsedLine& p : front.lines) {
        if (!commit(p, line_base + p.line)) {
          result_.lines = static_cast<std::size_t>(line_base + p.line);
          return std::move(result_);
        }
      }
      line_base += front.line_count;
      window.pop_front();
    }
    result_.lines = static_cast<std::size_t>(line_base);
    if (in.bad()) report(line_base, "read error");
    if (!reportIndefinite()) return std::move(result_);
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
  /// The next chunk of whole lines, or null at the end of the input. A chunk is at least
  /// `chunk_bytes` long (but for the last) and extends to the end of its last line; the
  /// part of a line read past it is carried into the next chunk. At the end of the input
  /// the chunk holds everything that is left, a last line without a line end included.
  static std::unique_ptr<Chunk> readChunk(std::istream& in, std::size_t chunk_bytes,
                                          std::string& carry, bool& eof) {
    auto chunk = std::make_unique<Chunk>();
    std::string& text = chunk->text;
    text.swap(carry);
    carry.clear();
    while (!eof) {
      const std::size_t old = text.size();
      text.resize(old + chunk_bytes);
      in.read(text.data() + old, static_cast<std::streamsize>(chunk_bytes));
      text.resize(old + static_cast<std::size_t>(in.gcount()));
      if (!in) {
        eof = true;
        break;
      }
      // Only the part just read can hold a line end (the carry holds none).
      const std::size_t last = std::string_view(text).substr(old).rfind('\n');
      if (last != std::string_view::npos) {
        // Whole lines only: the rest begins the next chunk.
        carry.assign(text, old + last + 1, std::string::npos);
        text.resize(old + last + 1);
        break;
      }
    }
    if (text.empty()) return nullptr;
    return chunk;
  }

  /// Worker threads parsing queued chunks, oldest first; the calling thread parses the
  /// oldest itself when no worker has taken it by the time it is to be added.
  class Workers {
   public:
    Workers(const TypeRegistry& types, const LoadOptions& options)
        : types_(types), options_(options) {}
    Workers(const Workers&) = delete;
    Workers& operator=(const Workers&) = delete;
    ~Workers() {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        done_ = true;
        todo_.clear();
      }
      ready_.notify_all();
      for (auto& t : threads_) t.join();
    }

    void start(int count) {
      while (static_cast<int>(threads_.size()) < count) {
        threads_.emplace_back([this] {
          LineParser parser(types_, options_);
          while (Chunk* c = take()) parseOne(parser, *c);
        });
      }
    }

    void push(Chunk& chunk) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        todo_.push_back(&chunk);
      }
      ready_.notify_one();
    }

    /// Returns when `chunk`, the oldest chunk not yet added, is parsed: parses it when no
    /// worker has taken it, else waits (the chunks after it are the workers').
    void waitFor(Chunk& chunk, LineParser& own) {
      std::unique_lock<std::mutex> lock(mutex_);
      if (!todo_.empty() && todo_.front() == &chunk) {
        todo_.pop_front();
        lock.unlock();
        parseOne(own, chunk);
        return;
      }
      parsed_.wait(lock, [&] { return chunk.parsed; });
    }

   private:
    /// The oldest queued chunk, once there is one; null when the reader is done.
    Chunk* take() {
      std::unique_lock<std::mutex> lock(mutex_);
      ready_.wait(lock, [&] { return done_ || !todo_.empty(); });
      if (todo_.empty()) return nullptr;
      Chunk* c = todo_.front();
      todo_.pop_front();
      return c;
    }

    void parseOne(LineParser& parser, Chunk& chunk) {
      try {
        parser.parse(chunk);
      } catch (...) {
        chunk.failure = std::current_exception();
      }
      {
        std::lock_guard<std::mutex> lock(mutex_);
        chunk.parsed = true;
      }
      parsed_.notify_all();
    }

    const TypeRegistry& types_;
    const LoadOptions& options_;
    std::mutex mutex_;
    std::condition_variable ready_, parsed_;
    std::deque<Chunk*> todo_;
    bool done_ = false;
    std::vector<std::thread> threads_;
  };

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

  /// The edges refused for their information (LoadOptions::information): the first few
  /// lines were listed as they came; a summary follows, and the load fails. Returns false
  /// then.
  bool reportIndefinite() {
    const std::size_t n = result_.refused_information;
    if (n == 0) return true;
    const std::size_t edges = result_.graph.numEdges() + n;
    std::string listed;
    if (n > LoadOptions::kListedLines) {
      listed = " (the first " + std::to_string(LoadOptions::kListedLines) + " are listed above)";
    }
    result_.diagnostics.push_back(
        {name_, 0,
         std::to_string(n) + " of " + std::to_string(edges) +
             " edges have an information matrix that is not positive definite" + listed +
             "; --information nearest-pd or --information isotropic repairs them"});
    result_.failed = true;
    return false;
  }

  /// Adds a parsed line to the graph (the checks that need the lines before it); returns
  /// false when loading must stop.
  bool commit(ParsedLine& p, int line_no) {
    if (p.bad) return report(line_no, std::move(p.error));
    if (p.indefinite && options_.strict && allDefined(*p.edge)) {
      // Counted to the end of the file, so that the message gives the whole extent.
      if (++result_.refused_information <= LoadOptions::kListedLines) {
        result_.diagnostics.push_back({name_, line_no, std::move(p.error)});
      }
      return true;
    }
    if (p.repaired) ++result_.repaired_information;
    if (!p.fix.empty()) {
      for (VertexId id : p.fix) fixes_.emplace_back(line_no, id);
      return true;
    }
    if (p.parameter) {
      const ParameterId id = p.parameter->id();
      if (result_.graph.parameter(id)) {
        return report(line_no, *p.tag + ": duplicate parameter id " + std::to_string(id));
      }
      if (!p.error.empty()) return report(line_no, std::move(p.error));
      result_.graph.addParameter(std::move(p.parameter));
      return true;
    }
    if (p.vertex) {
      const VertexId id = p.vertex->id();
      if (result_.graph.hasVertex(id)) {
        return report(line_no, *p.tag + ": duplicate vertex id " + std::to_string(id) +
                                   " (first defined on line " + std::to_string(vertexLine(id)) +
                                   ")");
      }
      if (!p.error.empty()) return report(line_no, std::move(p.error));
      result_.graph.addVertex(std::move(p.vertex));
      vertex_lines_.emplace_back(id, line_no);
      return true;
    }
    // The ids outlive an edge that addEdge refuses (and destroys); storage reused.
    ids_.assign(p.edge->vertexIds().begin(), p.edge->vertexIds().end());
    param_ids_.resize(static_cast<std::size_t>(p.edge->numParameters()));
    for (std::size_t i = 0; i < param_ids_.size(); ++i) param_ids_[i] = p.edge->parameterId(i);
    if (p.error.empty()) {
      // The usual case: addEdge finds the vertices (no second look-up here).
      try {
        result_.graph.addEdge(std::move(p.edge));
        result_.edge_lines.push_back(static_cast<std::size_t>(line_no));
        return true;
      } catch (const Error& err) {
        return report(line_no, edgeMessage(*p.tag, err.what()));
      }
    }
    return report(line_no, edgeMessage(*p.tag, p.error));
  }

  /// Whether every vertex and parameter the edge refers to is defined.
  bool allDefined(const Edge& e) const {
    for (VertexId id : e.vertexIds()) {
      if (!result_.graph.hasVertex(id)) return false;
    }
    for (int k = 0; k < e.numParameters(); ++k) {
      if (!result_.graph.parameter(e.parameterId(static_cast<std::size_t>(k)))) return false;
    }
    return true;
  }

  /// The message for an edge on the vertices ids_ that was not added: a vertex not defined
  /// before its line first, else `message` (addEdge's without its prefix, or the parser's).
  std::string edgeMessage(const std::string& tag, std::string message) const {
    for (VertexId id : ids_) {
      if (!result_.graph.hasVertex(id)) {
        return tag + ": refers to vertex " + std::to_string(id) +
               ", which is not defined before this line";
      }
    }
    for (ParameterId id : param_ids_) {
      if (!result_.graph.parameter(id)) {
        return tag + ": refers to parameter " + std::to_string(id) +
               ", which is not defined before this line";
      }
    }
    if (const std::string slot = wrongSlotMessage(tag); !slot.empty()) return slot;
    if (const std::string slot = wrongParameterMessage(tag); !slot.empty()) return slot;
    if (message.rfind("addEdge: ", 0) == 0) return tag + ": " + message.substr(9);
    return message;
  }

  /// For an edge refused because a vertex has the wrong type: which vertex, its tag and
  /// the tags the slot takes (from the registry); empty when every slot accepts its vertex.
  std::string wrongSlotMessage(const std::string& tag) const {
    const TypeRegistry::Entry* entry = types_.find(tag);
    if (!entry || entry->kind != TypeRegistry::Kind::kEdge) return {};
    const auto probe = entry->make_edge();
    for (std::size_t slot = 0; slot < ids_.size(); ++slot) {
      const Vertex* v = result_.graph.vertex(ids_[slot]);
      if (!v || probe->acceptsVertex(slot, *v)) continue;
      std::string takes;
      for (const TypeRegistry::Entry* e : types_.entries()) {
        if (e->kind != TypeRegistry::Kind::kVertex) continue;
        if (probe->acceptsVertex(slot, *e->make_vertex()))
          takes += (takes.empty() ? "" : " or ") + e->tag;
      }
      const std::string* is = types_.tagOf(*v);
      return tag + ": vertex " + std::to_string(ids_[slot]) + " has the wrong type for slot " +
             std::to_string(slot) + ": it is a " +
             (is ? *is : std::string("vertex of no registered tag")) + ", the slot takes " +
             (takes.empty() ? std::string("no registered vertex type") : takes);
    }
    return {};
  }

  /// For an edge refused because a parameter has the wrong type: which parameter, its tag
  /// and the tags the slot takes; empty when every slot accepts its parameter.
  std::string wrongParameterMessage(const std::string& tag) const {
    const TypeRegistry::Entry* entry = types_.find(tag);
    if (!entry || entry->kind != TypeRegistry::Kind::kEdge) return {};
    const auto probe = entry->make_edge();
    for (std::size_t slot = 0; slot < param_ids_.size(); ++slot) {
      const Parameter* p = result_.graph.parameter(param_ids_[slot]);
      if (!p || probe->acceptsParameter(slot, *p)) continue;
      std::string takes;
      for (const TypeRegistry::Entry* e : types_.entries()) {
        if (e->kind != TypeRegistry::Kind::kParameter) continue;
        if (probe->acceptsParameter(slot, *e->make_parameter()))
          takes += (takes.empty() ? "" : " or ") + e->tag;
      }
      const std::string* is = types_.tagOf(*p);
      return tag + ": parameter " + std::to_string(param_ids_[slot]) +
             " has the wrong type for parameter slot " + std::to_string(slot) + ": it is a " +
             (is ? *is : std::string("parameter of no registered tag")) + ", the slot takes " +
             (takes.empty() ? std::string("no registered parameter type") : takes);
    }
    return {};
  }

  /// Line of the vertex `id` (read earlier). Only a duplicate's message needs it: the
  /// index is built then, and kept up to date from there on.
  int vertexLine(VertexId id) {
    for (; indexed_ < vertex_lines_.size(); ++indexed_) {
      line_index_.emplace(vertex_lines_[indexed_].first, vertex_lines_[indexed_].second);
    }
    const auto it = line_index_.find(id);
    return it == line_index_.end() ? 0 : it->second;
  }

  std::string name_;
  const TypeRegistry& types_;
  LoadOptions options_;
  LoadResult result_;
  std::vector<std::pair<VertexId, int>> vertex_lines_;  ///< in file order
  std::unordered_map<VertexId, int> line_index_;        ///< vertex_lines_[0, indexed_)
  std::size_t indexed_ = 0;
  std::vector<VertexId> ids_;           ///< the vertices of the edge being added
  std::vector<ParameterId> param_ids_;  ///< its parameters
  std::vector<std::pair<int, VertexId>> fixes_;
};

}  // namespace

LoadResult readG2o(std::istream& in, const std::string& name, const TypeRegistry& types,
                   const LoadOptions& options) {
  return Reader(name, types, options).run(in);
}

LoadResult loadG2o(const std::string& path, const TypeRegistry& types, const LoadOptions& options) {
  errno = 0;
  std::ifstream in(path);
  if (!in) {
    const int reason = errno;
    LoadResult result;
    result.failed = true;
    result.diagnostics.push_back(
        {path, 0,
         std::string("cannot open: ") + (reason ? std::strerror(reason) : "unknown reason")});
    return result;
  }
  return readG2o(in, path, types, options);
}

}  // namespace graphslam::io
