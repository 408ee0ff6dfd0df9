// SPDX-License-Identifier: MIT
#include "graphslam/robust/apply.h"

#include <cerrno>
#include <cstdlib>
#include <typeinfo>

#include "graphslam/support/error.h"

namespace graphslam::robust {

namespace {

std::string knownKernels(const KernelRegistry& registry) {
  std::string names;
  for (const auto* k : registry.entries()) names += (names.empty() ? "" : ", ") + k->name;
  return names.empty() ? std::string("none is registered") : "known: " + names;
}

[[noreturn]] void badSpec(const std::string& spec, const std::string& why,
                          const KernelRegistry& registry) {
  throw RegistryError("robust kernel '" + spec + "': " + why +
                      " (expected NAME or NAME:WIDTH with a positive WIDTH; " +
                      knownKernels(registry) + ")");
}

}  // namespace

KernelSpec parseKernelSpec(const std::string& spec, const KernelRegistry& registry) {
  const std::size_t colon = spec.find(':');
  KernelSpec out;
  out.name = spec.substr(0, colon);
  if (out.name.empty()) badSpec(spec, "no kernel name", registry);
  if (!registry.find(out.name)) badSpec(spec, "unknown kernel '" + out.name + "'", registry);
  if (colon == std::string::npos) return out;
  const std::string text = spec.substr(colon + 1);
  if (text.empty()) badSpec(spec, "no width after ':'", registry);
  char* end = nullptr;
  errno = 0;
  const double width = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || errno == ERANGE) {
    badSpec(spec, "width '" + text + "' is not a number", registry);
  }
  if (!(width > 0.0) || !std::isfinite(width)) {
    badSpec(spec, "width '" + text + "' is not positive and finite", registry);
  }
  out.width = width;
  return out;
}

std::shared_ptr<RobustKernel> createKernel(const KernelSpec& spec, const KernelRegistry& registry) {
  return registry.create(spec.name, spec.width);
}

EdgeSelector parseEdgeSelection(const std::string& text, const TypeRegistry& registry) {
  if (text == "all") return {EdgeSelection::kAll, {}};
  if (text == "loop-closures") return {EdgeSelection::kLoopClosures, {}};
  const TypeRegistry::Entry* entry = registry.find(text);
  if (entry && entry->kind == TypeRegistry::Kind::kEdge) return {EdgeSelection::kTag, text};
  std::string tags;
  for (const auto* e : registry.entries()) {
    if (e->kind == TypeRegistry::Kind::kEdge) tags += (tags.empty() ? "" : ", ") + e->tag;
  }
  throw RegistryError("edge selection '" + text +
                      "' is neither all, loop-closures nor a known edge tag (edge tags: " +
                      (tags.empty() ? std::string("none is registered") : tags) + ")");
}

bool isLoopClosure(const Edge& edge, const Graph& graph) {
  if (edge.numVertices() != 2) return false;
  const VertexId i = edge.vertexId(0);
  const VertexId j = edge.vertexId(1);
  const long long gap = static_cast<long long>(i) - static_cast<long long>(j);
  if (gap == 1 || gap == -1) return false;
  const Vertex* a = graph.vertex(i);
  const Vertex* b = graph.vertex(j);
  if (!a || !b) return false;
  return typeid(*a) == typeid(*b) && a->dimension() == b->dimension();
}

bool selects(const EdgeSelector& selector, const Edge& edge, const Graph& graph,
             const TypeRegistry& registry) {
  switch (selector.kind) {
    case EdgeSelection::kAll:
      return true;
    case EdgeSelection::kLoopClosures:
      return isLoopClosure(edge, graph);
    case EdgeSelection::kTag: {
      const std::string* tag = registry.tagOf(edge);
      return tag && *tag == selector.tag;
    }
  }
  return false;
}

std::size_t applyRobustKernel(Graph& graph, const std::shared_ptr<const RobustKernel>& kernel,
                              const EdgeSelector& selector, const TypeRegistry& registry) {
  std::size_t count = 0;
  for (const auto& edge : graph.edges()) {
    if (!selects(selector, *edge, graph, registry)) continue;
    edge->setRobustKernel(kernel);
    ++count;
  }
  return count;
}

std::size_t applyRobustKernel(Graph& graph, const TypeRegistry& types,
                              const KernelRegistry& kernels, const std::string& kernel_spec,
                              const std::string& selection) {
  const KernelSpec spec = parseKernelSpec(kernel_spec, kernels);
  const EdgeSelector selector = parseEdgeSelection(selection, types);
  return applyRobustKernel(graph, createKernel(spec, kernels), selector, types);
}

}  // namespace graphslam::robust
