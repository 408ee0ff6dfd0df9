// SPDX-License-Identifier: MIT
// Private to graphslam::solvers: fill-reducing orderings computed on the block graph.
#pragma once

#include <string>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/ordering.h"

namespace graphslam::solvers::detail {

/// Symmetric block adjacency (both triangles and the diagonal) in CSC form.
struct BlockGraph {
  int num_blocks = 0;
  std::vector<int> ptr;
  std::vector<int> idx;
};

/// Block graph of H (one node per variable block).
[[nodiscard]] BlockGraph blockGraph(const SparseStructure& s);
/// Block graph of J^T J (columns sharing a row are adjacent).
[[nodiscard]] BlockGraph blockGraph(const JacobianStructure& s);

/// AMD on the block graph; `block_work` (if given) receives AMD's own count of the
/// factor's work (block_amd.cpp), or -1 when there is none.
[[nodiscard]] std::vector<int> amdBlocks(const BlockGraph& g, double* block_work = nullptr);

/// Orderings this build can compute (METIS needs CHOLMOD).
[[nodiscard]] std::vector<Ordering> availableOrderings();

/// Fill-reducing ordering of H's columns, computed on the block graph and expanded to
/// scalar columns: perm[k] = original column placed at position k. kColamd orders the
/// columns of H's block pattern as an unsymmetric matrix (as SuperLU's COLAMD option
/// does). Throws graphslam::Error for an ordering this build lacks. With a `cache`, the
/// AMD and METIS block orderings of graphs as large as its options say are looked up
/// there and kept.
[[nodiscard]] std::vector<int> orderColumns(Ordering ordering, const SparseStructure& s,
                                            OrderingCache* cache = nullptr);
/// The same with H's block graph already built (blockGraph(s)).
[[nodiscard]] std::vector<int> orderColumns(Ordering ordering, const SparseStructure& s,
                                            const BlockGraph& g, OrderingCache* cache = nullptr);
/// orderColumns(kAmd, s, g, cache), and AMD's own count of the factor's work on the block
/// graph: block_work = sum over block columns of (blocks in the column, diagonal
/// included)^2, close to the exact count; -1 when there is none (this build has no
/// SuiteSparse, AMD set dense rows aside, or the graph is large enough for `cache` to
/// keep its orderings).
[[nodiscard]] std::vector<int> orderColumnsAmd(const SparseStructure& s, const BlockGraph& g,
                                               double* block_work, OrderingCache* cache);
/// Same for the columns of J: kColamd orders J's block pattern (fill in R of J = QR);
/// kAmd and kMetis order the block graph of J^T J.
[[nodiscard]] std::vector<int> orderColumns(Ordering ordering, const JacobianStructure& s);

/// chooseOrdering() with H's block graph already built (blockGraph(s)), the auto solver's
/// tuning and its cache of block orderings (may be null). With `exact` false, a small
/// system (METIS cannot pay even at AMD's own bound on the work) gets no exact prediction:
/// factor_nonzeros is -1 and flops that bound.
[[nodiscard]] ChosenOrdering chooseOrdering(const SparseStructure& s, const BlockGraph& g,
                                            const AutoSolverOptions& options,
                                            OrderingCache* cache, bool exact = true);

/// The cost model of the auto solver's options (the built-in one when they name none).
[[nodiscard]] const CostModel& costModel(const AutoSolverOptions& options);

/// A backend and its predicted seconds per factorisation.
struct BackendChoice {
  FactorBackend backend = FactorBackend::kEigenLdlt;
  double seconds = 0.0;
};
/// The backend `model` predicts fastest for a system of `n` unknowns whose largest vertex
/// has `block_size` dimensions and whose factorisation takes `flops`: block-llt (block sizes
/// 1 to 6), eigen-ldlt, supernodal CHOLMOD (when built with it).
[[nodiscard]] BackendChoice fastestBackend(const CostModel& model, int block_size, double n,
                                           double flops);

/// Inverse of a permutation.
[[nodiscard]] std::vector<int> inversePermutation(const std::vector<int>& perm);

/// The block of every scalar column of a structure.
[[nodiscard]] std::vector<int> blockOfColumn(const int* block_starts, int num_blocks, int n);

}  // namespace graphslam::solvers::detail
