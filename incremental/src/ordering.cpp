// SPDX-License-Identifier: MIT
#include "ordering.h"

#include <algorithm>
#include <numeric>

#include "graphslam/core/error.h"

#ifdef GRAPHSLAM_INCREMENTAL_HAVE_CAMD
#include <camd.h>
#endif

namespace graphslam::incremental {

std::vector<int> constrainedBlockOrdering(const std::vector<std::vector<int>>& adjacency,
                                          const std::vector<char>& last) {
  const int n = static_cast<int>(adjacency.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
#ifdef GRAPHSLAM_INCREMENTAL_HAVE_CAMD
  if (n == 0) return order;
  std::vector<int> col_ptr(n + 1, 0);
  std::vector<int> rows;
  for (int j = 0; j < n; ++j) {
    std::vector<int> column = adjacency[j];
    std::sort(column.begin(), column.end());
    column.erase(std::unique(column.begin(), column.end()), column.end());
    rows.insert(rows.end(), column.begin(), column.end());
    col_ptr[j + 1] = static_cast<int>(rows.size());
  }
  std::vector<int> constraint(n, 0);
  for (int j = 0; j < n; ++j) constraint[j] = last[j] != 0 ? 1 : 0;
  // CAMD needs the constraint sets numbered below n: when every block is to go last there
  // is nothing to constrain (a single block would otherwise be set 1 of 1).
  if (std::find(constraint.begin(), constraint.end(), 0) == constraint.end()) {
    std::fill(constraint.begin(), constraint.end(), 0);
  }
  const int status = camd_order(n, col_ptr.data(), rows.empty() ? col_ptr.data() : rows.data(),
                                order.data(), nullptr, nullptr, constraint.data());
  if (status < CAMD_OK)
    throw Error("incremental: CAMD ordering failed (status " + std::to_string(status) + ")");
#else
  (void)last;
#endif
  return order;
}

}  // namespace graphslam::incremental
