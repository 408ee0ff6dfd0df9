// SPDX-License-Identifier: MIT
// Private to graphslam::core: a dense index of a graph's vertex ids, for passes that keep
// one entry per vertex (checkConstraints, checkObservability).
#pragma once

#include <cstddef>
#include <unordered_map>
#include <vector>

#include "graphslam/core/graph.h"

namespace graphslam::detail {

/// Index of each added vertex id of a graph: a table over the graph's id range when that is
/// at most kDenseFactor times the number of vertices (the ids of real files are nearly
/// contiguous; a million look-ups in a hash map took about half of checkConstraints' time),
/// else a hash map.
class IdIndex {
 public:
  static constexpr std::size_t kDenseFactor = 4;

  explicit IdIndex(const Graph& graph) {
    if (graph.numVertices() == 0) return;
    first_ = graph.vertices().begin()->first;
    const auto range = static_cast<std::size_t>(
        static_cast<long long>(graph.vertices().rbegin()->first) - first_ + 1);
    if (range <= kDenseFactor * graph.numVertices()) {
      table_.assign(range, -1);
    } else {
      map_.reserve(graph.numVertices());
    }
  }
  void add(VertexId id, int k) {
    if (!table_.empty()) {
      table_[static_cast<std::size_t>(static_cast<long long>(id) - first_)] = k;
    } else {
      map_.emplace(id, k);
    }
  }
  /// The index of a vertex of the graph that was added.
  [[nodiscard]] int at(VertexId id) const {
    return table_.empty() ? map_.at(id)
                          : table_[static_cast<std::size_t>(static_cast<long long>(id) - first_)];
  }
  /// The same, or -1 for a vertex of the graph that was not added.
  [[nodiscard]] int find(VertexId id) const {
    if (!table_.empty()) {
      return table_[static_cast<std::size_t>(static_cast<long long>(id) - first_)];
    }
    const auto it = map_.find(id);
    return it == map_.end() ? -1 : it->second;
  }

 private:
  long long first_ = 0;
  std::vector<int> table_;
  std::unordered_map<VertexId, int> map_;
};

}  // namespace graphslam::detail
