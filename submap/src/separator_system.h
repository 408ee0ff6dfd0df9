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
#include "submap_system.h"

namespace graphslam::submap::detail {

/// S dx_S = -r with S = sum of the submaps' Schur complements (scattered into the separator's
/// columns, Partition::separator_offsets) and r the sum of their reduced gradients: the
/// separator part of the Gauss-Newton (or damped) step of the whole graph.
class SeparatorSystem {
 public:
  /// With `solvers`, the system is factorised by their solver `solver` (a sparse Cholesky
  /// that takes H in its given order, such as "cholmod"); without, by Eigen's simplicial
  /// LLT^T. Throws RegistryError for an unknown name.
  SeparatorSystem(const Partition& partition, const SolverRegistry* solvers = nullptr,
                  const std::string& solver = "cholmod");
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
  struct Blocked;  ///< the block CSC layout for a registry's solver
  /// Stored entries of S (upper triangle), after the last solve.
  [[nodiscard]] std::size_t nonzeros() const { return nonzeros_; }

 private:
  [[nodiscard]] bool solveBlocked(double lambda, Eigen::VectorXd& step, std::string& message) const;

  const Partition* partition_;
  std::unique_ptr<Blocked> blocked_;  // the registry's solver on a block CSC, or null
  std::vector<Eigen::Triplet<double>> triplets_;
  Eigen::VectorXd reduced_, gradient_;
  mutable std::size_t nonzeros_ = 0;
};

}  // namespace graphslam::submap::detail
