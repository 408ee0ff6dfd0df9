// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cmath>

#include "strategies.h"

namespace graphslam::detail {

LinearSolverResult Dogleg::gaussNewtonStep(StepContext& ctx, double& lambda) {
  Optimizer::Impl& im = ctx.im;
  const int n = im.structure.dimension();
  im.saveDiagonal();
  im.damping_diag.assign(static_cast<std::size_t>(n), 1.0);
  double max_diag = 0.0;
  for (int i = 0; i < n; ++i) max_diag = std::max(max_diag, std::abs(im.saved_diag[i]));
  lambda = 0.0;
  for (int attempt = 1;; ++attempt) {
    ctx.stats.attempts = attempt;
    LinearSolverResult r = solveStep(ctx, lambda);
    const bool finite =
        std::all_of(im.dx.begin(), im.dx.end(), [](double x) { return std::isfinite(x); });
    if ((r.ok() && finite) || attempt > ctx.options.max_rejections) return r;
    lambda = lambda == 0.0 ? ctx.options.dogleg.initial_regularization * std::max(max_diag, 1e-12)
                           : lambda * 10.0;
  }
}

// One factorisation; then points of the dogleg path at a shrinking radius until one lowers
// the objective. The radius grows to expand_factor times an accepted step whose decrease
// the model predicted within expand_agreement, and shrinks to shrink_factor times a step
// that was rejected or predicted poorly (Nocedal and Wright, Algorithm 4.1).
StepResult Dogleg::step(StepContext& ctx) {
  const Optimizer::Options::Dogleg& o = ctx.options.dogleg;
  Optimizer::Impl& im = ctx.im;
  StepResult result;
  result.cost = ctx.cost;
  result.solver = gaussNewtonStep(ctx, result.lambda);
  if (!result.solver.ok()) {
    result.kind = StepResult::Kind::kFailed;
    return result;
  }
  result.undamped = result.lambda == 0.0;
  if (!path_.build(im.structure, im.dx)) {
    result.kind = StepResult::Kind::kConverged;
    result.message = "the gradient vanishes";
    return result;
  }
  if (radius_ <= 0.0) radius_ = o.initial_radius > 0.0 ? o.initial_radius : path_.gaussNewtonNorm();
  for (int trials = 1;; ++trials) {
    ctx.stats.dogleg_trials = trials;
    ctx.stats.trust_radius = radius_;
    const double predicted = path_.point(radius_, im.dx);
    const double new_cost = evaluateStep(ctx);
    const double rho = (ctx.cost - new_cost) / predicted;
    const double step = path_.norm(im.dx);
    if (std::isfinite(new_cost) && rho > 0.0) {
      if (rho > o.expand_agreement) {
        radius_ = std::max(radius_, o.expand_factor * step);
      } else if (rho < o.shrink_agreement) {
        radius_ = o.shrink_factor * step;
      }
      result.cost = new_cost;
      result.step_norm = norm(im.dx);
      return result;
    }
    im.undoUpdate();
    radius_ = o.shrink_factor * step;
    if (!(predicted > ctx.options.function_tolerance * ctx.cost)) {
      result.kind = StepResult::Kind::kConverged;  // the model promises no real decrease
      result.message = "no further decrease possible";
      result.cost = im.evalChi2(ctx.graph);
      return result;
    }
    if (trials > ctx.options.max_rejections) {
      result.kind = StepResult::Kind::kNoProgress;
      result.message = "no decreasing step after " + std::to_string(trials) + " trials";
      result.cost = im.evalChi2(ctx.graph);
      return result;
    }
  }
}

}  // namespace graphslam::detail
