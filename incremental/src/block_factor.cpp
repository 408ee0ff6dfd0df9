// SPDX-License-Identifier: MIT
#include "block_factor.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <queue>

#include "ordering.h"

namespace graphslam::incremental {

using Eigen::Index;
using MatrixMap = Eigen::Map<Eigen::MatrixXd>;
using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd>;
using ConstVectorMap = Eigen::Map<const Eigen::VectorXd>;

// Largest vertex dimension whose back-substitution works in a stack buffer.
constexpr int kMaxStackDim = 16;

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
  next_key_ = 0;
  affected_list_.clear();
  local_.clear();
  queued_.clear();
  order_.clear();
  columns_.clear();
  parent_.clear();
  children_.clear();
  chain_child_.clear();
  in_front_.clear();
  moved_.clear();
  front_offset_.clear();
  y_.clear();
  x_.clear();
  affected_.clear();
}

int BlockFactor::add(int dim) {
  const int node = size();
  dims_.push_back(dim);
  if (starts_.empty()) starts_.push_back(0);
  starts_.push_back(starts_.back() + dim);
  pos_.push_back(next_key_++);
  local_.push_back(-1);
  queued_.push_back(0);
  columns_.emplace_back();
  parent_.push_back(-1);
  children_.emplace_back();
  chain_child_.push_back(-1);
  in_front_.push_back(0);
  moved_.push_back(0);
  front_offset_.push_back(0);
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
                                          const std::vector<int>& last, const Neighbors& neighbors,
                                          const Assemble& assemble) {
  const std::vector<int> affected = affectedNodes(changed);
  order_ = orderAffected(affected, last, neighbors);
  moveToEnd(affected, order_);
  Result result;
  for (std::size_t i = 0; i < order_.size();) {
    int p = order_[i];
    assembleFront(p, assemble);
    extendAddChildren(p);
    // A chain (the next node is p's parent, p its only child, and the parent's edges stay
    // within the front) goes on in the same front: no update matrix between them.
    for (;;) {
      if (!factorPivot(p)) {
        result.failed = p;
        return result;
      }
      ++result.eliminated;
      ++i;
      const int q = parent_[p];
      if (i < order_.size() && order_[i] == q && children_[q].size() == 1 &&
          columns_[p].height >= chain_min_front_rows_ && continueFront(q, assemble)) {
        chain_child_[q] = p;
        p = q;
        continue;
      }
      keepUpdate(p);
      break;
    }
  }
  return result;
}

// The changed nodes and all their ancestors (parent = first row of a column).
std::vector<int> BlockFactor::affectedNodes(const std::vector<int>& changed) {
  for (int node : affected_list_) affected_[node] = 0;
  std::vector<int> affected;
  for (int node : changed) {
    for (int k = node; k >= 0 && affected_[k] == 0; k = parent(k)) {
      affected_[k] = 1;
      affected.push_back(k);
      // The nodes below k in its chain kept no update matrix: they go with it.
      for (int d = chain_child_[k]; d >= 0 && affected_[d] == 0; d = chain_child_[d]) {
        affected_[d] = 1;
        affected.push_back(d);
      }
    }
  }
  affected_list_ = affected;
  return affected;
}

// CAMD on the affected nodes' graph: their edges in H and, for every unaffected subtree
// hanging below them, the clique of the affected rows of its root's column (what eliminating
// the subtree left among them).
std::vector<int> BlockFactor::orderAffected(const std::vector<int>& affected,
                                            const std::vector<int>& last,
                                            const Neighbors& neighbors) {
  std::vector<int>& local = local_;
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
    for (int k : children_[node]) {
      if (affected_[k] != 0) continue;
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
  for (int node : affected) local[node] = -1;
  return order;
}

// New keys: the affected nodes, in `order`, after every other node (whose columns keep their
// values). The roots of the unaffected subtrees below them find their parents among the
// new keys; the affected nodes' columns are emptied for elimination.
void BlockFactor::moveToEnd(const std::vector<int>& affected, const std::vector<int>& order) {
  for (int node : order) pos_[node] = next_key_++;
  std::vector<int> orphans;
  for (int q : affected) {
    for (int k : children_[q]) {
      if (affected_[k] == 0) orphans.push_back(k);
    }
    children_[q].clear();
    chain_child_[q] = -1;
    columns_[q].rows.clear();
    columns_[q].height = 0;
  }
  for (int k : orphans) {
    const std::vector<int>& rows = columns_[k].rows;
    parent_[k] =
        *std::min_element(rows.begin(), rows.end(), [this](int a, int b) { return before(a, b); });
    children_[parent_[k]].push_back(k);
  }
}

// The front of p: its rows (H's neighbours after p and its children's rows, in key order),
// column p of H and the right-hand side of p.
void BlockFactor::assembleFront(int p, const Assemble& assemble) {
  builder_.begin(p, dims_);
  assemble(p, builder_);
  for (int child : children_[p]) {
    for (int q : columns_[child].rows) {
      if (q != p) (void)builder_.block(q);
    }
  }
  front_rows_.assign(builder_.rows_.begin(), builder_.rows_.end());
  std::sort(front_rows_.begin() + 1, front_rows_.end(),
            [this](int a, int b) { return before(a, b); });
  int height = 0;
  for (int q : front_rows_) {
    front_offset_[q] = height;
    in_front_[q] = 1;
    height += dims_[q];
  }
  const int dp = dims_[p];
  front_.setZero(height, height);
  front_rhs_.setZero(height);
  for (int q : front_rows_) front_.block(front_offset_[q], 0, dims_[q], dp) = builder_.block(q);
  front_rhs_.head(dp) = builder_.rhs();
}

// Adds column q of H into the current front when all its rows are there (q continues a
// chain); returns false, changing nothing, otherwise.
bool BlockFactor::continueFront(int q, const Assemble& assemble) {
  builder_.begin(q, dims_);
  assemble(q, builder_);
  for (int r : builder_.rows_) {
    if (in_front_[r] == 0) return false;
  }
  const int fq = front_offset_[q];
  for (int r : builder_.rows_) {
    front_.block(front_offset_[r], fq, dims_[r], dims_[q]) += builder_.block(r);
  }
  front_rhs_.segment(fq, dims_[q]) += builder_.rhs();
  return true;
}

// Adds the children's update matrices and vectors into the front's lower triangle
// (extend-add).
void BlockFactor::extendAddChildren(int p) {
  for (int child : children_[p]) {
    const Column& cc = columns_[child];
    const int dc = dims_[child];
    const int h = cc.height - dc;
    const ConstMatrixMap update(cc.update.data(), h, h);
    for (std::size_t a = 0; a < cc.rows.size(); ++a) {
      const int qa = cc.rows[a];
      const int da = dims_[qa];
      const int ua = cc.row_offsets[a] - dc;
      const int fa = front_offset_[qa];
      front_rhs_.segment(fa, da) += ConstVectorMap(cc.vector.data() + ua, da);
      for (std::size_t b = 0; b <= a; ++b) {
        // The child's rows need not be in key order: each block goes to the front's lower
        // triangle, transposed when its row comes first there.
        const int qb = cc.rows[b];
        const int db = dims_[qb];
        const int fb = front_offset_[qb];
        const auto block = update.block(ua, cc.row_offsets[b] - dc, da, db);
        if (fa >= fb) {
          front_.block(fa, fb, da, db) += block;
        } else {
          front_.block(fb, fa, db, da) += block.transpose();
        }
      }
    }
  }
}

// Eliminates p, the first node left in the front: L(p, p), L(rows, p) and y_p, and the
// Schur complement of the rows after it, in place. Only the lower triangle is read.
bool BlockFactor::factorPivot(int p) {
  const int dp = dims_[p];
  const int top = front_offset_[p];
  const int h = static_cast<int>(front_.rows()) - top - dp;
  auto pivot = front_.block(top, top, dp, dp);
  if (!pivot.allFinite() || !front_.block(top + dp, top, h, dp).allFinite()) return false;
  llt_.compute(pivot.selfadjointView<Eigen::Lower>());
  if (llt_.info() != Eigen::Success) return false;
  Column& c = columns_[p];
  c.rows.clear();
  c.row_offsets.clear();
  for (auto it = std::find(front_rows_.begin(), front_rows_.end(), p) + 1; it != front_rows_.end();
       ++it) {
    c.rows.push_back(*it);
    c.row_offsets.push_back(front_offset_[*it] - top);
  }
  c.height = dp + h;
  c.update.clear();
  c.vector.clear();
  c.panel.resize(static_cast<std::size_t>(c.height) * dp);
  MatrixMap panel(c.panel.data(), c.height, dp);
  panel.topRows(dp) = llt_.matrixL();
  auto below = panel.bottomRows(h);
  below = front_.block(top + dp, top, h, dp);
  llt_.matrixU().solveInPlace<Eigen::OnTheRight>(below);  // L(R, p) = F(R, p) L(p, p)^-T
  Eigen::Map<Eigen::VectorXd> y(y_.data() + starts_[p], dp);
  y = llt_.matrixL().solve(front_rhs_.segment(top, dp));
  front_.bottomRightCorner(h, h).selfadjointView<Eigen::Lower>().rankUpdate(below, -1.0);
  front_rhs_.tail(h).noalias() -= below * y;
  parent_[p] = c.rows.empty() ? -1 : c.rows.front();
  if (parent_[p] >= 0) children_[parent_[p]].push_back(p);
  return true;
}

// The end of a chain: what is left of the front is p's update matrix and vector, kept for
// p's ancestors (only the lower triangle of the update matrix is ever read).
void BlockFactor::keepUpdate(int p) {
  Column& c = columns_[p];
  const int h = c.height - dims_[p];
  c.update.resize(static_cast<std::size_t>(h) * h);
  MatrixMap update(c.update.data(), h, h);
  update.triangularView<Eigen::Lower>() = front_.bottomRightCorner(h, h);
  c.vector.resize(h);
  Eigen::Map<Eigen::VectorXd>(c.vector.data(), h) = front_rhs_.tail(h);
  for (int q : front_rows_) in_front_[q] = 0;
}

// From the root down, latest key first: the eliminated nodes, and the children of solved
// nodes with a row whose solution moved by more than the threshold. (A node's rows other than
// its parent are rows of its parent: when the parent is not solved again, neither is it.)
std::vector<int> BlockFactor::solve(double threshold) {
  const auto later_first = [this](int a, int b) { return before(a, b); };
  std::priority_queue<int, std::vector<int>, decltype(later_first)> pending(later_first);
  for (int node : affected_list_) {
    queued_[node] = 1;
    pending.push(node);
  }
  std::vector<int> visited;
  std::vector<int> changed;
  while (!pending.empty()) {
    const int p = pending.top();
    pending.pop();
    visited.push_back(p);
    const double change = solveNode(p);
    if (change > 0.0) changed.push_back(p);
    moved_[p] = change > threshold ? 1 : 0;
    for (int child : children_[p]) {
      if (queued_[child] != 0) continue;
      const std::vector<int>& rows = columns_[child].rows;
      if (std::none_of(rows.begin(), rows.end(), [this](int q) { return moved_[q] != 0; }))
        continue;
      queued_[child] = 1;
      pending.push(child);
    }
  }
  for (int node : visited) queued_[node] = moved_[node] = 0;
  for (int node : affected_list_) affected_[node] = 0;
  affected_list_.clear();
  return changed;
}

// x_p = L(p, p)^-T (y_p - L(rows, p)^T x_rows); returns the largest change of an entry.
double BlockFactor::solveNode(int p) {
  const Column& c = columns_[p];
  const int dp = dims_[p];
  gathered_.resize(c.height - dp);
  for (std::size_t j = 0; j < c.rows.size(); ++j) {
    const int q = c.rows[j];
    gathered_.segment(c.row_offsets[j] - dp, dims_[q]) =
        ConstVectorMap(x_.data() + starts_[q], dims_[q]);
  }
  const ConstMatrixMap panel(c.panel.data(), c.height, dp);
  // Vertex dimensions are small: r lives on the stack (no allocation per solved node).
  using Small = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStackDim, 1>;
  Small r;
  Eigen::VectorXd heap;  // only for a vertex of more than kMaxStackDim dimensions
  Eigen::Map<Eigen::VectorXd> rv = [&] {
    if (dp <= kMaxStackDim) {
      r.resize(dp);
      return Eigen::Map<Eigen::VectorXd>(r.data(), dp);
    }
    heap.resize(dp);
    return Eigen::Map<Eigen::VectorXd>(heap.data(), dp);
  }();
  rv = ConstVectorMap(y_.data() + starts_[p], dp);
  // One dot product per column: for the few columns of a vertex this is cheaper than a
  // general matrix-vector product.
  const Index h = c.height - dp;
  for (int k = 0; k < dp; ++k) rv[k] -= panel.col(k).tail(h).dot(gathered_);
  panel.topRows(dp).transpose().triangularView<Eigen::Upper>().solveInPlace(rv);
  Eigen::Map<Eigen::VectorXd> x(x_.data() + starts_[p], dp);
  const double change = (rv - x).cwiseAbs().maxCoeff();
  x = rv;
  return change;
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
    if (parent_[cur] < 0) break;
    cur = parent_[cur];
    const auto next = std::find_if(pending.begin(), pending.end(),
                                   [cur](const auto& entry) { return entry.first == cur; });
    z = std::move(next->second);
    pending.erase(next);
  }
  return result;
}

}  // namespace graphslam::incremental
