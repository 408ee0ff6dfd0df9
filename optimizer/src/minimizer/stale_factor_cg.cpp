// SPDX-License-Identifier: MIT
#include "stale_factor_cg.h"

#include <algorithm>
#include <cmath>

namespace graphslam::detail {

void hessianProduct(const LinearSystem& system, const std::vector<double>& x,
                    std::vector<double>& y) {
  const SparseStructure h = system.hessianStructure();
  const double* v = system.hessianValues().data();
  const int* diag = system.hessianDiagonalPositions().data();
  y.assign(x.size(), 0.0);
  const double* xv = x.data();
  double* yv = y.data();
  for (int c = 0; c < h.n; ++c) {
    const int first = h.lower ? diag[c] + 1 : h.col_ptr[c];
    const int last = h.lower ? h.col_ptr[c + 1] : diag[c];
    const double xc = xv[c];
    double yc = v[diag[c]] * xc;
    for (int k = first; k < last; ++k) {
      const int r = h.row_idx[k];
      yc += v[k] * xv[r];
      yv[r] += v[k] * xc;
    }
    yv[c] += yc;
  }
}

StaleFactorCgResult staleFactorCg(const LinearSystem& system, LinearSolver& solver,
                                  const std::vector<double>& rhs, std::vector<double>& dx,
                                  double relative_tolerance, double absolute_tolerance,
                                  int max_iterations, std::vector<double> scratch[3]) {
  const std::size_t n = rhs.size();
  // r = rhs - H dx; z = M^-1 r is dead once p is updated, and H p takes its place.
  std::vector<double>& r = scratch[0];
  std::vector<double>& p = scratch[1];
  std::vector<double>& z = scratch[2];
  std::vector<double>& hp = scratch[2];
  r = rhs;
  dx.assign(n, 0.0);
  p.assign(n, 0.0);
  z.resize(n);
  double rz_old = 0.0;
  double first_decrease = 0.0;
  for (int k = 1; k <= max_iterations; ++k) {
    if (!solver.solve(r.data(), z.data()).ok()) return {0, false};
    double rz = 0.0;
    for (std::size_t i = 0; i < n; ++i) rz += r[i] * z[i];
    const double beta = k == 1 ? 0.0 : rz / rz_old;
    for (std::size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    hessianProduct(system, p, hp);
    double php = 0.0;
    for (std::size_t i = 0; i < n; ++i) php += p[i] * hp[i];
    if (!(php > 0.0 && rz > 0.0 && std::isfinite(php) && std::isfinite(rz))) {
      return {k - 1, rz == 0.0 && k > 1};  // at the solution (or broken down)
    }
    const double alpha = rz / php;
    for (std::size_t i = 0; i < n; ++i) {
      dx[i] += alpha * p[i];
      r[i] -= alpha * hp[i];
    }
    const double decrease = alpha * rz;
    if (k == 1) first_decrease = decrease;
    if (decrease <= std::max(relative_tolerance * first_decrease, absolute_tolerance)) {
      return {k, true};
    }
    rz_old = rz;
  }
  return {max_iterations, false};
}

}  // namespace graphslam::detail
