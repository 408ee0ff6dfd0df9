// SPDX-License-Identifier: MIT
#include "ordering.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <numeric>

#include "graphslam/core/block_ordering.h"
#include "graphslam/core/error.h"

#ifdef GRAPHSLAM_HAVE_CHOLMOD
#include <cholmod.h>
#include <colamd.h>
#endif

namespace graphslam::solvers::detail {

std::vector<int> blockOfColumn(const int* block_starts, int num_blocks, int n) {
  std::vector<int> block(static_cast<std::size_t>(n));
  for (int b = 0; b < num_blocks; ++b) {
    for (int c = block_starts[b]; c < block_starts[b + 1]; ++c) block[c] = b;
  }
  return block;
}

namespace {

/// CSC from per-column adjacency lists (sorted, unique).
BlockGraph fromLists(std::vector<std::vector<int>>& lists) {
  BlockGraph g;
  g.num_blocks = static_cast<int>(lists.size());
  g.ptr.assign(lists.size() + 1, 0);
  for (std::size_t b = 0; b < lists.size(); ++b) {
    auto& l = lists[b];
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    g.ptr[b + 1] = g.ptr[b] + static_cast<int>(l.size());
    g.idx.insert(g.idx.end(), l.begin(), l.end());
  }
  return g;
}

/// Expands a block permutation to scalar columns.
std::vector<int> expand(const std::vector<int>& block_perm, const int* block_starts, int n) {
  std::vector<int> perm;
  perm.reserve(static_cast<std::size_t>(n));
  for (int b : block_perm) {
    for (int c = block_starts[b]; c < block_starts[b + 1]; ++c) perm.push_back(c);
  }
  return perm;
}

std::vector<int> amdBlocks(const BlockGraph& g) {
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
}

#ifdef GRAPHSLAM_HAVE_CHOLMOD
/// COLAMD on a rows x cols pattern (CSC), returns the column order.
std::vector<int> colamdColumns(int rows, int cols, const std::vector<int>& ptr,
                               const std::vector<int>& idx) {
  const int nnz = static_cast<int>(idx.size());
  const auto alen = colamd_recommended(nnz, rows, cols);
  if (alen == 0) throw Error("colamd: matrix too large");
  std::vector<int> a(alen);
  std::copy(idx.begin(), idx.end(), a.begin());
  std::vector<int> p(ptr.begin(), ptr.end());
  double knobs[COLAMD_KNOBS];
  colamd_set_defaults(knobs);
  int stats[COLAMD_STATS];
  if (!colamd(rows, cols, static_cast<int>(alen), a.data(), p.data(), knobs, stats)) {
    throw Error("colamd failed (status " + std::to_string(stats[COLAMD_STATUS]) + ")");
  }
  return {p.begin(), p.begin() + cols};
}

/// METIS nested dissection (through CHOLMOD) on a symmetric block graph.
std::vector<int> metisBlocks(const BlockGraph& g) {
  cholmod_common cc;
  cholmod_start(&cc);
  cc.print = 0;
  cc.error_handler = nullptr;
  cholmod_sparse a{};
  a.nrow = a.ncol = static_cast<size_t>(g.num_blocks);
  a.nzmax = g.idx.size();
  a.p = const_cast<int*>(g.ptr.data());
  a.i = const_cast<int*>(g.idx.data());
  a.stype = 1;  // symmetric: METIS takes the graph of A itself (upper part read)
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_PATTERN;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  std::vector<int> perm(static_cast<std::size_t>(g.num_blocks));
  const int ok = cholmod_metis(&a, nullptr, 0, 1, perm.data(), &cc);
  const int status = cc.status;
  cholmod_finish(&cc);
  if (!ok || status < CHOLMOD_OK) {
    throw Error("METIS ordering failed (CHOLMOD status " + std::to_string(status) + ")");
  }
  return perm;
}
#endif

std::vector<int> orderBlockGraph(Ordering ordering, const BlockGraph& g) {
  switch (ordering) {
    case Ordering::kDefault:
    case Ordering::kAmd:
      return amdBlocks(g);
    case Ordering::kNatural: {
      std::vector<int> p(static_cast<std::size_t>(g.num_blocks));
      std::iota(p.begin(), p.end(), 0);
      return p;
    }
    case Ordering::kColamd:
#ifdef GRAPHSLAM_HAVE_CHOLMOD
      return colamdColumns(g.num_blocks, g.num_blocks, g.ptr, g.idx);
#else
      break;
#endif
    case Ordering::kMetis:
#ifdef GRAPHSLAM_HAVE_CHOLMOD
      return metisBlocks(g);
#else
      break;
#endif
  }
  throw Error(std::string("ordering '") + toString(ordering) +
              "' is not available in this build (it needs SuiteSparse)");
}

}  // namespace

BlockGraph blockGraph(const SparseStructure& s) {
  const auto block = blockOfColumn(s.block_starts, s.num_blocks, s.n);
  std::vector<std::vector<int>> lists(static_cast<std::size_t>(s.num_blocks));
  for (int b = 0; b < s.num_blocks; ++b) {
    const int c = s.block_starts[b];  // every column of a block has the same pattern
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      const int rb = block[s.row_idx[k]];
      lists[b].push_back(rb);
      if (rb != b) lists[rb].push_back(b);
    }
  }
  return fromLists(lists);
}

BlockGraph blockGraph(const JacobianStructure& s) {
  const auto block = blockOfColumn(s.block_starts, s.num_blocks, s.cols);
  // Blocks of every residual row (damping rows touch one column only: skipped).
  std::vector<std::vector<int>> blocks_of_row(static_cast<std::size_t>(s.damping_row));
  for (int b = 0; b < s.num_blocks; ++b) {
    const int c = s.block_starts[b];
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      if (s.row_idx[k] < s.damping_row) blocks_of_row[s.row_idx[k]].push_back(b);
    }
  }
  std::vector<std::vector<int>> lists(static_cast<std::size_t>(s.num_blocks));
  for (int b = 0; b < s.num_blocks; ++b) lists[b].push_back(b);
  for (const auto& bs : blocks_of_row) {
    for (int a : bs) lists[a].insert(lists[a].end(), bs.begin(), bs.end());
  }
  return fromLists(lists);
}

std::vector<Ordering> availableOrderings() {
#ifdef GRAPHSLAM_HAVE_CHOLMOD
  return {Ordering::kAmd, Ordering::kNatural, Ordering::kColamd, Ordering::kMetis};
#else
  return {Ordering::kAmd, Ordering::kNatural};
#endif
}

std::vector<int> orderColumns(Ordering ordering, const SparseStructure& s) {
  if (ordering == Ordering::kAmd || ordering == Ordering::kDefault) return blockAmdOrdering(s);
  return orderColumns(ordering, s, blockGraph(s));
}

std::vector<int> orderColumns(Ordering ordering, const SparseStructure& s, const BlockGraph& g) {
  if (ordering == Ordering::kAmd || ordering == Ordering::kDefault) return blockAmdOrdering(s);
  return expand(orderBlockGraph(ordering, g), s.block_starts, s.n);
}

std::vector<int> orderColumns(Ordering ordering, const JacobianStructure& s) {
#ifdef GRAPHSLAM_HAVE_CHOLMOD
  if (ordering == Ordering::kColamd) {
    // Pattern of J's residual rows against block columns.
    std::vector<int> ptr(1, 0), idx;
    for (int b = 0; b < s.num_blocks; ++b) {
      const int c = s.block_starts[b];
      for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
        if (s.row_idx[k] < s.damping_row) idx.push_back(s.row_idx[k]);
      }
      ptr.push_back(static_cast<int>(idx.size()));
    }
    return expand(colamdColumns(s.damping_row, s.num_blocks, ptr, idx), s.block_starts, s.cols);
  }
#endif
  return expand(orderBlockGraph(ordering, blockGraph(s)), s.block_starts, s.cols);
}

std::vector<int> inversePermutation(const std::vector<int>& perm) {
  std::vector<int> inv(perm.size());
  for (std::size_t k = 0; k < perm.size(); ++k)
    inv[static_cast<std::size_t>(perm[k])] = static_cast<int>(k);
  return inv;
}

}  // namespace graphslam::solvers::detail
