// SPDX-License-Identifier: MIT
// The submap solver across MPI ranks (library graphslam::submap_mpi, built when CMake finds
// MPI; docs/SUBMAPS.md).
#pragma once

#include "graphslam/core/graph.h"
#include "graphslam/submap/submap_solver.h"

namespace graphslam::submap {

/// MPI_Init on construction, MPI_Finalize on destruction (one per process).
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }

 private:
  int rank_ = 0;
  int size_ = 1;
};

/// The submap solver with its submaps spread over the ranks of MPI_COMM_WORLD: every rank
/// holds the same graph (read from the same file) and computes the same partition; rank r
/// holds the submaps k with k % size == r, eliminates their interiors and sends rank 0 the
/// Schur complements and reduced gradients on their separators; rank 0 solves the
/// separator system and broadcasts the separator step; every rank back-substitutes its
/// submaps. Objectives are summed per submap in submap order, so every rank takes the same
/// decisions and the result is that of SubmapSolver in one process.
/// Every rank must call optimize(); every rank returns the same summary (with the bytes the
/// ranks sent one another per iteration). Afterwards rank 0's graph holds every vertex's
/// final estimate; the other ranks' graphs only their own submaps' and the separator's.
class MpiSubmapSolver {
 public:
  /// The graph must outlive the solver. MPI must be initialised (MpiSession).
  MpiSubmapSolver(Graph& graph, Options options);
  /// Throws graphslam::Error for a partition it refuses (on every rank alike).
  Summary optimize();

 private:
  Graph& graph_;
  Options options_;
};

}  // namespace graphslam::submap
