// SPDX-License-Identifier: MIT
// The evaluator of the minimizer (step_strategy.h): tries the steps a strategy proposes.
#include "../timing.h"
#include "step_strategy.h"

namespace graphslam::detail {

namespace {

/// Applies im.dx to the estimates and returns the objective there.
double applyAndScore(StepContext& ctx) {
  const auto t0 = Clock::now();
  ctx.im.applyUpdate();
  const double cost = ctx.im.evalChi2(ctx.graph);
  ctx.stats.time.solve += seconds(t0, Clock::now());
  return cost;
}

StepResult::Kind kindOf(Verdict::Next next) {
  switch (next) {
    case Verdict::Next::kConverged:
      return StepResult::Kind::kConverged;
    case Verdict::Next::kNoProgress:
      return StepResult::Kind::kNoProgress;
    case Verdict::Next::kFailed:
      return StepResult::Kind::kFailed;
    case Verdict::Next::kRestarted:
      return StepResult::Kind::kRestarted;
    case Verdict::Next::kDone:
    case Verdict::Next::kRetry:
      break;
  }
  return StepResult::Kind::kAccepted;
}

/// The result of a proposal that is not a step.
StepResult fromProposal(const Proposal& p, double cost) {
  StepResult r;
  r.cost = cost;
  r.solver = p.solver;
  r.message = p.message;
  r.undamped = p.undamped;
  switch (p.kind) {
    case Proposal::Kind::kConverged:
      r.kind = StepResult::Kind::kConverged;
      break;
    case Proposal::Kind::kFailed:
      r.kind = StepResult::Kind::kFailed;
      break;
    case Proposal::Kind::kRestarted:
      r.kind = StepResult::Kind::kRestarted;
      r.cost = p.cost;
      r.step_norm = 1.0;  // not converged: the new method starts now
      r.may_stop = p.may_stop;
      break;
    case Proposal::Kind::kStep:
      break;
  }
  return r;
}

}  // namespace

Verdict rejectedStep(const StepContext& ctx, const Trial& trial, int attempts, const char* what) {
  Verdict v;
  if (!(trial.predicted > ctx.options.function_tolerance * ctx.cost)) {
    v.next = Verdict::Next::kConverged;  // the model promises no real decrease
    v.message = "no further decrease possible";
  } else if (attempts > ctx.options.max_rejections) {
    v.next = Verdict::Next::kNoProgress;
    v.message = "no decreasing step after " + std::to_string(attempts) + " " + what;
  } else {
    v.next = Verdict::Next::kRetry;
  }
  return v;
}

bool StepStrategy::keeps(StepContext& /*ctx*/, const Trial& trial) {
  return trial.finite() && trial.after < trial.before;
}

// Propose, apply and score, keep or undo, update; until the strategy ends the iteration.
// When the iteration ends on an undone step, the errors are computed again at the estimate
// it keeps (the undone trial left its own in the edges).
StepResult runIteration(StepStrategy& strategy, StepContext& ctx) {
  strategy.begin(ctx);
  for (;;) {
    const Proposal p = strategy.propose(ctx);
    if (p.kind != Proposal::Kind::kStep) return fromProposal(p, ctx.cost);
    const Trial trial{ctx.cost, applyAndScore(ctx), p.predicted};
    ++ctx.stats.trials;
    const bool kept = strategy.keeps(ctx, trial);
    if (!kept) ctx.im.undoUpdate();
    const Verdict v = strategy.update(ctx, trial, kept);
    if (v.next == Verdict::Next::kRetry) continue;
    StepResult r;
    r.kind = kindOf(v.next);
    r.may_stop = v.may_stop;
    r.undamped = v.undamped;
    r.message = v.message;
    if (v.next == Verdict::Next::kRestarted) {
      r.cost = v.cost;
      r.step_norm = 1.0;  // not converged: the new method starts now
    } else if (kept) {
      r.cost = trial.after;
      r.step_norm = norm(ctx.im.dx);
    } else {
      r.cost = ctx.im.evalChi2(ctx.graph);
    }
    return r;
  }
}

}  // namespace graphslam::detail
