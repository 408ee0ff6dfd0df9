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
//
// A two-way solver takes both kinds of values on one analysis: the orientation and the
// position systems of the SE(2) initial guess have one pattern, so B's layout, its order
// and CHOLMOD's symbolic factor serve both (CHOLMOD's factor switches between complex and
// real values); the d components of an isotropic right-hand side are solved in one pass.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "common.h"
#include "factories.h"
#include "ordering.h"
#include "symbolic.h"
#include "tail_cholesky.h"
#ifdef GRAPHSLAM_HAVE_CHOLMOD
#include "suitesparse.h"
#endif

namespace graphslam::solvers {

namespace {

/// Off-diagonal entries of a block, and differences between its diagonal entries, must
/// be below this fraction of its (0, 0) entry.
constexpr double kRelativeTolerance = 1e-12;

class IsotropicSolver final : public detail::OrderedSolver {
 public:
  /// `conformal`: takes blocks [a -b; b a]; `isotropic`: takes H_s (x) I_d (both: a
  /// two-way solver, vertices of dimension 2).
  IsotropicSolver(Ordering ordering, bool conformal, bool isotropic, const SolverOptions& options)
      : ordering_(ordering),
        conformal_(conformal),
        isotropic_(isotropic),
        complex_values_(conformal),
        options_(options.isotropic),
        model_(options.auto_solver.cost_model),
        cholmod_options_(options.cholmod),
        block_options_(options.block_cholesky) {}

  std::string name() const override {
    if (conformal_ && isotropic_) return "conformal and isotropic";
    return conformal_ ? "conformal" : "isotropic";
  }
  Ordering ordering() const override { return ordering_; }

  LinearSolverResult analyzeOrdered(const SparseStructure& s, std::vector<int> order,
                                    Ordering label) override {
    ordering_ = label;
    inner_.reset();
    complex_values_ = conformal_;  // a conformal inner solver starts complex
#ifdef GRAPHSLAM_HAVE_LAPACK
    tail_ = nullptr;
#endif
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
    // The block order (every d-th scalar column of the block-expanded order). H_s is laid
    // out in that order (B = P H_s P^T), for CHOLMOD postordered by its elimination tree,
    // so that the inner solver factorises B in its natural order and never permutes.
    block_order_.clear();
    block_order_.reserve(static_cast<std::size_t>(nb_));
    bool identity_order = true;
    for (std::size_t k = 0; k < order.size(); k += static_cast<std::size_t>(d_)) {
      identity_order = identity_order && order[k] / d_ == static_cast<int>(block_order_.size());
      block_order_.push_back(order[k] / d_);
    }
    // Entries of H_s: block (r, c) of H's stored triangle (r <= c, or r >= c for the lower
    // one) is entry (r, c); its value is H's entry at the block's (0, 0), at the position
    // of row r*d in column c*d (every d-th entry of column c*d: blocks are complete); a
    // conformal block's imaginary part is its (0, 1) entry, at the same place in the next
    // column. In the identity order from H's upper triangle they already are B's upper
    // triangle, column by column with rows ascending: laid out directly.
    const bool direct = identity_order && !conformal_ && !s.lower;
    for (auto* v : {&entry_row_, &entry_col_, &entry_pos_, &entry_pos01_, &row_idx_, &source_}) {
      v->clear();
    }
    col_ptr_.assign(static_cast<std::size_t>(nb_) + 1, 0);
    if (direct) {  // at most one entry per stored block of H
      row_idx_.reserve(s.nnz() / static_cast<std::size_t>(d_ * d_));
      source_.reserve(s.nnz() / static_cast<std::size_t>(d_ * d_));
    }
    // A fixed block size divides by shifts and multiplications.
    const int incomplete = detail::withFixedSize(
        d_, [&](auto size) { return readEntries<decltype(size)::value>(s, direct); });
    if (incomplete >= 0) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "isotropic: column " + std::to_string(incomplete) +
              " does not store complete blocks (as SparseStructure asks)",
          incomplete);
    }
    h_ = s;
    if (direct) {
      setScalar();
    } else {
      buildPermuted(false);  // B's upper triangle in the given order: its cost and tree
    }
    std::vector<int> identity(static_cast<std::size_t>(nb_));
    std::iota(identity.begin(), identity.end(), 0);
    std::vector<int> parent, counts;
#ifdef GRAPHSLAM_HAVE_LAPACK
    // tail-llt: a dense tail holding most of the flops (landmarks seen from most poses)
    // gets its Schur complement from BLAS, the cheap columns before it (or all columns of
    // a small system) a left-looking loop, without CHOLMOD's supernodal analysis and
    // per-supernode work. It takes B's upper triangle as it is, and declines when its
    // loop would cost more than CHOLMOD's supernodal factorisation of the whole (the cost
    // model's crossing point), leaving its elimination tree and column counts.
    if (!conformal_ && scalar_.nnz() <= options_.tail_probe_entries) {
      auto tail = std::make_unique<detail::TailCholesky>(supernodalFrom(nb_));
      if (tail->analyzeOrdered(scalar_, identity, label).ok()) {
        tail_ = tail.get();
        inner_ = std::move(tail);
        freeEntries();
        return LinearSolverResult::success();
      }
      parent = tail->parent();
      counts = tail->counts();
    }
#endif
    detail::SymbolicCost cost;
    if (static_cast<int>(counts.size()) == nb_) {
      for (const int c : counts) cost.flops += static_cast<double>(c) * c;
    } else {
      cost = detail::symbolicCostNatural(scalar_, &parent, &counts);
    }
    // A complex multiply-add is four real ones.
    const bool supernodal = (conformal_ ? 4.0 : 1.0) * cost.flops > supernodalFrom(nb_);
#ifdef GRAPHSLAM_HAVE_CHOLMOD
    if (conformal_) {
      inner_ = makeCholmodComplexSolver(supernodal, label, true, cholmod_options_);
    } else if (supernodal) {
      inner_ = makeCholmodSolver(true, label, true, cholmod_options_);
    }
#else
    static_cast<void>(supernodal);  // block-llt for every size
    if (conformal_) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                         "conformal: needs CHOLMOD (SuiteSparse)");
    }
#endif
    if (inner_) {
      // CHOLMOD: the same fill, with each subtree's columns contiguous (its supernodes),
      // and B's lower triangle.
      if (direct) entriesOfB();  // B is laid out again, postordered
      const std::vector<int> post = detail::postorder(parent, counts);
      std::vector<int> composed(static_cast<std::size_t>(nb_));
      for (int k = 0; k < nb_; ++k) composed[k] = block_order_[post[k]];
      block_order_ = std::move(composed);
      buildPermuted(true);
    } else {
      // block-llt's up-looking factorisation needs no postorder: B's upper triangle as it is.
      inner_ = makeBlockCholesky(Ordering::kNatural, block_options_);
    }
    freeEntries();
    return inner_->analyzeOrdered(scalar_, std::move(identity), label);
  }

  LinearSolverResult factorize(const double* h) override {
    if (!inner_) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
    // A two-way solver takes isotropic values when they are, else conformal ones.
    if (conformal_ && !(isotropic_ && detail::firstNonIsotropicColumn(h_, h) < 0)) {
      return factorizeConformal(h);
    }
    if (conformal_ && !inner_->setComplexValues(false)) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                         name() + ": the inner solver takes no real values");
    }
    complex_values_ = false;
    const int bad = detail::firstNonIsotropicColumn(h_, h);
    if (bad >= 0) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          name() + ": H is not H_s (x) I_" + std::to_string(d_) + ": a block of columns " +
              std::to_string(bad - bad % d_) + ".." + std::to_string(bad - bad % d_ + d_ - 1) +
              " is not a multiple of the identity",
          bad);
    }
    values_.resize(source_.size());
    for (std::size_t k = 0; k < source_.size(); ++k) values_[k] = h[source_[k]];
    LinearSolverResult r = inner_->factorize(values_.data());
    // B's column k is the vertex block_order_[k]: its first column in H.
    if (!r.ok() && r.column >= 0) r.column = block_order_[r.column] * d_;
    return r;
  }

  LinearSolverResult solve(const double* rhs, double* x) override {
    if (!inner_) return LinearSolverResult::failure(LinearSolverStatus::kFailure, "not analysed");
#ifdef GRAPHSLAM_HAVE_LAPACK
    if (tail_) {
      return solveInterleaved(rhs, x, [this](double* b) { return tail_->solveInterleaved(b, d_); });
    }
#endif
    // H's unknowns (x_0, x_1) per vertex are the interleaved complex z = x_0 + i x_1;
    // real values: the d components are d right-hand sides of B, one column each.
    const int per = complex_values_ ? 2 : 1;  // doubles per unknown of B
    const int columns = complex_values_ ? 1 : d_;
    const std::size_t nb = static_cast<std::size_t>(nb_);
    b_.resize(nb * per * columns);
    y_.resize(nb * per * columns);
    for (int j = 0; j < columns; ++j) {
      for (int k = 0; k < nb_; ++k) {
        for (int t = 0; t < per; ++t) b_[j * nb + k * per + t] = rhs[block_order_[k] * d_ + j + t];
      }
    }
    const LinearSolverResult r = inner_->solveColumns(b_.data(), y_.data(), nb_, columns);
    if (!r.ok()) return r;
    for (int j = 0; j < columns; ++j) {
      for (int k = 0; k < nb_; ++k) {
        for (int t = 0; t < per; ++t) x[block_order_[k] * d_ + j + t] = y_[j * nb + k * per + t];
      }
    }
    return LinearSolverResult::success();
  }

  std::size_t factorNonZeros() const override {
    if (!inner_) return 0;
    // Conformal: a complex entry is a 2x2 real block (3 entries on the diagonal).
    if (complex_values_) return inner_->factorNonZeros() * 4 - static_cast<std::size_t>(nb_);
    // L = L_s (x) I_d: d entries per non-zero of L_s.
    return inner_->factorNonZeros() * static_cast<std::size_t>(d_);
  }

 private:
  /// The d components of every unknown in one pass: H's interleaved layout permuted to
  /// B's order, solved in place by `solve_b`, and back.
  template <typename SolveB>
  LinearSolverResult solveInterleaved(const double* rhs, double* x, SolveB&& solve_b) {
    b_.resize(static_cast<std::size_t>(nb_) * d_);
    for (int k = 0; k < nb_; ++k) {
      for (int j = 0; j < d_; ++j) b_[k * d_ + j] = rhs[block_order_[k] * d_ + j];
    }
    const LinearSolverResult r = solve_b(b_.data());
    if (!r.ok()) return r;
    for (int k = 0; k < nb_; ++k) {
      for (int j = 0; j < d_; ++j) x[block_order_[k] * d_ + j] = b_[k * d_ + j];
    }
    return r;
  }

  LinearSolverResult factorizeConformal(const double* h) {
    const int bad = detail::firstNonConformalColumn(h_, h);
    if (bad >= 0) {
      return LinearSolverResult::failure(
          LinearSolverStatus::kFailure,
          "conformal: a block of columns " + std::to_string(bad - bad % 2) + ".." +
              std::to_string(bad - bad % 2 + 1) + " is not of the form [a -b; b a]",
          bad);
    }
    if (isotropic_ && !inner_->setComplexValues(true)) {
      return LinearSolverResult::failure(LinearSolverStatus::kFailure,
                                         name() + ": the inner solver takes no complex values");
    }
    complex_values_ = true;
    // Entry (r, c) of M (a block of H's stored triangle): a + ib for H's block
    // [a -b; b a]; b is read from the block's (0, 1) entry (diagonal entries are real). An
    // entry the permutation moved to the other triangle is M(c, r) = conj(M(r, c)).
    values_.resize(2 * source_.size());
    for (std::size_t k = 0; k < source_.size(); ++k) {
      values_[2 * k] = h[source_[k]];
      values_[2 * k + 1] = imag_sign_[k] * h[source01_[k]];
    }
    LinearSolverResult r = inner_->factorize(values_.data());
    if (!r.ok() && r.column >= 0) r.column = block_order_[r.column] * 2;
    return r;
  }

  /// The entry lists of a B laid out directly in the identity order (its upper triangle).
  void entriesOfB() {
    entry_row_ = row_idx_;
    entry_pos_ = source_;
    entry_col_.resize(row_idx_.size());
    for (int c = 0; c < nb_; ++c) {
      std::fill(entry_col_.begin() + col_ptr_[c], entry_col_.begin() + col_ptr_[c + 1], c);
    }
  }

  /// Reads H_s's entries out of H (blocks of D x D; D = 0: d_): into B's arrays
  /// (`direct`) or the entry lists. The first column of H that does not store complete
  /// blocks, or -1.
  template <int D>
  int readEntries(const SparseStructure& s, bool direct) {
    const int d = D > 0 ? D : d_;
    for (int c = 0; c < nb_; ++c) {
      const int col = c * d;
      int stored = 0;
      for (int p = s.col_ptr[col]; p < s.col_ptr[col + 1]; p += d) {
        const int row = s.row_idx[p];
        const int block = row / d;
        if (row != block * d) return col;
        if (s.lower ? row < col : row > col) continue;
        ++stored;
        if (direct) {
          row_idx_.push_back(block);
          source_.push_back(p);
          continue;
        }
        entry_row_.push_back(block);
        entry_col_.push_back(c);
        entry_pos_.push_back(p);
        if (conformal_) entry_pos01_.push_back(s.col_ptr[col + 1] + (p - s.col_ptr[col]));
      }
      col_ptr_[c + 1] = static_cast<int>(row_idx_.size());
      for (int j = 0; j < d; ++j) {
        if (s.col_ptr[col + j + 1] - s.col_ptr[col + j] != stored * d) return col + j;
      }
    }
    return -1;
  }

  /// The entry lists served only to lay B out (source_ maps B to H from then on).
  void freeEntries() {
    for (auto* v : {&entry_row_, &entry_col_, &entry_pos_, &entry_pos01_}) {
      std::vector<int>().swap(*v);
    }
  }

  /// Lays H_s out as B = P H_s P^T (P from block_order_), its upper triangle or (`lower`)
  /// its lower one, rows sorted in every column, into scalar_, with the position in H's
  /// values of every entry (source_, and source01_ / imag_sign_ for conformal blocks).
  /// Two counting passes: the entries are bucketed by their row in B, then appended to
  /// their columns row by row.
  void buildPermuted(bool lower) {
    std::vector<int> pos(static_cast<std::size_t>(nb_));
    for (int k = 0; k < nb_; ++k) pos[block_order_[k]] = k;
    const std::size_t m = entry_pos_.size();
    std::vector<int> row_of(m), col_of(m);  // every entry's place in B
    std::vector<int> row_start(static_cast<std::size_t>(nb_) + 1, 0);
    col_ptr_.assign(static_cast<std::size_t>(nb_) + 1, 0);
    for (std::size_t e = 0; e < m; ++e) {
      const int a = pos[entry_row_[e]], b = pos[entry_col_[e]];
      row_of[e] = lower ? std::max(a, b) : std::min(a, b);
      col_of[e] = lower ? std::min(a, b) : std::max(a, b);
      ++row_start[row_of[e] + 1];
      ++col_ptr_[col_of[e] + 1];
    }
    for (int k = 0; k < nb_; ++k) {
      row_start[k + 1] += row_start[k];
      col_ptr_[k + 1] += col_ptr_[k];
    }
    std::vector<int> by_row(m);  // entries grouped by their row in B
    for (std::size_t e = 0; e < m; ++e) by_row[row_start[row_of[e]]++] = static_cast<int>(e);
    row_idx_.resize(m);
    source_.resize(m);
    source01_.resize(conformal_ ? m : 0);
    imag_sign_.resize(conformal_ ? m : 0);
    std::vector<int> next(col_ptr_.begin(), col_ptr_.end() - 1);
    for (const int e : by_row) {  // rows in increasing order: sorted within every column
      const int i = row_of[e];
      const int at = next[col_of[e]]++;
      row_idx_[at] = i;
      source_[at] = entry_pos_[e];
      if (conformal_) {
        // B(i, j) = M(r, c) when row i holds r, else conj(M(r, c)); M's imaginary part
        // is minus the block's (0, 1) entry.
        // A diagonal entry is real (its (0, 1) entry may lie in the triangle not read).
        source01_[at] = entry_pos01_[e];
        imag_sign_[at] = entry_row_[e] == entry_col_[e] ? 0.0
                         : pos[entry_row_[e]] == i      ? -1.0
                                                        : 1.0;
      }
    }
    setScalar();
  }

  /// scalar_ describes B (col_ptr_, row_idx_) as 1 x 1 blocks.
  void setScalar() {
    block_starts_.resize(static_cast<std::size_t>(nb_) + 1);
    std::iota(block_starts_.begin(), block_starts_.end(), 0);
    scalar_.n = nb_;
    scalar_.col_ptr = col_ptr_.data();
    scalar_.row_idx = row_idx_.data();
    scalar_.block_starts = block_starts_.data();
    scalar_.num_blocks = nb_;
  }

  Ordering ordering_;
  bool conformal_ = false;       // takes conformal values (B's layout has their imaginary parts)
  bool isotropic_ = true;        // takes isotropic values
  bool complex_values_ = false;  // the last factorisation's values were conformal
  IsotropicSolverOptions options_;
  /// The flops above which the cost model predicts CHOLMOD's supernodal factorisation of a
  /// scalar system of n unknowns faster than block-llt's (infinite when never).
  [[nodiscard]] double supernodalFrom(int n) const {
    const CostModel& model = model_ ? *model_ : CostModel::builtIn();
    const CostLine& loop = model.block_llt[0];
    const CostLine& cholmod = model.cholmod_supernodal;
    if (loop.per_flop <= cholmod.per_flop) return std::numeric_limits<double>::infinity();
    const double fixed = cholmod.predict(n, 0.0) - loop.predict(n, 0.0);
    return std::max(0.0, fixed / (loop.per_flop - cholmod.per_flop));
  }

  std::shared_ptr<const CostModel> model_;  // of the auto solver's options (null: built in)
  CholmodOptions cholmod_options_;          // of a CHOLMOD inner solver
  BlockCholeskyOptions block_options_;      // of a block-llt inner solver
  std::unique_ptr<detail::OrderedSolver> inner_;
#ifdef GRAPHSLAM_HAVE_LAPACK
  detail::TailCholesky* tail_ = nullptr;  // inner_ when it is tail-llt
#endif
  int nb_ = 0, d_ = 1;
  SparseStructure h_;  // H's structure (its arrays live until the next analysis)
  // H_s's entries in H's order: block row, block column, positions in H's values.
  std::vector<int> entry_row_, entry_col_, entry_pos_, entry_pos01_;
  std::vector<int> block_order_;  // B's column k is H_s's column block_order_[k]
  std::vector<int> col_ptr_, row_idx_, source_, source01_, block_starts_;
  std::vector<double> imag_sign_;
  SparseStructure scalar_;
  std::vector<double> values_, b_, y_;
};

}  // namespace

namespace detail {

namespace {
/// firstNonIsotropicColumn for blocks of D x D (D > 0) or of any size d (D = 0): the
/// loops over a block unrolled when D is fixed.
template <int D>
int firstNonIsotropicColumnOf(const SparseStructure& s, const double* h, int d) {
  if constexpr (D > 0) d = D;
  for (int c = 0; c < s.num_blocks; ++c) {
    const int first = s.block_starts[c];
    if (s.block_starts[c + 1] - first != d) return first;
    if constexpr (D == 2) {
      // Both columns of the block column at once, without a branch per entry; the
      // entry-by-entry pass below names the column only when a block fails.
      const int stored = s.col_ptr[first + 1] - s.col_ptr[first];
      if (s.col_ptr[first + 2] - s.col_ptr[first + 1] != stored) return first + 1;
      const double* c0 = h + s.col_ptr[first];
      const double* c1 = h + s.col_ptr[first + 1];
      const int* rows = s.row_idx + s.col_ptr[first];
      bool ok = true;
      for (int k = 0; k < stored; k += 2) {
        const double v = c0[k];
        const double tol = kRelativeTolerance * std::abs(v);
        // The diagonal block stores both triangles: (1, 0) is not read from the upper
        // one, (0, 1) not from the lower one.
        const bool diagonal = rows[k] == first;
        const bool lower10 = (diagonal && !s.lower) || std::abs(c0[k + 1]) <= tol;
        const bool upper01 = (diagonal && s.lower) || std::abs(c1[k]) <= tol;
        ok = ok & lower10 & upper01 & (std::abs(c1[k + 1] - v) <= tol);
      }
      if (ok) continue;
    }
    // Block k of the column starts at entry k*d of every column of the block column
    // (complete blocks); its (0, 0) entry is v, every entry must be v I.
    const int stored = s.col_ptr[first + 1] - s.col_ptr[first];
    const double* v0 = h + s.col_ptr[first];
    for (int j = 0; j < d; ++j) {
      const int col = first + j;
      if (s.col_ptr[col + 1] - s.col_ptr[col] != stored) return col;
      const double* column = h + s.col_ptr[col];
      const int* rows = s.row_idx + s.col_ptr[col];
      for (int k = 0; k < stored; k += d) {
        const double v = v0[k];
        const double tol = kRelativeTolerance * std::abs(v);
        // The diagonal block stores both triangles; the one not read is skipped.
        const bool diagonal = rows[k] == first;
        for (int i = 0; i < d; ++i) {
          if (diagonal && (s.lower ? i < j : i > j)) continue;
          const double expected = i == j ? v : 0.0;
          if (!(std::abs(column[k + i] - expected) <= tol)) return col;
        }
      }
    }
  }
  return -1;
}
}  // namespace

int firstNonIsotropicColumn(const SparseStructure& s, const double* h) {
  if (s.num_blocks == 0) return -1;
  const int d = s.block_starts[1] - s.block_starts[0];
  return withFixedSize(
      d, [&](auto size) { return firstNonIsotropicColumnOf<decltype(size)::value>(s, h, d); });
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
      const bool diagonal = s.row_idx[p0] == first;
      const double a = h[p0];
      // A diagonal block's b is read from the triangle stored: (0, 1) holds -b, (1, 0) b.
      const double b = diagonal && s.lower ? h[p0 + 1] : -h[p1];
      const double tol = kRelativeTolerance * (std::abs(a) + std::abs(b));
      if (!(std::abs(h[p1 + 1] - a) <= tol)) return first + 1;
      // Diagonal block: symmetric, so b = 0; otherwise (1, 0) = b.
      if (diagonal ? !(std::abs(b) <= tol) : !(std::abs(h[p0 + 1] - b) <= tol)) return first;
    }
  }
  return -1;
}

}  // namespace detail

std::unique_ptr<detail::OrderedSolver> makeIsotropicSolver(Ordering ordering,
                                                           const SolverOptions& options) {
  return std::make_unique<IsotropicSolver>(ordering, false, true, options);
}

std::unique_ptr<detail::OrderedSolver> makeConformalSolver(Ordering ordering,
                                                           const SolverOptions& options) {
  return std::make_unique<IsotropicSolver>(ordering, true, false, options);
}

std::unique_ptr<detail::OrderedSolver> makeTwoWayIsotropicSolver(Ordering ordering,
                                                                 const SolverOptions& options) {
  return std::make_unique<IsotropicSolver>(ordering, true, true, options);
}

}  // namespace graphslam::solvers
