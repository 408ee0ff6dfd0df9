// SPDX-License-Identifier: MIT
// Isotropic normal equations: H = H_s (x) I_d, every d x d block a multiple of the
// identity. Linear SLAM with isotropic noise has this form (point robots with
// displacement measurements, the positions of an SE(2) initial guess): each edge's
// Jacobian blocks are +-I and its information is s I. Then L = L_s (x) I_d, where
// L_s L_s^T = H_s is the Cholesky factor of the scalar matrix on the block graph, with
// d^2 fewer non-zeros' worth of storage per block and d^3 fewer flops; the d components of
// the right-hand side are d solves with L_s.
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
  explicit IsotropicSolver(Ordering ordering) : ordering_(ordering) {}

  std::string name() const override { return "isotropic"; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering label) override {
    ordering_ = label;
    inner_.reset();
    nb_ = s.num_blocks;
    d_ = nb_ > 0 ? s.block_starts[1] - s.block_starts[0] : 1;
    for (int b = 0; b < nb_; ++b) {
      if (s.block_starts[b + 1] - s.block_starts[b] != d_) {
        return LinearSolverResult::failure(
            LinearSolverStatus::kFailure,
            "isotropic: every vertex must have the same dimension (H = H_s (x) I_d)",
            s.block_starts[b]);
      }
    }
    // Scalar pattern of H_s: block (r, c), r <= c, is entry (r, c); its value is H's
    // entry at the block's (0, 0), at the position of row r*d in column c*d.
    col_ptr_.assign(static_cast<std::size_t>(nb_) + 1, 0);
    row_idx_.clear();
    source_.clear();
    for (int c = 0; c < nb_; ++c) {
      const int col = c * d_;
      for (int p = s.col_ptr[col]; p < s.col_ptr[col + 1]; ++p) {
        const int row = s.row_idx[p];
        if (row % d_ != 0 || row > col) continue;
        row_idx_.push_back(row / d_);
        source_.push_back(p);
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
#ifdef GRAPHSLAM_HAVE_CHOLMOD
    if (cost.flops > kSupernodalFlops) inner_ = makeCholmodSolver(true, label);
#endif
    if (!inner_) inner_ = makeEigenLdlt();
    return inner_->analyzeOrdered(scalar_, std::move(block_order), label);
  }

  LinearSolverResult factorize(const double* h) override {
    if (!inner_) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
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
    // L = L_s (x) I_d: d entries per non-zero of L_s.
    return inner_ ? inner_->factorNonZeros() * static_cast<std::size_t>(d_) : 0;
  }

 private:
  Ordering ordering_;
  std::unique_ptr<detail::OrderedSolver> inner_;
  int nb_ = 0, d_ = 1;
  SparseStructure h_;  // H's structure (its arrays live until the next analysis)
  std::vector<int> col_ptr_, row_idx_, source_, block_starts_;
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

}  // namespace detail

std::unique_ptr<detail::OrderedSolver> makeIsotropicSolver(Ordering ordering) {
  return std::make_unique<IsotropicSolver>(ordering);
}

}  // namespace graphslam::solvers
