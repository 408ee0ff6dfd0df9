// SPDX-License-Identifier: MIT
// A graph's vertices split into parts by recursive node bisection (METIS's vertex separator,
// reached through CHOLMOD's Partition module).
#pragma once

#include <vector>

namespace graphslam::submap::detail {

/// The part of every vertex, and which vertices the bisection put into separators.
struct NodeSplit {
  std::vector<int> part;
  std::vector<char> is_separator;
};

/// Whether this build can bisect (SuiteSparse's CHOLMOD with its Partition module).
[[nodiscard]] bool haveNodeBisection();

/// Splits the vertices of a symmetric graph (compressed rows: `starts` of n + 1 entries,
/// `neighbours` by increasing index, no self-loops) into `num_parts` parts: a part of p parts
/// is bisected by a vertex separator, its larger side gets ceil(p/2) of the parts, and the
/// separator vertices leave the recursion. Afterwards no edge joins two non-separator
/// vertices of different parts; a separator vertex's part is the lowest among its
/// non-separator neighbours' (the part whose edges it most likely shares). Deterministic.
/// Throws graphslam::Error when METIS fails or the build has no bisection.
[[nodiscard]] NodeSplit nodeBisection(const std::vector<int>& starts,
                                      const std::vector<int>& neighbours, int num_parts);

}  // namespace graphslam::submap::detail
