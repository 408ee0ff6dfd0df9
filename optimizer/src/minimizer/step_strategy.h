// SPDX-License-Identifier: MIT
// The minimizer's step strategies and the one evaluator that tries their steps, in the shape
// of Ceres' trust-region minimizer: a strategy proposes a step of the system linearised at
// the current estimate and the decrease of the objective its model predicts; the evaluator
// (runIteration) applies the step, scores it, asks the strategy whether it is kept (a
// monotone rule by default; the default strategy's is not) and undoes it if not; the
// strategy then updates its own state (damping, trust radius, best point) and says whether
// the iteration is done or another step is to be tried on the same linearisation.
// Private to graphslam::optimizer.
#pragma once

#include <cmath>
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
  IterationStats& stats;  ///< times, factorisations and trials are counted into it
  int iteration = 1;
  double cost = 0.0;  ///< objective at the current estimate
};

/// A step a strategy proposes; the step itself is in ctx.im.dx.
struct Proposal {
  enum class Kind {
    kStep,       ///< try im.dx
    kConverged,  ///< no step can lower the objective meaningfully (message says why)
    kFailed,     ///< numerical failure (solver: the solver's result)
    kRestarted,  ///< the strategy moved the estimate itself (to `cost`) and changed method
  };
  Kind kind = Kind::kStep;
  double predicted = 0.0;  ///< the model's decrease of the objective by the step
  double cost = 0.0;       ///< kRestarted: the objective where the strategy moved
  bool may_stop = true;    ///< kRestarted: whether the convergence test may stop there
  bool undamped = false;   ///< kConverged: the undamped H was factorised successfully
  LinearSolverResult solver;
  std::string message;
};

/// A tried step: the objective before and after it, and the model's prediction.
struct Trial {
  double before = 0.0;
  double after = 0.0;
  double predicted = 0.0;
  [[nodiscard]] double ratio() const { return (before - after) / predicted; }
  [[nodiscard]] bool finite() const { return std::isfinite(after); }
};

/// What the iteration does after a trial.
struct Verdict {
  enum class Next {
    kDone,        ///< the iteration ends with the kept step
    kRetry,       ///< propose again on the same linearisation
    kConverged,   ///< at a minimum: no step lowers the objective meaningfully
    kNoProgress,  ///< no acceptable step within the budget
    kFailed,      ///< numerical failure (message)
    kRestarted,   ///< the strategy moved the estimate (to `cost`) and changed method
  };
  Next next = Next::kDone;
  /// False when the convergence test must not stop here (the default's undamped phase
  /// above its best point, a restart).
  bool may_stop = true;
  /// The iteration factorised the undamped H successfully.
  bool undamped = false;
  double cost = 0.0;  ///< kRestarted: the objective where the strategy moved
  std::string message;
};

/// The verdict "propose again on the same linearisation".
[[nodiscard]] inline Verdict retry() {
  Verdict v;
  v.next = Verdict::Next::kRetry;
  return v;
}

/// The verdict on a rejected step of a trust-region strategy (LM, dogleg): converged when
/// the model promises no meaningful decrease (below function_tolerance of the objective),
/// no progress after more than max_rejections `attempts` (named `what` in the message),
/// else retry.
[[nodiscard]] Verdict rejectedStep(const StepContext& ctx, const Trial& trial, int attempts,
                                   const char* what);

/// How an iteration ended, for the optimizer's loop.
struct StepResult {
  enum class Kind { kAccepted, kRestarted, kConverged, kNoProgress, kFailed };
  Kind kind = Kind::kAccepted;
  double cost = 0.0;       ///< objective at the estimate after the iteration
  double step_norm = 0.0;  ///< Euclidean norm of the step kept (0 when none)
  bool may_stop = true;
  bool undamped = false;
  LinearSolverResult solver;
  std::string message;
};

class StepStrategy {
 public:
  virtual ~StepStrategy() = default;
  /// A new linearisation is in ctx.im (called once per iteration, before any proposal).
  virtual void begin(StepContext& ctx) { (void)ctx; }
  /// Puts the next step into ctx.im.dx with its predicted decrease (or says why there is
  /// none).
  virtual Proposal propose(StepContext& ctx) = 0;
  /// Whether the evaluator keeps the tried step. Default: monotone, the objective fell.
  virtual bool keeps(StepContext& ctx, const Trial& trial);
  /// After the evaluator kept or undid the step: the strategy's own update and what the
  /// iteration does next.
  virtual Verdict update(StepContext& ctx, const Trial& trial, bool kept) = 0;
  /// After the last iteration: the strategy may move the estimate (the default returns to
  /// its best point). Returns the objective at the final estimate.
  virtual double finish(StepContext& ctx) { return ctx.cost; }
  /// The strategy's figures of the iteration that just ended (IterationStats::strategy).
  [[nodiscard]] virtual StrategyReport report() const { return {}; }
};

/// The strategy of `algorithm`.
std::unique_ptr<StepStrategy> makeStepStrategy(Algorithm algorithm);

/// The evaluator: one iteration of `strategy` on the linearisation in ctx.im.
StepResult runIteration(StepStrategy& strategy, StepContext& ctx);

// Shared phases of the strategies, timed into ctx.stats.

/// Factorises the system with damping lambda (Impl::factorize) and solves it into im.dx;
/// counts the factorisation.
LinearSolverResult solveStep(StepContext& ctx, double lambda);
/// Euclidean norm.
double norm(const std::vector<double>& v);
/// -g^T dx: the quadratic model's decrease of chi2 by dx when H dx = -g.
double modelDecrease(const Optimizer::Impl& im);

/// Undamped steps H dx = -g, always kept while the objective is finite.
class GaussNewton final : public StepStrategy {
 public:
  Proposal propose(StepContext& ctx) override;
  bool keeps(StepContext& ctx, const Trial& trial) override;
  Verdict update(StepContext& ctx, const Trial& trial, bool kept) override;
  [[nodiscard]] StrategyReport report() const override;
};

/// Levenberg-Marquardt: steps of (H + lambda D) dx = -g, D = I (g2o) or diag(H)
/// (Marquardt); lambda grows on rejection and shrinks on success by Nielsen's rule. Reports
/// "lambda" (of the kept step).
class LevenbergMarquardt final : public StepStrategy {
 public:
  void begin(StepContext& ctx) override;
  Proposal propose(StepContext& ctx) override;
  bool keeps(StepContext& ctx, const Trial& trial) override;
  Verdict update(StepContext& ctx, const Trial& trial, bool kept) override;
  [[nodiscard]] StrategyReport report() const override;
  /// Start again from an initial lambda at the next iteration.
  void reset() { lambda_ = -1.0; }

 private:
  double lambda_ = -1.0;  // < 0: initialise from H at the next iteration
  double lambda_floor_ = 0.0;
  double nu_ = 2.0;
  int attempts_ = 0;  // factorisations and trials of this iteration
  double kept_lambda_ = 0.0;
};

}  // namespace graphslam::detail
