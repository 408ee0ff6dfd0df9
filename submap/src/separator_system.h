// SPDX-License-Identifier: MIT
// Private: the reduced system on the separator variables, summed from the submaps.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/submap/partition.h"
#include "graphslam/submap/submap_solver.h"
#include "submap_system.h"

namespace graphslam::submap::detail {

/// S dx_S = -r with S = sum of the submaps' Schur complements (scattered into the separator's
/// columns, Partition::separator_offsets) and r the sum of their reduced gradients: the
/// separator part of the Gauss-Newton (or damped) step of the whole graph.
class SeparatorSystem {
 public:
  /// Solved as `options` says (Options::separator_method): by conjugate gradients on the
  /// assembled blocks in place; or factorised by `options.separator_solver` of
  /// `options.solvers` (a sparse Cholesky that takes the matrix in its given order, such as
  /// "cholmod"), or by Eigen's simplicial LL^T without a registry. `solves` false: a
  /// process that only sums contributions (no solver made). Throws RegistryError for an
  /// unknown solver name.
  SeparatorSystem(const Partition& partition, const Options& options, bool solves = true);
  ~SeparatorSystem();

  /// Forgets every contribution.
  void clear();
  /// Adds the contribution of submap `index`.
  void add(int index, const Contribution& contribution);
  /// Solves (S + lambda I) dx_S = -r into `step` (separator dimension); false with a
  /// message when S + lambda I is not positive definite. The contributions stay.
  [[nodiscard]] bool solve(double lambda, Eigen::VectorXd& step, std::string& message) const;
  /// |g_S|^2 of the summed (undamped, unreduced) separator gradient.
  [[nodiscard]] double gradientSquared() const { return gradient_.squaredNorm(); }
  struct Blocked;  ///< the block CSC layout (a registry's solver or conjugate gradients)
  /// Stored entries of S (upper triangle), after the last solve.
  [[nodiscard]] std::size_t nonzeros() const { return nonzeros_; }
  /// Conjugate-gradient iterations of the last solve (0 when factorised).
  [[nodiscard]] int iterations() const { return iterations_; }

 private:
  [[nodiscard]] bool solveBlocked(double lambda, Eigen::VectorXd& step, std::string& message) const;
  [[nodiscard]] bool solveByCg(double lambda, Eigen::VectorXd& step, std::string& message) const;

  const Partition* partition_;
  std::unique_ptr<Blocked> blocked_;  // the block CSC (and a registry's solver), or null
  std::vector<Eigen::Triplet<double>> triplets_;
  Eigen::VectorXd reduced_, gradient_;
  bool cg_ = false;
  double cg_tolerance_ = 0.0;
  int cg_max_iterations_ = 0;
  int cg_local_dimension_ = 0;
  bool cg_coarse_ = false;
  std::vector<int> aggregates_;  // per separator vertex, for the CG's preconditioner (or empty)
  int num_aggregates_ = 0;
  mutable std::size_t nonzeros_ = 0;
  mutable int iterations_ = 0;
};

}  // namespace graphslam::submap::detail
