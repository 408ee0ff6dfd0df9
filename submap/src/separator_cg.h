// SPDX-License-Identifier: MIT
// Private: conjugate gradients on the separator system in its assembled storage.
#pragma once

#include <Eigen/Core>
#include <string>

namespace graphslam::submap::detail {

/// A symmetric matrix stored as its upper triangle by columns (CSC) with complete diagonal
/// blocks: every column of block b holds its row blocks a <= b in increasing order, the
/// last being b's whole diagonal block; `diagonal[col]` is the position of entry
/// (col, col). The arrays belong to the caller.
struct BlockUpperCsc {
  int n = 0;
  const int* col_ptr = nullptr;
  const int* row_idx = nullptr;
  const double* values = nullptr;
  const int* diagonal = nullptr;
  const int* block_starts = nullptr;  ///< num_blocks + 1 entries
  int num_blocks = 0;
  /// Optional aggregates for the preconditioner (CgPreconditioner): block b belongs to
  /// aggregate block_group[b] (0 to num_groups - 1); null: block Jacobi alone.
  const int* block_group = nullptr;
  int num_groups = 0;
};

/// What solveByConjugateGradients did.
struct CgOutcome {
  bool ok = false;
  int iterations = 0;
  double relative_residual = 0.0;  ///< the recurrence's |b - (S + lambda I) x| / |b| at the end
  std::string message;             ///< when !ok
};

/// The preconditioner of solveByConjugateGradients.
struct CgPreconditioner {
  /// With aggregates: the additive coarse level, E = Z^T (S + lambda I) Z with one unknown
  /// per aggregate and component (the aggregate's blocks moved as one), factorised; it
  /// carries a correction across the whole separator at every iteration.
  bool coarse_level = true;
  /// With aggregates: the local level factorises each aggregate's blocks together, in
  /// chunks of at most this many columns (dense). 0, or no aggregates: each block alone
  /// (block Jacobi).
  int local_dimension = 0;
};

/// Solves (S + lambda I) x = b by preconditioned conjugate gradients from x = 0, until
/// |b - (S + lambda I) x| <= tolerance |b| or max_iterations. The preconditioner is the
/// inverse of S + lambda I's diagonal blocks (or of its aggregates' chunks), plus the coarse
/// level's correction. S is read in place: besides the preconditioner's factors, nothing but
/// six vectors of n is allocated. Not ok, with a message, when a diagonal block, the coarse
/// system or a search direction shows S + lambda I is not positive definite or the
/// iterations run out.
CgOutcome solveByConjugateGradients(const BlockUpperCsc& s, double lambda, const Eigen::VectorXd& b,
                                    Eigen::VectorXd& x, double tolerance, int max_iterations,
                                    const CgPreconditioner& preconditioner = {});

/// The coarse level's matrix E = Z^T (S + lambda I) Z, dense (s must have aggregates):
/// unknowns numbered by aggregate, each as wide as its widest block.
[[nodiscard]] Eigen::MatrixXd coarseSystem(const BlockUpperCsc& s, double lambda);

}  // namespace graphslam::submap::detail
