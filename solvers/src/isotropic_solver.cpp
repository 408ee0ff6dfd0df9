// SPDX-License-Identifier: MIT
// Isotropic normal equations: H = H_s (x) I_d, every d x d block a multiple of the
// identity. Linear SLAM with isotropic noise has this form (point robots with
// displacement measurements, the positions of an SE(2) initial guess): each edge's
// Jacobian blocks are +-I and its information is s I. Then L = L_s (x) I_d, where
// L_s L_s^T = H_s is the Cholesky factor of the scalar matrix on the block graph, with
// d^2 fewer non-zeros' worth of storage per block and d^3 fewer flops; the d components of
// the right-hand side are d solves with L_s.
//
// Conformal normal equations, the same idea for 2x2 blocks of the form [a -b; b a]
// (a scaled rotation, the real form of the complex number a + ib): H is then the real
// form of a Hermitian complex matrix M on the block graph, and H x = g is M z = g with
// z = x_0 + i x_1 per vertex, which is how H's unknowns are already laid out. The
// orientation system of the SE(2) initial guess (chordal relaxation: rotations as unit
// vectors, an edge asks r_j = R r_i) has this form. CHOLMOD factorises M as a complex
// matrix: half the memory of the 2x2 block factor and half its flops.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "common.h"
#include "ordering.h"
#include "symbolic.h"
#ifdef GRAPHSLAM_HAVE_CHOLMOD
#include "suitesparse.h"
#endif

namespace graphslam::solvers {

std::unique_ptr<detail::OrderedSolver> makeEigenLdlt();

namespace {

/// Above this many predicted flops of the scalar factorisation, CHOLMOD's supernodal
/// factorisation takes it (dense fronts: a few dense landmark columns seen from every
/// pose make the factor's trailing part dense); below, Eigen's simplicial LDL^T, which has
/// no per-supernode overhead and names the column of a failed pivot.
constexpr double kSupernodalFlops = 2e6;
/// Off-diagonal entries of a block, and differences between its diagonal entries, must
/// be below this fraction of its (0, 0) entry.
constexpr double kRelativeTolerance = 1e-12;

class IsotropicSolver final : public detail::OrderedSolver {
 public:
  explicit IsotropicSolver(Ordering ordering, bool conformal = false)
      : ordering_(ordering), conformal_(conformal) {}

  std::string name() const override { return conformal_ ? "conformal" : "isotropic"; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering label) override {
    ordering_ = label;
    inner_.reset();
    nb_ = s.num_blocks;
    d_ = nb_ > 0 ? s.block_starts[1] - s.block_starts[0] : 1;
    for (int b = 0; b < nb_; ++b) {
      if (s.block_starts[b + 1] - s.block_starts[b] != d_ || (conformal_ && d_ != 2)) {
        return LinearSolverResult::failure(
            LinearSolverStatus::kFailure,
            conformal_ ? "conformal: every vertex must have dimension 2"
                       : "isotropic: every vertex must have the same dimension (H = H_s (x) I_d)",
            s.block_starts[b]);
      }
    }
    // Scalar pattern of H_s: block (r, c), r <= c, is entry (r, c); its value is H's
    // entry at the block's (0, 0), at the position of row r*d in column c*d.
    col_ptr_.assign(static_cast<std::size_t>(nb_) + 1, 0);
    row_idx_.clear();
    source_.clear();
    source01_.clear();
    for (int c = 0; c < nb_; ++c) {
      const int col = c * d_;
      for (int p = s.col_ptr[col]; p < s.col_ptr[col + 1]; ++p) {
        const int row = s.row_idx[p];
        if (row % d_ != 0 || row > col) continue;
        row_idx_.push_back(row / d_);
        source_.push_back(p);
        // The block's (0, 1) entry: the same place in the next column (complete blocks).
        if (conformal_) source01_.push_back(s.col_ptr[col + 1] + (p - s.col_ptr[col]));
      }
      col_ptr_[c + 1] = static_cast<int>(row_idx_.size());
      const int stored = (col_ptr_[c + 1] - col_ptr_[c]) * d_;
      for (int j = 0; j < d_; ++j) {
        if (s.col_ptr[col + j + 1] - s.col_ptr[col + j] != stored) {
          return LinearSolverResult::failure(
              LinearSolverStatus::kFailure,
              "isotropic: column " + std::to_string(col + j) +
                  " does not store complete blocks (as SparseStructure asks)",
              col + j);
        }
      }
    }
    h_ = s;
    block_starts_.resize(static_cast<std::size_t>(nb_) + 1);
    for (int b = 0; b <= nb_; ++b) block_starts_[b] = b;
    scalar_.n = nb_;
    scalar_.col_ptr = col_ptr_.data();
    scalar_.row_idx = row_idx_.data();
    scalar_.block_starts = block_starts_.data();
    scalar_.num_blocks = nb_;
    // The block order (every d-th scalar column of the block-expanded order).
    std::vector<int> block_order;
    block_order.reserve(static_cast<std::size_t>(nb_));
    for (std::size_t k = 0; k < order.size(); k += static_cast<std::size_t>(d_)) {
      block_order.push_back(order[k] / d_);
    }
    const detail::SymbolicCost cost = detail::symbolicCost(scalar_, block_order);
    if (conformal_) {
#ifdef GRAPHSLAM_HAVE_CHOLMOD
      // A complex multiply-add is four real ones.
      inner_ = makeCholmodComplexSolver(4.0 * cost.flops > kSupernodalFlops, label);
#else
      return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                         "conformal: needs CHOLMOD (SuiteSparse)");
#endif
    }
#ifdef GRAPHSLAM_HAVE_CHOLMOD
    if (!inner_ && cost.flops > kSupernodalFlops) inner_ = makeCholmodSolver(true, label);
#endif
    if (!inner_) inner_ = makeEigenLdlt();
    return inner_->analyzeOrdered(scalar_, std::move(block_order), label);
  }

  LinearSolverResult factorize(const double* h) override {
    if (!inner_) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    if (conformal_) return factorizeConformal(h);
    const int bad = detail::firstNonIsotropicColumn(h_, h);
    if (bad >= 0) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "isotropic: H is not H_s (x) I_" + std::to_string(d_) + ": a block of columns " +
              std::to_string(bad - bad % d_) + ".." + std::to_string(bad - bad % d_ + d_ - 1) +
              " is not a multiple of the identity",
          bad);
    }
    values_.resize(source_.size());
    for (std::size_t k = 0; k < source_.size(); ++k) values_[k] = h[source_[k]];
    LinearSolverResult r = inner_->factorize(values_.data());
    if (!r.ok() && r.column >= 0) r.column *= d_;  // the vertex's first column in H
    return r;
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    if (!inner_) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    // H's unknowns (x_0, x_1) per vertex are the interleaved complex z = x_0 + i x_1.
    if (conformal_) return inner_->solve(rhs, x);
    b_.resize(static_cast<std::size_t>(nb_));
    y_.resize(static_cast<std::size_t>(nb_));
    for (int j = 0; j < d_; ++j) {
      for (int b = 0; b < nb_; ++b) b_[b] = rhs[b * d_ + j];
      const LinearSolverResult r = inner_->solve(b_.data(), y_.data());
      if (!r.ok()) return r;
      for (int b = 0; b < nb_; ++b) x[b * d_ + j] = y_[b];
    }
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    if (!inner_) return 0;
    // Conformal: a complex entry is a 2x2 real block (3 entries on the diagonal).
    if (conformal_) return inner_->factorNonZeros() * 4 - static_cast<std::size_t>(nb_);
    // L = L_s (x) I_d: d entries per non-zero of L_s.
    return inner_->factorNonZeros() * static_cast<std::size_t>(d_);
  }

 private:
  LinearSolverResult factorizeConformal(const double* h) {
    const int bad = detail::firstNonConformalColumn(h_, h);
    if (bad >= 0) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "conformal: a block of columns " + std::to_string(bad - bad % 2) + ".." +
              std::to_string(bad - bad % 2 + 1) + " is not of the form [a -b; b a]",
          bad);
    }
    // Upper entry (r, c) of M: a + ib for H's block [a -b; b a]; b is read from the
    // block's (0, 1) entry, which is stored for diagonal blocks too (and is 0 there).
    values_.resize(2 * source_.size());
    for (std::size_t k = 0; k < source_.size(); ++k) {
      values_[2 * k] = h[source_[k]];
      values_[2 * k + 1] = -h[source01_[k]];
    }
    LinearSolverResult r = inner_->factorize(values_.data());
    if (!r.ok() && r.column >= 0) r.column *= 2;
    return r;
  }

  Ordering ordering_;
  bool conformal_ = false;
  std::unique_ptr<detail::OrderedSolver> inner_;
  int nb_ = 0, d_ = 1;
  SparseStructure h_;  // H's structure (its arrays live until the next analysis)
  std::vector<int> col_ptr_, row_idx_, source_, source01_, block_starts_;
  SparseStructure scalar_;
  std::vector<double> values_, b_, y_;
};

}  // namespace

namespace detail {

int firstNonIsotropicColumn(const SparseStructure& s, const double* h) {
  if (s.num_blocks == 0) return -1;
  const int d = s.block_starts[1] - s.block_starts[0];
  for (int c = 0; c < s.num_blocks; ++c) {
    const int first = s.block_starts[c];
    if (s.block_starts[c + 1] - first != d) return first;
    // Block k of the column starts at entry k*d of every column of the block column
    // (complete blocks); its (0, 0) entry is v, every entry must be v I.
    const int stored = s.col_ptr[first + 1] - s.col_ptr[first];
    for (int j = 0; j < d; ++j) {
      const int col = first + j;
      if (s.col_ptr[col + 1] - s.col_ptr[col] != stored) return col;
      for (int k = 0; k < stored; k += d) {
        const double v = h[s.col_ptr[first] + k];
        const int p = s.col_ptr[col] + k;
        const int row0 = s.row_idx[p];
        for (int i = 0; i < d && row0 + i <= col; ++i) {  // below the diagonal: not read
          const double expected = i == j ? v : 0.0;
          if (!(std::abs(h[p + i] - expected) <= kRelativeTolerance * std::abs(v))) return col;
        }
      }
    }
  }
  return -1;
}

int firstNonConformalColumn(const SparseStructure& s, const double* h) {
  for (int c = 0; c < s.num_blocks; ++c) {
    const int first = s.block_starts[c];
    if (s.block_starts[c + 1] - first != 2) return first;
    const int stored = s.col_ptr[first + 1] - s.col_ptr[first];
    if (s.col_ptr[first + 2] - s.col_ptr[first + 1] != stored) return first + 1;
    for (int k = 0; k < stored; k += 2) {
      const int p0 = s.col_ptr[first] + k;      // (0, 0), then (1, 0)
      const int p1 = s.col_ptr[first + 1] + k;  // (0, 1), then (1, 1)
      const double a = h[p0];
      const double b = -h[p1];
      const double tol = kRelativeTolerance * (std::abs(a) + std::abs(b));
      if (!(std::abs(h[p1 + 1] - a) <= tol)) return first + 1;
      // Diagonal block: symmetric, so b = 0 (its (1, 0) entry is below the diagonal and
      // not read); otherwise (1, 0) = b.
      const bool diagonal = s.row_idx[p0] == first;
      if (diagonal ? !(std::abs(b) <= tol) : !(std::abs(h[p0 + 1] - b) <= tol)) return first;
    }
  }
  return -1;
}

}  // namespace detail

std::unique_ptr<detail::OrderedSolver> makeIsotropicSolver(Ordering ordering) {
  return std::make_unique<IsotropicSolver>(ordering);
}

std::unique_ptr<detail::OrderedSolver> makeConformalSolver(Ordering ordering) {
  return std::make_unique<IsotropicSolver>(ordering, true);
}

}  // namespace graphslam::solvers
