// SPDX-License-Identifier: MIT
#include "block_factor.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <new>
#include <stdexcept>
#include <utility>

#include "dense_front.h"
#include "graphslam/support/fixed_size.h"
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
  order_.clear();
  columns_.clear();
  parent_.clear();
  children_.clear();
  chain_child_.clear();
  in_front_.clear();
  marked_.clear();
  supernode_starts_.clear();
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
  columns_.emplace_back();
  parent_.push_back(-1);
  children_.emplace_back();
  chain_child_.push_back(-1);
  in_front_.push_back(0);
  marked_.push_back(0);
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
  analyse(neighbors);
  Result result;
  for (std::size_t s = 0; s + 1 < supernode_starts_.size(); ++s) {
    const int first = supernode_starts_[s];
    const int end = supernode_starts_[s + 1];
    assembleFront(first, end, assemble);
    if (!factorFront(first, end)) {
      result.failed = failedMember(first, end, assemble);
      return result;
    }
    result.eliminated += end - first;
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
  const int n = static_cast<int>(affected.size());
  std::vector<int>& local = local_;
  for (int i = 0; i < n; ++i) local[affected[i]] = i;
  // An unaffected subtree passes its root's update matrix up: a dense clique on that root's
  // rows, which are all affected (ancestors of an affected node). Which cliques each
  // affected node is in, as compressed lists (a counting sort).
  OrderingScratch& o = ordering_;
  o.cliques.clear();
  for (int node : affected) {
    for (int k : children_[node]) {
      if (affected_[k] == 0) o.cliques.push_back(k);
    }
  }
  o.member_ptr.assign(n + 1, 0);
  for (int k : o.cliques) {
    for (int a : columns_[k].rows) ++o.member_ptr[local[a] + 1];
  }
  for (int i = 0; i < n; ++i) o.member_ptr[i + 1] += o.member_ptr[i];
  o.member_of.resize(o.member_ptr[n]);
  o.cursor.assign(o.member_ptr.begin(), o.member_ptr.end() - 1);
  for (int c = 0; c < static_cast<int>(o.cliques.size()); ++c) {
    for (int a : columns_[o.cliques[c]].rows) o.member_of[o.cursor[local[a]]++] = c;
  }
  // Column i of the pattern: node i's neighbours in H and its cliques' other members.
  BlockPattern& pattern = o.pattern;
  pattern.col_ptr.assign(n + 1, 0);
  pattern.rows.clear();
  o.mark.assign(n, -1);
  std::vector<int> around;
  const auto add = [&](int i, int j) {
    if (o.mark[j] == i) return;
    o.mark[j] = i;
    pattern.rows.push_back(j);
  };
  for (int i = 0; i < n; ++i) {
    o.mark[i] = i;
    around.clear();
    neighbors(affected[i], around);
    for (int q : around) {
      if (local[q] >= 0) add(i, local[q]);
    }
    for (int m = o.member_ptr[i]; m < o.member_ptr[i + 1]; ++m) {
      for (int a : columns_[o.cliques[o.member_of[m]]].rows) add(i, local[a]);
    }
    pattern.col_ptr[i + 1] = static_cast<int>(pattern.rows.size());
  }
  std::vector<char> at_end(affected.size(), 0);
  for (int node : last) {
    if (local[node] >= 0) at_end[local[node]] = 1;
  }
  std::vector<int> order = constrainedBlockOrdering(pattern, at_end);
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

// Symbolic elimination of the affected nodes (in order_): each one's rows -- its neighbours in
// H after it and its children's rows -- its parent (the row of the smallest key) and its
// children. Then new keys in a postorder of their tree, each supernode's members
// consecutive, and the supernodes' bounds in supernode_starts_.
void BlockFactor::analyse(const Neighbors& neighbors) {
  std::vector<int> around;
  for (int p : order_) {
    Column& c = columns_[p];
    c.rows.clear();
    marked_[p] = 1;
    const auto add_row = [&](int q) {
      if (marked_[q] != 0) return;
      marked_[q] = 1;
      c.rows.push_back(q);
    };
    around.clear();
    neighbors(p, around);
    for (int q : around) {
      if (before(p, q)) add_row(q);
    }
    for (int k : children_[p]) {
      for (int q : columns_[k].rows) add_row(q);
    }
    marked_[p] = 0;
    c.height = dims_[p];
    for (int q : c.rows) {
      marked_[q] = 0;
      c.height += dims_[q];
    }
    parent_[p] = c.rows.empty() ? -1
                                : *std::min_element(c.rows.begin(), c.rows.end(),
                                                    [this](int a, int b) { return before(a, b); });
    if (parent_[p] >= 0) children_[parent_[p]].push_back(p);
  }
  findSupernodes();
}

// A node is eliminated in the front of a child (its chain_child_, one of its children) whose
// rows are the node and the node's rows, when that front has at least chain_min_front_rows_
// rows. The new keys follow a postorder that visits such a child last, so a supernode is a
// run of consecutive keys, each member's parent the next.
void BlockFactor::findSupernodes() {
  for (int p : order_) {
    const int q = parent_[p];
    if (q >= 0 && chain_child_[q] < 0 && columns_[p].rows.size() == columns_[q].rows.size() + 1 &&
        columns_[p].height >= chain_min_front_rows_) {
      chain_child_[q] = p;
    }
  }
  std::vector<int> post;
  post.reserve(order_.size());
  std::vector<std::pair<int, std::size_t>> stack;  // node, next child to visit
  for (int root : order_) {
    if (parent_[root] >= 0) continue;
    stack.emplace_back(root, 0);
    while (!stack.empty()) {
      const int q = stack.back().first;
      std::size_t& next = stack.back().second;
      const std::vector<int>& kids = children_[q];
      while (next < kids.size() && (affected_[kids[next]] == 0 || kids[next] == chain_child_[q]))
        ++next;
      int visit = -1;
      if (next < kids.size()) {
        visit = kids[next++];
      } else if (next == kids.size() && chain_child_[q] >= 0) {
        ++next;
        visit = chain_child_[q];
      }
      if (visit >= 0) {
        stack.emplace_back(visit, 0);
        continue;
      }
      post.push_back(q);
      stack.pop_back();
    }
  }
  order_ = std::move(post);
  supernode_starts_.clear();
  for (std::size_t i = 0; i < order_.size(); ++i) {
    pos_[order_[i]] = next_key_++;
    if (i == 0 || chain_child_[order_[i]] != order_[i - 1])
      supernode_starts_.push_back(static_cast<int>(i));
  }
  supernode_starts_.push_back(static_cast<int>(order_.size()));
}

// The front of the supernode order_[first, end): its members, then the rows of the last
// (in key order); the members' columns of H and right-hand sides, and their other children's
// update matrices and vectors.
void BlockFactor::assembleFront(int first, int end, const Assemble& assemble) {
  const int head = order_[first];
  front_rows_.assign(1, head);
  front_rows_.insert(front_rows_.end(), columns_[head].rows.begin(), columns_[head].rows.end());
  std::sort(front_rows_.begin() + 1, front_rows_.end(),
            [this](int a, int b) { return before(a, b); });
  int height = 0;
  for (int q : front_rows_) {
    front_offset_[q] = height;
    in_front_[q] = 1;
    height += dims_[q];
  }
  // Only the lower triangle is read, so only the blocks on and below the diagonal are zeroed.
  front_storage_.resize(static_cast<std::size_t>(height) * height);
  new (&front_) MatrixMap(front_storage_.data(), height, height);  // Eigen's way to re-seat a Map
  front_rhs_storage_.resize(height);
  new (&front_rhs_) Eigen::Map<Eigen::VectorXd>(front_rhs_storage_.data(), height);
  for (int q : front_rows_) {
    const int fq = front_offset_[q];
    front_.block(fq, fq, height - fq, dims_[q]).setZero();
  }
  front_rhs_.setZero();
  for (int i = first; i < end; ++i) {
    const int p = order_[i];
    builder_.begin(p, dims_);
    assemble(p, builder_);
    const int fp = front_offset_[p];
    for (int r : builder_.rows_) {
      if (in_front_[r] == 0)
        throw std::logic_error("incremental factor: a column of H has a row its analysis missed");
      front_.block(front_offset_[r], fp, dims_[r], dims_[p]) += builder_.block(r);
    }
    front_rhs_.segment(fp, dims_[p]) += builder_.rhs();
    extendAddChildren(p);
  }
}

// Adds the update matrices and vectors of p's children (but the member of p's supernode
// below it, which kept none) into the front's lower triangle (extend-add), entry by entry
// through the front row of each update row.
void BlockFactor::extendAddChildren(int p) {
  std::vector<int>& target = extend_rows_;
  for (int child : children_[p]) {
    if (child == chain_child_[p]) continue;
    const Column& cc = columns_[child];
    const int dc = dims_[child];
    const int h = cc.height - dc;
    target.resize(h);
    int ua = 0;
    for (int qa : cc.rows) {
      for (int i = 0; i < dims_[qa]; ++i) target[ua + i] = front_offset_[qa] + i;
      ua += dims_[qa];
    }
    const double* update = cc.update.data();
    double* front = front_.data();
    const Index ld = front_.rows();
    for (int j = 0; j < h; ++j) {
      const Index fj = target[j];
      front_rhs_[fj] += cc.vector.data()[j];
      // The child's rows need not be in key order: an entry whose front row comes first
      // goes to the transposed place, in the lower triangle.
      for (int i = j; i < h; ++i) {
        const Index fi = target[i];
        const double u = update[i + static_cast<Index>(j) * h];
        if (fi >= fj) {
          front[fi + fj * ld] += u;
        } else {
          front[fj + fi * ld] += u;
        }
      }
    }
  }
}

// Eliminates the supernode's members, the front's first k columns, at once: their block
// L11 L11^T, the rows below L21 = F21 L11^-T, their part y1 of the forward solution, and the
// Schur complement F22 - L21 L21^T (one rank-k update) with its vector. Only the blocks on and
// below the diagonal are read. Returns false when a column is not finite or L11 does not exist
// (the front is then spoilt: see failedMember).
bool BlockFactor::factorFront(int first, int end) {
  const int last = order_[end - 1];
  const int k = front_offset_[last] + dims_[last];
  for (int i = first; i < end; ++i) {
    if (!memberFinite(i)) return false;
  }
  if (!eliminateLeading(front_, front_rhs_, k)) return false;
  const auto y = front_rhs_.head(k);
  for (int i = first; i < end; ++i) {
    const int p = order_[i];
    const int dp = dims_[p];
    const int top = front_offset_[p];
    Column& c = columns_[p];
    c.rows.assign(front_rows_.begin() + (i - first) + 1, front_rows_.end());
    c.height = static_cast<int>(front_.rows()) - top;
    c.panel.resize(static_cast<std::size_t>(c.height) * dp);
    MatrixMap panel(c.panel.data(), c.height, dp);
    panel = front_.block(top, top, c.height, dp);
    panel.topRows(dp).triangularView<Eigen::StrictlyUpper>().setZero();
    Eigen::Map<Eigen::VectorXd>(y_.data() + starts_[p], dp) = y.segment(top, dp);
  }
  keepUpdate(last);
  return true;
}

// Whether member i's column (on and below the diagonal) is finite.
bool BlockFactor::memberFinite(int i) const {
  const int top = front_offset_[order_[i]];
  return front_.block(top, top, front_.rows() - top, dims_[order_[i]]).allFinite();
}

// After factorFront failed: the member of the supernode order_[first, end) with a column
// that is not finite or the first whose leading block is not positive definite, found on
// the front assembled again.
int BlockFactor::failedMember(int first, int end, const Assemble& assemble) {
  assembleFront(first, end, assemble);
  for (int i = first; i < end; ++i) {
    const int p = order_[i];
    if (!memberFinite(i)) return p;
    const int n = front_offset_[p] + dims_[p];
    const Eigen::LLT<Eigen::MatrixXd> leading(
        front_.topLeftCorner(n, n).selfadjointView<Eigen::Lower>());
    if (leading.info() != Eigen::Success) return p;
  }
  return order_[end - 1];
}

// The end of a supernode: what is left of the front is p's update matrix and vector, kept for
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

// From the roots down, parents before children (a node's rows are its ancestors, so they are
// solved first): the eliminated nodes, and the children of solved nodes with a row whose
// solution changed (solveNode keeps only changes above the threshold). A node's rows other
// than its parent are rows of its parent: when the parent is not solved again, neither is it.
std::vector<int> BlockFactor::solve(double threshold) {
  std::vector<int> pending;
  for (int node : affected_list_) {
    if (parent_[node] < 0) pending.push_back(node);
  }
  std::vector<int> visited;
  std::vector<int> changed;
  while (!pending.empty()) {
    const int p = pending.back();
    pending.pop_back();
    visited.push_back(p);
    const double change = solveNode(p, threshold);
    if (change > 0.0) changed.push_back(p);
    moved_[p] = change > 0.0 ? 1 : 0;
    for (int child : children_[p]) {
      const std::vector<int>& rows = columns_[child].rows;
      if (affected_[child] != 0 ||
          std::any_of(rows.begin(), rows.end(), [this](int q) { return moved_[q] != 0; }))
        pending.push_back(child);
    }
  }
  for (int node : visited) moved_[node] = 0;
  for (int node : affected_list_) affected_[node] = 0;
  affected_list_.clear();
  return changed;
}

// r -= L(rows, p)^T x_rows for a node of dimension dp (D when D > 0): one pass over the rows,
// reading their solutions where they are, each entry's products for all dp columns at once.
template <int D>
void BlockFactor::subtractBelow(const Column& c, int dp, double* r) const {
  const int d = D > 0 ? D : dp;
  const double* pj = c.panel.data() + dp;  // the first row's block
  for (int q : c.rows) {
    const double* xq = x_.data() + starts_[q];
    for (int t = 0; t < dims_[q]; ++t) {
      const double v = xq[t];
      for (int k = 0; k < d; ++k) r[k] -= pj[static_cast<std::size_t>(k) * c.height + t] * v;
    }
    pj += dims_[q];
  }
}

// x_p = L(p, p)^-T (y_p - L(rows, p)^T x_rows), kept only when an entry changes by more than
// the threshold (so that many changes below it cannot add up unseen: x_p is what p's
// descendants were last solved with); returns that change, or 0 when x_p was kept.
double BlockFactor::solveNode(int p, double threshold) {
  const Column& c = columns_[p];
  const int dp = dims_[p];
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
  // The common vertex dimensions with the loop over them unrolled.
  support::withFixedSize<2, 3, 6>(
      dp, [&](auto fixed) { subtractBelow<decltype(fixed)::value>(c, dp, rv.data()); });
  // L(p, p)^T x = r by hand: Eigen's general triangular solver costs more than the few
  // multiplications of a vertex block.
  for (int k = dp - 1; k >= 0; --k) {
    double v = rv[k];
    for (int j = k + 1; j < dp; ++j) v -= panel(j, k) * rv[j];
    rv[k] = v / panel(k, k);
  }
  Eigen::Map<Eigen::VectorXd> x(x_.data() + starts_[p], dp);
  const double change = (rv - x).cwiseAbs().maxCoeff();
  if (change <= threshold) return 0.0;
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
    Index row = dims_[cur];
    for (int q : c.rows) {
      auto it = std::find_if(pending.begin(), pending.end(),
                             [q](const auto& entry) { return entry.first == q; });
      if (it == pending.end()) {
        pending.emplace_back(q, Eigen::MatrixXd::Zero(dims_[q], dn));
        it = pending.end() - 1;
      }
      it->second.noalias() -= panel.middleRows(row, dims_[q]) * z;
      row += dims_[q];
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
