// SPDX-License-Identifier: MIT
// The step strategies besides Gauss-Newton and Levenberg-Marquardt (step_strategy.h), one
// file each. Private to graphslam::optimizer.
#pragma once

#include <vector>

#include "chord_steps.h"
#include "dogleg_path.h"
#include "step_strategy.h"

namespace graphslam::detail {

/// Powell's dogleg in a trust region (dogleg.cpp): the step is the point of the dogleg
/// path (DoglegPath) at the trust radius, measured in the D-norm, D = diag(H). One
/// factorisation per iteration; a rejected step shrinks the radius and tries the same
/// path again (chi2 evaluations only); the radius grows after steps whose decrease the
/// model predicted well (Options::Dogleg). Reports "trust_radius" (of the last trial),
/// "trials" and "regularization" (the lambda of H + lambda I when H alone did not
/// factorise).
class Dogleg final : public StepStrategy {
 public:
  void begin(StepContext& ctx) override;
  Proposal propose(StepContext& ctx) override;
  bool keeps(StepContext& ctx, const Trial& trial) override;
  Verdict update(StepContext& ctx, const Trial& trial, bool kept) override;
  [[nodiscard]] StrategyReport report() const override;

 private:
  /// The Gauss-Newton step into im.dx; when H does not factorise, with the smallest
  /// regularisation lambda I (grown tenfold per failure) that does.
  LinearSolverResult gaussNewtonStep(StepContext& ctx);
  DoglegPath path_;
  bool path_built_ = false;  // this iteration's path is in path_
  double radius_ = -1.0;     // < 0: set at the first step
  double lambda_ = 0.0;      // regularisation of this iteration's factorisation
  double tried_radius_ = 0.0;
  int trials_ = 0;
};

/// The default algorithm (Algorithm::kGaussNewtonFallback, gauss_newton_fallback.cpp):
/// undamped steps kept non-monotonically, chord steps, a dogleg first step, and
/// Levenberg-Marquardt from the best estimate once the undamped steps stop improving or
/// the undamped system does not factorise. Reports the step taken ("chord" with
/// "cg_iterations", "first-step dogleg" with "halvings" and "trials", "gauss-newton", or
/// Levenberg-Marquardt's report once damped).
class GaussNewtonFallback final : public StepStrategy {
 public:
  void begin(StepContext& ctx) override;
  Proposal propose(StepContext& ctx) override;
  bool keeps(StepContext& ctx, const Trial& trial) override;
  Verdict update(StepContext& ctx, const Trial& trial, bool kept) override;
  double finish(StepContext& ctx) override;
  [[nodiscard]] StrategyReport report() const override;

 private:
  /// The undamped phase's steps of one iteration, in the order they are tried.
  enum class Phase {
    kChord,        // conjugate gradients on the last factorisation
    kGaussNewton,  // a fresh factorisation
    kDogleg,       // the first iteration's dogleg path, halving the radius
    kDoglegBest,   // the lowest point of that path, taken after the last halving
  };
  /// The first iteration's Gauss-Newton step raised chi2 to `gn_cost`: the dogleg path of
  /// its factorisation is tried instead (the step, undone, is in im.dx).
  Verdict startFirstStepDogleg(StepContext& ctx, double gn_cost);
  /// A dogleg trial at 2^-halvings_ of the Gauss-Newton step's length was made.
  Verdict afterDoglegTrial(StepContext& ctx, const Trial& trial, bool kept);
  /// The undamped phase kept a step: non-monotone bookkeeping, chord steps' record.
  Verdict keptUndamped(StepContext& ctx, double cost);
  /// Back to the best estimate, and Levenberg-Marquardt from there; the objective there.
  double switchToDamped(StepContext& ctx);

  LevenbergMarquardt lm_;
  bool damped_ = false;
  ChordSteps chord_;
  Phase phase_ = Phase::kGaussNewton;
  // Non-monotone acceptance: the best objective seen at the start of an iteration, its
  // estimate, and the undamped steps in a row that did not beat it.
  double best_cost_ = 0.0;
  std::vector<double> best_state_;
  int non_improving_ = 0;
  // The first-step dogleg: its path, the halvings of the current trial, the lowest
  // objective seen along it and at which halving (0: the Gauss-Newton step itself).
  DoglegPath path_;
  bool path_ok_ = false;  // path_ was built (a Gauss-Newton step with a gradient)
  int halvings_ = 0;
  int best_halvings_ = 0;
  double best_trial_ = 0.0;
  int dogleg_trials_ = 0;
  StrategyReport report_;
};

}  // namespace graphslam::detail
