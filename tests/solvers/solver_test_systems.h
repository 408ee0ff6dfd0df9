// SPDX-License-Identifier: MIT
// Block-sparse test systems shared by the solver tests: random SPD patterns and grids.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "graphslam/core/linear_solver.h"

namespace graphslam::test {

/// A random symmetric block-sparse matrix stored as the optimizer stores H: upper
/// triangle, diagonal blocks full.
struct BlockSystem {
  int nb = 0;
  int bs = 3;
  std::vector<int> block_starts, col_ptr, row_idx;
  std::set<std::pair<int, int>> blocks;  // (row block <= col block)

  BlockSystem(int num_blocks, int block_size, std::mt19937& rng) : nb(num_blocks), bs(block_size) {
    std::uniform_int_distribution<int> pick(0, nb - 1);
    for (int b = 0; b < nb; ++b) blocks.insert({b, b});
    for (int b = 0; b + 1 < nb; ++b) blocks.insert({b, b + 1});
    for (int k = 0; k < nb; ++k) {
      int a = pick(rng), c = pick(rng);
      if (a != c) blocks.insert({std::min(a, c), std::max(a, c)});
    }
    layOut();
  }
  /// The pattern of `upper_blocks` (row block <= column block; the diagonal is added).
  BlockSystem(int num_blocks, int block_size, std::set<std::pair<int, int>> upper_blocks)
      : nb(num_blocks), bs(block_size), blocks(std::move(upper_blocks)) {
    for (int b = 0; b < nb; ++b) blocks.insert({b, b});
    layOut();
  }

  void layOut() {
    for (int b = 0; b <= nb; ++b) block_starts.push_back(b * bs);
    col_ptr.push_back(0);
    for (int cb = 0; cb < nb; ++cb) {
      for (int k = 0; k < bs; ++k) {
        for (const auto& [rb, c] : blocks) {
          if (c != cb) continue;
          for (int r = 0; r < bs; ++r) row_idx.push_back(rb * bs + r);
        }
        col_ptr.push_back(static_cast<int>(row_idx.size()));
      }
    }
  }
  int n() const { return nb * bs; }
  SparseStructure structure() const {
    SparseStructure s;
    s.n = n();
    s.col_ptr = col_ptr.data();
    s.row_idx = row_idx.data();
    s.block_starts = block_starts.data();
    s.num_blocks = nb;
    return s;
  }
  /// Values of the dense symmetric matrix M in this pattern.
  std::vector<double> values(const Eigen::MatrixXd& m) const {
    std::vector<double> v;
    for (int c = 0; c < n(); ++c) {
      for (int k = col_ptr[c]; k < col_ptr[c + 1]; ++k) v.push_back(m(row_idx[k], c));
    }
    return v;
  }
  /// H_s (x) I from the (0, 0) entries of m's blocks (positive definite when m is
  /// diagonally dominant, as randomSpd makes it).
  Eigen::MatrixXd isotropic(const Eigen::MatrixXd& m) const {
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n(), n());
    for (int r = 0; r < nb; ++r) {
      for (int c = 0; c < nb; ++c) {
        for (int i = 0; i < bs; ++i) k(r * bs + i, c * bs + i) = m(r * bs, c * bs);
      }
    }
    return k;
  }
  /// The real form of a Hermitian complex matrix (2x2 blocks [a -b; b a], a from m's
  /// block (0, 0), b from its (1, 0); diagonal blocks a I), made diagonally dominant.
  Eigen::MatrixXd conformal(const Eigen::MatrixXd& m) const {
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n(), n());
    Eigen::VectorXd row_sum = Eigen::VectorXd::Zero(nb);
    for (const auto& [rb, cb] : blocks) {
      if (rb == cb) continue;
      const double a = m(rb * 2, cb * 2), b = m(rb * 2 + 1, cb * 2);
      k.block<2, 2>(rb * 2, cb * 2) << a, -b, b, a;
      k.block<2, 2>(cb * 2, rb * 2) = k.block<2, 2>(rb * 2, cb * 2).transpose();
      row_sum[rb] += std::abs(a) + std::abs(b);
      row_sum[cb] += std::abs(a) + std::abs(b);
    }
    for (int b = 0; b < nb; ++b)
      k.block<2, 2>(b * 2, b * 2) = (row_sum[b] + 1.0) * Eigen::Matrix2d::Identity();
    return k;
  }
  /// A random SPD matrix with this block pattern.
  Eigen::MatrixXd randomSpd(std::mt19937& rng) const {
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n(), n());
    for (const auto& [rb, cb] : blocks) {
      for (int r = 0; r < bs; ++r)
        for (int c = 0; c < bs; ++c) {
          const double x = u(rng);
          m(rb * bs + r, cb * bs + c) += x;
          if (rb != cb) m(cb * bs + c, rb * bs + r) += x;
        }
    }
    m = (m + m.transpose()).eval() * 0.5;
    // Diagonal dominance makes it SPD.
    for (int i = 0; i < n(); ++i) m(i, i) = m.row(i).cwiseAbs().sum() + 1.0;
    return m;
  }
};

/// The upper CSC pattern of a side x side grid graph (one scalar unknown per node,
/// 4-neighbours), with its diagonal.
struct GridPattern {
  std::vector<int> col_ptr{0}, row_idx, block_starts;
  SparseStructure structure;

  explicit GridPattern(int side) {
    const int n = side * side;
    for (int c = 0; c < n; ++c) {
      if (c - side >= 0) row_idx.push_back(c - side);
      if (c % side > 0) row_idx.push_back(c - 1);
      row_idx.push_back(c);
      col_ptr.push_back(static_cast<int>(row_idx.size()));
    }
    for (int b = 0; b <= n; ++b) block_starts.push_back(b);
    structure.n = n;
    structure.col_ptr = col_ptr.data();
    structure.row_idx = row_idx.data();
    structure.block_starts = block_starts.data();
    structure.num_blocks = n;
  }
};

/// A grid's pattern with 2x2 blocks, stored complete: columns 2c and 2c+1 hold rows 2r,
/// 2r+1 for every row r of grid column c.
struct GridOfPairs {
  std::vector<int> col_ptr{0}, row_idx, block_starts;
  SparseStructure structure;

  explicit GridOfPairs(const GridPattern& grid) {
    for (int c = 0; c < grid.structure.n; ++c) {
      for (int j = 0; j < 2; ++j) {
        for (int k = grid.col_ptr[c]; k < grid.col_ptr[c + 1]; ++k) {
          row_idx.push_back(2 * grid.row_idx[k]);
          row_idx.push_back(2 * grid.row_idx[k] + 1);
        }
        col_ptr.push_back(static_cast<int>(row_idx.size()));
      }
    }
    for (int b = 0; b <= grid.structure.n; ++b) block_starts.push_back(2 * b);
    structure.n = 2 * grid.structure.n;
    structure.col_ptr = col_ptr.data();
    structure.row_idx = row_idx.data();
    structure.block_starts = block_starts.data();
    structure.num_blocks = grid.structure.n;
  }

  /// max |H x - rhs| with H from the upper triangle and complete diagonal blocks.
  [[nodiscard]] double residual(const std::vector<double>& values, const std::vector<double>& x,
                                const std::vector<double>& rhs) const {
    std::vector<double> hx(rhs.size(), 0.0);
    for (int c = 0; c < structure.n; ++c) {
      for (int k = col_ptr[c]; k < col_ptr[c + 1]; ++k) {
        const int r = row_idx[k];
        hx[r] += values[k] * x[c];
        if (r / 2 != c / 2) hx[c] += values[k] * x[r];  // the mirrored off-diagonal block
      }
    }
    double err = 0.0;
    for (std::size_t i = 0; i < rhs.size(); ++i) err = std::max(err, std::abs(hx[i] - rhs[i]));
    return err;
  }
};

}  // namespace graphslam::test
