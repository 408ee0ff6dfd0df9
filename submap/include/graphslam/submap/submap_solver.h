// SPDX-License-Identifier: MIT
// Nonlinear least squares over a graph split into submaps: each Gauss-Newton step solved
// exactly by eliminating every submap's interior onto the separator variables.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/submap/partition.h"

namespace graphslam::submap {

/// One iteration (one linearisation) of the submap solver.
struct IterationStats {
  int iteration = 0;           ///< 1-based
  double chi2 = 0.0;           ///< objective after the iteration (robust kernels applied)
  double gradient_norm = 0.0;  ///< |J^T Omega e| at the iteration's linearisation point
  double step_norm = 0.0;      ///< Euclidean norm of the accepted step (0 when none)
  double lambda = 0.0;         ///< damping of the accepted step (0: Gauss-Newton)
  bool accepted = true;        ///< false when no step lowered the objective
  int trials = 0;              ///< steps tried (each a full elimination)
  std::size_t separator_vertices = 0;
  int separator_dimension = 0;
  std::size_t separator_nonzeros = 0;  ///< stored entries of the separator system (upper)
  /// Conjugate-gradient iterations of the accepted step's separator solve (0: factorised).
  int separator_iterations = 0;
  double time_eliminate = 0.0;  ///< linearise, assemble, factorise interiors, Schur complements
  double time_separator = 0.0;  ///< assemble and solve the separator system
  double time_back = 0.0;       ///< back-substitution, update and objective of the step
  double time = 0.0;            ///< the iteration's wall time
  double elapsed = 0.0;         ///< since optimize() started
  /// MPI (MpiSubmapSolver): bytes the ranks sent one another this iteration; 0 in one process.
  std::size_t bytes_communicated = 0;
};

/// Result of SubmapSolver::optimize().
struct Summary {
  TerminationStatus status = TerminationStatus::kUnderDetermined;
  std::string message;
  double initial_chi2 = 0.0, final_chi2 = 0.0;  ///< sum of e^T Omega e (kernels ignored)
  double initial_cost = 0.0, final_cost = 0.0;  ///< the objective minimised
  /// |J^T Omega e| at the final estimate: near 0 at the optimum of the whole graph.
  double final_gradient_norm = 0.0;
  int iterations = 0;
  std::vector<IterationStats> per_iteration;
  std::string partition;              ///< Partition::describe()
  std::vector<VertexId> gauge_fixed;  ///< vertices fixed for the run to remove a free gauge
  double total_time = 0.0;
  std::size_t bytes_communicated = 0;  ///< MPI: total over the iterations
  [[nodiscard]] bool succeeded() const {
    return status == TerminationStatus::kConverged || status == TerminationStatus::kMaxIterations;
  }
  [[nodiscard]] std::string report() const;
};

struct Options {
  PartitionOptions partition;
  int max_iterations = 100;
  /// Converged when an accepted step lowers the objective by less than this fraction...
  double function_tolerance = 1e-10;
  /// ...or the step's norm is below this, or the gradient's norm is below this.
  double step_tolerance = 1e-12;
  double gradient_tolerance = 0.0;
  /// Damping after a step that raises the objective or does not factorise: lambda I with
  /// lambda first this fraction of the largest diagonal entry of H, then ten times larger
  /// per rejection (up to max_rejections in one iteration); a kept step divides it by ten,
  /// and below 1e-12 of that scale the steps are undamped again (Gauss-Newton).
  double initial_lambda_factor = 1e-5;
  int max_rejections = 10;
  /// Threads, each eliminating whole submaps (the result does not depend on the count).
  int threads = 1;
  /// Fix the gauge of components nothing anchors, as Optimizer::Options::fix_gauge does
  /// (the same vertices, so both reach the same optimum).
  bool fix_gauge = true;
  /// Keep each submap's factorisation from elimination to back-substitution: one
  /// factorisation per submap and step instead of two, at the price of every submap's
  /// factor in memory at once. Off: memory holds the largest submaps being worked on (one
  /// per thread) plus the separator system.
  bool keep_factorizations = false;
  /// Factorise each submap's whole system with its separator last by CHOLMOD's supernodal
  /// Cholesky (BLAS-3 on dense supernodes; the Schur complement read off the factor's
  /// trailing block). Off, or in a build without CHOLMOD: Eigen's simplicial LL^T of the
  /// interior, then the Schur complement from its triangular solves.
  bool supernodal_interiors = true;
  /// How the separator system is solved.
  enum class SeparatorMethod {
    /// Factorised by `separator_solver`: its factor and a copy of the matrix beside the
    /// assembled one.
    factorization,
    /// Conjugate gradients with a two-level preconditioner (below), reading
    /// the assembled matrix in place: no factor and no copy, so memory holds the matrix's
    /// values and pattern once; each iteration is one product with it. The step is the
    /// direct path's to `separator_cg_tolerance` (the summary's gradient norm shows it).
    conjugate_gradients,
  };
  SeparatorMethod separator_method = SeparatorMethod::factorization;
  /// Conjugate gradients stop at |r + (S + lambda I) dx_S| <= this * |r| (S the separator
  /// system, r its reduced gradient)...
  double separator_cg_tolerance = 1e-10;
  /// ...and refuse the step when this many iterations do not reach it (a damped retry).
  int separator_cg_max_iterations = 20000;
  /// The conjugate gradients' preconditioner works on aggregates: the separator vertices
  /// touched by the same set of submaps. A coarse level, one small system with an unknown
  /// per aggregate and component (the aggregate moved as one), corrects the whole separator
  /// at every iteration; without it, information crosses one block per iteration and the
  /// iteration count grows with the number of submaps across the map.
  bool separator_cg_coarse = true;
  /// The local level factorises each aggregate's diagonal blocks together, in dense chunks
  /// of at most this many columns (memory: up to this many doubles per separator column);
  /// 0: each separator vertex's block alone (block Jacobi).
  int separator_cg_local_dimension = 300;
  /// The factorisation: `separator_solver` of `solvers` (a sparse Cholesky that takes the
  /// matrix in its given order: "cholmod", supernodal, fits the dense blocks the submaps
  /// leave there), or Eigen's simplicial LL^T when `solvers` is null.
  const SolverRegistry* solvers = nullptr;
  std::string separator_solver = "cholmod";
  std::function<void(const IterationStats&)> callback;
};

/// Optimises a graph by submaps in one process (threads over submaps): Levenberg-Marquardt
/// steps of the whole graph (undamped, Gauss-Newton, while they lower the objective), each
/// solved by Schur complement onto the separator, so every step is the direct path's step.
class SubmapSolver {
 public:
  /// The graph must outlive the solver.
  SubmapSolver(Graph& graph, Options options);
  /// Partitions (throws graphslam::Error for a partition it refuses, Partition) and runs
  /// up to max_iterations iterations from the current estimates.
  Summary optimize();

 private:
  Graph& graph_;
  Options options_;
};

}  // namespace graphslam::submap
