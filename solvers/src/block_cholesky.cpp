// SPDX-License-Identifier: MIT
// Block up-looking Cholesky LL^T on fixed-size B x B blocks (B = the largest vertex
// dimension, 1, 2 or 3): the compiler unrolls every block operation, where a scalar
// simplicial factorisation walks one entry at a time. Smaller vertices (landmarks of
// dimension 2 among poses of dimension 3) are padded: the extra unknown gets a unit
// diagonal and no coupling, so it solves to zero and leaves the others exact.
// A dense trailing part of the factor (the last columns, each holding every row below it:
// the landmarks of a landmark graph under AMD) made largely of padded vertices is
// factorised as one dense matrix with Eigen's blocked LL^T, unpadded.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "block_kernels.h"
#include "common.h"
#include "factories.h"
#include "graphslam/support/large_array.h"
#include "ordering.h"

namespace graphslam::solvers {

namespace {

/// First column of the dense matrix `a` (lower triangle) at which an unblocked LL^T, in
/// place, finds a non-positive pivot; -1 when there is none. Only for naming a failure.
Eigen::Index firstNonPositivePivot(Eigen::MatrixXd& a) {
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    const Eigen::Index below = a.rows() - j - 1;
    double d = a(j, j) - a.row(j).head(j).squaredNorm();
    if (!(d > 0.0)) return j;
    d = std::sqrt(d);
    a(j, j) = d;
    a.col(j).tail(below) =
        (a.col(j).tail(below) - a.bottomLeftCorner(below, j) * a.row(j).head(j).transpose()) / d;
  }
  return -1;
}

/// L^{-1} of the Cholesky factor L L^T = A of the symmetric B x B block at the top of `a`
/// (its lower triangle is read), unrolled: false when a pivot is not positive (or NaN).
template <int B, typename In>
bool inverseCholeskyFactor(const In& a, Eigen::Matrix<double, B, B>& inv) {
  Eigen::Matrix<double, B, B> l;
  for (int j = 0; j < B; ++j) {
    double d = a(j, j);
    for (int t = 0; t < j; ++t) d -= l(j, t) * l(j, t);
    if (!(d > 0.0)) return false;
    l(j, j) = std::sqrt(d);
    const double r = 1.0 / l(j, j);
    inv(j, j) = r;
    for (int i = j + 1; i < B; ++i) {
      double v = a(i, j);
      for (int t = 0; t < j; ++t) v -= l(i, t) * l(j, t);
      l(i, j) = v * r;
    }
  }
  // L X = I by forward substitution: X(i, j) = -sum_{t=j}^{i-1} L(i, t) X(t, j) / L(i, i).
  for (int j = 0; j < B; ++j) {
    for (int i = 0; i < j; ++i) inv(i, j) = 0.0;
    for (int i = j + 1; i < B; ++i) {
      double v = 0.0;
      for (int t = j; t < i; ++t) v += l(i, t) * inv(t, j);
      inv(i, j) = -v * inv(i, i);
    }
  }
  return true;
}

/// L = blocks in column storage: column i holds the inverse of its diagonal block, then one block
/// per row k > i of its pattern, rows ascending. The row patterns are kept too (the up-looking
/// order). Everything but the values is built once per structure.
template <int B>
class BlockCholesky final : public detail::OrderedSolver {
 public:
  using Block = Eigen::Matrix<double, B, B>;
  /// Accumulator of a row of L (y in factorizeColumns): B x B, padded to whole vectors
  /// for the kernel (block_kernels.h).
  static constexpr int P = detail::paddedRows(B);
  using Work = Eigen::Matrix<double, P, B>;
  using PVec = Eigen::Matrix<double, P, 1>;  // a block of the solves' vector, padded alike
  // The kernels walk these arrays as plain doubles.
  static_assert(sizeof(Block) == sizeof(double) * B * B && sizeof(Work) == sizeof(double) * P * B &&
                sizeof(PVec) == sizeof(double) * P);

  explicit BlockCholesky(const BlockCholeskyOptions& options)
      : options_(options),
        eliminate_(detail::eliminateKernel(B)),
        solve_(detail::solveKernels(B)) {}

  std::string name() const override { return "block-llt"; }

  /// Only through BlockCholeskyAny, which owns the ordering.
  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering /*label*/) override {
    nb_ = s.num_blocks;
    n_ = s.n;
    start_.assign(s.block_starts, s.block_starts + nb_ + 1);
    if (LinearSolverResult r = checkBlocks(s); !r.ok()) return r;
    const std::vector<int> block = detail::blockOfColumn(s.block_starts, nb_, s.n);
    std::vector<int> pos(static_cast<std::size_t>(nb_), -1);
    permuteBlocks(order, block, pos);
    gatherUpperBlocks(s, block, pos);
    std::vector<int> count(static_cast<std::size_t>(nb_), 0);  // off-diagonal blocks per column
    std::vector<double> below(static_cast<std::size_t>(nb_), 0.0);  // and their scalar rows
    findRowPatterns(count, below);
    predictCost(below);
    buildColumnStorage(count);
    chooseDenseTail(count);
    // Every entry is written before it is read (factorize): no initialisation.
    values_.clear();
    values_.resize(static_cast<std::size_t>(col_ptr_[nb_]));
    work_.clear();
    work_.resize(static_cast<std::size_t>(nb_));
    return LinearSolverResult::success();
  }

  LinearSolverResult factorize(const double* h) override {
    if (col_ptr_.empty())
      return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    const LinearSolverResult r = factorizeColumns(h);
    if (!r.ok() || tail_ == nb_) return r;
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(tail_matrix_);
    if (llt.info() == Eigen::Success) return LinearSolverResult::success();
    // Name the vertex of the failing pivot: the tail matrix once more, factorised by an
    // unblocked pass that stops there (only on failure).
    (void)factorizeColumns(h);
    const Eigen::Index bad = firstNonPositivePivot(tail_matrix_);
    int k = tail_;
    while (k + 1 < nb_ && bad >= 0 && tailAt(k) + tailDim(k) <= bad) ++k;
    return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                       "non-positive pivot block", start_[old_[k]]);
  }

  /// The block columns before the tail, and the tail matrix A_TT - L_T,<tail L_T,<tail^T.
  LinearSolverResult factorizeColumns(const double* h) {
    for (int k = 0; k < nb_; ++k) {
      const bool in_tail = k >= tail_;
      // y = A(k, 0..k) into work_ (the diagonal block too).
      for (int q = row_ptr_[k]; q < row_ptr_[k + 1]; ++q) work_[row_idx_[q]].setZero();
      Work diag = Work::Zero();
      const int dk = dim(old_[k]);
      for (int q = a_ptr_[k]; q < a_ptr_[k + 1]; ++q) {
        const AEntry& e = a_[q];
        Block blk;
        if (uniform_ || (e.rows == B && e.cols == B)) {
          blk = Eigen::Map<const Block, 0, Eigen::OuterStride<>>(h + e.first,
                                                                 Eigen::OuterStride<>(e.stride));
        } else {
          // H's block (r, c) is rows x cols; padded with zeros (unit diagonal: below).
          blk.setZero();
          const double* src = h + e.first;
          for (int j = 0; j < e.cols; ++j) {
            for (int i = 0; i < e.rows; ++i) blk(i, j) = src[i + j * e.stride];
          }
        }
        if (e.row == k) {
          diag.template topRows<B>() = blk.template selfadjointView<Eigen::Upper>();
        } else if (e.transposed) {
          work_[e.row].template topRows<B>() = blk;  // stored as (k, row) in H: A(k, row)
        } else {
          // A(row, k) stored: A(k, row) is its transpose
          work_[e.row].template topRows<B>() = blk.transpose();
        }
      }
      for (int q = row_ptr_[k]; q < row_ptr_[k + 1]; ++q) {
        const int i = row_idx_[q];
        // In the tail, L(k, i) of the columns i before it only; the tail's own columns
        // are the dense factorisation's (below).
        if (i >= tail_) continue;
        // L(k, i) = y_i L(i, i)^{-T}, with the inverse kept from column i's factorisation
        // (a product: a triangular solve of fixed size is slower), then
        // y_p -= L(k, i) L(p, i)^T for the rows p < k of column i (stored before (k, i))
        // and the diagonal block's, in one call of the kernel.
        const int e = col_ptr_[i] + 1;
        eliminate_(work_[i].data(), values_[col_ptr_[i]].data(), values_[entry_[q]].data(),
                   values_.data()->data() + static_cast<std::ptrdiff_t>(e) * B * B,
                   col_row_.data() + e, entry_[q] - e, work_.data()->data(), diag.data());
      }
      if (in_tail) {
        // Row k of the tail matrix, A_TT - L_T,<tail L_T,<tail^T: the entries y_p of the
        // tail's columns p < k and the diagonal block, unpadded (lower triangle).
        const int r0 = tailAt(k);
        for (int p = tail_; p < k; ++p) {
          tail_matrix_.block(r0, tailAt(p), dk, tailDim(p)) =
              work_[p].topLeftCorner(dk, tailDim(p));
        }
        tail_matrix_.block(r0, r0, dk, dk).template triangularView<Eigen::Lower>() =
            diag.topLeftCorner(dk, dk);
        continue;
      }
      for (int t = dk; t < B; ++t) diag(t, t) = 1.0;  // padding
      // Column k's first block holds L(k, k)^{-1}, the only form the elimination and the
      // solves use (products: a triangular solve of fixed size is slower).
      if (!inverseCholeskyFactor(diag, values_[col_ptr_[k]])) {
        return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite,
                                           "non-positive pivot block", start_[old_[k]]);
      }
    }
    return LinearSolverResult::success();
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    std::vector<PVec, Eigen::aligned_allocator<PVec>>& y = y_;
    y.resize(static_cast<std::size_t>(nb_));
    for (int k = 0; k < nb_; ++k) {
      const int b = old_[k];
      y[k].setZero();
      y[k].head(dim(b)) = Eigen::Map<const Eigen::VectorXd>(rhs + start_[b], dim(b));
    }
    // The kernels step through y by P doubles.
    const auto at = [&](int k) { return y.data()->data() + static_cast<std::ptrdiff_t>(k) * P; };
    const auto blocks = [&](int e) {
      return values_.data()->data() + static_cast<std::ptrdiff_t>(e) * B * B;
    };
    for (int i = 0; i < tail_; ++i) {  // L y = b, by columns
      const int e = col_ptr_[i] + 1;
      solve_.forward(values_[col_ptr_[i]].data(), at(i), blocks(e), col_row_.data() + e,
                     col_ptr_[i + 1] - e, at(0));
    }
    if (tail_ < nb_) {  // the dense tail, both ways
      Eigen::VectorXd& t = tail_rhs_;
      t.resize(tail_matrix_.rows());
      for (int k = tail_; k < nb_; ++k) {
        t.segment(tailAt(k), tailDim(k)) = y[k].head(tailDim(k));
      }
      tail_matrix_.triangularView<Eigen::Lower>().solveInPlace(t);
      tail_matrix_.triangularView<Eigen::Lower>().transpose().solveInPlace(t);
      for (int k = tail_; k < nb_; ++k) {
        y[k].head(tailDim(k)) = t.segment(tailAt(k), tailDim(k));
      }
    }
    for (int i = tail_ - 1; i >= 0; --i) {  // L^T x = y
      const int e = col_ptr_[i] + 1;
      solve_.backward(values_[col_ptr_[i]].data(), at(i), blocks(e), col_row_.data() + e,
                      col_ptr_[i + 1] - e, at(0));
    }
    for (int k = 0; k < nb_; ++k) {
      const int b = old_[k];
      Eigen::Map<Eigen::VectorXd>(x + start_[b], dim(b)) = y[k].head(dim(b));
    }
    if (!detail::allFinite(x, n_)) return detail::notFinite();
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    // Lower triangle of the diagonal blocks plus the off-diagonal blocks, unpadded.
    return static_cast<std::size_t>(cost_.factor_nonzeros);
  }
  std::optional<CholeskyPrediction> analysedCost() const override { return cost_; }

  /// L's lower triangle in the permuted scalar order: per block column, the lower triangle
  /// of its diagonal block and every stored block below it (the dense tail included), as
  /// factorNonZeros() counts them.
  bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const override {
    if (col_ptr_.empty()) return false;
    std::vector<int> first(static_cast<std::size_t>(nb_) + 1, 0);  // scalar start of block k
    for (int k = 0; k < nb_; ++k) first[k + 1] = first[k] + dim(old_[k]);
    col_ptr.assign(1, 0);
    row_idx.clear();
    for (int i = 0; i < nb_; ++i) {
      for (int c = first[i]; c < first[i + 1]; ++c) {
        for (int r = c; r < first[i + 1]; ++r) row_idx.push_back(r);
        for (int q = col_ptr_[i] + 1; q < col_ptr_[i + 1]; ++q) {
          const int k = col_row_[q];
          for (int r = first[k]; r < first[k + 1]; ++r) row_idx.push_back(r);
        }
        col_ptr.push_back(static_cast<int>(row_idx.size()));
      }
    }
    return true;
  }

 private:
  int dim(int original_block) const { return start_[original_block + 1] - start_[original_block]; }

  /// Every vertex of dimension 1..B with its columns storing the same rows; sets uniform_
  /// (all of dimension B).
  LinearSolverResult checkBlocks(const SparseStructure& s) {
    uniform_ = true;
    for (int b = 0; b < nb_; ++b) {
      const int d = start_[b + 1] - start_[b];
      if (d < 1 || d > B) {
        return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                           "block-llt: a vertex of dimension " + std::to_string(d) +
                                               " in blocks of " + std::to_string(B));
      }
      uniform_ = uniform_ && d == B;
      // Blocks are read with one stride per block column: every column of a block must
      // store the same rows (complete blocks, as SparseStructure asks).
      const int len = s.col_ptr[start_[b] + 1] - s.col_ptr[start_[b]];
      for (int c = start_[b] + 1; c < start_[b + 1]; ++c) {
        if (s.col_ptr[c + 1] - s.col_ptr[c] != len) {
          return LinearSolverResult::failure(
              LinearSolverStatus::kFailure,
              "block-llt: columns " + std::to_string(start_[b]) + " and " + std::to_string(c) +
                  " of one vertex store different rows (blocks must be stored complete)",
              c);
        }
      }
    }
    return LinearSolverResult::success();
  }

  /// Block permutation from the scalar `order`: old_[k] = original block at position k,
  /// pos[b] = position of original block b (`block`: block of each scalar column).
  void permuteBlocks(const std::vector<int>& order, const std::vector<int>& block,
                     std::vector<int>& pos) {
    old_.clear();
    for (int c : order) {
      const int b = block[c];
      if (pos[b] >= 0) continue;
      pos[b] = static_cast<int>(old_.size());
      old_.push_back(b);
    }
  }

  /// A's upper blocks per new column k (a_ptr_, a_): (new row i <= k, first value, stride,
  /// shape, transposed). Counted, then filled; the rows of a column stay in H's order,
  /// unsorted: the row-pattern pass finds a topological order from any order of them (as
  /// LDL's and CSparse's reach do), and the factorisation scatters them.
  void gatherUpperBlocks(const SparseStructure& s, const std::vector<int>& block,
                         const std::vector<int>& pos) {
    a_ptr_.assign(static_cast<std::size_t>(nb_) + 2, 0);
    auto for_blocks = [&](auto&& visit) {
      for (int c = 0; c < nb_; ++c) {
        const int col0 = start_[c];
        for (int p = s.col_ptr[col0]; p < s.col_ptr[col0 + 1];) {
          const int r = block[s.row_idx[p]];  // H's upper block (r, c), r <= c
          visit(r, c, p);
          // Every block B rows when all are (the next position then does not wait for
          // this block's loads).
          p += uniform_ ? B : start_[r + 1] - start_[r];
        }
      }
    };
    for_blocks([&](int r, int c, int) { ++a_ptr_[std::max(pos[r], pos[c]) + 2]; });
    for (int k = 0; k < nb_; ++k) a_ptr_[k + 2] += a_ptr_[k + 1];
    a_.resize(static_cast<std::size_t>(a_ptr_[nb_ + 1]));
    for_blocks([&](int r, int c, int p) {
      const int pr = pos[r], pc = pos[c];
      const auto rows = static_cast<std::int8_t>(start_[r + 1] - start_[r]);
      const auto cols = static_cast<std::int8_t>(start_[c + 1] - start_[c]);
      const int stride = s.col_ptr[start_[c] + 1] - s.col_ptr[start_[c]];
      // In the new order the block is (min, max); transposed when the row moved below.
      if (pr <= pc) {
        a_[a_ptr_[pc + 1]++] = {pr, p, stride, rows, cols, false};
      } else {
        a_[a_ptr_[pr + 1]++] = {pc, p, stride, rows, cols, true};
      }
    });
    a_ptr_.pop_back();
  }

  /// Elimination tree and the row patterns of L (row subtrees: row_ptr_, row_idx_) in one
  /// pass, as LDL's symbolic analysis does: row k's pattern is every node on the paths up
  /// the tree from the rows of A(k, 0..k-1) until k or a node already met; a node on such a
  /// path without a parent yet has k as its parent. Each path is stacked in front of those
  /// found before it (which it ends in), so each row i comes after every row below it in the
  /// tree, as the up-looking factorisation needs; no sort. Adds to count[i] the off-diagonal
  /// blocks of column i, to below[i] their scalar rows.
  void findRowPatterns(std::vector<int>& count, std::vector<double>& below) {
    std::vector<int> parent(static_cast<std::size_t>(nb_), -1);
    std::vector<int> flag(static_cast<std::size_t>(nb_), -1);
    row_ptr_.assign(static_cast<std::size_t>(nb_) + 1, 0);
    row_idx_.clear();
    std::vector<int> stack(static_cast<std::size_t>(nb_)), path(static_cast<std::size_t>(nb_));
    for (int k = 0; k < nb_; ++k) {
      flag[k] = k;
      int top = nb_;
      for (int q = a_ptr_[k]; q < a_ptr_[k + 1]; ++q) {
        int len = 0;
        for (int i = a_[q].row; flag[i] != k; i = parent[i]) {
          if (parent[i] < 0) parent[i] = k;
          flag[i] = k;
          path[len++] = i;
        }
        while (len > 0) stack[--top] = path[--len];
      }
      const int dk = dim(old_[k]);
      for (int t = top; t < nb_; ++t) {
        ++count[stack[t]];
        below[stack[t]] += dk;
      }
      row_idx_.insert(row_idx_.end(), stack.begin() + top, stack.end());
      row_ptr_[k + 1] = static_cast<int>(row_idx_.size());
    }
  }

  /// Size and work of L, unpadded (cost_): scalar column t of block column i holds d_i - t
  /// rows of the diagonal block and below[i] below it.
  void predictCost(const std::vector<double>& below) {
    cost_ = {};
    for (int i = 0; i < nb_; ++i) {
      const int d = dim(old_[i]);
      for (int t = 0; t < d; ++t) {
        const double c = (d - t) + below[i];
        cost_.factor_nonzeros += c;
        cost_.flops += c * c;
      }
    }
  }

  /// Column storage (col_ptr_, col_row_, entry_): column i = diagonal block then count[i]
  /// blocks; entry of (k, i) in row order of k gets the next free slot of column i.
  void buildColumnStorage(const std::vector<int>& count) {
    col_ptr_.assign(static_cast<std::size_t>(nb_) + 1, 0);
    for (int i = 0; i < nb_; ++i) col_ptr_[i + 1] = col_ptr_[i] + 1 + count[i];
    col_row_.assign(static_cast<std::size_t>(col_ptr_[nb_]), 0);
    entry_.assign(row_idx_.size(), 0);
    std::vector<int> next(col_ptr_.begin(), col_ptr_.end() - 1);
    for (int i = 0; i < nb_; ++i) col_row_[next[i]++] = i;
    for (int k = 0; k < nb_; ++k) {
      for (int q = row_ptr_[k]; q < row_ptr_[k + 1]; ++q) {
        const int i = row_idx_[q];
        entry_[q] = next[i];
        col_row_[next[i]++] = k;
      }
    }
  }

  /// Dense tail (tail_, tail_start_, tail_matrix_): the last columns k >= tail_ each hold
  /// every row below them. Kept when it is long enough and padding would be at least
  /// dense_tail_min_padding of it (of B x B blocks, the up-looking loop is as fast as the
  /// dense factorisation).
  void chooseDenseTail(const std::vector<int>& count) {
    tail_ = nb_;
    while (tail_ > 0 && count[tail_ - 1] == nb_ - tail_) --tail_;
    tail_start_.assign(1, 0);
    for (int k = tail_; k < nb_; ++k) tail_start_.push_back(tail_start_.back() + dim(old_[k]));
    const double padded = static_cast<double>(B) * (nb_ - tail_);
    if (nb_ - tail_ < options_.dense_tail_min_blocks ||
        tail_start_.back() > (1.0 - options_.dense_tail_min_padding) * padded) {
      tail_ = nb_;
      tail_start_.assign(1, 0);
    }
    tail_matrix_.resize(tail_start_.back(), tail_start_.back());
  }

  struct AEntry {
    int row;
    int first;               // H value of the block's (0, 0)
    int stride;              // H values between its columns
    std::int8_t rows, cols;  // H's block (r, c) is rows x cols
    bool transposed;
  };

  /// Position of tail block column k in the dense tail matrix, and its dimension.
  int tailAt(int k) const { return tail_start_[k - tail_]; }
  int tailDim(int k) const { return tail_start_[k - tail_ + 1] - tail_start_[k - tail_]; }

  int nb_ = 0;
  int n_ = 0;
  bool uniform_ = true;
  std::vector<int> start_;  // H's block starts (original blocks)
  std::vector<int> old_;
  std::vector<int> a_ptr_;
  std::vector<AEntry> a_;
  std::vector<int> row_ptr_, row_idx_, entry_;
  std::vector<int> col_ptr_, col_row_;
  support::LargeVector<Block> values_;
  support::LargeVector<Work> work_;
  std::vector<PVec, Eigen::aligned_allocator<PVec>> y_;
  CholeskyPrediction cost_;      // L's size and work (analysis)
  int tail_ = 0;                 // first block column of the dense tail (nb_: none)
  std::vector<int> tail_start_;  // tail block column k at tail_start_[k - tail_]
  Eigen::MatrixXd tail_matrix_;  // its factor (lower triangle)
  Eigen::VectorXd tail_rhs_;
  BlockCholeskyOptions options_;
  detail::EliminateFn eliminate_;
  detail::SolveKernels solve_;
};

/// Picks the block size at analysis: the largest vertex dimension (1, 2 or 3).
class BlockCholeskyAny final : public detail::OrderedSolver {
 public:
  BlockCholeskyAny(Ordering ordering, const BlockCholeskyOptions& options)
      : ordering_(ordering), options_(options) {}
  std::string name() const override { return "block-llt"; }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering label) override {
    ordering_ = label;
    impl_.reset();
    const int b = maxBlockSize(s);
    if (b <= 1) impl_ = std::make_unique<BlockCholesky<1>>(options_);
    if (b == 2) impl_ = std::make_unique<BlockCholesky<2>>(options_);
    if (b == 3) impl_ = std::make_unique<BlockCholesky<3>>(options_);
    if (b > 3 && b <= 6) impl_ = std::make_unique<BlockCholesky<6>>(options_);
    if (!impl_) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "block-llt handles vertices of dimension at most 6 (use eigen-ldlt)");
    }
    return impl_->analyzeOrdered(s, std::move(order), label);
  }
  LinearSolverResult factorize(const double* values) override {
    if (!impl_) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    return impl_->factorize(values);
  }
  LinearSolverResult solve(const double* rhs, double* x) override {
    if (!impl_) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    return impl_->solve(rhs, x);
  }
  std::size_t factorNonZeros() const override { return impl_ ? impl_->factorNonZeros() : 0; }
  std::optional<CholeskyPrediction> analysedCost() const override {
    return impl_ ? impl_->analysedCost() : std::nullopt;
  }
  bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const override {
    return impl_ && impl_->factorPattern(col_ptr, row_idx);
  }

 private:
  Ordering ordering_;
  BlockCholeskyOptions options_;
  std::unique_ptr<detail::OrderedSolver> impl_;
};

}  // namespace

int maxBlockSize(const SparseStructure& s) {
  int size = 0;
  for (int b = 0; b < s.num_blocks; ++b) {
    size = std::max(size, s.block_starts[b + 1] - s.block_starts[b]);
  }
  return size;
}

std::unique_ptr<detail::OrderedSolver> makeBlockCholesky(Ordering ordering,
                                                         const BlockCholeskyOptions& options) {
  return std::make_unique<BlockCholeskyAny>(ordering, options);
}

}  // namespace graphslam::solvers
