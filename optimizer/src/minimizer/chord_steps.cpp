// SPDX-License-Identifier: MIT
#include "chord_steps.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "../timing.h"
#include "stale_factor_cg.h"

namespace graphslam::detail {

int ChordSteps::budget(const Optimizer::Impl& im, int max_iterations) {
  const double n = std::max(1, im.structure.dimension());
  const double per_column = static_cast<double>(im.solver->factorNonZeros()) / n;
  return std::clamp(static_cast<int>(per_column / 6.0), 1, max_iterations);
}

// A chord step follows a step that lowered the objective by very little, or one whose
// decrease agreed closely with its model when the factor is dense enough for a few
// preconditioned iterations to be worth a factorisation.
int ChordSteps::propose(StepContext& ctx) {
  if (!ready_) return 0;
  const Optimizer::Options::ChordSteps& o = ctx.options.chord_steps;
  const int iterations = budget(ctx.im, o.max_iterations);
  if (!(last_decrease_ < o.trigger * ctx.cost ||
        (std::abs(1.0 - last_rho_) < o.agreement && iterations >= o.agreement_iterations))) {
    return 0;
  }
  const auto t0 = Clock::now();
  const StaleFactorCgResult cg = staleFactorCg(
      ctx.im.structure, *ctx.im.solver, ctx.im.rhs, ctx.im.dx, o.relative_tolerance,
      o.absolute_tolerance * ctx.options.function_tolerance * ctx.cost, iterations, scratch_);
  converged_ = cg.converged;
  ctx.stats.time.solve += seconds(t0, Clock::now());
  return cg.iterations;
}

// The solver holds a usable factorisation after a step from a fresh one, or after a chord
// step whose iterations reached their tolerance (one that did not is followed by a
// factorisation); never after a step that raised the objective.
void ChordSteps::record(const StepContext& ctx, bool factorized, bool chord_taken, double old_cost,
                        double new_cost, double model_decrease) {
  ready_ = !ctx.im.jacobian_form && (factorized || (chord_taken && converged_)) &&
           ctx.options.function_tolerance > 0 && new_cost <= old_cost;
  const double decrease = old_cost - new_cost;
  last_rho_ = model_decrease > 0 ? decrease / model_decrease : 0.0;
  // After a chord step only its agreement with the model may call for another.
  last_decrease_ = chord_taken ? std::numeric_limits<double>::infinity() : decrease;
}

}  // namespace graphslam::detail
