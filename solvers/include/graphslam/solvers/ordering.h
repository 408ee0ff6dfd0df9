// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/solvers/options.h"

namespace graphslam::solvers {

/// Fill-reducing ordering of H's columns computed on the block graph and expanded to
/// scalar columns: perm[k] = original column at position k. kMetis and kColamd need
/// SuiteSparse; an ordering this build lacks throws graphslam::Error. With a `cache`, the
/// AMD and METIS block orderings of large graphs are looked up there and kept.
[[nodiscard]] std::vector<int> fillReducingOrdering(Ordering ordering, const SparseStructure& s,
                                                    OrderingCache* cache = nullptr);

/// Size and work of the Cholesky factor of P H P^T predicted exactly from the pattern
/// (block elimination tree and row subtrees, O(non-zero blocks of L)).
struct CholeskyPrediction {
  double factor_nonzeros = 0.0;  ///< scalar non-zeros of L, diagonal included
  double flops = 0.0;            ///< sum over columns of (column count)^2
};
[[nodiscard]] CholeskyPrediction predictCholesky(const SparseStructure& s,
                                                 const std::vector<int>& perm);

/// The ordering the "auto" solver uses: AMD, or METIS when the cost model
/// (options.cost_model) says computing it pays and it predicts a faster factorisation.
struct ChosenOrdering {
  Ordering ordering = Ordering::kAmd;
  std::vector<int> perm;
  CholeskyPrediction prediction;
};
[[nodiscard]] ChosenOrdering chooseOrdering(const SparseStructure& s,
                                            const AutoSolverOptions& options = {});

}  // namespace graphslam::solvers
