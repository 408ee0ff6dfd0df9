// SPDX-License-Identifier: MIT
// A block Cholesky factor H = L L^T kept across changes of H (iSAM2's Bayes tree in matrix
// form). Nodes are vertex blocks with stable ids; each has an elimination key. When H
// changes in some nodes' columns, the affected part of the factor -- those nodes and their
// ancestors in the elimination tree, a set closed towards the root -- is moved to the end of
// the elimination order, ordered again (CAMD, the caller's newest nodes last) and eliminated
// again. The rest of the factor does not depend on the affected part and stays as it is.
// Elimination is multifrontal: every node keeps the update matrix (Schur complement) and
// vector its subtree passes to its ancestors, so eliminating a node again costs its
// children's updates, not its whole subtree. Nodes with the same rows below them
// (supernodes) are eliminated in one front at once, and only the last keeps an update.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

#include "ordering.h"

namespace graphslam::incremental {

/// Receives the blocks of one column p of H (rows q at or after p) and the right-hand side.
class ColumnBuilder {
 public:
  /// The block H(q, p), d_q x d_p, column-major, to add into (zero at first).
  Eigen::Map<Eigen::MatrixXd> block(int q);
  /// The right-hand side of p, d_p entries, to add into (zero at first).
  Eigen::Map<Eigen::VectorXd> rhs();

 private:
  friend class BlockFactor;
  void begin(int p, const std::vector<int>& dims);

  int p_ = -1;
  const std::vector<int>* dims_ = nullptr;
  std::vector<int> slot_of_;  // node -> index into rows_, -1 when absent
  std::vector<int> rows_;     // nodes added, in order of appearance (p first)
  std::vector<int> offsets_;  // start of each row's block in values_
  std::vector<double> values_;
  std::vector<double> rhs_;
};

/// An array of doubles that keeps its capacity and leaves its entries uninitialised when it
/// grows (the old entries are not kept): every user writes the entries it reads, so
/// eliminating a node again neither zeroes its arrays nor maps fresh pages for them.
class Storage {
 public:
  /// Room for at least n entries.
  void resize(std::size_t n) {
    if (n > capacity_) {
      data_.reset(new double[n]);
      capacity_ = n;
    }
  }
  [[nodiscard]] double* data() { return data_.get(); }
  [[nodiscard]] const double* data() const { return data_.get(); }

 private:
  std::unique_ptr<double[]> data_;
  std::size_t capacity_ = 0;
};

class BlockFactor {
 public:
  /// Assembles column `node` of H (rows at or after it in position()) and the right-hand
  /// side -g of the node.
  using Assemble = std::function<void(int node, ColumnBuilder& builder)>;
  /// Appends the nodes adjacent to `node` in H.
  using Neighbors = std::function<void(int node, std::vector<int>& out)>;

  void clear();
  /// A node and the child whose rows are the node and its rows (a supernode) are eliminated
  /// in one front only when the child's front has at least this many rows (see
  /// incremental::Options::chain_min_front_rows).
  void setChainMinFrontRows(int rows) { chain_min_front_rows_ = rows; }
  /// A new node of dimension `dim` (ids count up from 0); it enters the factor at the next
  /// refactor, which must name it as changed.
  int add(int dim);
  [[nodiscard]] int size() const { return static_cast<int>(dims_.size()); }
  /// Elimination key of a node: nodes are eliminated in increasing key (keys grow with
  /// every reordering and are not dense).
  [[nodiscard]] long long position(int node) const { return pos_[node]; }
  [[nodiscard]] std::size_t offDiagonalBlocks() const;

  struct Result {
    int eliminated = 0;  ///< nodes eliminated
    int failed = -1;     ///< node whose pivot block is not positive definite
  };
  /// Re-eliminates the nodes whose columns of H changed and their ancestors, ordered again
  /// with the nodes of `last` at the end (and computes their part of the forward solution
  /// L y = rhs). On failure the factor is unusable until clear().
  Result refactor(const std::vector<int>& changed, const std::vector<int>& last,
                  const Neighbors& neighbors, const Assemble& assemble);

  /// Back-substitution L^T x = y. A node is solved again when the last refactor eliminated
  /// it or a solution it depends on changed; its new solution is kept only when it differs
  /// from the old by more than `threshold` (iSAM2's wildfire). Returns the nodes whose
  /// solution changed.
  std::vector<int> solve(double threshold);
  /// Solution block of a node (its dimension in entries).
  [[nodiscard]] Eigen::Map<const Eigen::VectorXd> solution(int node) const;
  /// Sets a node's solution block to zero (its vertex was relinearised there).
  void zeroSolution(int node);

  /// The block of H^-1 of a node: Z^T Z with Z = L^-1 E_node, which is non-zero only on the
  /// path from the node to the root.
  [[nodiscard]] Eigen::MatrixXd inverseBlock(int node) const;

 private:
  struct Column {
    std::vector<int> rows;  // nodes q after this one with L(q, p) != 0
    int height = 0;         // d_p + sum of the rows' dimensions
    Storage panel;          // height x d_p, column-major: L(p, p), then L(q, p) for each row
                            // q in the order of `rows`
    // What the subtree of p passes to its ancestors (rows as above, h = height - d_p):
    // (left stale, and never read, for a supernode member below the last):
    Storage update;  // h x h, lower triangle: the Schur complement onto the rows
    Storage vector;  // h: the forward solution's contribution
  };
  [[nodiscard]] int parent(int node) const { return parent_[node]; }
  std::vector<int> affectedNodes(const std::vector<int>& changed);
  std::vector<int> orderAffected(const std::vector<int>& affected, const std::vector<int>& last,
                                 const Neighbors& neighbors);
  void moveToEnd(const std::vector<int>& affected, const std::vector<int>& order);
  [[nodiscard]] bool before(int a, int b) const { return pos_[a] < pos_[b]; }
  void analyse(const Neighbors& neighbors);
  void findSupernodes();
  void assembleFront(int first, int end, const Assemble& assemble);
  void extendAddChildren(int p);
  bool factorFront(int first, int end);
  [[nodiscard]] bool memberFinite(int i) const;
  int failedMember(int first, int end, const Assemble& assemble);
  void keepUpdate(int p);
  double solveNode(int p, double threshold);
  template <int D>
  void subtractBelow(const Column& c, int dp, double* r) const;

  std::vector<int> dims_;
  std::vector<int> starts_;     // scalar offset of each node in y and x
  std::vector<long long> pos_;  // node -> elimination key
  long long next_key_ = 0;
  // Per-node flags and their lists (reset by list, so an update costs what it touches):
  std::vector<char> affected_;  // by the last refactor
  std::vector<int> affected_list_;
  std::vector<int> local_;     // orderAffected's node -> index among the affected
  struct OrderingScratch {     // orderAffected's, kept for their capacity
    std::vector<int> cliques;  // the unaffected children of affected nodes
    std::vector<int> member_ptr, member_of, cursor;  // affected index -> its cliques
    std::vector<int> mark;
    BlockPattern pattern;
  } ordering_;
  std::vector<char> moved_;  // solve's: the solution changed by more than its threshold
  std::vector<int> order_;   // the affected nodes in elimination order (a postorder)
  std::vector<Column> columns_;
  // Elimination tree: a node's parent is its row of the smallest key (-1 for a root).
  std::vector<int> parent_;
  std::vector<std::vector<int>> children_;
  // The child eliminated in the same front as a node (its supernode's member below it; -1:
  // none); that child kept no update matrix, so it is eliminated again whenever the node is.
  std::vector<int> chain_child_;
  std::vector<int> supernode_starts_;  // the last refactor's supernodes: bounds in order_
  std::vector<char> marked_;           // analyse's
  int chain_min_front_rows_ = 48;
  std::vector<double> y_, x_;
  ColumnBuilder builder_;
  // The frontal matrix of the node being eliminated (its column and rows) and its
  // right-hand side; front_offset_ maps a node to its first row in them.
  Storage front_storage_;
  Eigen::Map<Eigen::MatrixXd> front_{nullptr, 0, 0};  // on front_storage_
  Storage front_rhs_storage_;
  Eigen::Map<Eigen::VectorXd> front_rhs_{nullptr, 0};  // on front_rhs_storage_
  std::vector<int> front_rows_;                        // nodes of the front, in key order
  std::vector<int> front_offset_;
  std::vector<int> extend_rows_;  // extendAddChildren's: front row of each update row
  std::vector<char> in_front_;
};

}  // namespace graphslam::incremental
