// SPDX-License-Identifier: MIT
#include <cmath>

#include "../timing.h"
#include "graphslam/support/logging.h"
#include "strategies.h"

namespace graphslam::detail {

// Each iteration of the undamped phase tries, in order: a chord step when the last step
// calls for one (kept when it lowers the objective), then a step of a fresh factorisation
// (kept even when the objective rises: Gauss-Newton often climbs for a few steps before it
// drops into a much better basin), and at the first iteration, when that step raised the
// objective, points of its dogleg path. After fallback_patience kept steps in a row without
// a new best, or a non-finite objective, the strategy returns to the best estimate and goes
// on as Levenberg-Marquardt.
void GaussNewtonFallback::begin(StepContext& ctx) {
  if (damped_) {
    lm_.begin(ctx);
    return;
  }
  if (best_state_.empty() || ctx.cost <= best_cost_) {
    best_cost_ = ctx.cost;
    ctx.im.saveState(best_state_);
  }
  phase_ = Phase::kChord;
  report_ = {};
}

Proposal GaussNewtonFallback::propose(StepContext& ctx) {
  if (damped_) return lm_.propose(ctx);
  Proposal p;
  switch (phase_) {
    case Phase::kChord:
      if (const int iterations = chord_.propose(ctx); iterations > 0) {
        report_ = {"chord",
                   "chord step: previous factorisation, " + std::to_string(iterations) +
                       (iterations == 1 ? " CG iteration" : " CG iterations"),
                   {{"cg_iterations", iterations}}};
        p.predicted = modelDecrease(ctx.im);
        return p;
      }
      phase_ = Phase::kGaussNewton;
      [[fallthrough]];
    case Phase::kGaussNewton:
      report_ = {"gauss-newton", "", {}};
      p.solver = solveStep(ctx, 0.0);
      if (!p.solver.ok()) {
        support::log(support::LogLevel::kInfo,
                     std::string("the undamped system does not factorise (") +
                         toString(p.solver.status) +
                         "): Levenberg-Marquardt from the best estimate");
        p.kind = Proposal::Kind::kRestarted;
        p.cost = switchToDamped(ctx);
        p.may_stop = false;  // nothing was tried yet from this estimate
        return p;
      }
      p.predicted = modelDecrease(ctx.im);
      return p;
    case Phase::kDogleg:
      p.predicted = path_.point(std::ldexp(path_.gaussNewtonNorm(), -halvings_), ctx.im.dx);
      return p;
    case Phase::kDoglegBest:
      // Without a path im.dx still holds the Gauss-Newton step (undone, not changed).
      p.predicted = !path_ok_
                        ? modelDecrease(ctx.im)
                        : path_.point(best_halvings_ == 0
                                          ? path_.gaussNewtonNorm()
                                          : std::ldexp(path_.gaussNewtonNorm(), -best_halvings_),
                                      ctx.im.dx);
      return p;
  }
  return p;
}

bool GaussNewtonFallback::keeps(StepContext& ctx, const Trial& trial) {
  if (damped_) return lm_.keeps(ctx, trial);
  switch (phase_) {
    case Phase::kChord:
      return trial.after < trial.before || (trial.after == trial.before && trial.before == 0.0);
    case Phase::kGaussNewton:
      // From the initial estimate the quadratic model can be far off: a first step that
      // raises chi2 gives way to the dogleg path (first_step_dogleg).
      return !(ctx.iteration == 1 && ctx.options.first_step_dogleg && !ctx.im.jacobian_form &&
               !(trial.after <= trial.before));
    case Phase::kDogleg:
      return std::abs(1.0 - trial.ratio()) <= ctx.options.first_step_agreement;
    case Phase::kDoglegBest:
      break;
  }
  return true;
}

Verdict GaussNewtonFallback::update(StepContext& ctx, const Trial& trial, bool kept) {
  if (damped_) return lm_.update(ctx, trial, kept);
  switch (phase_) {
    case Phase::kChord:
      if (kept) return keptUndamped(ctx, trial.after);
      phase_ = Phase::kGaussNewton;  // the chord step did not lower the objective
      return retry();
    case Phase::kGaussNewton:
      if (kept) return keptUndamped(ctx, trial.after);
      return startFirstStepDogleg(ctx, trial.after);
    case Phase::kDogleg:
    case Phase::kDoglegBest:
      break;
  }
  return afterDoglegTrial(ctx, trial, kept);
}

// The first trial skips a halving when the Gauss-Newton step's own chi2 says so: chi2
// interpolated along that step by a parabola (chi2 and its slope at the origin, gn_cost at
// the step) has its minimum at 1 / (2 - rho) of the step, rho the step's actual over
// predicted decrease (Dennis and Schnabel's backtracking rule). At or below a quarter
// (rho <= -2), the first trial is at a quarter; the radius never shrinks more than four
// times at once (Nocedal and Wright's factor).
Verdict GaussNewtonFallback::startFirstStepDogleg(StepContext& ctx, double gn_cost) {
  best_halvings_ = 0;
  best_trial_ = gn_cost;
  dogleg_trials_ = 0;
  path_ok_ = path_.build(ctx.im.structure, ctx.im.dx);
  if (!path_ok_) {
    phase_ = Phase::kDoglegBest;  // no path: the Gauss-Newton step itself, kept after all
    return retry();
  }
  const bool far_off = !(gn_cost - ctx.cost < 2.0 * path_.gaussNewtonDecrease());
  halvings_ = far_off ? 2 : 1;
  phase_ = halvings_ <= ctx.options.first_step_max_halvings ? Phase::kDogleg : Phase::kDoglegBest;
  return retry();
}

// The trust radius halves from the Gauss-Newton step's length until the model predicts the
// decrease within first_step_agreement; after first_step_max_halvings the lowest point seen
// (the Gauss-Newton step's when none is lower) is taken.
Verdict GaussNewtonFallback::afterDoglegTrial(StepContext& ctx, const Trial& trial, bool kept) {
  if (phase_ == Phase::kDogleg) {
    ++dogleg_trials_;
    if (trial.after < best_trial_) {
      best_trial_ = trial.after;
      best_halvings_ = halvings_;
    }
    if (kept) best_halvings_ = halvings_;
  }
  if (!kept) {
    if (++halvings_ > ctx.options.first_step_max_halvings) phase_ = Phase::kDoglegBest;
    return retry();
  }
  report_ = {best_halvings_ > 0 ? "first-step dogleg" : "gauss-newton",
             best_halvings_ > 0 ? "dogleg step: trust radius = Gauss-Newton step / 2^" +
                                      std::to_string(best_halvings_)
                                : "",
             {{"halvings", best_halvings_}, {"trials", dogleg_trials_}}};
  return keptUndamped(ctx, trial.after);
}

Verdict GaussNewtonFallback::keptUndamped(StepContext& ctx, double cost) {
  const bool chord = phase_ == Phase::kChord;
  const double model_decrease = modelDecrease(ctx.im);
  non_improving_ = (std::isfinite(cost) && cost < best_cost_) ? 0 : non_improving_ + 1;
  Verdict v;
  if (non_improving_ >= ctx.options.fallback_patience || !std::isfinite(cost)) {
    v.next = Verdict::Next::kRestarted;
    v.cost = switchToDamped(ctx);
    return v;
  }
  v.undamped = true;  // the factorisation of this step, or of the one a chord step reuses
  chord_.record(ctx, !chord, chord, ctx.cost, cost, model_decrease);
  // At the optimum chi2 jitters by rounding; above the best by no more than the function
  // tolerance counts as being there.
  v.may_stop = !(cost > best_cost_ + ctx.options.function_tolerance * std::abs(best_cost_));
  return v;
}

double GaussNewtonFallback::switchToDamped(StepContext& ctx) {
  ctx.im.restoreState(best_state_);
  damped_ = true;
  lm_.reset();
  chord_.disable();
  return ctx.im.evalChi2(ctx.graph);
}

double GaussNewtonFallback::finish(StepContext& ctx) {
  if (damped_ || best_state_.empty() || !(ctx.cost > best_cost_)) return ctx.cost;
  ctx.im.restoreState(best_state_);  // the undamped phase ended above its best point
  return ctx.im.evalChi2(ctx.graph);
}

StrategyReport GaussNewtonFallback::report() const { return damped_ ? lm_.report() : report_; }

}  // namespace graphslam::detail
