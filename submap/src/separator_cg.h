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
};

/// What solveByConjugateGradients did.
struct CgOutcome {
  bool ok = false;
  int iterations = 0;
  double relative_residual = 0.0;  ///< the recurrence's |b - (S + lambda I) x| / |b| at the end
  std::string message;             ///< when !ok
};

/// Solves (S + lambda I) x = b by conjugate gradients preconditioned by the inverse of
/// S + lambda I's diagonal blocks (block Jacobi), from x = 0, until
/// |b - (S + lambda I) x| <= tolerance |b| or max_iterations. S is read in place: nothing
/// but six vectors of n and the diagonal blocks' factors is allocated. Not ok, with a
/// message, when a diagonal block or a search direction shows S + lambda I is not positive
/// definite or the iterations run out.
CgOutcome solveByConjugateGradients(const BlockUpperCsc& s, double lambda, const Eigen::VectorXd& b,
                                    Eigen::VectorXd& x, double tolerance, int max_iterations);

}  // namespace graphslam::submap::detail
