// SPDX-License-Identifier: MIT
#include "ordering.h"

#include <algorithm>
#include <numeric>

#include "graphslam/support/error.h"

#ifdef GRAPHSLAM_INCREMENTAL_HAVE_CAMD
#include <camd.h>
#endif

namespace graphslam::incremental {

std::vector<int> constrainedBlockOrdering(const BlockPattern& pattern,
                                          const std::vector<char>& last) {
  const int n = static_cast<int>(pattern.col_ptr.size()) - 1;
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
#ifdef GRAPHSLAM_INCREMENTAL_HAVE_CAMD
  if (n == 0) return order;
  std::vector<int> constraint(n, 0);
  for (int j = 0; j < n; ++j) constraint[j] = last[j] != 0 ? 1 : 0;
  // CAMD needs the constraint sets numbered below n: when every block is to go last there
  // is nothing to constrain (a single block would otherwise be set 1 of 1).
  if (std::find(constraint.begin(), constraint.end(), 0) == constraint.end()) {
    std::fill(constraint.begin(), constraint.end(), 0);
  }
  // Unsorted columns are valid input: CAMD sorts them in one linear pass of its own.
  const int* rows = pattern.rows.empty() ? pattern.col_ptr.data() : pattern.rows.data();
  const int status = camd_order(n, pattern.col_ptr.data(), rows, order.data(), nullptr, nullptr,
                                constraint.data());
  if (status < CAMD_OK)
    throw Error("incremental: CAMD ordering failed (status " + std::to_string(status) + ")");
#else
  (void)last;
#endif
  return order;
}

}  // namespace graphslam::incremental
