// SPDX-License-Identifier: MIT
#include "block_factor.h"

#include <algorithm>
#include <numeric>

#include <Eigen/Cholesky>

#include "ordering.h"

namespace graphslam::incremental {

using Eigen::Index;
using MatrixMap = Eigen::Map<Eigen::MatrixXd>;
using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd>;
using ConstVectorMap = Eigen::Map<const Eigen::VectorXd>;

void ColumnBuilder::begin(int p, const std::vector<int>& dims) {
  for (int q : rows_) slot_of_[q] = -1;
  if (slot_of_.size() < dims.size()) slot_of_.resize(dims.size(), -1);
  p_ = p;
  dims_ = &dims;
  rows_.assign(1, p);
  offsets_.assign(1, 0);
  slot_of_[p] = 0;
  values_.assign(static_cast<std::size_t>(dims[p]) * dims[p], 0.0);
  rhs_.assign(dims[p], 0.0);
}

Eigen::Map<Eigen::MatrixXd> ColumnBuilder::block(int q) {
  const int dp = (*dims_)[p_];
  int slot = slot_of_[q];
  if (slot < 0) {
    slot = static_cast<int>(rows_.size());
    slot_of_[q] = slot;
    rows_.push_back(q);
    offsets_.push_back(static_cast<int>(values_.size()));
    values_.resize(values_.size() + static_cast<std::size_t>((*dims_)[q]) * dp, 0.0);
  }
  return {values_.data() + offsets_[slot], (*dims_)[q], dp};
}

Eigen::Map<Eigen::VectorXd> ColumnBuilder::rhs() {
  return {rhs_.data(), static_cast<Index>(rhs_.size())};
}

void BlockFactor::clear() {
  dims_.clear();
  starts_.assign(1, 0);
  pos_.clear();
  node_at_.clear();
  columns_.clear();
  row_of_.clear();
  y_.clear();
  x_.clear();
  affected_.clear();
}

int BlockFactor::add(int dim) {
  const int node = size();
  dims_.push_back(dim);
  if (starts_.empty()) starts_.push_back(0);
  starts_.push_back(starts_.back() + dim);
  pos_.push_back(node);
  node_at_.push_back(node);
  columns_.emplace_back();
  row_of_.emplace_back();
  y_.resize(starts_.back(), 0.0);
  x_.resize(starts_.back(), 0.0);
  affected_.push_back(0);
  return node;
}

std::size_t BlockFactor::offDiagonalBlocks() const {
  std::size_t blocks = 0;
  for (const Column& c : columns_) blocks += c.rows.size();
  return blocks;
}

BlockFactor::Result BlockFactor::refactor(const std::vector<int>& changed,
                                          const std::vector<int>& last,
                                          const Neighbors& neighbors, const Assemble& assemble) {
  const std::vector<int> affected = affectedNodes(changed);
  moveToEnd(affected, orderAffected(affected, last, neighbors));
  Result result;
  for (int p = size() - static_cast<int>(affected.size()); p < size(); ++p) {
    const int node = node_at_[p];
    if (!eliminate(node, assemble)) {
      result.failed = node;
      return result;
    }
    ++result.eliminated;
  }
  return result;
}

// The changed nodes and all their ancestors (parent = first row of a column).
std::vector<int> BlockFactor::affectedNodes(const std::vector<int>& changed) {
  std::fill(affected_.begin(), affected_.end(), 0);
  std::vector<int> affected;
  for (int node : changed) {
    for (int k = node; k >= 0 && affected_[k] == 0; k = parent(k)) {
      affected_[k] = 1;
      affected.push_back(k);
    }
  }
  return affected;
}

// CAMD on the affected nodes' graph: their edges in H and, for every unaffected subtree
// hanging below them, the clique of the affected rows of its root's column (what eliminating
// the subtree left among them).
std::vector<int> BlockFactor::orderAffected(const std::vector<int>& affected,
                                            const std::vector<int>& last,
                                            const Neighbors& neighbors) const {
  std::vector<int> local(size(), -1);
  for (std::size_t i = 0; i < affected.size(); ++i) local[affected[i]] = static_cast<int>(i);
  std::vector<std::vector<int>> adjacency(affected.size());
  std::vector<int> around;
  for (std::size_t i = 0; i < affected.size(); ++i) {
    const int node = affected[i];
    around.clear();
    neighbors(node, around);
    for (int q : around) {
      if (local[q] >= 0 && q != node) adjacency[i].push_back(local[q]);
    }
    for (int k : row_of_[node]) {
      if (affected_[k] != 0 || parent(k) != node) continue;
      const std::vector<int>& clique = columns_[k].rows;
      for (int a : clique) {
        for (int b : clique) {
          if (a != b) adjacency[local[a]].push_back(local[b]);
        }
      }
    }
  }
  std::vector<char> at_end(affected.size(), 0);
  for (int node : last) {
    if (local[node] >= 0) at_end[local[node]] = 1;
  }
  std::vector<int> order = constrainedBlockOrdering(adjacency, at_end);
  for (int& i : order) i = affected[i];
  return order;
}

// New positions: the unaffected nodes keep their relative order, the affected ones follow in
// `order`. Columns of unaffected nodes keep their values; those with affected rows get their
// rows sorted again. The affected nodes' columns are emptied for elimination.
void BlockFactor::moveToEnd(const std::vector<int>& affected, const std::vector<int>& order) {
  int next = 0;
  std::vector<int> node_at(size());
  for (int node : node_at_) {
    if (affected_[node] == 0) node_at[next++] = node;
  }
  for (int node : order) node_at[next++] = node;
  node_at_ = std::move(node_at);
  for (int p = 0; p < size(); ++p) pos_[node_at_[p]] = p;
  std::vector<int> resort;
  for (int q : affected) {
    std::vector<int>& rows = row_of_[q];
    for (int k : rows) {
      if (affected_[k] == 0 && (resort.empty() || resort.back() != k)) resort.push_back(k);
    }
    rows.erase(std::remove_if(rows.begin(), rows.end(), [this](int k) { return affected_[k] != 0; }),
               rows.end());
  }
  std::sort(resort.begin(), resort.end());
  resort.erase(std::unique(resort.begin(), resort.end()), resort.end());
  for (int k : resort) sortRows(k);
  for (int q : affected) columns_[q] = Column{};
}

void BlockFactor::sortRows(int node) {
  Column& c = columns_[node];
  const auto by_position = [this](int a, int b) { return pos_[a] < pos_[b]; };
  if (std::is_sorted(c.rows.begin(), c.rows.end(), by_position)) return;
  std::vector<std::size_t> idx(c.rows.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
    return pos_[c.rows[a]] < pos_[c.rows[b]];
  });
  const int dp = dims_[node];
  Column sorted;
  sorted.height = dp;
  sorted.panel.resize(c.panel.size());
  MatrixMap to(sorted.panel.data(), c.height, dp);
  const ConstMatrixMap from(c.panel.data(), c.height, dp);
  to.topRows(dp) = from.topRows(dp);
  for (std::size_t i : idx) {
    const int q = c.rows[i];
    sorted.rows.push_back(q);
    sorted.row_offsets.push_back(sorted.height);
    to.middleRows(sorted.height, dims_[q]) = from.middleRows(c.row_offsets[i], dims_[q]);
    sorted.height += dims_[q];
  }
  c = std::move(sorted);
}

bool BlockFactor::eliminate(int p, const Assemble& assemble) {
  builder_.begin(p, dims_);
  assemble(p, builder_);
  subtractDescendants(p);
  const int dp = dims_[p];
  const MatrixMap pivot(builder_.values_.data(), dp, dp);
  if (!pivot.allFinite()) return false;
  const Eigen::LLT<Eigen::MatrixXd> llt(pivot);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd lpp = llt.matrixL();
  Eigen::Map<Eigen::VectorXd> y(y_.data() + starts_[p], dp);
  y = lpp.triangularView<Eigen::Lower>().solve(builder_.rhs());
  storeColumn(p, lpp);
  return true;
}

// H(q, p) -= L(q, k) L(p, k)^T and rhs_p -= L(p, k) y_k for every node k before p with
// L(p, k) != 0: one product of k's panel from row p down with L(p, k)^T per such node.
void BlockFactor::subtractDescendants(int p) {
  const int dp = dims_[p];
  Eigen::Map<Eigen::VectorXd> rhs = builder_.rhs();
  Eigen::MatrixXd product;
  for (int k : row_of_[p]) {
    const Column& c = columns_[k];
    const int dk = dims_[k];
    const auto it = std::lower_bound(c.rows.begin(), c.rows.end(), p,
                                     [this](int a, int b) { return pos_[a] < pos_[b]; });
    const auto i = static_cast<std::size_t>(it - c.rows.begin());
    const int first = c.row_offsets[i];
    const ConstMatrixMap panel(c.panel.data(), c.height, dk);
    const auto lpk = panel.middleRows(first, dp);
    product.noalias() = panel.bottomRows(c.height - first) * lpk.transpose();
    builder_.block(p) -= product.topRows(dp);
    for (std::size_t j = i + 1; j < c.rows.size(); ++j) {
      const int q = c.rows[j];
      builder_.block(q) -= product.middleRows(c.row_offsets[j] - first, dims_[q]);
    }
    rhs.noalias() -= lpk * ConstVectorMap(y_.data() + starts_[k], dk);
  }
}

void BlockFactor::storeColumn(int p, const Eigen::MatrixXd& pivot_factor) {
  const int dp = dims_[p];
  Column c;
  c.rows.assign(builder_.rows_.begin() + 1, builder_.rows_.end());
  std::sort(c.rows.begin(), c.rows.end(), [this](int a, int b) { return pos_[a] < pos_[b]; });
  c.height = dp;
  for (int q : c.rows) {
    c.row_offsets.push_back(c.height);
    c.height += dims_[q];
    row_of_[q].push_back(p);
  }
  c.panel.resize(static_cast<std::size_t>(c.height) * dp);
  MatrixMap panel(c.panel.data(), c.height, dp);
  panel.topRows(dp) = pivot_factor;
  for (std::size_t j = 0; j < c.rows.size(); ++j) {
    const int q = c.rows[j];
    panel.middleRows(c.row_offsets[j], dims_[q]) = builder_.block(q);
  }
  // L(q, p) = H'(q, p) L(p, p)^-T for all rows at once.
  auto below = panel.bottomRows(c.height - dp);
  pivot_factor.transpose().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(below);
  columns_[p] = std::move(c);
}

std::vector<int> BlockFactor::solve(double threshold) {
  std::vector<char> propagate(size(), 0);
  std::vector<int> changed;
  Eigen::VectorXd gathered;
  Eigen::VectorXd r;
  for (int position = size() - 1; position >= 0; --position) {
    const int p = node_at_[position];
    const Column& c = columns_[p];
    bool needed = affected_[p] != 0;
    for (std::size_t j = 0; !needed && j < c.rows.size(); ++j) needed = propagate[c.rows[j]] != 0;
    if (!needed) continue;
    const int dp = dims_[p];
    gathered.resize(c.height - dp);
    for (std::size_t j = 0; j < c.rows.size(); ++j) {
      const int q = c.rows[j];
      gathered.segment(c.row_offsets[j] - dp, dims_[q]) = ConstVectorMap(x_.data() + starts_[q], dims_[q]);
    }
    const ConstMatrixMap panel(c.panel.data(), c.height, dp);
    r = ConstVectorMap(y_.data() + starts_[p], dp);
    r.noalias() -= panel.bottomRows(c.height - dp).transpose() * gathered;
    panel.topRows(dp).transpose().triangularView<Eigen::Upper>().solveInPlace(r);
    Eigen::Map<Eigen::VectorXd> x(x_.data() + starts_[p], dp);
    const double change = (r - x).cwiseAbs().maxCoeff();
    if (change > 0.0) changed.push_back(p);
    if (change > threshold) propagate[p] = 1;
    x = r;
  }
  std::fill(affected_.begin(), affected_.end(), 0);
  return changed;
}

Eigen::Map<const Eigen::VectorXd> BlockFactor::solution(int node) const {
  return {x_.data() + starts_[node], dims_[node]};
}

void BlockFactor::zeroSolution(int node) {
  std::fill(x_.begin() + starts_[node], x_.begin() + starts_[node + 1], 0.0);
}

Eigen::MatrixXd BlockFactor::inverseBlock(int node) const {
  const int dn = dims_[node];
  std::vector<std::pair<int, Eigen::MatrixXd>> pending;  // rows of Z = L^-1 E_node being summed
  Eigen::MatrixXd z = Eigen::MatrixXd::Identity(dn, dn);
  Eigen::MatrixXd result = Eigen::MatrixXd::Zero(dn, dn);
  for (int cur = node;;) {
    const Column& c = columns_[cur];
    const ConstMatrixMap panel(c.panel.data(), c.height, dims_[cur]);
    panel.topRows(dims_[cur]).triangularView<Eigen::Lower>().solveInPlace(z);
    result.noalias() += z.transpose() * z;
    for (std::size_t j = 0; j < c.rows.size(); ++j) {
      const int q = c.rows[j];
      auto it = std::find_if(pending.begin(), pending.end(),
                             [q](const auto& entry) { return entry.first == q; });
      if (it == pending.end()) {
        pending.emplace_back(q, Eigen::MatrixXd::Zero(dims_[q], dn));
        it = pending.end() - 1;
      }
      it->second.noalias() -= panel.middleRows(c.row_offsets[j], dims_[q]) * z;
    }
    if (c.rows.empty()) break;
    cur = c.rows.front();
    const auto next = std::find_if(pending.begin(), pending.end(),
                                   [cur](const auto& entry) { return entry.first == cur; });
    z = std::move(next->second);
    pending.erase(next);
  }
  return result;
}

}  // namespace graphslam::incremental
