// SPDX-License-Identifier: MIT
#include "slot_types.h"

namespace graphslam::io::detail {

std::vector<const TypeRegistry::Entry*> acceptedVertexTypes(const TypeRegistry& types,
                                                            const Edge& probe, std::size_t slot) {
  std::vector<const TypeRegistry::Entry*> out;
  for (const TypeRegistry::Entry* e : types.entries()) {
    if (e->kind == TypeRegistry::Kind::kVertex && probe.acceptsVertex(slot, *e->make_vertex())) {
      out.push_back(e);
    }
  }
  return out;
}

std::vector<const TypeRegistry::Entry*> acceptedParameterTypes(const TypeRegistry& types,
                                                               const Edge& probe,
                                                               std::size_t slot) {
  std::vector<const TypeRegistry::Entry*> out;
  for (const TypeRegistry::Entry* e : types.entries()) {
    if (e->kind == TypeRegistry::Kind::kParameter &&
        probe.acceptsParameter(slot, *e->make_parameter())) {
      out.push_back(e);
    }
  }
  return out;
}

std::string joinTags(const std::vector<const TypeRegistry::Entry*>& entries,
                     const std::string& none) {
  if (entries.empty()) return none;
  std::string out;
  for (const TypeRegistry::Entry* e : entries) out += (out.empty() ? "" : " or ") + e->tag;
  return out;
}

const TypeRegistry::Entry* SlotVertexTypes::typeFor(const std::string& edge_tag, std::size_t slot) {
  const auto key = std::make_pair(edge_tag, slot);
  if (const auto it = chosen_.find(key); it != chosen_.end()) return it->second;
  const TypeRegistry::Entry* chosen = nullptr;
  const TypeRegistry::Entry* entry = types_.find(edge_tag);
  if (entry && entry->kind == TypeRegistry::Kind::kEdge) {
    auto& probe = probes_[edge_tag];
    if (!probe) probe = entry->make_edge();
    const auto accepted = acceptedVertexTypes(types_, *probe, slot);
    if (!accepted.empty()) chosen = accepted.front();
  }
  chosen_.emplace(key, chosen);
  return chosen;
}

}  // namespace graphslam::io::detail
