// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: helpers shared by the backends.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/ordering.h"
#include "graphslam/support/fixed_size.h"

namespace graphslam::solvers::detail {

/// f(std::integral_constant<int, D>{}) with D = d for block sizes 1, 2 and 3 (loops over a
/// block unrolled), D = 0 for any other d (the callee reads d at run time).
template <typename F>
decltype(auto) withFixedSize(int d, F&& f) {
  return graphslam::support::withFixedSize<1, 2, 3>(d, f);
}

using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// Dense symmetric matrix from the upper triangle of H (entries below the diagonal of the
/// stored full diagonal blocks are ignored).
inline Eigen::MatrixXd denseSymmetric(const SparseStructure& s, const double* values) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(s.n, s.n);
  for (int c = 0; c < s.n; ++c) {
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      const int r = s.row_idx[k];
      if (r > c) continue;
      m(r, c) = values[k];
      m(c, r) = values[k];
    }
  }
  return m;
}

/// A symmetric permutation of H prepared once per structure: the upper triangle of
/// P H P^T as CSC, and for each of its entries the position of the value in H's array.
struct PermutedUpper {
  int n = 0;
  std::vector<int> col_ptr, row_idx, source;

  /// perm[k] = original column at position k.
  void build(const SparseStructure& s, const std::vector<int>& perm);
  /// Values of P H P^T (upper) from H's values.
  void fill(const double* h_values, std::vector<double>& out) const {
    out.resize(source.size());
    for (std::size_t k = 0; k < source.size(); ++k) out[k] = h_values[source[k]];
  }
  [[nodiscard]] Eigen::Map<const SpMat> map(const std::vector<double>& values) const {
    return {n, n, static_cast<int>(row_idx.size()), col_ptr.data(), row_idx.data(), values.data()};
  }
};

/// Full (both triangles) CSC of H prepared once per structure, with a permutation of
/// the columns applied: entry k of the result takes H's value at source[k].
struct FullPattern {
  int n = 0;
  std::vector<int> col_ptr, row_idx, source;
  void build(const SparseStructure& s);
  void fill(const double* h_values, std::vector<double>& out) const {
    out.resize(source.size());
    for (std::size_t k = 0; k < source.size(); ++k) out[k] = h_values[source[k]];
  }
};

/// The columns of J in a new order (perm[k] = original column at position k), with the
/// value sources. With `drop_damping`, the damping rows are left out (rows = damping_row):
/// QR solvers factorise J without them while no damping is applied, because the
/// structurally present (zero) damping rows fill the Householder vectors.
struct PermutedColumns {
  int rows = 0, cols = 0;
  std::vector<int> col_ptr, row_idx, source;
  /// Row order used (row_order[k] = original row at position k); identity unless
  /// sort_rows was requested.
  std::vector<int> row_order;
  /// With `sort_rows`, rows are renumbered by their leftmost column in the new column
  /// order (a row then enters the QR at its first column: left-looking Householder QR
  /// fills far less).
  void build(const JacobianStructure& s, const std::vector<int>& perm, bool drop_damping = false,
             bool sort_rows = false);
  void fill(const double* values, std::vector<double>& out) const {
    out.resize(source.size());
    for (std::size_t k = 0; k < source.size(); ++k) out[k] = values[source[k]];
  }
  [[nodiscard]] Eigen::Map<const SpMat> map(const std::vector<double>& values) const {
    return {rows,           cols,           static_cast<int>(row_idx.size()),
            col_ptr.data(), row_idx.data(), values.data()};
  }
};

/// Whether every damping entry of J's values is zero.
inline bool dampingIsZero(const JacobianStructure& s, const double* values) {
  for (int c = 0; c < s.cols; ++c) {
    if (values[s.col_ptr[c + 1] - 1] != 0.0) return false;
  }
  return true;
}

/// A normal-equations solver that can also take a fill-reducing order computed elsewhere
/// (the auto solver picks the ordering and the backend separately).
class OrderedSolver : public LinearSolver {
 public:
  /// analyzeOrdered() with the solver's own ordering(), computed on the block graph.
  LinearSolverResult analyze(const SparseStructure& s) override;
  /// As analyze(), with `order` (order[k] = original column at position k) instead of
  /// the solver's own ordering; ordering() then reports `label`.
  [[nodiscard]] virtual LinearSolverResult analyzeOrdered(const SparseStructure& s,
                                                          std::vector<int> order,
                                                          Ordering label) = 0;
  /// The exact size and work of the factor, from the last analysis, when the solver counts
  /// them there (as symbolicCost() would: same non-zeros and flops).
  [[nodiscard]] virtual std::optional<CholeskyPrediction> analysedCost() const {
    return std::nullopt;
  }
  /// Makes the next factorisations take complex values (a Hermitian matrix, interleaved
  /// (re, im)) or real ones, keeping the symbolic analysis; the factor of the other kind is
  /// dropped. False when the solver takes one kind only (the default).
  [[nodiscard]] virtual bool setComplexValues(bool /*complex*/) { return false; }
  /// Solves for `columns` right-hand sides of n unknowns at once (column-major, one after
  /// the other in rhs and x). By default one solve per column.
  [[nodiscard]] virtual LinearSolverResult solveColumns(const double* rhs, double* x, int n,
                                                        int columns) {
    for (int k = 0; k < columns; ++k) {
      const std::size_t at = static_cast<std::size_t>(k) * static_cast<std::size_t>(n);
      const LinearSolverResult r = solve(rhs + at, x + at);
      if (!r.ok()) return r;
    }
    return LinearSolverResult::success();
  }
  /// The block orderings analyze() looks up and keeps (null, the default: none).
  void setOrderingCache(std::shared_ptr<OrderingCache> cache) {
    ordering_cache_ = std::move(cache);
  }

 private:
  std::shared_ptr<OrderingCache> ordering_cache_;
};

/// First column of H (CSC of its stored triangle, complete blocks) whose vertex block column holds
/// a block that is not a multiple of the identity, or whose vertices differ in dimension; -1 when H
/// = H_s (x) I_d (isotropic_solver.cpp).
[[nodiscard]] int firstNonIsotropicColumn(const SparseStructure& s, const double* h);
/// First column of H (CSC of its stored triangle, complete blocks) whose vertex is not of dimension
/// 2 or whose block column holds a block not of the form [a -b; b a] (diagonal blocks: a I); -1
/// when H is the real form of a Hermitian complex matrix (isotropic_solver.cpp).
[[nodiscard]] int firstNonConformalColumn(const SparseStructure& s, const double* h);

/// Tolerance below which a pivot or eigenvalue of an n x n matrix counts as zero, relative
/// to the largest.
inline double zeroTolerance(int n, double largest) {
  return static_cast<double>(n) * Eigen::NumTraits<double>::epsilon() * largest;
}

inline LinearSolverResult notFinite() {
  return LinearSolverResult::failure(LinearSolverStatus::kSingular, "solution is not finite");
}

inline bool allFinite(const double* x, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(x[i])) return false;
  }
  return true;
}

/// Pattern of an Eigen sparse matrix, for LinearSolver::factorPattern.
template <typename Matrix>
bool exportPattern(const Matrix& m, std::vector<int>& col_ptr, std::vector<int>& row_idx) {
  SpMat copy = m;
  copy.makeCompressed();
  col_ptr.assign(copy.outerIndexPtr(), copy.outerIndexPtr() + copy.outerSize() + 1);
  row_idx.assign(copy.innerIndexPtr(), copy.innerIndexPtr() + copy.nonZeros());
  return true;
}

}  // namespace graphslam::solvers::detail
