// SPDX-License-Identifier: MIT
// Closed-form rho, rho', rho'' of the robust kernels (formulas in kernels.h).
#include "graphslam/robust/kernels.h"

#include <cmath>
#include <limits>

namespace graphslam::robust {

namespace {

/// rho = s: the quadratic (inlier) branch every kernel starts with.
void quadratic(double s, double rho[3]) {
  rho[0] = s;
  rho[1] = 1.0;
  rho[2] = 0.0;
}

/// rho = min(s, c^2).
void truncated(double s, double c2, double rho[3]) {
  if (s <= c2) {
    quadratic(s, rho);
  } else {
    rho[0] = c2;
    rho[1] = 0.0;
    rho[2] = 0.0;
  }
}

}  // namespace

void HuberKernel::robustify(double s, double rho[3]) const {
  const double c = width();
  if (s <= c * c) {
    quadratic(s, rho);
    return;
  }
  const double r = std::sqrt(s);
  rho[0] = 2.0 * c * r - c * c;
  rho[1] = c / r;
  rho[2] = -0.5 * rho[1] / s;  // d/ds (c s^-1/2) = -c s^-3/2 / 2
}

void PseudoHuberKernel::robustify(double s, double rho[3]) const {
  const double c2 = width() * width();
  const double q = 1.0 + s / c2;
  const double root = std::sqrt(q);
  rho[0] = 2.0 * s / (root + 1.0);  // 2 c^2 (root - 1) without the cancellation for small s
  rho[1] = 1.0 / root;
  rho[2] = -0.5 * rho[1] / (q * c2);
}

void CauchyKernel::robustify(double s, double rho[3]) const {
  const double c2 = width() * width();
  const double q = 1.0 + s / c2;
  rho[0] = c2 * std::log1p(s / c2);
  rho[1] = 1.0 / q;
  rho[2] = -rho[1] * rho[1] / c2;
}

void GemanMcClureKernel::robustify(double s, double rho[3]) const {
  const double c2 = width() * width();
  const double q = c2 / (c2 + s);  // exactly 1 at s = 0
  rho[0] = q * s;
  rho[1] = q * q;
  rho[2] = -2.0 * rho[1] / (c2 + s);
}

void WelschKernel::robustify(double s, double rho[3]) const {
  const double c2 = width() * width();
  const double w = std::exp(-s / c2);
  rho[0] = -c2 * std::expm1(-s / c2);  // c^2 (1 - exp(-s/c^2)), exact for small s
  rho[1] = w;
  rho[2] = -w / c2;
}

void FairKernel::robustify(double s, double rho[3]) const {
  const double c = width();
  const double r = std::sqrt(s);
  const double a = r / c;
  rho[0] = 2.0 * c * c * (a - std::log1p(a));
  rho[1] = 1.0 / (1.0 + a);
  // d/ds (1 + a)^-1 = -(1 + a)^-2 da/ds, da/ds = 1 / (2 c sqrt(s)).
  rho[2] = s > 0.0 ? -rho[1] * rho[1] / (2.0 * c * r) : -std::numeric_limits<double>::infinity();
}

void TukeyKernel::robustify(double s, double rho[3]) const {
  const double c2 = width() * width();
  if (s <= c2) {
    const double u = 1.0 - s / c2;
    rho[0] = c2 * (1.0 - u * u * u) / 3.0;
    rho[1] = u * u;
    rho[2] = -2.0 * u / c2;
  } else {
    rho[0] = c2 / 3.0;
    rho[1] = 0.0;
    rho[2] = 0.0;
  }
}

void SaturatedKernel::robustify(double s, double rho[3]) const {
  truncated(s, width() * width(), rho);
}

void TruncatedLeastSquaresKernel::robustify(double s, double rho[3]) const {
  truncated(s, width() * width(), rho);
}

void DcsKernel::robustify(double s, double rho[3]) const {
  const double phi = width();
  if (s <= phi) {
    quadratic(s, rho);
    return;
  }
  const double inv = 1.0 / (phi + s);
  const double scale = 2.0 * phi * inv;
  rho[0] = phi * (3.0 * s - phi) * inv;
  rho[1] = scale * scale;
  rho[2] = -2.0 * rho[1] * inv;  // d/ds 4 phi^2 (phi + s)^-2
}

}  // namespace graphslam::robust
