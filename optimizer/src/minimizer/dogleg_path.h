// SPDX-License-Identifier: MIT
// Powell's dogleg path of a linearised system: from the origin along the steepest descent
// of chi2, scaled by D = diag(H), to its minimum (the Cauchy point), then straight to the
// Gauss-Newton step. Shared by the dogleg strategy and the default algorithm's first step.
// Private to graphslam::core.
#pragma once

#include <vector>

#include "graphslam/optimizer/linear_system.h"

namespace graphslam::detail {

class DoglegPath {
 public:
  /// Builds the path from the assembled system (g, H) and the Gauss-Newton step `gn_step`
  /// (H s = -g, or a damped approximation of it). Returns false when the path is undefined
  /// (the gradient is zero, or H is not positive along it).
  bool build(const LinearSystem& system, const std::vector<double>& gn_step);

  /// D-norm of the Gauss-Newton step and of the Cauchy point.
  [[nodiscard]] double gaussNewtonNorm() const { return gn_norm_; }
  [[nodiscard]] double cauchyNorm() const { return c_norm_; }

  /// The point of the path at D-norm `delta` (the Gauss-Newton step itself at or beyond
  /// its norm), into `dx`; returns the quadratic model's decrease of chi2 there,
  /// -2 g^T p - p^T H p.
  double point(double delta, std::vector<double>& dx) const;
  /// The model's decrease of chi2 by the Gauss-Newton step, -g^T s (exact when H s = -g).
  [[nodiscard]] double gaussNewtonDecrease() const { return -gs_; }
  /// D-norm of a vector.
  [[nodiscard]] double norm(const std::vector<double>& v) const;

 private:
  std::vector<double> scale_;   // D's entries, diag(H) clamped to [1e-6, 1e32]
  std::vector<double> cauchy_;  // c = -a D^-1 g, a minimising the model along D^-1 g
  std::vector<double> gn_;      // s
  std::vector<double> scratch_;
  // Scalars of the path: D-norms, g^T c, g^T s, c^T H c, and the D-products.
  double cc_ = 0.0, cs_ = 0.0, ss_ = 0.0, gc_ = 0.0, gs_ = 0.0, chc_ = 0.0;
  double gn_norm_ = 0.0, c_norm_ = 0.0;
};

}  // namespace graphslam::detail
