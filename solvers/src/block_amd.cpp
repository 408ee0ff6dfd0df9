// SPDX-License-Identifier: MIT
// Approximate minimum degree on the block graph: chains and leaves eliminated first (as
// minimum degree would), SuiteSparse's AMD on the rest; Eigen's AMD without SuiteSparse.
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "ordering.h"

#ifdef GRAPHSLAM_HAVE_CHOLMOD
#include <amd.h>
#endif

namespace graphslam::solvers::detail {

namespace {

#ifdef GRAPHSLAM_HAVE_CHOLMOD
/// A block graph without its diagonal: adjacency lists at ptr[b], len[b] entries each (the
/// lists shrink in place as blocks are eliminated).
struct AdjacencyLists {
  std::vector<int> ptr, len, adj;
};

AdjacencyLists withoutDiagonal(const BlockGraph& g) {
  const int n = g.num_blocks;
  const auto size = static_cast<std::size_t>(n);
  AdjacencyLists a{std::vector<int>(size + 1), std::vector<int>(size), {}};
  std::vector<int>& ptr = a.ptr;
  std::vector<int>& len = a.len;
  std::vector<int>& adj = a.adj;
  adj.reserve(g.idx.size());
  for (int b = 0; b < n; ++b) {
    ptr[b] = static_cast<int>(adj.size());
    for (int q = g.ptr[b]; q < g.ptr[b + 1]; ++q) {
      if (g.idx[q] != b) adj.push_back(g.idx[q]);
    }
    len[b] = static_cast<int>(adj.size()) - ptr[b];
  }
  ptr[size] = static_cast<int>(adj.size());
  return a;
}

/// Eliminates the blocks of at most two neighbours first, as minimum degree would take
/// them: eliminating one never adds a neighbour to another block (a leaf leaves its
/// neighbour's list; a block between a and b becomes b in a's list and a in b's, or leaves
/// both when a and b are adjacent already), so the lists shrink in place and each step may
/// free the next. Pose chains without loop closures (most blocks of a typical pose graph)
/// go this way, and AMD orders only the rest, where it spends its time. Appends them to
/// `order`, marks them in `eliminated` and adds AMD's counts of their factor columns to
/// `lnz` and `nms` (b_j entries below the diagonal, b_j (b_j + 1) / 2 multiply-subtract
/// pairs).
void eliminateChains(AdjacencyLists& lists, std::vector<int>& order, std::vector<char>& eliminated,
                     double& lnz, double& nms) {
  const std::vector<int>& ptr = lists.ptr;
  std::vector<int>& len = lists.len;
  std::vector<int>& adj = lists.adj;
  const int n = static_cast<int>(len.size());
  // Minimum degree's order among them: blocks of at most one neighbour (leaves) before
  // those of two (a chain's middle first would join its neighbours for nothing).
  std::vector<int> leaves, middles;
  for (int b = n - 1; b >= 0; --b) {
    if (len[b] <= 1) leaves.push_back(b);
    if (len[b] == 2) middles.push_back(b);
  }
  const auto drop = [&](int a, int v) {  // removes v from a's list
    int* first = adj.data() + ptr[a];
    int* at = std::find(first, first + len[a], v);
    *at = first[--len[a]];
  };
  const auto replace = [&](int a, int v, int b) {  // v -> b in a's list
    int* first = adj.data() + ptr[a];
    *std::find(first, first + len[a], v) = b;
  };
  while (!leaves.empty() || !middles.empty()) {
    std::vector<int>& from = leaves.empty() ? middles : leaves;
    const int v = from.back();
    from.pop_back();
    if (eliminated[v] || len[v] > 2) continue;
    const int d = len[v];
    lnz += d;
    nms += 0.5 * d * (d + 1);
    if (d == 1) {
      drop(adj[ptr[v]], v);
    } else if (d == 2) {
      const int a = adj[ptr[v]], b = adj[ptr[v] + 1];
      const int* first = adj.data() + ptr[a];
      if (std::find(first, first + len[a], b) != first + len[a]) {
        drop(a, v);
        drop(b, v);
      } else {
        replace(a, v, b);
        replace(b, v, a);
      }
    }
    for (int k = 0; k < d; ++k) {
      const int u = adj[ptr[v] + k];
      if (len[u] <= 1) leaves.push_back(u);
      if (len[u] == 2) middles.push_back(u);
    }
    len[v] = 0;
    eliminated[v] = 1;
    order.push_back(v);
  }
}

/// SuiteSparse's AMD core (amd_2) on the `m` blocks not eliminated yet, renumbered:
/// amd_order's checks, its transpose and its A + A^T would only copy the graph again, and
/// half the entries again as elbow room spare it amd_order's garbage collections (the same
/// order either way). Appends them to `order` and AMD's counts to `lnz` and `nms`; true
/// when AMD set dense rows aside.
bool amdRemaining(const AdjacencyLists& lists, const std::vector<char>& eliminated, int m,
                  std::vector<int>& order, double& lnz, double& nms) {
  const std::vector<int>& ptr = lists.ptr;
  const std::vector<int>& len = lists.len;
  const std::vector<int>& adj = lists.adj;
  const int n = static_cast<int>(len.size());
  const auto size = static_cast<std::size_t>(n);
  std::vector<int> local(size, -1), global;
  global.reserve(static_cast<std::size_t>(m));
  for (int b = 0; b < n; ++b) {
    if (eliminated[b]) continue;
    local[b] = static_cast<int>(global.size());
    global.push_back(b);
  }
  const auto msize = static_cast<std::size_t>(m);
  std::vector<int> pe(msize), mlen(msize);
  int nz = 0;
  for (int b : global) nz += len[b];
  const int iwlen = nz + nz / 2 + m;
  std::vector<int> iw(static_cast<std::size_t>(iwlen));
  int at = 0;
  for (int k = 0; k < m; ++k) {
    const int b = global[k];
    pe[k] = at;
    for (int q = ptr[b]; q < ptr[b] + len[b]; ++q) iw[at++] = local[adj[q]];
    mlen[k] = len[b];
  }
  std::vector<int> nv(msize), pinv(msize), p(msize), head(msize), elen(msize), degree(msize),
      w(msize);
  double control[AMD_CONTROL];
  double info[AMD_INFO];
  amd_defaults(control);
  amd_2(m, pe.data(), iw.data(), mlen.data(), iwlen, nz, nv.data(), pinv.data(), p.data(),
        head.data(), elen.data(), degree.data(), w.data(), control, info);
  for (int k : p) order.push_back(global[k]);
  lnz += info[AMD_LNZ];
  nms += info[AMD_NMULTSUBS_LDL];
  return info[AMD_NDENSE] > 0;
}
#endif

}  // namespace

/// AMD on the block graph; `block_work` (if given) receives AMD's own count of the
/// factor's work, sum over block columns of (blocks in the column)^2 (close to the exact
/// count, above it), or -1 when there is none: this build has no SuiteSparse, or AMD set
/// dense rows aside (its counts then leave out their entries in the other columns).
std::vector<int> amdBlocks(const BlockGraph& g, double* block_work) {
  if (block_work) *block_work = -1.0;
#ifdef GRAPHSLAM_HAVE_CHOLMOD
  const int n = g.num_blocks;
  if (n == 0) return {};
  const auto size = static_cast<std::size_t>(n);
  AdjacencyLists lists = withoutDiagonal(g);
  // AMD's counts of the factor, for the eliminated blocks as AMD defines them.
  double lnz = 0.0, nms = 0.0;
  std::vector<int> order;
  order.reserve(size);
  std::vector<char> eliminated(size, 0);
  eliminateChains(lists, order, eliminated, lnz, nms);
  const int m = n - static_cast<int>(order.size());
  bool dense = false;
  if (m > 0) dense = amdRemaining(lists, eliminated, m, order, lnz, nms);
  // With b_j the blocks below the diagonal in block column j: sum (b_j + 1)^2 =
  // 2 NMULTSUBS + LNZ + n.
  if (block_work && !dense) *block_work = 2.0 * nms + lnz + n;
  return order;
#else
  // Eigen's AMD reads only the pattern, but takes a matrix with values.
  const std::vector<double> ones(g.idx.size(), 1.0);
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::ColMajor, int>> m(
      g.num_blocks, g.num_blocks, static_cast<int>(g.idx.size()), g.ptr.data(), g.idx.data(),
      ones.data());
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> copy = m;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p;
  Eigen::AMDOrdering<int> amd;
  amd(copy, p);
  return {p.indices().data(), p.indices().data() + p.indices().size()};
#endif
}

}  // namespace graphslam::solvers::detail
