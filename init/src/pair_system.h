// SPDX-License-Identifier: MIT
// The linear systems of the global SE(2) initialisation (global_se2.cpp): 2-vector
// unknowns coupled in pairs, laid out in the linear solver interface's form, and their
// solution by a LinearSolver or Eigen's simplicial LDL^T.
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/linear_solver.h"
#include "graphslam/support/block_pattern.h"

namespace graphslam::init::detail {

using SpMat = Eigen::SparseMatrix<double>;

/// A symmetric linear system over `n` variables of dimension 2, assembled straight into
/// the linear solver interface's form: upper triangle in CSC, every stored 2x2 block
/// complete (diagonal blocks full). The pattern holds every diagonal block and the blocks
/// of the given pairs of variables.
class PairSystem {
 public:
  PairSystem(int n, const std::vector<std::pair<int, int>>& pairs)
      : n_(n), pattern_(support::BlockPattern::fromPairs(n, pairs)) {
    col_ptr_.assign(2 * static_cast<std::size_t>(n) + 1, 0);
    row_idx_.reserve(4 * pattern_.rows.size());
    for (int c = 0; c < n; ++c) {
      for (int j = 0; j < 2; ++j) {
        for (int k = pattern_.ptr[c]; k < pattern_.ptr[c + 1]; ++k) {
          row_idx_.push_back(2 * pattern_.rows[k]);
          row_idx_.push_back(2 * pattern_.rows[k] + 1);
        }
        col_ptr_[2 * c + j + 1] = static_cast<int>(row_idx_.size());
      }
    }
    values_.assign(row_idx_.size(), 0.0);
    rhs_ = Eigen::VectorXd::Zero(2 * n);
  }

  /// Adds m to the block of variables (r, c) (and so m^T to (c, r)).
  void add(int r, int c, const Eigen::Matrix2d& m) {
    if (r > c) {
      add(c, r, m.transpose());
      return;
    }
    const int k = pattern_.find(r, c) - pattern_.ptr[c];
    const int stride = col_ptr_[2 * c + 1] - col_ptr_[2 * c];
    double* v = values_.data() + col_ptr_[2 * c] + 2 * k;
    v[0] += m(0, 0);
    v[1] += m(1, 0);
    v[stride] += m(0, 1);
    v[stride + 1] += m(1, 1);
  }
  /// Zero values and right-hand side: the same pattern for another system.
  void clear() {
    std::fill(values_.begin(), values_.end(), 0.0);
    rhs_.setZero();
  }
  Eigen::VectorXd& rhs() { return rhs_; }
  [[nodiscard]] const Eigen::VectorXd& rhs() const { return rhs_; }
  [[nodiscard]] int unknowns() const { return 2 * n_; }
  [[nodiscard]] const std::vector<int>& colPtr() const { return col_ptr_; }
  [[nodiscard]] const std::vector<int>& rowIdx() const { return row_idx_; }
  [[nodiscard]] const std::vector<double>& values() const { return values_; }

 private:
  int n_;
  support::BlockPattern pattern_;       // upper block pattern
  std::vector<int> col_ptr_, row_idx_;  // scalar pattern
  std::vector<double> values_;
  Eigen::VectorXd rhs_;
};

/// Solves symmetric positive definite PairSystems with `solver`, or with Eigen's
/// simplicial LDL^T when it is null. A system with the pattern of the previous one reuses
/// its symbolic analysis (ordering and all): a pose graph's orientation and position
/// systems share theirs.
class SpdSolver {
 public:
  explicit SpdSolver(LinearSolver* solver) : solver_(solver) {}

  /// Seconds spent in the linear solver's analyses (its fill-reducing ordering included).
  [[nodiscard]] double analysisSeconds() const { return analysis_seconds_; }
  /// Why the last solve() failed.
  [[nodiscard]] const std::string& failure() const { return failure_; }

  /// False on failure (failure() says why).
  bool solve(const PairSystem& sys, Eigen::VectorXd& x) {
    failure_.clear();
    const int n = sys.unknowns();
    x.resize(n);
    const bool same = analyzed_ && sys.colPtr() == col_ptr_ && sys.rowIdx() == row_idx_;
    if (!same) {
      // The solver reads these arrays until its next analysis: they live here.
      col_ptr_ = sys.colPtr();
      row_idx_ = sys.rowIdx();
      analyzed_ = false;
    }
    if (!solver_) {
      const Eigen::Map<const SpMat> a(n, n, static_cast<Eigen::Index>(row_idx_.size()),
                                      col_ptr_.data(), row_idx_.data(), sys.values().data());
      if (!same) ldlt_.analyzePattern(a);
      analyzed_ = true;
      ldlt_.factorize(a);
      if (ldlt_.info() == Eigen::Success) x = ldlt_.solve(sys.rhs());
      if (ldlt_.info() != Eigen::Success) return fail("not positive definite (singular)");
      return x.allFinite() || fail("its solution is not finite");
    }
    if (!same) {
      block_starts_.clear();
      for (int c = 0; c <= n; c += 2) block_starts_.push_back(c);
      SparseStructure st;
      st.n = n;
      st.col_ptr = col_ptr_.data();
      st.row_idx = row_idx_.data();
      st.block_starts = block_starts_.data();
      st.num_blocks = n / 2;
      const auto t0 = std::chrono::steady_clock::now();
      const LinearSolverResult analysis = solver_->analyze(st);
      analyzed_ = analysis.ok();
      analysis_seconds_ +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!analyzed_) return fail(solver_->name() + "'s analysis failed: " + analysis.message);
    }
    LinearSolverResult r = solver_->factorize(sys.values().data());
    if (r.ok()) r = solver_->solve(sys.rhs().data(), x.data());
    if (!r.ok()) return fail(solver_->name() + ": " + r.message);
    return x.allFinite() || fail("its solution is not finite");
  }

 private:
  bool fail(std::string why) {
    failure_ = std::move(why);
    return false;
  }

  LinearSolver* solver_;
  std::string failure_;
  Eigen::SimplicialLDLT<SpMat, Eigen::Upper> ldlt_;
  std::vector<int> col_ptr_, row_idx_, block_starts_;
  bool analyzed_ = false;
  double analysis_seconds_ = 0.0;
};

}  // namespace graphslam::init::detail
