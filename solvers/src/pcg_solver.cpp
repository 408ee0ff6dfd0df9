// SPDX-License-Identifier: MIT
// Block-Jacobi preconditioned conjugate gradients on H; on H = H_s (x) I_d (isotropic
// linear SLAM) d independent conjugate-gradient runs on H_s that share its products.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "block_kernels.h"
#include "common.h"
#include "graphslam/solvers/register.h"

namespace graphslam::solvers {

namespace {

/// A symmetric matrix kept as all its rows (both triangles): CSR, and for every entry the
/// position of its value in H's array.
struct SymmetricRows {
  int n = 0;
  std::vector<int> row_ptr, col, source, diagonal;  // diagonal[i]: H position of (i, i)
  std::vector<double> values;

  /// The rows of H (granularity 1) or of H_s (granularity d: block (r, c) of H is entry
  /// (r, c), its value H's entry at the block's (0, 0), every d-th entry of column c*d),
  /// from H's stored triangle (complete diagonal blocks; the other triangle is ignored).
  /// The first column of H that does not store complete blocks, or -1.
  int build(const SparseStructure& s, int granularity) {
    const int g = granularity;
    n = s.n / g;
    row_ptr.assign(static_cast<std::size_t>(n) + 1, 0);
    diagonal.assign(static_cast<std::size_t>(n), -1);
    // Pass 1: count the entries of every row; pass 2: place them.
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<int> next;
      if (pass == 1) {
        for (int i = 0; i < n; ++i) row_ptr[i + 1] += row_ptr[i];
        next.assign(row_ptr.begin(), row_ptr.end() - 1);
        col.resize(static_cast<std::size_t>(row_ptr[n]));
        source.resize(col.size());
      }
      for (int c = 0; c < n; ++c) {
        const int column = c * g;
        for (int p = s.col_ptr[column]; p < s.col_ptr[column + 1]; p += g) {
          const int row = s.row_idx[p];
          const int r = row / g;
          if (row != r * g) return column;
          if (s.lower ? r < c : r > c) continue;
          if (pass == 0) {
            ++row_ptr[r + 1];
            if (r != c) ++row_ptr[c + 1];
            continue;
          }
          col[next[r]] = c;
          source[next[r]++] = p;
          if (r != c) {
            col[next[c]] = r;
            source[next[c]++] = p;
          } else {
            diagonal[c] = p;
          }
        }
      }
    }
    for (int i = 0; i < n; ++i) {
      if (diagonal[i] < 0) return i * g;
    }
    return -1;
  }

  /// The values from H's; returns their sum.
  double fill(const double* h) {
    values.resize(source.size());
    double sum = 0.0;
    for (std::size_t k = 0; k < source.size(); ++k) sum += values[k] = h[source[k]];
    return sum;
  }
};

/// Conjugate gradients with a block-Jacobi preconditioner (the inverse of every vertex's
/// diagonal block) to a relative residual of kTolerance. When every block of H is a
/// multiple of the identity (H = H_s (x) I_d), the iteration runs on H_s with the d
/// coordinates of H's right-hand side as d right-hand sides, each its own conjugate-
/// gradient run (their step lengths apart), the product with H_s shared: H_s has 1/d^2 of
/// H's entries and the block-Jacobi preconditioner is then H_s's diagonal.
class PcgSolver final : public LinearSolver {
 public:
  static constexpr double kTolerance = 1e-14;

  std::string name() const override { return "pcg"; }
  Ordering ordering() const override { return Ordering::kNatural; }

  LinearSolverResult analyze(const SparseStructure& s) override {
    structure_ = s;
    d_ = s.num_blocks > 0 ? s.block_starts[1] - s.block_starts[0] : 1;
    uniform_ = true;
    for (int b = 0; b < s.num_blocks && uniform_; ++b) {
      uniform_ = s.block_starts[b + 1] - s.block_starts[b] == d_;
    }
    scalar_ready_ = full_ready_ = false;
    isotropic_ = false;
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* values) override {
    const SparseStructure& s = structure_;
    isotropic_ = uniform_ && d_ > 1 && detail::firstNonIsotropicColumn(s, values) < 0;
    if (isotropic_) {
      if (!scalar_ready_) {
        const int bad = scalar_.build(s, d_);
        if (bad >= 0) return incomplete(bad);
        scalar_ready_ = true;
      }
      // The values, and 1^T H_s 1 (all of them) on the way: the coarse correction is used
      // only when that sum is clearly above its rounding error (the rows of a Laplacian
      // sum to zero: what is left are the priors).
      const double total = scalar_.fill(values);
      inverse_.resize(static_cast<std::size_t>(scalar_.n));
      double largest = 0.0, trace = 0.0;
      for (int i = 0; i < scalar_.n; ++i) {
        const double v = values[scalar_.diagonal[i]];
        largest = std::max(largest, v);
        trace += v;
      }
      const double tol = detail::zeroTolerance(1, largest);
      for (int i = 0; i < scalar_.n; ++i) {
        const double v = values[scalar_.diagonal[i]];
        if (!(v > tol)) return notPositive(v < -tol, i * d_);
        inverse_[i] = 1.0 / v;
      }
      const double rounding = 64.0 * Eigen::NumTraits<double>::epsilon() * trace;
      coarse_ = total > rounding ? 1.0 / total : 0.0;
      return LinearSolverResult::success();
    }
    if (!full_ready_) {
      const int bad = full_.build(s, 1);
      if (bad >= 0) return incomplete(bad);
      full_ready_ = true;
    }
    full_.fill(values);
    // Every diagonal block's inverse, row-major, one after the other.
    inverse_.clear();
    for (int b = 0; b < s.num_blocks; ++b) {
      const int c0 = s.block_starts[b];
      const int d = s.block_starts[b + 1] - c0;
      Eigen::MatrixXd block(d, d);
      for (int j = 0; j < d; ++j) {
        for (int k = s.col_ptr[c0 + j]; k < s.col_ptr[c0 + j + 1]; ++k) {
          const int r = s.row_idx[k];
          if (r < c0 || r >= c0 + d) continue;
          const bool stored = s.lower ? r >= c0 + j : r <= c0 + j;
          if (!stored) continue;
          block(r - c0, j) = values[k];
          block(j, r - c0) = values[k];
        }
      }
      Eigen::LDLT<Eigen::MatrixXd> ldlt(block);
      const Eigen::VectorXd dvec = ldlt.vectorD();
      const double tol = detail::zeroTolerance(d, block.cwiseAbs().maxCoeff());
      if (ldlt.info() != Eigen::Success || !(dvec.minCoeff() > tol)) {
        return notPositive(dvec.minCoeff() < -tol, c0);
      }
      const Eigen::MatrixXd inv = ldlt.solve(Eigen::MatrixXd::Identity(d, d));
      for (int i = 0; i < d; ++i) {
        for (int j = 0; j < d; ++j) inverse_.push_back(inv(i, j));
      }
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    const int n = structure_.n;
    LinearSolverResult r;
    if (isotropic_) {
      r = detail::withFixedSize(
          d_, [&](auto size) { return iterateIsotropic<decltype(size)::value>(rhs, x); });
    } else if (uniform_) {
      r = detail::withFixedSize(
          d_, [&](auto size) { return iterateBlocks<decltype(size)::value>(rhs, x); });
    } else {
      r = iterateBlocks<0>(rhs, x);
    }
    if (r.ok() && !detail::allFinite(x, n)) return detail::notFinite();
    return r;
  }

  /// Non-zeros of the preconditioner (the inverted diagonal blocks, or H_s's diagonal).
  std::size_t factorNonZeros() const override { return inverse_.size(); }

 private:
  static LinearSolverResult notPositive(bool negative, int column) {
    return LinearSolverResult::failure(
        negative ? LinearSolverStatus::kNotPositiveDefinite : LinearSolverStatus::kSingular,
        "diagonal block is not positive definite", column);
  }
  static LinearSolverResult incomplete(int column) {
    return LinearSolverResult::failure(
        LinearSolverStatus::kFailure,
        "pcg: column " + std::to_string(column) +
            " does not store complete blocks (as SparseStructure asks)",
        column);
  }
  int maxIterations() const { return std::max(100, std::min(10 * structure_.n, 5000)); }
  LinearSolverResult notConverged(double relative) const {
    return LinearSolverResult::failure(
        LinearSolverStatus::kSingular,
        "conjugate gradients did not converge in " + std::to_string(maxIterations()) +
            " iterations (relative residual " + std::to_string(relative) + ")");
  }
  static LinearSolverResult negativeCurvature() {
    return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                       "non-positive curvature p^T H p");
  }

  /// The isotropic iteration: H_s (scalar_) times D interleaved vectors (D = 0: d_), D
  /// conjugate-gradient runs. Vectors are in H's layout: entry i*d + t is coordinate t of
  /// H_s's row i. The preconditioner is H_s's diagonal plus, when coarse_ > 0, the coarse
  /// correction on the constant vector (1 (1^T r) / (1^T H_s 1)): H_s of linear SLAM is a
  /// weighted graph Laplacian plus priors, whose smallest eigenvalues belong to the whole
  /// map's translation, which the diagonal does not see.
  template <int D>
  LinearSolverResult iterateIsotropic(const double* rhs, double* x) {
    const int d = D > 0 ? D : d_;
    const int m = scalar_.n;
    const auto len = static_cast<std::size_t>(m) * static_cast<std::size_t>(d);
    r_.assign(rhs, rhs + len);
    sol_.assign(len, 0.0);
    q_.resize(len);
    p_.resize(len);
    // Per coordinate: r.z (rz), p.q (pq), sum of r (sum), the step (step), r.D^-1.r (wr2)
    // and a row of q (acc), in one array of 6 d: fixed-size for D > 0. z = D^-1 r +
    // coarse sum is never stored: r.z = r.D^-1.r + coarse sum^2, and p = z + beta p is
    // formed from r directly.
    constexpr int kFixed = D > 0 ? D : 1;
    std::vector<double> wide(D > 0 ? 0 : 6 * static_cast<std::size_t>(d));
    double fixed[6 * kFixed];
    double* rz = D > 0 ? fixed : wide.data();
    double* pq = rz + d;
    double* sum = pq + d;
    double* step = sum + d;
    double* wr2 = step + d;
    double* acc = wr2 + d;
    const double* inv = inverse_.data();
    const double coarse = coarse_;
    double b2 = 0.0;
    for (int t = 0; t < d; ++t) sum[t] = wr2[t] = 0.0;
    for (int i = 0; i < m; ++i) {
      for (int t = 0; t < d; ++t) {
        const double v = r_[static_cast<std::size_t>(i) * d + t];
        sum[t] += v;
        b2 += v * v;
        wr2[t] += inv[i] * v * v;
      }
    }
    for (int t = 0; t < d; ++t) {
      rz[t] = wr2[t] + coarse * sum[t] * sum[t];
      sum[t] *= coarse;  // the preconditioner's constant shift
    }
    for (int i = 0; i < m; ++i) {  // p = z
      for (int t = 0; t < d; ++t) {
        const std::size_t e = static_cast<std::size_t>(i) * d + t;
        p_[e] = inv[i] * r_[e] + sum[t];
      }
    }
    const double limit = kTolerance * kTolerance * b2;
    double r2 = b2;
    const int* ptr = scalar_.row_ptr.data();
    const int* col = scalar_.col.data();
    const double* val = scalar_.values.data();
    double* p = p_.data();
    double* q = q_.data();
    for (int it = 0; r2 > limit; ++it) {
      if (it >= maxIterations()) return notConverged(std::sqrt(r2 / b2));
      // q = H_s p, and p.q per coordinate.
      for (int t = 0; t < d; ++t) pq[t] = 0.0;
      if constexpr (D == 2) {
        pair_product_(ptr, col, val, m, p, q, pq);
      } else {
        for (int i = 0; i < m; ++i) {
          double* a = acc;
          std::fill(a, a + d, 0.0);
          for (int k = ptr[i]; k < ptr[i + 1]; ++k) {
            const double v = val[k];
            const double* pj = p + static_cast<std::size_t>(col[k]) * d;
            for (int t = 0; t < d; ++t) a[t] += v * pj[t];
          }
          const std::size_t e = static_cast<std::size_t>(i) * d;
          for (int t = 0; t < d; ++t) {
            q[e + t] = a[t];
            pq[t] += p[e + t] * a[t];
          }
        }
      }
      for (int t = 0; t < d; ++t) {
        // A coordinate already solved exactly (rz = 0) stays where it is.
        if (rz[t] == 0.0) {
          step[t] = 0.0;
        } else if (!(pq[t] > 0.0)) {
          return negativeCurvature();
        } else {
          step[t] = rz[t] / pq[t];
        }
        sum[t] = wr2[t] = 0.0;
      }
      // The per-coordinate sums in local arrays when D is fixed (registers: nothing else
      // can point at them).
      double local_step[kFixed], local_sum[kFixed] = {}, local_wr2[kFixed] = {};
      double* st = D > 0 ? local_step : step;
      double* sm = D > 0 ? local_sum : sum;
      double* w2 = D > 0 ? local_wr2 : wr2;
      if constexpr (D > 0) std::copy(step, step + D, local_step);
      double* const sol = sol_.data();
      double* const r = r_.data();
      r2 = 0.0;
      for (int i = 0; i < m; ++i) {
        for (int t = 0; t < d; ++t) {
          const std::size_t e = static_cast<std::size_t>(i) * d + t;
          sol[e] += st[t] * p[e];
          const double v = r[e] - st[t] * q[e];
          r[e] = v;
          sm[t] += v;
          r2 += v * v;
          w2[t] += inv[i] * v * v;
        }
      }
      for (int t = 0; t < d; ++t) {
        const double rz_new = w2[t] + coarse * sm[t] * sm[t];
        st[t] = rz[t] == 0.0 ? 0.0 : rz_new / rz[t];  // beta
        rz[t] = rz_new;
        sm[t] *= coarse;  // the shift
      }
      for (int i = 0; i < m; ++i) {  // p = z + beta p
        for (int t = 0; t < d; ++t) {
          const std::size_t e = static_cast<std::size_t>(i) * d + t;
          p[e] = inv[i] * r[e] + sm[t] + st[t] * p[e];
        }
      }
    }
    std::copy(sol_.begin(), sol_.end(), x);
    return LinearSolverResult::success();
  }

  /// The general iteration: H (full_) times one vector, block-Jacobi on blocks of D x D
  /// (D = 0: every block its own size).
  template <int D>
  LinearSolverResult iterateBlocks(const double* rhs, double* x) {
    const SparseStructure& s = structure_;
    const int n = s.n;
    const auto len = static_cast<std::size_t>(n);
    r_.assign(rhs, rhs + len);
    sol_.assign(len, 0.0);
    z_.resize(len);
    q_.resize(len);
    const auto precondition = [&]() {
      double rz = 0.0;
      std::size_t at = 0;
      for (int b = 0; b < s.num_blocks; ++b) {
        const int c0 = s.block_starts[b];
        const int d = D > 0 ? D : s.block_starts[b + 1] - c0;
        for (int i = 0; i < d; ++i) {
          double acc = 0.0;
          for (int j = 0; j < d; ++j) acc += inverse_[at + i * d + j] * r_[c0 + j];
          z_[c0 + i] = acc;
          rz += r_[c0 + i] * acc;
        }
        at += static_cast<std::size_t>(d) * d;
      }
      return rz;
    };
    double rz = precondition();
    p_ = z_;
    double b2 = 0.0;
    for (int i = 0; i < n; ++i) b2 += rhs[i] * rhs[i];
    const double limit = kTolerance * kTolerance * b2;
    double r2 = b2;
    const int* ptr = full_.row_ptr.data();
    const int* col = full_.col.data();
    const double* val = full_.values.data();
    for (int it = 0; r2 > limit; ++it) {
      if (it >= maxIterations()) return notConverged(std::sqrt(r2 / b2));
      double pq = 0.0;
      for (int i = 0; i < n; ++i) {
        double acc = 0.0;
        for (int k = ptr[i]; k < ptr[i + 1]; ++k) acc += val[k] * p_[col[k]];
        q_[i] = acc;
        pq += p_[i] * acc;
      }
      if (!(pq > 0.0)) return negativeCurvature();
      const double alpha = rz / pq;
      r2 = 0.0;
      for (int i = 0; i < n; ++i) {
        sol_[i] += alpha * p_[i];
        r_[i] -= alpha * q_[i];
        r2 += r_[i] * r_[i];
      }
      const double rz_new = precondition();
      const double beta = rz_new / rz;
      rz = rz_new;
      for (int i = 0; i < n; ++i) p_[i] = z_[i] + beta * p_[i];
    }
    std::copy(sol_.begin(), sol_.end(), x);
    return LinearSolverResult::success();
  }

  SparseStructure structure_;
  detail::PairProductFn pair_product_ = detail::pairProductKernel();  // H_s p, two coordinates
  int d_ = 1;
  bool uniform_ = true, isotropic_ = false;
  bool scalar_ready_ = false, full_ready_ = false;
  SymmetricRows scalar_, full_;  // H_s's rows (isotropic), H's rows
  std::vector<double> inverse_;  // H_s's inverse diagonal, or the inverse diagonal blocks
  double coarse_ = 0.0;          // 1 / (1^T H_s 1), or 0: no coarse correction
  std::vector<double> r_, z_, p_, q_, sol_;
};

}  // namespace

std::unique_ptr<LinearSolver> makePcgSolver() { return std::make_unique<PcgSolver>(); }

}  // namespace graphslam::solvers
