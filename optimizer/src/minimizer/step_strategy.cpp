// SPDX-License-Identifier: MIT
#include "step_strategy.h"

#include <cmath>

#include "../timing.h"
#include "strategies.h"

namespace graphslam::detail {

LinearSolverResult solveStep(StepContext& ctx, double lambda) {
  const auto t0 = Clock::now();
  LinearSolverResult r = ctx.im.factorize(lambda);
  const auto t1 = Clock::now();
  ctx.stats.time.factorize += seconds(t0, t1);
  if (r.ok()) r = ctx.im.solve();
  ctx.stats.time.solve += seconds(t1, Clock::now());
  return r;
}

double evaluateStep(StepContext& ctx) {
  const auto t0 = Clock::now();
  ctx.im.applyUpdate();
  const double cost = ctx.im.evalChi2(ctx.graph);
  ctx.stats.time.solve += seconds(t0, Clock::now());
  return cost;
}

double rejectStep(StepContext& ctx) {
  ctx.im.undoUpdate();
  return ctx.im.evalChi2(ctx.graph);
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

StepResult GaussNewton::step(StepContext& ctx) {
  StepResult result;
  result.solver = solveStep(ctx, 0.0);
  if (!result.solver.ok()) {
    result.kind = StepResult::Kind::kFailed;
    result.cost = ctx.cost;
    return result;
  }
  result.cost = evaluateStep(ctx);
  if (!std::isfinite(result.cost)) {
    result.cost = rejectStep(ctx);
    result.kind = StepResult::Kind::kFailed;
    result.message = "chi2 is not finite after the update";
    return result;
  }
  result.step_norm = norm(ctx.im.dx);
  return result;
}

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
