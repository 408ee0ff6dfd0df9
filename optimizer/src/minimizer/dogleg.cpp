// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "strategies.h"

namespace graphslam::detail {

LinearSolverResult Dogleg::gaussNewtonStep(StepContext& ctx) {
  Optimizer::Impl& im = ctx.im;
  const int n = im.structure.dimension();
  im.saveDiagonal();
  im.damping_diag.assign(static_cast<std::size_t>(n), 1.0);
  double max_diag = 0.0;
  for (int i = 0; i < n; ++i) max_diag = std::max(max_diag, std::abs(im.saved_diag[i]));
  lambda_ = 0.0;
  for (int attempt = 1;; ++attempt) {
    LinearSolverResult r = solveStep(ctx, lambda_);
    const bool finite =
        std::all_of(im.dx.begin(), im.dx.end(), [](double x) { return std::isfinite(x); });
    if ((r.ok() && finite) || attempt > ctx.options.max_rejections) return r;
    lambda_ = lambda_ == 0.0 ? ctx.options.dogleg.initial_regularization * std::max(max_diag, 1e-12)
                             : lambda_ * 10.0;
  }
}

void Dogleg::begin(StepContext& /*ctx*/) {
  trials_ = 0;
  path_built_ = false;
}

// One factorisation per iteration (the first proposal); then points of the same dogleg path
// at a shrinking radius.
Proposal Dogleg::propose(StepContext& ctx) {
  Proposal p;
  if (!path_built_) {
    p.solver = gaussNewtonStep(ctx);
    if (!p.solver.ok()) {
      p.kind = Proposal::Kind::kFailed;
      return p;
    }
    if (!path_.build(ctx.im.structure, ctx.im.dx)) {
      p.kind = Proposal::Kind::kConverged;
      p.message = "the gradient vanishes";
      p.undamped = lambda_ == 0.0;
      return p;
    }
    path_built_ = true;
    if (radius_ <= 0.0) {
      radius_ = ctx.options.dogleg.initial_radius > 0.0 ? ctx.options.dogleg.initial_radius
                                                        : path_.gaussNewtonNorm();
    }
  }
  ++trials_;
  tried_radius_ = radius_;
  p.predicted = path_.point(radius_, ctx.im.dx);
  return p;
}

bool Dogleg::keeps(StepContext& /*ctx*/, const Trial& trial) {
  return trial.finite() && trial.ratio() > 0.0;
}

// The radius grows to expand_factor times a kept step whose decrease the model predicted
// within expand_agreement, and shrinks to shrink_factor times a step that was rejected or
// predicted poorly (Nocedal and Wright, Algorithm 4.1).
Verdict Dogleg::update(StepContext& ctx, const Trial& trial, bool kept) {
  const Optimizer::Options::Dogleg& o = ctx.options.dogleg;
  const double step = path_.norm(ctx.im.dx);
  Verdict v;
  v.undamped = lambda_ == 0.0;
  if (kept) {
    if (trial.ratio() > o.expand_agreement) {
      radius_ = std::max(radius_, o.expand_factor * step);
    } else if (trial.ratio() < o.shrink_agreement) {
      radius_ = o.shrink_factor * step;
    }
    return v;
  }
  radius_ = o.shrink_factor * step;
  Verdict rejected = rejectedStep(ctx, trial, trials_, "trials");
  rejected.undamped = v.undamped;
  return rejected;
}

StrategyReport Dogleg::report() const {
  char note[64];
  std::snprintf(note, sizeof note, "trust radius %.3e, %d %s", tried_radius_, trials_,
                trials_ == 1 ? "trial" : "trials");
  return {"dogleg",
          note,
          {{"trust_radius", tried_radius_}, {"trials", trials_}, {"regularization", lambda_}}};
}

}  // namespace graphslam::detail
