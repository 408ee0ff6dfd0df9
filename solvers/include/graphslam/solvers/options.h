// SPDX-License-Identifier: MIT
// Tuning of the solvers of graphslam::solvers, and the cache of block orderings a caller
// may share between solvers. Every default is the value the solvers were tuned with
// (docs/BENCHMARKS.md holds the measurements).
#pragma once

#include <cstddef>
#include <memory>

#include "graphslam/solvers/cost_model.h"

namespace graphslam::solvers {

/// Tuning of an OrderingCache.
struct OrderingCacheOptions {
  /// Block graphs of at least this many blocks have their AMD and METIS orderings kept.
  /// Below, an ordering costs less than comparing the graph with the kept one is worth
  /// the memory; above, AMD and METIS take seconds on a million blocks.
  int min_blocks = 50000;
  /// METIS orderings are kept from this many blocks on: METIS takes tens of milliseconds on
  /// a 10000-block pose graph (more than the initial guess's two factorisations of it),
  /// the fingerprint that recognises the graph again a few microseconds.
  int metis_min_blocks = 2000;
};

/// Block orderings (AMD and METIS, one of each: the most recent block graph) of large
/// block graphs (METIS's of smaller ones too), kept for the next request with the same
/// graph. The SE(2) global initial guess (2x2 blocks) and the optimizer (3x3 blocks) order
/// one pose graph: solvers that share a cache compute its orderings once. The cache is the
/// caller's object: nothing is kept between solvers that do not share one. Thread safe; a
/// graph is recognised by a 64-bit fingerprint of its pattern (a collision could only cost
/// fill: every permutation of the blocks is a valid ordering).
class OrderingCache {
 public:
  explicit OrderingCache(OrderingCacheOptions options = {});
  ~OrderingCache();
  OrderingCache(const OrderingCache&) = delete;
  OrderingCache& operator=(const OrderingCache&) = delete;

  [[nodiscard]] const OrderingCacheOptions& options() const { return options_; }
  /// Forgets every kept ordering.
  void clear();

  /// Implementation state (solvers/src/ordering.cpp).
  struct Impl;
  [[nodiscard]] Impl& impl() { return *impl_; }

 private:
  OrderingCacheOptions options_;
  std::unique_ptr<Impl> impl_;
};

/// Tuning of the "auto" solver's choice of ordering and backend. Both follow one cost model
/// of the factorisation (cost_model.h), measured by `graphslam calibrate`: auto takes the
/// backend the model predicts fastest for the system (block-llt for vertices of 2 to 6
/// dimensions, eigen-ldlt, supernodal CHOLMOD), and computes METIS beside AMD when the
/// predicted saving over the factorisations of an optimisation pays for it.
struct AutoSolverOptions {
  /// The model; null: the built-in one (CostModel::builtIn()).
  std::shared_ptr<const CostModel> cost_model;
  /// Factorisations one ordering serves, for weighing METIS's cost against the saving per
  /// factorisation it predicts (an optimisation of a pose graph takes 3-10 Gauss-Newton
  /// factorisations; the initial guess's two systems one each).
  double expected_factorizations = 5.0;
  /// From this many blocks on, METIS is computed on a second thread while AMD runs (both
  /// are serial codes, and graphs this large always need METIS as well).
  int concurrent_ordering_blocks = 200000;
};

/// Tuning of block-llt (the block up-looking Cholesky of 1x1 to 6x6 blocks).
struct BlockCholeskyOptions {
  /// A dense trailing part of L of at least this many block columns is factorised as
  /// one dense matrix (without padding the vertices smaller than the block size) ...
  int dense_tail_min_blocks = 16;
  /// ... when padding would be at least this fraction of its padded size.
  double dense_tail_min_padding = 0.2;
};

/// Tuning of the CHOLMOD backends. CHOLMOD merges a supernode into its parent when the
/// merged one would have at most zrelax[0] explicit zeros (as a fraction of its entries)
/// up to 16 columns, zrelax[1] up to 48 columns and zrelax[2] beyond.
struct CholmodOptions {
  /// Systems of blocks (vertices of dimension > 1): every supernode also stores its
  /// diagonal block as a full rectangle, so tighter amalgamation than CHOLMOD's default
  /// saves more memory than the relaxed entries would save time.
  double block_zrelax[3] = {0.2, 0.05, 0.02};
  /// Scalar systems (the isotropic and complex paths of the SE(2) initial guess) keep
  /// CHOLMOD's default: their fundamental supernodes are narrow, and BLAS calls on narrow
  /// supernodes are slow.
  double scalar_zrelax[3] = {0.8, 0.1, 0.05};
};

/// Tuning of the isotropic and conformal paths (H = H_s (x) I_d, and 2x2 blocks
/// [a -b; b a] factorised as one Hermitian complex matrix).
struct IsotropicSolverOptions {
  /// The scalar factorisation goes to CHOLMOD's supernodal factorisation where the cost
  /// model (AutoSolverOptions::cost_model) predicts it faster than block-llt's up-looking
  /// LL^T on 1x1 blocks, which has no per-supernode overhead, works on the arrays as they
  /// are and names the column of a failed pivot. With BLAS and LAPACK, tail-llt goes first,
  /// while the work its loop would do stays below the cost model's crossing point.
  /// Up to this many stored entries of H_s, tail-llt's analysis decides whether it
  /// factorises (its row patterns are the symbolic analysis every path needs); beyond,
  /// where a dense tail cannot hold most of the work, it is not tried.
  std::size_t tail_probe_entries = std::size_t{1} << 20;
};

/// Tuning of every solver registerSolvers() registers.
struct SolverOptions {
  AutoSolverOptions auto_solver;
  BlockCholeskyOptions block_cholesky;
  CholmodOptions cholmod;
  IsotropicSolverOptions isotropic;
  /// Options of the cache every "auto" solver makes for itself when `ordering_cache` is
  /// null.
  OrderingCacheOptions ordering_cache_options;
  /// A cache shared by every solver made from the registry (the caller keeps it alive
  /// with them). Null (the default): each "auto" solver keeps its own, and the other
  /// solvers keep none.
  std::shared_ptr<OrderingCache> ordering_cache;
};

}  // namespace graphslam::solvers
