// SPDX-License-Identifier: MIT
// The minimizer's step strategies: each computes the iteration's step from the system
// linearised at the current estimate, tries it, and accepts or rejects it by its own rule
// (Gauss-Newton: always; Levenberg-Marquardt: damping; dogleg: trust region; the default:
// Gauss-Newton with non-monotone acceptance, chord steps and a fall-back to LM).
// Private to graphslam::core.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "../optimizer_impl.h"

namespace graphslam::detail {

/// One iteration's inputs: the system linearised and assembled at the current estimate.
struct StepContext {
  Optimizer::Impl& im;
  Graph& graph;
  const Optimizer::Options& options;
  IterationStats& stats;  ///< the strategy fills lambda, attempts, cg_iterations, times
  int iteration = 1;
  double cost = 0.0;  ///< objective at the current estimate
};

/// How an iteration ended.
struct StepResult {
  enum class Kind {
    kAccepted,    ///< a step was taken
    kRestarted,   ///< the strategy moved the estimate (back to its best) and changed method
    kConverged,   ///< no step lowers the objective meaningfully: at a minimum
    kNoProgress,  ///< no acceptable step within the retry budget
    kFailed,      ///< numerical failure (solver: the solver's result; otherwise message)
  };
  Kind kind = Kind::kAccepted;
  double cost = 0.0;       ///< objective at the estimate after the iteration
  double step_norm = 0.0;  ///< Euclidean norm of the step taken (0 when none)
  double lambda = 0.0;     ///< damping of the step taken
  /// False when the convergence test must not stop here (the default's undamped phase
  /// above its best point).
  bool may_stop = true;
  /// The iteration factorised the undamped H successfully (a Gauss-Newton step, a chord
  /// step on such a factorisation, dogleg's unregularised Gauss-Newton point).
  bool undamped = false;
  LinearSolverResult solver;
  std::string message;
};

class StepStrategy {
 public:
  virtual ~StepStrategy() = default;
  /// Computes, tries and accepts or rejects steps from the linearisation in ctx.im. On
  /// return the estimates are the ones of the result (errors current).
  virtual StepResult step(StepContext& ctx) = 0;
  /// After the last iteration: the strategy may move the estimate (the default returns to
  /// its best point). Returns the objective at the final estimate.
  virtual double finish(StepContext& ctx) { return ctx.cost; }
};

/// The strategy of `algorithm`.
std::unique_ptr<StepStrategy> makeStepStrategy(Algorithm algorithm);

// Shared phases of the strategies, timed into ctx.stats.

/// Factorises the system with damping lambda (Impl::factorize) and solves it into im.dx.
LinearSolverResult solveStep(StepContext& ctx, double lambda);
/// Applies im.dx to the estimates and returns the objective there.
double evaluateStep(StepContext& ctx);
/// Undoes the applied step and recomputes the errors; returns the objective.
double rejectStep(StepContext& ctx);
/// Euclidean norm.
double norm(const std::vector<double>& v);
/// -g^T dx: the quadratic model's decrease of chi2 by dx when H dx = -g.
double modelDecrease(const Optimizer::Impl& im);

/// Levenberg-Marquardt: steps of (H + lambda D) dx = -g, D = I (g2o) or diag(H)
/// (Marquardt); lambda grows on rejection and shrinks on success by Nielsen's rule.
class LevenbergMarquardt final : public StepStrategy {
 public:
  StepResult step(StepContext& ctx) override;
  /// Start again from an initial lambda at the next step.
  void reset() { lambda_ = -1.0; }

 private:
  void beginIteration(StepContext& ctx);
  double lambda_ = -1.0;  // < 0: initialise from H at the next step
  double lambda_floor_ = 0.0;
  double nu_ = 2.0;
};

}  // namespace graphslam::detail
