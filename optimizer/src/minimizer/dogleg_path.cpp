// SPDX-License-Identifier: MIT
#include "dogleg_path.h"

#include <algorithm>
#include <cmath>

#include "stale_factor_cg.h"

namespace graphslam::detail {

bool DoglegPath::build(const LinearSystem& system, const std::vector<double>& gn_step) {
  const std::size_t n = gn_step.size();
  const auto& g = system.gradient();
  const auto& h = system.hessianValues();
  const auto& diag = system.hessianDiagonalPositions();
  gn_ = gn_step;
  scale_.resize(n);
  cauchy_.resize(n);
  double gdg = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    scale_[i] = std::clamp(h[diag[i]], 1e-6, 1e32);
    cauchy_[i] = -g[i] / scale_[i];
    gdg -= g[i] * cauchy_[i];
  }
  hessianProduct(system, cauchy_, scratch_);
  double chc = 0.0;
  for (std::size_t i = 0; i < n; ++i) chc += cauchy_[i] * scratch_[i];
  const double a = gdg / chc;
  if (!(a > 0.0) || !std::isfinite(a)) return false;
  for (double& c : cauchy_) c *= a;
  chc_ = chc * a * a;
  // s^T H s = -g^T s and c^T H s = -g^T c when H s = -g.
  cc_ = cs_ = ss_ = gc_ = gs_ = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = scale_[i];
    cc_ += d * cauchy_[i] * cauchy_[i];
    cs_ += d * cauchy_[i] * gn_[i];
    ss_ += d * gn_[i] * gn_[i];
    gc_ += g[i] * cauchy_[i];
    gs_ += g[i] * gn_[i];
  }
  gn_norm_ = std::sqrt(ss_);
  c_norm_ = std::sqrt(cc_);
  return true;
}

double DoglegPath::point(double delta, std::vector<double>& dx) const {
  const std::size_t n = gn_.size();
  dx.resize(n);
  if (delta >= gn_norm_) {
    dx = gn_;
    return -gs_;
  }
  if (delta <= c_norm_) {
    const double u = delta / c_norm_;
    for (std::size_t i = 0; i < n; ++i) dx[i] = u * cauchy_[i];
    return -2.0 * u * gc_ - u * u * chc_;
  }
  // (1 - t) c + t s at D-norm delta: |c + t (s - c)|^2 = delta^2.
  const double qa = cc_ - 2.0 * cs_ + ss_;
  const double qb = 2.0 * (cs_ - cc_);
  const double qc = cc_ - delta * delta;
  const double t = (-qb + std::sqrt(std::max(0.0, qb * qb - 4.0 * qa * qc))) / (2.0 * qa);
  for (std::size_t i = 0; i < n; ++i) dx[i] = (1.0 - t) * cauchy_[i] + t * gn_[i];
  const double gp = (1.0 - t) * gc_ + t * gs_;
  const double php = (1.0 - t) * (1.0 - t) * chc_ - 2.0 * t * (1.0 - t) * gc_ - t * t * gs_;
  return -2.0 * gp - php;
}

double DoglegPath::norm(const std::vector<double>& v) const {
  double s = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) s += scale_[i] * v[i] * v[i];
  return std::sqrt(s);
}

}  // namespace graphslam::detail
