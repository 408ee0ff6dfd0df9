// SPDX-License-Identifier: MIT
// The step strategies besides Levenberg-Marquardt (step_strategy.h), one file each.
// Private to graphslam::core.
#pragma once

#include <vector>

#include "chord_steps.h"
#include "dogleg_path.h"
#include "step_strategy.h"

namespace graphslam::detail {

/// Undamped steps H dx = -g, always accepted (gauss_newton: step_strategy.cpp).
class GaussNewton final : public StepStrategy {
 public:
  StepResult step(StepContext& ctx) override;
};

/// Powell's dogleg in a trust region (dogleg.cpp): the step is the point of the dogleg
/// path (DoglegPath) at the trust radius, measured in the D-norm, D = diag(H). One
/// factorisation per iteration; a rejected step shrinks the radius and tries the same
/// path again (chi2 evaluations only); the radius grows after steps whose decrease the
/// model predicted well (Options::Dogleg).
class Dogleg final : public StepStrategy {
 public:
  StepResult step(StepContext& ctx) override;

 private:
  /// The Gauss-Newton step into im.dx; when H does not factorise, with the smallest
  /// regularisation lambda I (grown tenfold per failure) that does.
  LinearSolverResult gaussNewtonStep(StepContext& ctx, double& lambda);
  DoglegPath path_;
  double radius_ = -1.0;  // < 0: set at the first step
};

/// The default algorithm (Algorithm::kGaussNewtonFallback, gauss_newton_fallback.cpp):
/// undamped steps accepted non-monotonically, chord steps, a dogleg first step, and
/// Levenberg-Marquardt from the best estimate once the undamped steps stop improving or
/// the undamped system does not factorise.
class GaussNewtonFallback final : public StepStrategy {
 public:
  StepResult step(StepContext& ctx) override;
  double finish(StepContext& ctx) override;

 private:
  StepResult undampedStep(StepContext& ctx);
  /// The first iteration's dogleg step, when the undamped step (applied) raised chi2 to
  /// `gn_cost`: returns the objective after it.
  double firstStepDogleg(StepContext& ctx, double gn_cost);
  /// Back to the best estimate, and Levenberg-Marquardt from there.
  StepResult switchToDamped(StepContext& ctx);

  LevenbergMarquardt lm_;
  bool damped_ = false;
  ChordSteps chord_;
  // Non-monotone acceptance: the best objective seen at the start of an iteration, its
  // estimate, and the undamped steps in a row that did not beat it.
  double best_cost_ = 0.0;
  std::vector<double> best_state_;
  int non_improving_ = 0;
  DoglegPath path_;
};

}  // namespace graphslam::detail
