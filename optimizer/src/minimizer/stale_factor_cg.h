// SPDX-License-Identifier: MIT
// Conjugate gradients on the normal equations H dx = rhs, preconditioned with a
// factorisation the solver holds of an earlier H (the chord steps of the default
// algorithm). Private to graphslam::core.
#pragma once

#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/optimizer/linear_system.h"

namespace graphslam::detail {

/// y = H x, H the system's assembled Hessian (its stored triangle; the other triangles of
/// the diagonal blocks, also stored, are skipped: in every column they are the entries
/// past the diagonal of an upper H, before it in a lower one).
void hessianProduct(const LinearSystem& system, const std::vector<double>& x,
                    std::vector<double>& y);

struct StaleFactorCgResult {
  int iterations = 0;      ///< 0: a solve with the preconditioner failed
  bool converged = false;  ///< the tolerance was reached (not the iteration budget)
};

/// Solves H dx = rhs by conjugate gradients preconditioned with `solver`'s last
/// factorisation. The first iteration is the plain preconditioned step scaled to the
/// minimum of the quadratic model along it. Iteration k lowers the model's chi2 by
/// alpha_k r_k^T M^-1 r_k; the iterations stop when that is below
/// max(relative_tolerance times the first one's, absolute_tolerance) (the decreases shrink
/// geometrically), or after max_iterations. `scratch` holds two vectors between calls.
StaleFactorCgResult staleFactorCg(const LinearSystem& system, LinearSolver& solver,
                                  const std::vector<double>& rhs, std::vector<double>& dx,
                                  double relative_tolerance, double absolute_tolerance,
                                  int max_iterations, std::vector<double> scratch[3]);

}  // namespace graphslam::detail
