// SPDX-License-Identifier: MIT
// Private to graphslam::core: which registered types fit the slots of an edge type, for the
// loader's messages ("the slot takes VERTEX_SE2") and for the vertices it creates from edges
// (io::LoadOptions::create_missing_vertices).
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/edge.h"
#include "graphslam/core/type_registry.h"

namespace graphslam::io::detail {

/// The registered vertex types that slot `slot` of `probe` accepts (Edge::acceptsVertex on a
/// default-made vertex of each type), in tag order.
[[nodiscard]] std::vector<const TypeRegistry::Entry*> acceptedVertexTypes(const TypeRegistry& types,
                                                                          const Edge& probe,
                                                                          std::size_t slot);

/// The same for parameter slot `slot` (Edge::acceptsParameter).
[[nodiscard]] std::vector<const TypeRegistry::Entry*> acceptedParameterTypes(
    const TypeRegistry& types, const Edge& probe, std::size_t slot);

/// "A or B or C"; `none` for an empty list.
[[nodiscard]] std::string joinTags(const std::vector<const TypeRegistry::Entry*>& entries,
                                   const std::string& none);

/// The vertex type to create for a slot of an edge type, remembered per (edge tag, slot).
/// When the slot accepts several registered vertex types, the first in tag order is taken
/// (a fixed, documented rule: the registry's own order, independent of registration order).
class SlotVertexTypes {
 public:
  explicit SlotVertexTypes(const TypeRegistry& types) : types_(types) {}

  /// Null when no registered vertex type fits (or `edge_tag` is not an edge tag).
  [[nodiscard]] const TypeRegistry::Entry* typeFor(const std::string& edge_tag, std::size_t slot);

 private:
  const TypeRegistry& types_;
  std::map<std::string, std::unique_ptr<Edge>> probes_;
  std::map<std::pair<std::string, std::size_t>, const TypeRegistry::Entry*> chosen_;
};

}  // namespace graphslam::io::detail
