// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/robust_kernel.h"

namespace graphslam::robust {

// The robust kernels of g2o, GTSAM and Ceres, in g2o's convention: the argument is the
// squared error s = e^T Omega e, rho(s) ~ s for small s (rho(0) = 0, rho'(0) = 1), and the
// width c (g2o's delta) is a Mahalanobis length: the kernel bends away from s around
// s = c^2. robustify() gives rho, rho' and rho'' in closed form (rho' is the weight the
// optimizer puts on the edge's information). Exceptions to the width convention are said
// at the kernel (DCS). All kernels are immutable.

/// Huber: rho = s for s <= c^2, else 2 c sqrt(s) - c^2. Weight min(1, c / sqrt(s)).
class HuberKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

/// Pseudo-Huber (smooth Huber): rho = 2 c^2 (sqrt(1 + s / c^2) - 1), rho' = (1 + s/c^2)^-1/2.
class PseudoHuberKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

/// Cauchy (Lorentzian): rho = c^2 log(1 + s / c^2), rho' = 1 / (1 + s / c^2).
class CauchyKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

/// Geman-McClure: rho = c^2 s / (c^2 + s), rho' = c^4 / (c^2 + s)^2 (bounded by c^2).
/// g2o's RobustKernelGemanMcClure writes delta where this writes c^2 (its delta is in chi2
/// units); GTSAM's GemanMcClure is this with c^2 (and its usual factor 1/2).
class GemanMcClureKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

/// Welsch (Leclerc): rho = c^2 (1 - exp(-s / c^2)), rho' = exp(-s / c^2).
class WelschKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

/// Fair: with a = sqrt(s) / c, rho = 2 c^2 (a - log(1 + a)), rho' = 1 / (1 + a),
/// rho'' = -1 / (2 c sqrt(s) (1 + a)^2) (-infinity at s = 0; g2o's rho'' of this kernel is
/// not the derivative of its rho', this one is).
class FairKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

/// Tukey's biweight: rho = c^2 (1 - (1 - s/c^2)^3) / 3 for s <= c^2, else c^2 / 3;
/// rho' = (1 - s/c^2)^2 inside, 0 outside.
class TukeyKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

/// Saturated (g2o): rho = min(s, c^2); weight 1 inside, 0 outside.
class SaturatedKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

/// Truncated least squares (the cost of GNC, Yang et al. 2020): rho = min(s, c^2). The same
/// function as SaturatedKernel, registered under the name users of GNC/TEASER know.
class TruncatedLeastSquaresKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

/// Dynamic covariance scaling (Agarwal et al. 2013): the information of an edge with
/// s > phi is scaled by w = (2 phi / (phi + s))^2, i.e. rho' = min(1, w). Here phi = width
/// itself, in chi2 units (as g2o's RobustKernelDCS, whose delta is phi; the paper's
/// phi = 1 is the registered default). rho is w's integral, continuous with its derivative
/// at s = phi: rho = s for s <= phi, else phi (3 s - phi) / (phi + s) (bounded by 3 phi),
/// rho'' = -8 phi^2 / (phi + s)^3. g2o returns s w as rho and that product's derivative as
/// rho', which is negative for s > phi; GTSAM's DCS keeps the weight w as here.
class DcsKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  void robustify(double s, double rho[3]) const override;
};

}  // namespace graphslam::robust
