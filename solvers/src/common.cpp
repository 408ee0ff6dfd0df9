// SPDX-License-Identifier: MIT
#include "common.h"

#include <algorithm>
#include <numeric>

#include "ordering.h"

namespace graphslam::solvers::detail {

void PermutedUpper::build(const SparseStructure& s, const std::vector<int>& perm) {
  n = s.n;
  const std::vector<int> pinv = inversePermutation(perm);  // original -> new
  // Count the upper entries of each new column, then fill.
  std::vector<int> count(static_cast<std::size_t>(n), 0);
  for (int c = 0; c < n; ++c) {
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      const int r = s.row_idx[k];
      if (r > c) continue;
      ++count[std::max(pinv[r], pinv[c])];
    }
  }
  col_ptr.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int j = 0; j < n; ++j) col_ptr[j + 1] = col_ptr[j] + count[j];
  row_idx.assign(static_cast<std::size_t>(col_ptr[n]), 0);
  source.assign(row_idx.size(), 0);
  std::vector<int> next(col_ptr.begin(), col_ptr.end() - 1);
  for (int c = 0; c < n; ++c) {
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      const int r = s.row_idx[k];
      if (r > c) continue;
      const int i = std::min(pinv[r], pinv[c]);
      const int j = std::max(pinv[r], pinv[c]);
      row_idx[next[j]] = i;
      source[next[j]++] = k;
    }
  }
  // Sort every column by row.
  std::vector<int> order;
  std::vector<int> rows_tmp, src_tmp;
  for (int j = 0; j < n; ++j) {
    const int b = col_ptr[j], e = col_ptr[j + 1];
    order.resize(static_cast<std::size_t>(e - b));
    std::iota(order.begin(), order.end(), b);
    std::sort(order.begin(), order.end(), [&](int x, int y) { return row_idx[x] < row_idx[y]; });
    rows_tmp.clear();
    src_tmp.clear();
    for (int k : order) {
      rows_tmp.push_back(row_idx[k]);
      src_tmp.push_back(source[k]);
    }
    std::copy(rows_tmp.begin(), rows_tmp.end(), row_idx.begin() + b);
    std::copy(src_tmp.begin(), src_tmp.end(), source.begin() + b);
  }
}

void FullPattern::build(const SparseStructure& s) {
  n = s.n;
  std::vector<std::vector<std::pair<int, int>>> cols(static_cast<std::size_t>(n));
  for (int c = 0; c < n; ++c) {
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      const int r = s.row_idx[k];
      if (r > c) continue;
      cols[c].emplace_back(r, k);
      if (r != c) cols[r].emplace_back(c, k);
    }
  }
  col_ptr.assign(1, 0);
  row_idx.clear();
  source.clear();
  for (auto& col : cols) {
    std::sort(col.begin(), col.end());
    for (const auto& [r, k] : col) {
      row_idx.push_back(r);
      source.push_back(k);
    }
    col_ptr.push_back(static_cast<int>(row_idx.size()));
  }
}

void PermutedColumns::build(const JacobianStructure& s, const std::vector<int>& perm,
                            bool drop_damping, bool sort_rows) {
  rows = drop_damping ? s.damping_row : s.rows;
  cols = s.cols;
  row_order.resize(static_cast<std::size_t>(rows));
  std::iota(row_order.begin(), row_order.end(), 0);
  std::vector<int> new_row(row_order);  // original row -> position
  if (sort_rows) {
    std::vector<int> leftmost(static_cast<std::size_t>(rows), cols);
    for (int k = 0; k < cols; ++k) {
      const int c = perm[k];
      for (int e = s.col_ptr[c]; e < s.col_ptr[c + 1]; ++e) {
        const int r = s.row_idx[e];
        if (r < rows) leftmost[r] = std::min(leftmost[r], k);
      }
    }
    std::stable_sort(row_order.begin(), row_order.end(),
                     [&](int a, int b) { return leftmost[a] < leftmost[b]; });
    for (int k = 0; k < rows; ++k) new_row[row_order[k]] = k;
  }
  col_ptr.assign(1, 0);
  row_idx.clear();
  source.clear();
  std::vector<std::pair<int, int>> entries;
  for (int c : perm) {
    entries.clear();
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      if (s.row_idx[k] >= rows) continue;
      entries.emplace_back(new_row[s.row_idx[k]], k);
    }
    std::sort(entries.begin(), entries.end());
    for (const auto& [r, k] : entries) {
      row_idx.push_back(r);
      source.push_back(k);
    }
    col_ptr.push_back(static_cast<int>(row_idx.size()));
  }
}

}  // namespace graphslam::solvers::detail
