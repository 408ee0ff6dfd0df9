// SPDX-License-Identifier: MIT
#include "step_strategy.h"

#include <cmath>

#include "../timing.h"
#include "strategies.h"

namespace graphslam::detail {

LinearSolverResult solveStep(StepContext& ctx, double lambda) {
  const auto t0 = Clock::now();
  LinearSolverResult r = ctx.im.factorize(lambda);
  ++ctx.stats.factorizations;
  const auto t1 = Clock::now();
  ctx.stats.time.factorize += seconds(t0, t1);
  if (r.ok()) r = ctx.im.solve();
  ctx.stats.time.solve += seconds(t1, Clock::now());
  return r;
}

double norm(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

double modelDecrease(const Optimizer::Impl& im) {
  const auto& g = im.structure.gradient();
  double d = 0.0;
  for (std::size_t i = 0; i < im.dx.size(); ++i) d -= g[i] * im.dx[i];
  return d;
}

Proposal GaussNewton::propose(StepContext& ctx) {
  Proposal p;
  p.solver = solveStep(ctx, 0.0);
  if (!p.solver.ok()) {
    p.kind = Proposal::Kind::kFailed;
    return p;
  }
  p.predicted = modelDecrease(ctx.im);
  return p;
}

bool GaussNewton::keeps(StepContext& /*ctx*/, const Trial& trial) { return trial.finite(); }

Verdict GaussNewton::update(StepContext& /*ctx*/, const Trial& /*trial*/, bool kept) {
  Verdict v;
  if (!kept) {
    v.next = Verdict::Next::kFailed;
    v.message = "chi2 is not finite after the update";
  }
  return v;
}

StrategyReport GaussNewton::report() const { return {"gauss-newton", "", {}}; }

std::unique_ptr<StepStrategy> makeStepStrategy(Algorithm algorithm) {
  switch (algorithm) {
    case Algorithm::kGaussNewton:
      return std::make_unique<GaussNewton>();
    case Algorithm::kLevenbergMarquardt:
      return std::make_unique<LevenbergMarquardt>();
    case Algorithm::kDogleg:
      return std::make_unique<Dogleg>();
    case Algorithm::kGaussNewtonFallback:
      break;
  }
  return std::make_unique<GaussNewtonFallback>();
}

}  // namespace graphslam::detail
