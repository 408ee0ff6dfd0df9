// SPDX-License-Identifier: MIT
#include "separator_cg.h"

#include <Eigen/Cholesky>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <algorithm>
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

int dimension(const BlockUpperCsc& s, int b) { return s.block_starts[b + 1] - s.block_starts[b]; }

/// The blocks of each aggregate, increasing.
std::vector<std::vector<int>> aggregateMembers(const BlockUpperCsc& s) {
  std::vector<std::vector<int>> members(static_cast<std::size_t>(s.num_groups));
  for (int b = 0; b < s.num_blocks; ++b)
    members[static_cast<std::size_t>(s.block_group[b])].push_back(b);
  return members;
}

/// The preconditioner's local level: the Cholesky factors of S + lambda I restricted to
/// groups of blocks, and z = M^-1 r with them. A group is one block, or a chunk of an
/// aggregate's blocks: every submap that touches one block of an aggregate touches all of
/// them, so all of a chunk's blocks (a, b) are stored.
class LocalBlocks {
 public:
  /// Each block alone when `max_dimension` is 0 or there are no aggregates; else each
  /// aggregate's blocks in chunks of at most `max_dimension` columns (or one block).
  void group(const BlockUpperCsc& s, int max_dimension,
             const std::vector<std::vector<int>>& aggregates) {
    groups_.clear();
    if (max_dimension <= 0 || s.block_group == nullptr) {
      for (int b = 0; b < s.num_blocks; ++b) groups_.push_back({b});
      return;
    }
    for (const std::vector<int>& members : aggregates) {
      int columns = max_dimension;
      for (int b : members) {
        if (columns + dimension(s, b) > max_dimension) {
          groups_.emplace_back();
          columns = 0;
        }
        groups_.back().push_back(b);
        columns += dimension(s, b);
      }
    }
  }
  /// False, with the group's index in `bad_group`, when a group's matrix is not positive
  /// definite.
  bool compute(const BlockUpperCsc& s, double lambda, int& bad_group) {
    factors_.resize(groups_.size());
    Eigen::Index widest = 0;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      factors_[g].compute(gather(s, groups_[g], lambda));
      widest = std::max(widest, factors_[g].rows());
      if (factors_[g].info() != Eigen::Success) {
        bad_group = static_cast<int>(g);
        return false;
      }
    }
    scratch_.resize(widest);
    return true;
  }
  void apply(const BlockUpperCsc& s, const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      auto local = scratch_.head(factors_[g].rows());  // no allocation per group and iteration
      int k = 0;
      for (int b : groups_[g]) {
        for (int c = s.block_starts[b]; c < s.block_starts[b + 1]; ++c) local[k++] = r[c];
      }
      factors_[g].solveInPlace(local);
      k = 0;
      for (int b : groups_[g]) {
        for (int c = s.block_starts[b]; c < s.block_starts[b + 1]; ++c) z[c] = local[k++];
      }
    }
  }
  /// "the diagonal block of separator columns F-L" of the group's first block, and how
  /// many blocks it has more.
  [[nodiscard]] std::string describe(const BlockUpperCsc& s, int g) const {
    const std::vector<int>& blocks = groups_[static_cast<std::size_t>(g)];
    const int b = blocks.front();
    std::string text = "the diagonal block of separator columns " +
                       std::to_string(s.block_starts[b]) + "-" +
                       std::to_string(s.block_starts[b + 1] - 1);
    if (blocks.size() > 1) {
      text += " (factorised with " + std::to_string(blocks.size() - 1) +
              " more block(s) of its aggregate)";
    }
    return text;
  }

 private:
  /// S + lambda I on the group's columns, dense (blocks the storage leaves out are zero).
  static Eigen::MatrixXd gather(const BlockUpperCsc& s, const std::vector<int>& blocks,
                                double lambda) {
    std::vector<int> offset(1, 0);
    for (int b : blocks) offset.push_back(offset.back() + dimension(s, b));
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(offset.back(), offset.back());
    for (std::size_t j = 0; j < blocks.size(); ++j) {
      const int b = blocks[j], first = s.block_starts[b];
      const int* rows = s.row_idx + s.col_ptr[first];
      const int* rows_end = s.row_idx + s.col_ptr[first + 1];
      for (std::size_t i = 0; i <= j; ++i) {  // the blocks increase: (a, b) is an upper block
        const int a = blocks[i];
        const int* at = std::lower_bound(rows, rows_end, s.block_starts[a]);
        if (at == rows_end || *at != s.block_starts[a]) continue;
        for (int c = 0; c < dimension(s, b); ++c) {
          const double* column = s.values + s.col_ptr[first + c] + (at - rows);
          for (int x = 0; x < dimension(s, a); ++x) {
            m(offset[i] + x, offset[j] + c) = column[x];
            m(offset[j] + c, offset[i] + x) = column[x];
          }
        }
      }
    }
    m.diagonal().array() += lambda;
    return m;
  }

  std::vector<std::vector<int>> groups_;  // blocks, increasing
  mutable Eigen::VectorXd scratch_;       // as long as the widest group
  std::vector<Eigen::LLT<Eigen::MatrixXd>> factors_;
};

/// The preconditioner's coarse level: z += Z E^-1 Z^T r, where Z's column (g, c) is the
/// indicator of component c of aggregate g's blocks (the aggregate moved as one) and
/// E = Z^T (S + lambda I) Z, sparse: aggregates couple where a submap touches both.
class CoarseSpace {
 public:
  /// False when E is not positive definite.
  bool compute(const BlockUpperCsc& s, double lambda,
               const std::vector<std::vector<int>>& aggregates) {
    llt_.compute(matrix(s, lambda, aggregates));
    restricted_.resize(offsets_.back());
    solved_.resize(offsets_.back());
    return llt_.info() == Eigen::Success;
  }
  /// E = Z^T (S + lambda I) Z; `aggregates` lists each aggregate's blocks.
  Eigen::SparseMatrix<double> matrix(const BlockUpperCsc& s, double lambda,
                                     const std::vector<std::vector<int>>& aggregates) {
    numberUnknowns(s);
    std::vector<Eigen::Triplet<double>> triplets;
    assemble(s, aggregates, triplets);
    for (int b = 0; b < s.num_blocks; ++b) {
      for (int c = 0; c < dimension(s, b); ++c) {
        triplets.emplace_back(unknown(s, b, c), unknown(s, b, c), lambda);
      }
    }
    Eigen::SparseMatrix<double> e(offsets_.back(), offsets_.back());
    e.setFromTriplets(triplets.begin(), triplets.end());
    return e;
  }
  void addCorrection(const BlockUpperCsc& s, const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
    restricted_.setZero();
    for (int b = 0; b < s.num_blocks; ++b) {
      for (int c = 0; c < dimension(s, b); ++c)
        restricted_[unknown(s, b, c)] += r[s.block_starts[b] + c];
    }
    solved_ = llt_.solve(restricted_);  // both sized by compute(): no allocation per iteration
    for (int b = 0; b < s.num_blocks; ++b) {
      for (int c = 0; c < dimension(s, b); ++c)
        z[s.block_starts[b] + c] += solved_[unknown(s, b, c)];
    }
  }

 private:
  /// What column blocks of one aggregate add to E's blocks with one row aggregate.
  struct Sum {
    int group;
    Eigen::MatrixXd direct;    // E(row aggregate, this aggregate): every entry
    Eigen::MatrixXd mirrored;  // E(this aggregate, row aggregate)^T: off-diagonal blocks' entries
  };

  [[nodiscard]] int unknown(const BlockUpperCsc& s, int block, int component) const {
    return offsets_[static_cast<std::size_t>(s.block_group[block])] + component;
  }
  [[nodiscard]] int width(int group) const {
    return offsets_[static_cast<std::size_t>(group) + 1] -
           offsets_[static_cast<std::size_t>(group)];
  }

  /// An aggregate has as many unknowns as its widest block has components.
  void numberUnknowns(const BlockUpperCsc& s) {
    std::vector<int> widths(static_cast<std::size_t>(s.num_groups), 0);
    block_of_row_.resize(static_cast<std::size_t>(s.n));
    for (int b = 0; b < s.num_blocks; ++b) {
      int& w = widths[static_cast<std::size_t>(s.block_group[b])];
      w = std::max(w, dimension(s, b));
      std::fill(block_of_row_.begin() + s.block_starts[b],
                block_of_row_.begin() + s.block_starts[b + 1], b);
    }
    offsets_.assign(1, 0);
    for (int w : widths) offsets_.push_back(offsets_.back() + w);
  }

  /// E's triplets, aggregate by aggregate: its column blocks are summed into one dense
  /// block per row aggregate first, so E's assembly holds a few triplets per pair of
  /// aggregates, not one per entry of S.
  void assemble(const BlockUpperCsc& s, const std::vector<std::vector<int>>& members,
                std::vector<Eigen::Triplet<double>>& triplets) const {
    std::vector<int> slot(static_cast<std::size_t>(s.num_groups), -1);
    std::vector<Sum> sums;
    for (int g = 0; g < s.num_groups; ++g) {
      for (int b : members[static_cast<std::size_t>(g)]) addColumnBlock(s, b, slot, sums);
      for (const Sum& sum : sums) {
        for (int c = 0; c < width(g); ++c) {
          for (int x = 0; x < width(sum.group); ++x) {
            const int row = offsets_[static_cast<std::size_t>(sum.group)] + x;
            const int col = offsets_[static_cast<std::size_t>(g)] + c;
            triplets.emplace_back(row, col, sum.direct(x, c));
            triplets.emplace_back(col, row, sum.mirrored(x, c));
          }
        }
        slot[static_cast<std::size_t>(sum.group)] = -1;
      }
      sums.clear();
    }
  }

  /// Adds column block b's stored blocks (a, b) to the sums of their row aggregates. Every
  /// column of a block holds the same rows, so the first column's rows name them.
  void addColumnBlock(const BlockUpperCsc& s, int b, std::vector<int>& slot,
                      std::vector<Sum>& sums) const {
    const int first = s.block_starts[b], top = s.col_ptr[first];
    const int wb = width(s.block_group[b]);
    for (int q = top; q < s.col_ptr[first + 1];) {
      const int a = block_of_row_[static_cast<std::size_t>(s.row_idx[q])];
      const int h = s.block_group[a];
      int& k = slot[static_cast<std::size_t>(h)];
      if (k < 0) {
        k = static_cast<int>(sums.size());
        sums.push_back(
            {h, Eigen::MatrixXd::Zero(width(h), wb), Eigen::MatrixXd::Zero(width(h), wb)});
      }
      Sum& sum = sums[static_cast<std::size_t>(k)];
      for (int c = 0; c < dimension(s, b); ++c) {
        const double* column = s.values + s.col_ptr[first + c] + (q - top);
        for (int x = 0; x < dimension(s, a); ++x) {
          sum.direct(x, c) += column[x];
          if (a != b) sum.mirrored(x, c) += column[x];
        }
      }
      q += dimension(s, a);
    }
  }

  std::vector<int> offsets_;       // first unknown of each aggregate; one more: E's dimension
  std::vector<int> block_of_row_;  // the block of each row of S
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt_;
  mutable Eigen::VectorXd restricted_, solved_;  // Z^T r and E^-1 Z^T r
};

}  // namespace

Eigen::MatrixXd coarseSystem(const BlockUpperCsc& s, double lambda) {
  return Eigen::MatrixXd(CoarseSpace().matrix(s, lambda, aggregateMembers(s)));
}

CgOutcome solveByConjugateGradients(const BlockUpperCsc& s, double lambda, const Eigen::VectorXd& b,
                                    Eigen::VectorXd& x, double tolerance, int max_iterations,
                                    const CgPreconditioner& preconditioner) {
  CgOutcome out;
  x.setZero(s.n);
  const double b_norm = b.norm();
  if (b_norm == 0.0) {
    out.ok = true;
    return out;
  }
  const std::vector<std::vector<int>> aggregates =
      s.block_group != nullptr ? aggregateMembers(s) : std::vector<std::vector<int>>{};
  LocalBlocks local;
  local.group(s, preconditioner.local_dimension, aggregates);
  int bad_group = -1;
  if (!local.compute(s, lambda, bad_group)) {
    out.message = local.describe(s, bad_group) + " is not positive definite";
    return out;
  }
  const bool two_level = preconditioner.coarse_level && s.block_group != nullptr;
  CoarseSpace coarse;
  if (two_level && !coarse.compute(s, lambda, aggregates)) {
    out.message = "the coarse system of its " + std::to_string(s.num_groups) +
                  " aggregates is not positive definite";
    return out;
  }
  const auto precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    local.apply(s, r, z);
    if (two_level) coarse.addCorrection(s, r, z);
  };
  Eigen::VectorXd r = b, z(s.n), p(s.n), q(s.n);
  precondition(r, z);
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
    precondition(r, z);
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
