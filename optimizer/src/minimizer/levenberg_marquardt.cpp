// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cmath>

#include "step_strategy.h"

namespace graphslam::detail {

void LevenbergMarquardt::begin(StepContext& ctx) {
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
  attempts_ = 0;
  kept_lambda_ = 0.0;
}

// The step of the current lambda; a factorisation that fails counts as a rejection (lambda
// grows) until max_rejections are used up.
Proposal LevenbergMarquardt::propose(StepContext& ctx) {
  Proposal p;
  for (;;) {
    ++attempts_;
    p.solver = solveStep(ctx, lambda_);
    if (p.solver.ok()) break;
    if (attempts_ > ctx.options.max_rejections) {
      p.kind = Proposal::Kind::kFailed;
      return p;
    }
    lambda_ *= nu_;
    nu_ *= 2.0;
  }
  const Optimizer::Impl& im = ctx.im;
  double dx2 = 0.0;
  for (std::size_t i = 0; i < im.dx.size(); ++i) dx2 += im.dx[i] * im.dx[i] * im.damping_diag[i];
  p.predicted = lambda_ * dx2 + modelDecrease(im);
  return p;
}

bool LevenbergMarquardt::keeps(StepContext& /*ctx*/, const Trial& trial) {
  return trial.finite() && trial.predicted > 0 && trial.ratio() > 0;
}

// A kept step shrinks lambda by Nielsen's rule; a rejected one grows it, unless the model
// promises no meaningful decrease (converged) or max_rejections are used up.
Verdict LevenbergMarquardt::update(StepContext& ctx, const Trial& trial, bool kept) {
  const Optimizer::Options& o = ctx.options;
  Verdict v;
  if (kept) {
    kept_lambda_ = lambda_;
    const double a = 2.0 * trial.ratio() - 1.0;
    lambda_ = std::max(lambda_floor_, lambda_ * std::max(o.min_lambda_decrease, 1.0 - a * a * a));
    nu_ = 2.0;
    return v;
  }
  v = rejectedStep(ctx, trial, attempts_, "attempts");
  if (v.next == Verdict::Next::kRetry) {
    lambda_ *= nu_;
    nu_ *= 2.0;
  }
  return v;
}

StrategyReport LevenbergMarquardt::report() const {
  return {"levenberg-marquardt", "", {{"lambda", kept_lambda_}}};
}

}  // namespace graphslam::detail
