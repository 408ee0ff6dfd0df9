// SPDX-License-Identifier: MIT
#include <cmath>

#include "../timing.h"
#include "graphslam/support/logging.h"
#include "strategies.h"

namespace graphslam::detail {

StepResult GaussNewtonFallback::step(StepContext& ctx) {
  if (damped_) return lm_.step(ctx);
  if (best_state_.empty() || ctx.cost <= best_cost_) {
    best_cost_ = ctx.cost;
    ctx.im.saveState(best_state_);
  }
  return undampedStep(ctx);
}

// Undamped steps are accepted even when the objective rises (non-monotone): Gauss-Newton
// often climbs for a few steps before it drops into a much better basin. After
// fallback_patience steps in a row without a new best, or a non-finite objective, the
// strategy returns to the best estimate and goes on as Levenberg-Marquardt.
StepResult GaussNewtonFallback::undampedStep(StepContext& ctx) {
  StepResult result;
  double cost = ctx.cost;
  const bool chord = chord_.tryStep(ctx, cost);
  ctx.stats.attempts = chord ? 0 : 1;
  if (!chord) {
    result.solver = solveStep(ctx, 0.0);
    if (!result.solver.ok()) {
      support::log(support::LogLevel::kInfo,
                   std::string("the undamped system does not factorise (") +
                       toString(result.solver.status) +
                       "): Levenberg-Marquardt from the best estimate");
      StepResult r = switchToDamped(ctx);
      r.may_stop = false;  // nothing was tried yet from this estimate
      return r;
    }
    cost = evaluateStep(ctx);
    if (ctx.iteration == 1 && ctx.options.first_step_dogleg && !ctx.im.jacobian_form &&
        !(cost <= ctx.cost)) {
      cost = firstStepDogleg(ctx, cost);
    }
  }
  result.undamped = true;  // the factorisation of this step, or of the one a chord step reuses
  const double model_decrease = modelDecrease(ctx.im);
  result.step_norm = norm(ctx.im.dx);
  non_improving_ = (std::isfinite(cost) && cost < best_cost_) ? 0 : non_improving_ + 1;
  if (non_improving_ >= ctx.options.fallback_patience || !std::isfinite(cost)) {
    return switchToDamped(ctx);
  }
  chord_.record(ctx, !chord, chord, ctx.cost, cost, model_decrease);
  result.cost = cost;
  // At the optimum chi2 jitters by rounding; above the best by no more than the function
  // tolerance counts as being there.
  result.may_stop = !(cost > best_cost_ + ctx.options.function_tolerance * std::abs(best_cost_));
  return result;
}

StepResult GaussNewtonFallback::switchToDamped(StepContext& ctx) {
  ctx.im.restoreState(best_state_);
  damped_ = true;
  lm_.reset();
  chord_.disable();
  StepResult result;
  result.kind = StepResult::Kind::kRestarted;
  result.cost = ctx.im.evalChi2(ctx.graph);
  result.step_norm = 1.0;  // not converged: the damped phase starts now
  return result;
}

double GaussNewtonFallback::finish(StepContext& ctx) {
  if (damped_ || best_state_.empty() || !(ctx.cost > best_cost_)) return ctx.cost;
  ctx.im.restoreState(best_state_);  // the undamped phase ended above its best point
  return ctx.im.evalChi2(ctx.graph);
}

// The first undamped step (applied) raised chi2: from the initial estimate the quadratic
// model can be far off. The step taken instead is the point of the dogleg path at a trust
// radius halved from the Gauss-Newton step's length until the model predicts the decrease
// within first_step_agreement; after first_step_max_halvings the lowest chi2 seen, if it
// is below gn_cost. The first trial skips a halving when the Gauss-Newton step's own chi2
// says so: chi2 interpolated along that step by a parabola (chi2 and its slope at the
// origin, gn_cost at the step) has its minimum at 1 / (2 - rho) of the step, rho the
// step's actual over predicted decrease (Dennis and Schnabel's backtracking rule). At or
// below a quarter (rho <= -2), the first trial is at a quarter; the radius never shrinks
// more than four times at once (Nocedal and Wright's factor).
double GaussNewtonFallback::firstStepDogleg(StepContext& ctx, double gn_cost) {
  const auto t0 = Clock::now();
  Optimizer::Impl& im = ctx.im;
  im.undoUpdate();
  if (!path_.build(im.structure, im.dx)) {
    im.applyUpdate();
    ctx.stats.time.solve += seconds(t0, Clock::now());
    return gn_cost;
  }
  const double chi2 = ctx.cost;
  const bool far_off = !(gn_cost - chi2 < 2.0 * path_.gaussNewtonDecrease());
  double best_chi2 = gn_cost;
  int best = 0;
  int trials = 0;
  double result = gn_cost;
  bool agreed = false;
  for (int k = far_off ? 2 : 1; k <= ctx.options.first_step_max_halvings && !agreed; ++k) {
    const double predicted = path_.point(std::ldexp(path_.gaussNewtonNorm(), -k), im.dx);
    im.applyUpdate();
    const double trial = im.evalChi2(ctx.graph);
    ++trials;
    if (trial < best_chi2) {
      best_chi2 = trial;
      best = k;
    }
    if (std::abs(1.0 - (chi2 - trial) / predicted) <= ctx.options.first_step_agreement) {
      agreed = true;
      result = trial;
      best = k;
    } else {
      im.undoUpdate();
    }
  }
  if (!agreed) {
    path_.point(best == 0 ? path_.gaussNewtonNorm() : std::ldexp(path_.gaussNewtonNorm(), -best),
                im.dx);
    im.applyUpdate();
    result = im.evalChi2(ctx.graph);
  }
  ctx.stats.dogleg_halvings = best;
  ctx.stats.dogleg_trials = trials;
  ctx.stats.time.solve += seconds(t0, Clock::now());
  return result;
}

}  // namespace graphslam::detail
