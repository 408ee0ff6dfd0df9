// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cctype>

#include "graphslam/core/error.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/core/type_registry.h"

namespace graphslam {

namespace {
void checkName(const std::string& name, const char* what) {
  if (name.empty()) throw RegistryError(std::string("empty ") + what);
  if (std::any_of(name.begin(), name.end(),
                  [](unsigned char c) { return std::isspace(c) || !std::isprint(c); })) {
    throw RegistryError(std::string(what) + " '" + name + "' contains whitespace");
  }
}
}  // namespace

void TypeRegistry::addEntry(const std::string& tag, Kind kind, std::type_index type,
                            std::function<std::unique_ptr<Vertex>()> make_vertex,
                            std::function<std::unique_ptr<Edge>()> make_edge) {
  checkName(tag, "type tag");
  if ((kind == Kind::kVertex && !make_vertex) || (kind == Kind::kEdge && !make_edge)) {
    throw RegistryError("null factory for type tag '" + tag + "'");
  }
  if (entries_.count(tag)) throw RegistryError("type tag '" + tag + "' is already registered");
  auto t = tags_.find(type);
  if (t != tags_.end()) {
    throw RegistryError("type for tag '" + tag + "' is already registered as '" + t->second + "'");
  }
  entries_.emplace(tag, Entry{tag, kind, origin_, std::move(make_vertex), std::move(make_edge)});
  tags_.emplace(type, tag);
}

void TypeRegistry::registerVertexFactory(const std::string& tag, std::type_index type,
                                         std::function<std::unique_ptr<Vertex>()> factory) {
  addEntry(tag, Kind::kVertex, type, std::move(factory), nullptr);
}

void TypeRegistry::registerEdgeFactory(const std::string& tag, std::type_index type,
                                       std::function<std::unique_ptr<Edge>()> factory) {
  addEntry(tag, Kind::kEdge, type, nullptr, std::move(factory));
}

const TypeRegistry::Entry* TypeRegistry::find(const std::string& tag) const {
  auto it = entries_.find(tag);
  return it == entries_.end() ? nullptr : &it->second;
}

std::unique_ptr<Vertex> TypeRegistry::createVertex(const std::string& tag) const {
  const Entry* e = find(tag);
  if (!e || e->kind != Kind::kVertex) throw RegistryError("unknown vertex tag '" + tag + "'");
  return e->make_vertex();
}

std::unique_ptr<Edge> TypeRegistry::createEdge(const std::string& tag) const {
  const Entry* e = find(tag);
  if (!e || e->kind != Kind::kEdge) throw RegistryError("unknown edge tag '" + tag + "'");
  return e->make_edge();
}

const std::string* TypeRegistry::tagOf(const Vertex& v) const {
  auto it = tags_.find(std::type_index(typeid(v)));
  return it == tags_.end() ? nullptr : &it->second;
}

const std::string* TypeRegistry::tagOf(const Edge& e) const {
  auto it = tags_.find(std::type_index(typeid(e)));
  return it == tags_.end() ? nullptr : &it->second;
}

std::vector<const TypeRegistry::Entry*> TypeRegistry::entries() const {
  std::vector<const Entry*> out;
  for (const auto& [tag, entry] : entries_) out.push_back(&entry);
  return out;
}

const char* toString(LinearSolverStatus status) {
  switch (status) {
    case LinearSolverStatus::kSuccess:
      return "success";
    case LinearSolverStatus::kNotPositiveDefinite:
      return "not positive definite";
    case LinearSolverStatus::kSingular:
      return "singular";
    case LinearSolverStatus::kFailure:
      return "failure";
  }
  return "unknown";
}

void SolverRegistry::registerSolver(const std::string& name, const std::string& description,
                                    Factory factory) {
  checkName(name, "solver name");
  if (!factory) throw RegistryError("null factory for solver '" + name + "'");
  if (entries_.count(name)) throw RegistryError("solver '" + name + "' is already registered");
  entries_.emplace(name, Entry{name, description, origin_, std::move(factory)});
}

std::unique_ptr<LinearSolver> SolverRegistry::create(const std::string& name) const {
  auto it = entries_.find(name);
  if (it == entries_.end()) {
    std::string known;
    for (const auto& [n, e] : entries_) known += (known.empty() ? "" : ", ") + n;
    throw RegistryError("unknown linear solver '" + name +
                        "' (known: " + (known.empty() ? "none" : known) + ")");
  }
  return it->second.factory();
}

std::vector<const SolverRegistry::Entry*> SolverRegistry::entries() const {
  std::vector<const Entry*> out;
  for (const auto& [name, entry] : entries_) out.push_back(&entry);
  return out;
}

}  // namespace graphslam
