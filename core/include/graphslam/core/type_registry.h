// SPDX-License-Identifier: MIT
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <typeindex>
#include <unordered_map>
#include <vector>

#include "graphslam/core/edge.h"
#include "graphslam/core/parameter.h"
#include "graphslam/core/vertex.h"

namespace graphslam {

/// Maps `.g2o` tags to vertex, edge and parameter factories, and types back to their tags.
/// Filled by explicit registration functions
/// (`types_slam2d::registerTypes(registry)`), never by static initialisers; each program or test
/// owns its registry.
class TypeRegistry {
 public:
  enum class Kind { kVertex, kEdge, kParameter };

  struct Entry {
    std::string tag;
    Kind kind;
    std::string origin;  ///< module or plugin that registered it
    std::function<std::unique_ptr<Vertex>()> make_vertex;
    std::function<std::unique_ptr<Edge>()> make_edge;
    std::function<std::unique_ptr<Parameter>()> make_parameter;
  };

  /// Registers vertex type T under `tag`. Throws RegistryError on a duplicate tag, a tag
  /// that is empty or contains whitespace, or a type already registered under another tag.
  template <typename T>
  void registerVertex(const std::string& tag) {
    Entry entry{tag, Kind::kVertex, origin_, {}, {}, {}};
    entry.make_vertex = [] { return std::unique_ptr<Vertex>(std::make_unique<T>()); };
    addEntry(std::move(entry), std::type_index(typeid(T)));
  }
  /// Registers edge type T under `tag` (same rules as registerVertex).
  template <typename T>
  void registerEdge(const std::string& tag) {
    Entry entry{tag, Kind::kEdge, origin_, {}, {}, {}};
    entry.make_edge = [] { return std::unique_ptr<Edge>(std::make_unique<T>()); };
    addEntry(std::move(entry), std::type_index(typeid(T)));
  }
  /// Registers parameter type T under `tag` (same rules as registerVertex): lines
  /// `TAG id values...` define parameters that edges refer to by id.
  template <typename T>
  void registerParameter(const std::string& tag) {
    Entry entry{tag, Kind::kParameter, origin_, {}, {}, {}};
    entry.make_parameter = [] { return std::unique_ptr<Parameter>(std::make_unique<T>()); };
    addEntry(std::move(entry), std::type_index(typeid(T)));
  }
  /// Registers with explicit factories (for types built at run time).
  void registerVertexFactory(const std::string& tag, std::type_index type,
                             std::function<std::unique_ptr<Vertex>()> factory);
  void registerEdgeFactory(const std::string& tag, std::type_index type,
                           std::function<std::unique_ptr<Edge>()> factory);

  /// Label stored with the next registrations (e.g. "types_slam2d", a plugin's path).
  void setOrigin(std::string origin) { origin_ = std::move(origin); }

  [[nodiscard]] const Entry* find(const std::string& tag) const;
  [[nodiscard]] bool contains(const std::string& tag) const { return find(tag) != nullptr; }
  /// Throws RegistryError for an unknown or non-vertex tag.
  [[nodiscard]] std::unique_ptr<Vertex> createVertex(const std::string& tag) const;
  [[nodiscard]] std::unique_ptr<Edge> createEdge(const std::string& tag) const;
  [[nodiscard]] std::unique_ptr<Parameter> createParameter(const std::string& tag) const;

  /// Tag of the dynamic type of `v` / `e`, or nullptr when the type is not registered.
  [[nodiscard]] const std::string* tagOf(const Vertex& v) const;
  [[nodiscard]] const std::string* tagOf(const Edge& e) const;
  [[nodiscard]] const std::string* tagOf(const Parameter& p) const;

  /// All entries sorted by tag.
  [[nodiscard]] std::vector<const Entry*> entries() const;

 private:
  void addEntry(Entry entry, std::type_index type);

  std::map<std::string, Entry> entries_;
  std::unordered_map<std::type_index, std::string> tags_;
  std::string origin_;
};

}  // namespace graphslam
