// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cmath>

#include "step_strategy.h"

namespace graphslam::detail {

void LevenbergMarquardt::beginIteration(StepContext& ctx) {
  Optimizer::Impl& im = ctx.im;
  const Optimizer::Options& o = ctx.options;
  const int n = im.structure.dimension();
  im.saveDiagonal();
  double max_diag = 0.0;
  for (int i = 0; i < n; ++i) max_diag = std::max(max_diag, std::abs(im.saved_diag[i]));
  const bool identity = o.damping == Optimizer::Options::Damping::kIdentity;
  if (lambda_ < 0) {
    const double scale = identity ? std::max(max_diag, 1e-12) : 1.0;
    lambda_ = o.initial_lambda_factor * scale;
    // Below this the damping is lost in rounding: a lambda shrunk further by a long run of
    // good steps would need more rejections to matter again than an iteration allows, and
    // the optimizer would stop at a point that is not a minimum.
    lambda_floor_ = o.min_relative_lambda * scale;
    nu_ = 2.0;
  }
  if (identity) {
    im.damping_diag.assign(static_cast<std::size_t>(n), 1.0);
  } else {
    im.damping_diag.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) im.damping_diag[i] = std::clamp(im.saved_diag[i], 1e-6, 1e32);
  }
}

// Tries steps of growing damping until one lowers the objective (accepted: lambda shrinks
// by Nielsen's rule), the model promises no meaningful decrease (converged), or
// max_rejections is used up. A failed factorisation counts as a rejection.
StepResult LevenbergMarquardt::step(StepContext& ctx) {
  beginIteration(ctx);
  Optimizer::Impl& im = ctx.im;
  const Optimizer::Options& o = ctx.options;
  const int n = im.structure.dimension();
  StepResult result;
  result.cost = ctx.cost;
  for (int attempts = 1;; ++attempts) {
    ctx.stats.attempts = attempts;
    result.lambda = lambda_;
    result.solver = solveStep(ctx, lambda_);
    if (!result.solver.ok()) {
      if (attempts > o.max_rejections) {
        result.kind = StepResult::Kind::kFailed;
        return result;
      }
      lambda_ *= nu_;
      nu_ *= 2.0;
      continue;
    }
    const double new_cost = evaluateStep(ctx);
    double dx2 = 0.0;
    for (int i = 0; i < n; ++i) dx2 += im.dx[i] * im.dx[i] * im.damping_diag[i];
    const double predicted = lambda_ * dx2 + modelDecrease(im);
    const double rho = (ctx.cost - new_cost) / predicted;
    if (std::isfinite(new_cost) && predicted > 0 && rho > 0) {
      const double a = 2.0 * rho - 1.0;
      lambda_ = std::max(lambda_floor_, lambda_ * std::max(o.min_lambda_decrease, 1.0 - a * a * a));
      nu_ = 2.0;
      result.cost = new_cost;
      result.step_norm = norm(im.dx);
      return result;
    }
    im.undoUpdate();  // the errors are recomputed by the next try, or on leaving
    if (!(predicted > o.function_tolerance * ctx.cost)) {
      result.kind = StepResult::Kind::kConverged;  // the model promises no real decrease
      result.message = "no further decrease possible";
      result.cost = im.evalChi2(ctx.graph);
      return result;
    }
    if (attempts > o.max_rejections) {
      result.cost = im.evalChi2(ctx.graph);
      result.kind = StepResult::Kind::kNoProgress;
      result.message = "no decreasing step after " + std::to_string(attempts) + " attempts";
      return result;
    }
    lambda_ *= nu_;
    nu_ *= 2.0;
  }
}

}  // namespace graphslam::detail
