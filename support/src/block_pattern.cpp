// SPDX-License-Identifier: MIT
#include "graphslam/support/block_pattern.h"

#include <algorithm>

namespace graphslam::support {

BlockPattern BlockPattern::fromPairs(int num_blocks,
                                     const std::vector<std::pair<int, int>>& pairs) {
  BlockPattern p;
  const auto n = static_cast<std::size_t>(num_blocks);
  // Count (the diagonal and one entry per pair, in the higher column), then fill.
  p.ptr.assign(n + 1, 0);
  for (const auto& [a, b] : pairs) ++p.ptr[static_cast<std::size_t>(std::max(a, b)) + 1];
  for (std::size_t c = 0; c < n; ++c) p.ptr[c + 1] += p.ptr[c] + 1;
  p.rows.resize(static_cast<std::size_t>(p.ptr[n]));
  std::vector<int> next(p.ptr.begin(), p.ptr.end() - 1);
  for (std::size_t c = 0; c < n; ++c)
    p.rows[static_cast<std::size_t>(next[c]++)] = static_cast<int>(c);
  for (const auto& [a, b] : pairs) {
    p.rows[static_cast<std::size_t>(next[static_cast<std::size_t>(std::max(a, b))]++)] =
        std::min(a, b);
  }
  // Each column sorted (a handful of entries) and compacted without repeats, in place.
  int out = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const auto first = p.rows.begin() + p.ptr[c];
    const auto last = p.rows.begin() + p.ptr[c + 1];
    std::sort(first, last);
    const auto end = std::unique(first, last);
    p.ptr[c] = out;
    for (auto it = first; it != end; ++it) p.rows[static_cast<std::size_t>(out++)] = *it;
  }
  p.ptr[n] = out;
  p.rows.resize(static_cast<std::size_t>(out));
  return p;
}

int BlockPattern::find(int r, int c) const {
  const auto first = rows.begin() + ptr[static_cast<std::size_t>(c)];
  const auto last = rows.begin() + ptr[static_cast<std::size_t>(c) + 1];
  return static_cast<int>(std::lower_bound(first, last, r) - rows.begin());
}

}  // namespace graphslam::support
