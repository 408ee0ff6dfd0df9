// SPDX-License-Identifier: MIT
#include "separator_cg.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <vector>

namespace graphslam::submap::detail {
namespace {

/// y = (S + lambda I) x from the upper triangle: an entry of an off-diagonal block acts
/// twice (S_ij x_j into y_i, S_ij x_i into y_j), a diagonal block's entries once (the
/// block is stored whole).
void multiply(const BlockUpperCsc& s, double lambda, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  y = lambda * x;
  for (int b = 0; b < s.num_blocks; ++b) {
    const int first = s.block_starts[b];
    for (int col = first; col < s.block_starts[b + 1]; ++col) {
      const int diagonal_block = s.diagonal[col] - (col - first);
      const double xc = x[col];
      double gathered = 0.0;
      int p = s.col_ptr[col];
      for (; p < diagonal_block; ++p) {
        const int row = s.row_idx[p];
        y[row] += s.values[p] * xc;
        gathered += s.values[p] * x[row];
      }
      for (; p < s.col_ptr[col + 1]; ++p) y[s.row_idx[p]] += s.values[p] * xc;
      y[col] += gathered;
    }
  }
}

/// The Cholesky factors of S + lambda I's diagonal blocks, and z = M^-1 r with them.
class BlockJacobi {
 public:
  /// False, with the block's index in `bad_block`, when a block is not positive definite.
  bool compute(const BlockUpperCsc& s, double lambda, int& bad_block) {
    factors_.resize(static_cast<std::size_t>(s.num_blocks));
    for (int b = 0; b < s.num_blocks; ++b) {
      const int first = s.block_starts[b], d = s.block_starts[b + 1] - first;
      Eigen::MatrixXd block(d, d);
      for (int c = 0; c < d; ++c) {
        const int top = s.diagonal[first + c] - c;  // (first, first + c)
        for (int r = 0; r < d; ++r) block(r, c) = s.values[top + r];
      }
      block.diagonal().array() += lambda;
      auto& llt = factors_[static_cast<std::size_t>(b)];
      llt.compute(block);
      if (llt.info() != Eigen::Success) {
        bad_block = b;
        return false;
      }
    }
    return true;
  }
  void apply(const BlockUpperCsc& s, const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
    for (int b = 0; b < s.num_blocks; ++b) {
      const int first = s.block_starts[b], d = s.block_starts[b + 1] - first;
      auto zb = z.segment(first, d);
      zb = r.segment(first, d);
      factors_[static_cast<std::size_t>(b)].solveInPlace(zb);  // no temporary per block
    }
  }

 private:
  std::vector<Eigen::LLT<Eigen::MatrixXd>> factors_;
};

}  // namespace

CgOutcome solveByConjugateGradients(const BlockUpperCsc& s, double lambda, const Eigen::VectorXd& b,
                                    Eigen::VectorXd& x, double tolerance, int max_iterations) {
  CgOutcome out;
  x.setZero(s.n);
  const double b_norm = b.norm();
  if (b_norm == 0.0) {
    out.ok = true;
    return out;
  }
  BlockJacobi preconditioner;
  int bad_block = -1;
  if (!preconditioner.compute(s, lambda, bad_block)) {
    out.message = "the diagonal block of separator columns " +
                  std::to_string(s.block_starts[bad_block]) + "-" +
                  std::to_string(s.block_starts[bad_block + 1] - 1) + " is not positive definite";
    return out;
  }
  Eigen::VectorXd r = b, z(s.n), p(s.n), q(s.n);
  preconditioner.apply(s, r, z);
  p = z;
  double rz = r.dot(z);
  for (out.iterations = 1; out.iterations <= max_iterations; ++out.iterations) {
    multiply(s, lambda, p, q);
    const double curvature = p.dot(q);
    if (!(curvature > 0.0)) {
      out.message = "conjugate gradients met a direction of non-positive curvature (" +
                    std::to_string(curvature) + "): the system is not positive definite";
      return out;
    }
    const double alpha = rz / curvature;
    x += alpha * p;
    r -= alpha * q;
    out.relative_residual = r.norm() / b_norm;
    if (out.relative_residual <= tolerance) {
      out.ok = true;
      return out;
    }
    preconditioner.apply(s, r, z);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  out.iterations = max_iterations;
  out.message = "conjugate gradients did not reach a relative residual of " +
                std::to_string(tolerance) + " in " + std::to_string(max_iterations) +
                " iterations (" + std::to_string(out.relative_residual) + ")";
  return out;
}

}  // namespace graphslam::submap::detail
