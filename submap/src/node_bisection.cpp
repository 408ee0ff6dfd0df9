// SPDX-License-Identifier: MIT
#include "node_bisection.h"

#include <algorithm>
#include <climits>
#include <cstddef>
#include <utility>

#include "graphslam/solvers/ordered_factor.h"
#include "graphslam/solvers/register.h"

namespace graphslam::submap::detail {

namespace {

/// The side of each of `nodes` (sorted): 0 or 1, or 2 for METIS's vertex separator of the
/// subgraph they induce. `local` maps every vertex to -1 on entry and on return.
std::vector<int> bisectNodes(const std::vector<int>& starts, const std::vector<int>& neighbours,
                             const std::vector<int>& nodes, std::vector<int>& local) {
  const std::size_t m = nodes.size();
  for (std::size_t k = 0; k < m; ++k)
    local[static_cast<std::size_t>(nodes[k])] = static_cast<int>(k);
  // The subgraph's upper triangle, column by column (rows ascending: `nodes` is sorted).
  std::vector<int> column_starts(m + 1, 0), rows;
  for (std::size_t j = 0; j < m; ++j) {
    const auto v = static_cast<std::size_t>(nodes[j]);
    for (int k = starts[v]; k < starts[v + 1]; ++k) {
      const int i = local[static_cast<std::size_t>(neighbours[static_cast<std::size_t>(k)])];
      if (i >= 0 && static_cast<std::size_t>(i) < j) rows.push_back(i);
    }
    column_starts[j + 1] = static_cast<int>(rows.size());
  }
  for (int v : nodes) local[static_cast<std::size_t>(v)] = -1;
  if (rows.empty()) {  // no edges: any split is a separator-free one
    std::vector<int> side(m, 0);
    std::fill(side.begin() + static_cast<std::ptrdiff_t>(m / 2), side.end(), 1);
    return side;
  }
  return solvers::metisVertexSeparator(column_starts, rows);
}

/// Gives each separator vertex the lowest part among its non-separator neighbours.
void labelSeparators(const std::vector<int>& starts, const std::vector<int>& neighbours,
                     NodeSplit& split) {
  for (std::size_t v = 0; v < split.part.size(); ++v) {
    if (!split.is_separator[v]) continue;
    int lowest = INT_MAX;
    for (int k = starts[v]; k < starts[v + 1]; ++k) {
      const auto w = static_cast<std::size_t>(neighbours[static_cast<std::size_t>(k)]);
      if (!split.is_separator[w]) lowest = std::min(lowest, split.part[w]);
    }
    if (lowest != INT_MAX) split.part[v] = lowest;
  }
}

}  // namespace

bool haveNodeBisection() { return solvers::haveSuiteSparse(); }

NodeSplit nodeBisection(const std::vector<int>& starts, const std::vector<int>& neighbours,
                        int num_parts) {
  const std::size_t n = starts.empty() ? 0 : starts.size() - 1;
  NodeSplit split{std::vector<int>(n, 0), std::vector<char>(n, 0)};
  struct Task {
    std::vector<int> nodes;  // sorted
    int parts, first;
  };
  std::vector<Task> tasks;
  tasks.push_back({std::vector<int>(n), num_parts, 0});
  for (std::size_t v = 0; v < n; ++v) tasks.back().nodes[v] = static_cast<int>(v);
  std::vector<int> local(n, -1);
  while (!tasks.empty()) {
    Task t = std::move(tasks.back());
    tasks.pop_back();
    for (int v : t.nodes) split.part[static_cast<std::size_t>(v)] = t.first;
    if (t.parts == 1 || t.nodes.size() < 2) continue;
    const std::vector<int> side = bisectNodes(starts, neighbours, t.nodes, local);
    const auto ones = static_cast<std::size_t>(std::count(side.begin(), side.end(), 1));
    const auto zeros = static_cast<std::size_t>(std::count(side.begin(), side.end(), 0));
    const int larger = ones > zeros ? 1 : 0;  // goes to the ceil(p/2) parts
    const int left = t.parts / 2;
    Task low{{}, left, t.first}, high{{}, t.parts - left, t.first + left};
    for (std::size_t k = 0; k < t.nodes.size(); ++k) {
      const int v = t.nodes[k];
      if (side[k] == 2) {
        split.is_separator[static_cast<std::size_t>(v)] = 1;
      } else {
        (side[k] == larger ? high : low).nodes.push_back(v);
      }
    }
    tasks.push_back(std::move(high));
    tasks.push_back(std::move(low));
  }
  labelSeparators(starts, neighbours, split);
  return split;
}

}  // namespace graphslam::submap::detail
