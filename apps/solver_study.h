// SPDX-License-Identifier: MIT
// graphslam solvers' study: a graph's linear system copied out of LinearSystem, and timed
// runs of one linear solver on it.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"

namespace graphslam::apps {

/// The linear system of a graph at its current estimates, copied out of LinearSystem.
struct StudySystem {
  int n = 0;
  // H (upper, full diagonal blocks) and g.
  std::vector<int> h_ptr, h_idx, block_starts;
  std::vector<double> h_values, gradient;
  // Whitened J and r (with the damping rows, zero).
  JacobianStructure j;
  std::vector<int> j_ptr, j_idx;
  std::vector<double> j_values, residual;
  int num_blocks = 0;
  /// The active vertices and their first columns.
  std::vector<std::pair<Vertex*, int>> columns;

  SparseStructure hessian() const {
    SparseStructure s;
    s.n = n;
    s.col_ptr = h_ptr.data();
    s.row_idx = h_idx.data();
    s.block_starts = block_starts.data();
    s.num_blocks = num_blocks;
    return s;
  }
  JacobianStructure jacobian() const {
    JacobianStructure s = j;
    s.col_ptr = j_ptr.data();
    s.row_idx = j_idx.data();
    s.block_starts = block_starts.data();
    return s;
  }
  std::size_t jacobianNonZeros() const {  // without the damping rows
    std::size_t nnz = 0;
    for (int r : j_idx) nnz += r < j.damping_row ? 1u : 0u;
    return nnz;
  }
  /// y += H x (from the upper triangle).
  void multiplyAdd(const std::vector<double>& x, std::vector<double>& y) const {
    for (int c = 0; c < n; ++c) {
      for (int k = h_ptr[c]; k < h_ptr[c + 1]; ++k) {
        const int r = h_idx[k];
        if (r > c) continue;
        y[r] += h_values[k] * x[c];
        if (r != c) y[c] += h_values[k] * x[r];
      }
    }
  }
  /// y = J^T (J x + r): the gradient at x computed from J itself, which is more accurate
  /// than H x + g when H is ill-conditioned (corrected semi-normal equations).
  void gradientFromJacobian(const std::vector<double>& x, std::vector<double>& y) const {
    std::vector<double> jr(residual);  // J x + r, over all rows
    for (int c = 0; c < n; ++c) {
      for (int k = j_ptr[c]; k < j_ptr[c + 1]; ++k) jr[j_idx[k]] += j_values[k] * x[c];
    }
    y.assign(static_cast<std::size_t>(n), 0.0);
    for (int c = 0; c < n; ++c) {
      double acc = 0.0;
      for (int k = j_ptr[c]; k < j_ptr[c + 1]; ++k) acc += j_values[k] * jr[j_idx[k]];
      y[c] = acc;
    }
  }
  /// |H x + g| / |g|.
  double relativeResidual(const std::vector<double>& x) const {
    std::vector<double> y(gradient);
    multiplyAdd(x, y);
    double num = 0.0, den = 0.0;
    for (int i = 0; i < n; ++i) {
      num += y[i] * y[i];
      den += gradient[i] * gradient[i];
    }
    return den > 0 ? std::sqrt(num / den) : std::sqrt(num);
  }
};

/// The system of `graph` at its current estimates.
[[nodiscard]] StudySystem linearSystemOf(Graph& graph);

/// One solver spec's row of the study's table.
struct Row {
  std::string solver, ordering, form;
  double analyze = 0, factorize = 0, solve = 0;
  double refine = 0;  // iterative refinement after the solve (not in total())
  std::size_t factor_nnz = 0;
  double residual = NAN, max_diff = NAN, max_diff_unrefined = NAN;
  std::string status = "ok";
  std::vector<double> x, x_unrefined;
  std::vector<int> factor_ptr, factor_idx;  // for pictures
  [[nodiscard]] double total() const { return analyze + factorize + solve; }
  [[nodiscard]] bool ok() const { return status == "ok"; }
};

/// Runs one solver spec `repeats` times on fresh instances (the medians of the times); the
/// last run's solution, after `refine` steps of iterative refinement and without them, and
/// its factor's pattern when `want_pattern`.
[[nodiscard]] Row runSolver(const SolverRegistry& registry, const std::string& name,
                            Ordering ordering, const StudySystem& sys, int repeats,
                            bool want_pattern, int refine);

}  // namespace graphslam::apps
