// SPDX-License-Identifier: MIT
// Chord steps (Options::ChordSteps): near convergence, or where the problem is close to
// linear, H hardly changes between steps, and conjugate gradients preconditioned with the
// last factorisation give a step almost as good as a new factorisation for a few solves.
// Private to graphslam::optimizer.
#pragma once

#include <vector>

#include "step_strategy.h"

namespace graphslam::detail {

class ChordSteps {
 public:
  /// When the last step calls for a chord step: computes it into im.dx and returns its
  /// conjugate-gradient iterations; 0 when there is none to try.
  int propose(StepContext& ctx);
  /// After every undamped iteration: whether its step came from a fresh factorisation
  /// (`factorized`), the objectives before and after, and the step's model decrease.
  void record(const StepContext& ctx, bool factorized, bool chord_taken, double old_cost,
              double new_cost, double model_decrease);
  /// No chord step before the next factorisation.
  void disable() { ready_ = false; }

 private:
  /// Iterations a chord step may take: a factorisation costs at least nnz(L)/n / 4
  /// solves (sum c_j^2 flops against 4 sum c_j, c_j the column counts of L); a chord
  /// step may spend half of that, at least one and at most `max_iterations`.
  [[nodiscard]] static int budget(const Optimizer::Impl& im, int max_iterations);

  bool ready_ = false;      // the solver holds the factorisation of a recent H
  bool converged_ = false;  // the last chord step's iterations reached their tolerance
  double last_decrease_ = 0.0;
  double last_rho_ = 0.0;  // actual / model decrease of the last step
  std::vector<double> scratch_[3];
};

}  // namespace graphslam::detail
