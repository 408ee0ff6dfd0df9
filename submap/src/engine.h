// SPDX-License-Identifier: MIT
// Private: the iteration of the submap solver, shared by one process (threads) and MPI
// ranks: an Engine does the linear algebra where the submaps live; runIterations decides.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/submap/submap_solver.h"
#include "graphslam/support/thread_pool.h"
#include "submap_system.h"

namespace graphslam::submap::detail {

/// The outcome of one step attempt (the same on every process).
struct StepOutcome {
  bool ok = true;
  std::string message;  ///< when !ok: what failed (nothing was applied)
  double gradient_norm = 0.0;
  double step_norm = 0.0;
  double max_diagonal = 0.0;
  std::size_t separator_nonzeros = 0;
  int separator_iterations = 0;  ///< conjugate gradients' (0: factorised)
  double time_eliminate = 0.0, time_separator = 0.0, time_back = 0.0;
};

/// The objective: errors of every edge recomputed; (sum rho(chi2), sum chi2) in submap order.
using Cost = std::pair<double, double>;

class Engine {
 public:
  virtual ~Engine() = default;
  virtual Cost cost() = 0;
  /// Jacobians of every edge at the current estimates (errors current).
  virtual void linearize() = 0;
  /// Eliminates every submap with damping lambda, solves the separator system,
  /// back-substitutes and applies the step (the previous estimates saved).
  virtual StepOutcome step(double lambda) = 0;
  /// Puts back the estimates saved by the last step.
  virtual void undo() = 0;
  /// |g| at the current linearisation.
  virtual double gradientNorm() = 0;
  /// Bytes sent between processes since the last call.
  virtual std::size_t takeBytes() { return 0; }
};

/// The submaps one process holds, worked on by a thread pool (each thread whole submaps).
class LocalSubmaps {
 public:
  /// `supernodal`: Options::supernodal_interiors (ignored without CHOLMOD).
  LocalSubmaps(const Partition& partition, const std::vector<int>& indices, int threads,
               bool keep_factorizations, bool supernodal);
  [[nodiscard]] std::vector<SubmapSystem>& systems() { return systems_; }
  /// Objective and raw chi2 per held submap.
  std::vector<Cost> costs();
  void linearize();
  /// Eliminates the held submaps (damping lambda) in waves of one submap per thread and
  /// hands each contribution to `sink` in submap order, then frees it: the dense separator
  /// blocks of at most one wave are in memory at once.
  void eliminate(double lambda, const std::function<void(std::size_t, Contribution&)>& sink);
  std::vector<Contribution> gradients();
  /// Back-substitutes every held submap for the separator step (the whole separator's
  /// columns) and applies the interior steps; adds |dx_I|^2 to `squared_norm`. On a failure
  /// nothing is applied.
  bool backSubstituteAndApply(const Eigen::VectorXd& separator_step, double lambda,
                              double& squared_norm, std::string& message);
  void restore();

 private:
  template <class Fn>
  void forEach(const Fn& fn);

  const Partition* partition_;
  std::vector<SubmapSystem> systems_;
  support::ThreadPool pool_;
  bool serial_ = true;  // until the first linearisation shows no in-place Jacobian
};

/// The separator vertices' estimates: saved, stepped, restored.
class SeparatorEstimates {
 public:
  explicit SeparatorEstimates(const Partition& partition) : partition_(&partition) {}
  void apply(const Eigen::VectorXd& step);
  void restore();

 private:
  const Partition* partition_;
  std::vector<double> saved_;
};

/// Runs the iterations (Levenberg-Marquardt with undamped first steps) on `engine`.
Summary runIterations(Engine& engine, const Partition& partition, const Options& options);

/// Fixes the gauge of the components nothing anchors (as the Optimizer does) until
/// destroyed.
class GaugeFix {
 public:
  GaugeFix(Graph& graph, bool enabled);
  ~GaugeFix();
  GaugeFix(const GaugeFix&) = delete;
  GaugeFix& operator=(const GaugeFix&) = delete;
  [[nodiscard]] std::vector<VertexId> ids() const;

 private:
  std::vector<Vertex*> fixed_;
};

}  // namespace graphslam::submap::detail
