// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/robust_kernel.h"

namespace graphslam::robust {

/// Default width of the kernels whose width is a Mahalanobis length (all but dcs):
/// sqrt of the 95 % quantile of chi2 with 3 degrees of freedom, sqrt(7.8147) = 2.7955. An
/// SE(2) edge (3-dimensional error) with Gaussian noise as its information says then stays
/// in the kernel's quadratic part 95 % of the time, so a correct graph is optimised almost
/// as plain least squares. (g2o's default delta is 1, i.e. 1 sigma in Mahalanobis terms,
/// which down-weights a third of correct 3-DOF edges.) For edges of another dimension d
/// give sqrt(chi2_0.95(d)) explicitly: d = 1: 1.96, 2: 2.448, 6: 3.548.
constexpr double kDefaultWidth = 2.795483482915107;
/// Default phi of dcs (in chi2 units): 1, the value of Agarwal et al. and of g2o.
constexpr double kDefaultDcsPhi = 1.0;

/// Registers the robust kernels huber, pseudo-huber, cauchy, geman-mcclure, welsch, fair,
/// tukey, saturated, tls (truncated least squares) and dcs (formulas in kernels.h).
void registerKernels(KernelRegistry& registry);

}  // namespace graphslam::robust
