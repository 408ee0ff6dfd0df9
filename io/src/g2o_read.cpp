// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <fstream>
#include <memory>
#include <mutex>
#include <string_view>
#include <thread>
#include <unordered_map>

#include "g2o_parse.h"
#include "graphslam/io/g2o.h"
#include "graphslam/support/error.h"
#include "slot_types.h"

namespace graphslam::io {

std::string Diagnostic::str() const {
  return line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message;
}

namespace {

using graphslam::io::detail::Chunk;
using graphslam::io::detail::LineParser;
using graphslam::io::detail::ParsedLine;

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
        auto chunk = readChunk(in, chunk_bytes, options_.max_line_bytes, carry, eof);
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
    result_.vertex_lines.reserve(vertex_lines_.size());
    for (const VertexLine& v : vertex_lines_) {
      if (!v.created_by) result_.vertex_lines.emplace_back(v.id, static_cast<std::size_t>(v.line));
    }
    return std::move(result_);
  }

 private:
  /// The next chunk of whole lines, or null at the end of the input. A chunk is at least
  /// `chunk_bytes` long (but for the last) and extends to the end of its last line; the
  /// part of a line read past it is carried into the next chunk. At the end of the input
  /// the chunk holds everything that is left, a last line without a line end included.
  /// A line that grows past `max_line_bytes` ends the reading there (as if at the end of
  /// the input): the parser reports it, and memory stays bounded by the two sizes.
  static std::unique_ptr<Chunk> readChunk(std::istream& in, std::size_t chunk_bytes,
                                          std::size_t max_line_bytes, std::string& carry,
                                          bool& eof) {
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
      if (text.size() > max_line_bytes) {  // the carry and this read: one line, too long
        eof = true;
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
    if (p.bad && p.fatal) {
      result_.diagnostics.push_back({name_, line_no, std::move(p.error)});
      result_.failed = true;
      return false;
    }
    if (p.bad) return report(line_no, std::move(p.error));
    // With create_missing_vertices every vertex an edge refers to will exist.
    if (p.indefinite && options_.strict &&
        (options_.create_missing_vertices || allDefined(*p.edge))) {
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
        const VertexLine& first = vertexLine(id);
        if (first.created_by) {  // an edge before this line made it: still an error
          return report(first.line, *first.created_by + ": refers to vertex " + std::to_string(id) +
                                        ", which is not defined before this line (" + *p.tag +
                                        " defines it on line " + std::to_string(line_no) + ")");
        }
        return report(line_no, *p.tag + ": duplicate vertex id " + std::to_string(id) +
                                   " (first defined on line " + std::to_string(first.line) + ")");
      }
      if (!p.error.empty()) return report(line_no, std::move(p.error));
      result_.graph.addVertex(std::move(p.vertex));
      vertex_lines_.push_back({id, line_no, nullptr});
      return true;
    }
    // The ids outlive an edge that addEdge refuses (and destroys); storage reused.
    ids_.assign(p.edge->vertexIds().begin(), p.edge->vertexIds().end());
    param_ids_.resize(static_cast<std::size_t>(p.edge->numParameters()));
    for (std::size_t i = 0; i < param_ids_.size(); ++i) param_ids_[i] = p.edge->parameterId(i);
    if (p.error.empty()) {
      std::size_t created = 0;
      if (options_.create_missing_vertices) {
        std::string why;
        created = createMissingVertices(*p.tag, line_no, why);
        if (!why.empty()) return report(line_no, std::move(why));
      }
      // The usual case: addEdge finds the vertices (no second look-up here).
      try {
        result_.graph.addEdge(std::move(p.edge));
        result_.edge_lines.push_back(static_cast<std::size_t>(line_no));
        return true;
      } catch (const Error& err) {
        std::string message = edgeMessage(*p.tag, err.what());
        forgetCreatedVertices(created);
        return report(line_no, std::move(message));
      }
    }
    return report(line_no, edgeMessage(*p.tag, p.error));
  }

  /// Creates the vertices ids_ refers to that the graph does not have yet (the type their
  /// slot takes, default estimate); returns how many. `why` is set when a slot takes no
  /// registered vertex type (nothing is created then).
  std::size_t createMissingVertices(const std::string& tag, int line_no, std::string& why) {
    std::size_t created = 0;
    for (std::size_t slot = 0; slot < ids_.size(); ++slot) {
      const VertexId id = ids_[slot];
      if (result_.graph.hasVertex(id)) continue;
      const TypeRegistry::Entry* type = slot_types_.typeFor(tag, slot);
      if (!type) {
        forgetCreatedVertices(created);
        why = tag + ": refers to vertex " + std::to_string(id) +
              ", which no line defines, and no registered vertex type fits its slot " +
              std::to_string(slot) + " (so it cannot be created)";
        return 0;
      }
      auto v = type->make_vertex();
      v->setId(id);
      result_.graph.addVertex(std::move(v));
      vertex_lines_.push_back({id, line_no, &tag});
      ++created;
      ++result_.created_vertices;
    }
    return created;
  }

  /// Removes the last `count` vertices createMissingVertices made (their edge was refused).
  void forgetCreatedVertices(std::size_t count) {
    for (; count > 0; --count) {
      const VertexId id = vertex_lines_.back().id;
      if (indexed_ == vertex_lines_.size()) {
        line_index_.erase(id);
        --indexed_;
      }
      vertex_lines_.pop_back();
      result_.graph.removeVertex(id);
      --result_.created_vertices;
    }
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
  std::string edgeMessage(const std::string& tag, std::string message) {
    for (VertexId id : ids_) {
      // With create_missing_vertices, an edge with a bad line creates nothing: its own
      // message is the one to give.
      if (!options_.create_missing_vertices && !result_.graph.hasVertex(id)) {
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
  std::string wrongSlotMessage(const std::string& tag) {
    const TypeRegistry::Entry* entry = types_.find(tag);
    if (!entry || entry->kind != TypeRegistry::Kind::kEdge) return {};
    const auto probe = entry->make_edge();
    for (std::size_t slot = 0; slot < ids_.size(); ++slot) {
      const Vertex* v = result_.graph.vertex(ids_[slot]);
      if (!v || probe->acceptsVertex(slot, *v)) continue;
      const std::string* is = types_.tagOf(*v);
      const VertexLine& first = vertexLine(ids_[slot]);
      const std::string created = first.created_by
                                      ? " (created for the " + *first.created_by + " on line " +
                                            std::to_string(first.line) + ")"
                                      : std::string();
      return tag + ": vertex " + std::to_string(ids_[slot]) + " has the wrong type for slot " +
             std::to_string(slot) + ": it is a " +
             (is ? *is : std::string("vertex of no registered tag")) + created +
             ", the slot takes " +
             detail::joinTags(detail::acceptedVertexTypes(types_, *probe, slot),
                              "no registered vertex type");
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
      const std::string* is = types_.tagOf(*p);
      return tag + ": parameter " + std::to_string(param_ids_[slot]) +
             " has the wrong type for parameter slot " + std::to_string(slot) + ": it is a " +
             (is ? *is : std::string("parameter of no registered tag")) + ", the slot takes " +
             detail::joinTags(detail::acceptedParameterTypes(types_, *probe, slot),
                              "no registered parameter type");
    }
    return {};
  }

  /// Where a vertex of the graph came from: its own line, or the edge that created it.
  struct VertexLine {
    VertexId id = 0;
    int line = 0;
    const std::string* created_by = nullptr;  ///< the creating edge's tag; null: a vertex line
  };

  /// Where the vertex `id` (in the graph) came from. Only messages need it: the index is
  /// built at the first, and kept up to date from there on.
  const VertexLine& vertexLine(VertexId id) {
    for (; indexed_ < vertex_lines_.size(); ++indexed_) {
      line_index_.emplace(vertex_lines_[indexed_].id, indexed_);
    }
    static const VertexLine kUnknown;
    const auto it = line_index_.find(id);
    return it == line_index_.end() ? kUnknown : vertex_lines_[it->second];
  }

  std::string name_;
  const TypeRegistry& types_;
  LoadOptions options_;
  LoadResult result_;
  detail::SlotVertexTypes slot_types_{types_};
  std::vector<VertexLine> vertex_lines_;                  ///< in file order
  std::unordered_map<VertexId, std::size_t> line_index_;  ///< vertex_lines_[0, indexed_)
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
