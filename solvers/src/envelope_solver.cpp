// SPDX-License-Identifier: MIT
// The envelope solver: H factorised by envelope (profile) Cholesky (envelope_cholesky.h)
// in a block order that keeps the envelope small (reverse Cuthill-McKee by default).
//
// Two factors share one analysis. When every vertex has dimension d and H = H_s (x) I_d
// (isotropic linear SLAM: every block a multiple of the identity, see isotropic_solver.cpp),
// the scalar H_s is factorised (d^2 fewer entries, d^3 fewer flops) and the d components of
// the right-hand side are solved together. Any other H is factorised as it is, each vertex's
// columns kept together. Which one is decided at every factorisation from H's values; the
// analysis computes the block order and every block row's first block column, which give
// both envelopes (a scalar row of H starts at the first column of its block row's first
// block). H_s's layout is made at analysis; H's, which also maps every stored entry of H,
// at the first factorisation that needs it.
#include <algorithm>
#include <memory>
#include <numeric>
#include <string>
#include <type_traits>
#include <vector>

#include "common.h"
#include "envelope_cholesky.h"
#include "ordering.h"

namespace graphslam::solvers {

namespace {

class EnvelopeSolver final : public detail::OrderedSolver {
 public:
  explicit EnvelopeSolver(Ordering ordering) : ordering_(ordering) {}

  std::string name() const override { return "envelope"; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering label) override {
    ordering_ = label;
    active_ = nullptr;
    analysed_ = false;
    scalar_ = detail::EnvelopeCholesky();
    h_ = s;
    nb_ = s.num_blocks;
    order_ = std::move(order);
    d_ = nb_ > 0 ? s.block_starts[1] - s.block_starts[0] : 1;
    uniform_ = true;
    for (int b = 0; b < nb_ && uniform_; ++b) {
      uniform_ = s.block_starts[b + 1] - s.block_starts[b] == d_;
    }
    // The block order: every vertex's columns must stay together, in their order.
    block_order_.clear();
    block_order_.reserve(static_cast<std::size_t>(nb_));
    const std::vector<int> block =
        uniform_ ? std::vector<int>() : detail::blockOfColumn(s.block_starts, nb_, s.n);
    for (int k = 0; k < s.n;) {
      const int b = uniform_ ? order_[k] / d_ : block[order_[k]];
      const int dim = s.block_starts[b + 1] - s.block_starts[b];
      for (int i = 0; i < dim; ++i) {
        if (k + i >= s.n || order_[k + i] != s.block_starts[b] + i) {
          return LinearSolverResult::failure(
              LinearSolverStatus::kFailure,
              "envelope: the order must keep every vertex's columns together, in order", order_[k]);
        }
      }
      block_order_.push_back(b);
      k += dim;
    }
    std::vector<int> pos(static_cast<std::size_t>(nb_));
    for (int p = 0; p < nb_; ++p) pos[block_order_[p]] = p;
    // Block (r, c) of the stored triangle joins positions pos[r] and pos[c]: the later one's
    // row reaches back to the earlier one. Every column of a block has the same pattern
    // (complete blocks): a block column's first column is read, one entry per block row.
    block_first_.resize(static_cast<std::size_t>(nb_));
    std::iota(block_first_.begin(), block_first_.end(), 0);
    std::size_t blocks = 0;
    const int incomplete = forStoredBlocks(s, block, [&](int r, int c, int) {
      const int hi = std::max(pos[r], pos[c]), lo = std::min(pos[r], pos[c]);
      block_first_[hi] = std::min(block_first_[hi], lo);
      ++blocks;
    });
    if (incomplete >= 0) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "envelope: column " + std::to_string(incomplete) +
              " does not store complete blocks (as SparseStructure asks)",
          incomplete);
    }
    if (!uniform_) {
      analysed_ = true;
      return LinearSolverResult::success();
    }
    // H_s's envelope, and where each of its entries goes (its value at the block's (0, 0)).
    LinearSolverResult r = iso_.layout(block_first_);
    if (!r.ok()) return r;
    hs_dest_.resize(blocks);
    hs_source_.resize(blocks);
    std::ptrdiff_t* dest = hs_dest_.data();
    int* source = hs_source_.data();
    static_cast<void>(forStoredBlocks(s, block, [&](int r, int c, int k) {
      *dest++ = iso_.position(std::max(pos[r], pos[c]), std::min(pos[r], pos[c]));
      *source++ = k;
    }));
    analysed_ = true;
    return r;
  }

  LinearSolverResult factorize(const double* h) override {
    active_ = nullptr;
    if (!analysed_) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    }
    if (uniform_ && detail::firstNonIsotropicColumn(h_, h) < 0) {
      iso_.clear();
      double* v = iso_.values();
      for (std::size_t e = 0; e < hs_source_.size(); ++e) v[hs_dest_[e]] = h[hs_source_[e]];
      LinearSolverResult r = iso_.factorize();
      // Row p of H_s is the vertex block_order_[p]: its first column in H.
      if (!r.ok() && r.column >= 0) r.column = h_.block_starts[block_order_[r.column]];
      if (r.ok()) active_ = &iso_;
      return r;
    }
    if (!scalar_.laidOut()) {
      const LinearSolverResult r = layOutScalar();
      if (!r.ok()) return r;
    }
    scalar_.clear();
    double* v = scalar_.values();
    for (std::size_t p = 0; p < dest_.size(); ++p) {
      if (dest_[p] >= 0) v[dest_[p]] = h[p];
    }
    LinearSolverResult r = scalar_.factorize();
    if (!r.ok() && r.column >= 0) r.column = order_[r.column];
    if (r.ok()) active_ = &scalar_;
    return r;
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    if (active_ == nullptr) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not factorised");
    }
    const int n = h_.n;
    b_.resize(static_cast<std::size_t>(n));
    // Both factors take the unknowns in order_ (H_s's d components of a vertex interleaved).
    for (int k = 0; k < n; ++k) b_[k] = rhs[order_[k]];
    const LinearSolverResult r = active_->solveInterleaved(b_.data(), active_ == &iso_ ? d_ : 1);
    if (!r.ok()) return r;
    for (int k = 0; k < n; ++k) x[order_[k]] = b_[k];
    return r;
  }

  std::size_t factorNonZeros() const override {
    // L = L_s (x) I_d: d entries per entry of L_s.
    if (active_ == &iso_ || (active_ == nullptr && uniform_)) {
      return iso_.entries() * static_cast<std::size_t>(d_);
    }
    return scalar_.entries();
  }

 private:
  /// Calls f(r, c, k) for every block (r, c) of H's stored triangle, k the position of its
  /// (0, 0) entry, reading each block column's first column (complete blocks: every column
  /// of a block has the same pattern). `block` maps a column to its block when the
  /// vertices' dimensions differ (empty: every one d_). Returns the first column that does
  /// not store complete blocks, or -1.
  template <typename F>
  int forStoredBlocks(const SparseStructure& s, const std::vector<int>& block, F&& f) const {
    const auto scan = [&](auto size) {
      constexpr int D = decltype(size)::value;  // 0: d_ at run time, -1: block[]
      const int d = D > 0 ? D : d_;
      for (int c = 0; c < nb_; ++c) {
        const int col = s.block_starts[c];
        for (int k = s.col_ptr[col]; k < s.col_ptr[col + 1];) {
          const int row = s.row_idx[k];
          int r, dim;
          if constexpr (D < 0) {
            r = block[row];
            dim = s.block_starts[r + 1] - s.block_starts[r];
            if (row != s.block_starts[r]) return col;
          } else {
            r = row / d;
            dim = d;
            if (row != r * d) return col;
          }
          if (!(s.lower ? r < c : r > c)) f(r, c, k);  // else not in the triangle read
          k += dim;
        }
      }
      return -1;
    };
    if (!block.empty()) return scan(std::integral_constant<int, -1>{});
    return detail::withFixedSize(d_, scan);
  }

  /// H's own envelope: a scalar row of H starts at the first column of its block row's
  /// first block; dest_ maps every entry of H's stored triangle (-1: not read).
  LinearSolverResult layOutScalar() {
    const int n = h_.n;
    std::vector<int> pos_start(static_cast<std::size_t>(nb_) + 1, 0);  // B's column of p
    for (int p = 0; p < nb_; ++p) {
      const int b = block_order_[p];
      pos_start[p + 1] = pos_start[p] + h_.block_starts[b + 1] - h_.block_starts[b];
    }
    std::vector<int> first(static_cast<std::size_t>(n));
    for (int p = 0; p < nb_; ++p) {
      for (int i = pos_start[p]; i < pos_start[p + 1]; ++i) first[i] = pos_start[block_first_[p]];
    }
    LinearSolverResult r = scalar_.layout(first);
    if (!r.ok()) return r;
    std::vector<int> where(static_cast<std::size_t>(n));  // H's column -> B's
    for (int k = 0; k < n; ++k) where[order_[k]] = k;
    dest_.resize(h_.nnz());
    for (int c = 0; c < n; ++c) {
      for (int p = h_.col_ptr[c]; p < h_.col_ptr[c + 1]; ++p) {
        const int row = h_.row_idx[p];
        const bool stored = h_.lower ? row >= c : row <= c;  // the other triangle: not read
        const int a = where[row], b = where[c];
        dest_[p] = stored ? scalar_.position(std::max(a, b), std::min(a, b)) : -1;
      }
    }
    return r;
  }

  Ordering ordering_;
  SparseStructure h_;  // H's structure (its arrays live until the next analysis)
  int nb_ = 0, d_ = 1;
  bool analysed_ = false;   // the last analysis succeeded
  bool uniform_ = false;    // every vertex of dimension d_
  std::vector<int> order_;  // B's column k is H's column order_[k]
  std::vector<int> block_order_, block_first_;
  detail::EnvelopeCholesky iso_, scalar_;
  detail::EnvelopeCholesky* active_ = nullptr;  // the factor of the last factorisation
  std::vector<int> hs_source_;                  // H_s's entries: the position of their value in H's
  std::vector<std::ptrdiff_t> hs_dest_, dest_;
  std::vector<double> b_;
};

}  // namespace

std::unique_ptr<detail::OrderedSolver> makeEnvelopeSolver(Ordering ordering) {
  return std::make_unique<EnvelopeSolver>(ordering);
}

}  // namespace graphslam::solvers
