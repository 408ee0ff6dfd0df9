// SPDX-License-Identifier: MIT
#include "riemannian.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace graphslam::certify {

namespace {

/// A d x d matrix (d <= 3) without heap allocation.
using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;

double inner(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return a.cwiseProduct(b).sum(); }

/// The functions of one iterate: F, the Euclidean gradient 2 Q X, sym(G_i X_i^T) and the
/// Riemannian gradient.
struct Iterate {
  Eigen::MatrixXd x;
  double f = 0.0;
  Eigen::MatrixXd egrad;
  Eigen::MatrixXd blocks;
  Eigen::MatrixXd grad;
  double grad_norm = 0.0;

  Iterate(const Problem& problem, Eigen::MatrixXd point) : x(std::move(point)) {
    const int d = problem.dimension();
    egrad = 2.0 * problem.objectiveAndProduct(x, &f);
    blocks = symmetricBlockProducts(egrad, x, d);
    grad = subtractBlockProducts(egrad, blocks, x, d);
    grad_norm = grad.norm();
  }
};

/// The Riemannian Hessian at an iterate and the preconditioner (tangent vectors in and out).
struct Operators {
  const Problem& problem;
  const ShiftedFactor& factor;
  const Iterate& it;

  [[nodiscard]] Eigen::MatrixXd hessian(const Eigen::MatrixXd& v) const {
    const int d = problem.dimension();
    const Eigen::MatrixXd e = subtractBlockProducts(2.0 * problem.applyQ(v), it.blocks, v, d);
    return projectTangent(it.x, e, d);
  }
  [[nodiscard]] Eigen::MatrixXd precondition(const Eigen::MatrixXd& v) const {
    return projectTangent(it.x, 0.5 * factor.solve(v), problem.dimension());
  }
};

/// The approximate minimiser of the model <g, e> + <H e, e> / 2 within the trust region
/// |e|_P <= radius (Steihaug-Toint truncated CG, in the norm of the preconditioner).
struct InnerResult {
  Eigen::MatrixXd eta;
  Eigen::MatrixXd heta;
  int iterations = 0;
  bool boundary = false;
};

InnerResult truncatedCG(const Operators& ops, double radius, int max_iterations, double floor) {
  const Eigen::MatrixXd& grad = ops.it.grad;
  InnerResult out{Eigen::MatrixXd::Zero(grad.rows(), grad.cols()),
                  Eigen::MatrixXd::Zero(grad.rows(), grad.cols()), 0, false};
  Eigen::MatrixXd r = grad;
  Eigen::MatrixXd z = ops.precondition(r);
  double z_r = inner(z, r);
  double d_pd = z_r, e_pd = 0.0, e_pe = 0.0;
  Eigen::MatrixXd dir = -z;
  const double r0 = r.norm();
  // Superlinear near the optimum, but no finer than the outer loop's tolerance needs.
  const double target = std::max(r0 * std::min(r0, 0.1), floor);
  const double r2 = radius * radius;
  for (int j = 0; j < max_iterations; ++j) {
    out.iterations = j + 1;
    const Eigen::MatrixXd hd = ops.hessian(dir);
    const double d_hd = inner(dir, hd);
    const double alpha = z_r / d_hd;
    const double e_pe_new = e_pe + 2.0 * alpha * e_pd + alpha * alpha * d_pd;
    if (d_hd <= 0.0 || e_pe_new >= r2) {  // negative curvature or outside: to the boundary
      const double tau = (-e_pd + std::sqrt(e_pd * e_pd + d_pd * (r2 - e_pe))) / d_pd;
      out.eta += tau * dir;
      out.heta += tau * hd;
      out.boundary = true;
      return out;
    }
    e_pe = e_pe_new;
    out.eta += alpha * dir;
    out.heta += alpha * hd;
    r += alpha * hd;
    if (r.norm() <= target) return out;
    z = ops.precondition(r);
    const double z_r_old = z_r;
    z_r = inner(z, r);
    const double beta = z_r / z_r_old;
    dir = -z + beta * dir;
    e_pd = beta * (e_pd + alpha * d_pd);
    d_pd = z_r + beta * beta * d_pd;
  }
  return out;
}

}  // namespace

// Both loop over the columns outermost: X is column-major, so each pass reads a column of
// every block contiguously (Eigen's products of d x r blocks allocate per block).
Eigen::MatrixXd symmetricBlockProducts(const Eigen::MatrixXd& a, const Eigen::MatrixXd& x, int d) {
  const Eigen::Index rows = x.rows();
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(d, rows);  // A_i X_i^T, block i in columns d i..
  for (Eigen::Index k = 0; k < x.cols(); ++k) {
    const double* ak = a.col(k).data();
    const double* xk = x.col(k).data();
    for (Eigen::Index base = 0; base < rows; base += d) {
      for (int r = 0; r < d; ++r) {
        for (int c = 0; c < d; ++c) p(r, base + c) += ak[base + r] * xk[base + c];
      }
    }
  }
  Eigen::MatrixXd out(d, rows);
  for (Eigen::Index base = 0; base < rows; base += d) {
    for (int r = 0; r < d; ++r) {
      for (int c = 0; c < d; ++c) out(r, base + c) = 0.5 * (p(r, base + c) + p(c, base + r));
    }
  }
  return out;
}

Eigen::MatrixXd subtractBlockProducts(const Eigen::MatrixXd& z, const Eigen::MatrixXd& b,
                                      const Eigen::MatrixXd& x, int d) {
  const Eigen::Index rows = x.rows();
  Eigen::MatrixXd out = z;
  for (Eigen::Index k = 0; k < x.cols(); ++k) {
    double* ok = out.col(k).data();
    const double* xk = x.col(k).data();
    for (Eigen::Index base = 0; base < rows; base += d) {
      for (int r = 0; r < d; ++r) {
        double sum = 0.0;
        for (int c = 0; c < d; ++c) sum += b(r, base + c) * xk[base + c];
        ok[base + r] -= sum;
      }
    }
  }
  return out;
}

Eigen::MatrixXd projectTangent(const Eigen::MatrixXd& x, const Eigen::MatrixXd& z, int d) {
  return subtractBlockProducts(z, symmetricBlockProducts(z, x, d), x, d);
}

Eigen::MatrixXd retract(const Eigen::MatrixXd& x, const Eigen::MatrixXd& v, int d) {
  const Eigen::Index n = x.rows() / d;
  Eigen::MatrixXd out = x + v;
  Eigen::SelfAdjointEigenSolver<Small> eig;
  for (Eigen::Index i = 0; i < n; ++i) {
    auto block = out.middleRows(d * i, d);
    const Small g = block * block.transpose();
    eig.compute(g);  // (A A^T)^(-1/2) A is A's nearest matrix with orthonormal rows
    const Small inv_sqrt = eig.eigenvectors() *
                           eig.eigenvalues().cwiseSqrt().cwiseInverse().asDiagonal() *
                           eig.eigenvectors().transpose();
    block = (inv_sqrt * block).eval();
  }
  return out;
}

TrustRegionResult trustRegion(const Problem& problem, const Eigen::MatrixXd& x0,
                              const ShiftedFactor& preconditioner, const Options& options) {
  const int d = problem.dimension();
  const double scale = problem.scale();
  const double gradient_tolerance = options.gradient_tolerance * scale;
  Iterate it(problem, x0);
  TrustRegionResult out;
  double radius = -1.0;
  for (int k = 0; k < options.max_iterations && it.grad_norm > gradient_tolerance; ++k) {
    const Operators ops{problem, preconditioner, it};
    if (radius < 0.0) radius = std::sqrt(std::max(inner(ops.precondition(it.grad), it.grad), 0.0));
    const InnerResult step =
        truncatedCG(ops, radius, options.max_inner_iterations, 0.5 * gradient_tolerance);
    out.inner_iterations += step.iterations;
    ++out.iterations;
    Iterate trial(problem, retract(it.x, step.eta, d));
    const double model = -(inner(it.grad, step.eta) + 0.5 * inner(step.heta, step.eta));
    const double reg = std::max(1.0, std::abs(it.f)) * std::numeric_limits<double>::epsilon() * 1e3;
    const double rho = (it.f - trial.f + reg) / (model + reg);
    if (rho < 0.25) {
      radius *= 0.25;
    } else if (rho > 0.75 && step.boundary) {
      radius *= 2.0;
    }
    if (rho > 0.1) {
      const double decrease = it.f - trial.f;
      it = std::move(trial);
      if (decrease <= options.relative_decrease_tolerance * std::abs(it.f)) break;
    }
    if (radius < 1e-14 * std::sqrt(static_cast<double>(x0.rows()))) break;
  }
  out.objective = it.f;
  out.gradient_norm = it.grad_norm;
  out.x = std::move(it.x);
  return out;
}

}  // namespace graphslam::certify
