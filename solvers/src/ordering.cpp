// SPDX-License-Identifier: MIT
#include "ordering.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cstdint>
#include <memory>
#include <mutex>
#include <numeric>

#include "common.h"
#include "graphslam/support/error.h"
#include "suitesparse.h"

#ifdef GRAPHSLAM_HAVE_CHOLMOD
#include <amd.h>
#include <colamd.h>
#endif

namespace graphslam::solvers {

/// The kept orderings: one AMD and one METIS block ordering, each of the most recent
/// graph it was asked for.
struct OrderingCache::Impl {
  struct Entry {
    std::uint64_t key = 0;
    std::vector<int> perm;
  };
  std::mutex mutex;
  Entry amd, metis;
};

OrderingCache::OrderingCache(OrderingCacheOptions options)
    : options_(options), impl_(std::make_unique<Impl>()) {}

OrderingCache::~OrderingCache() = default;

void OrderingCache::clear() {
  const std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->amd = {};
  impl_->metis = {};
}

}  // namespace graphslam::solvers

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

#endif

/// Reverse Cuthill-McKee (George and Liu): each connected component by breadth-first
/// search from a pseudo-peripheral node, each node's unvisited neighbours taken in
/// increasing degree; the whole order reversed. Components in the order of their lowest
/// node. The root: from that node, the lowest-degree node of the last level while that
/// deepens the search; a candidate as deep as the root is as good a root, and its search
/// (every search sorts) is the order, which saves one search. Written here rather than
/// taken from a graph library: it works on the block graph as it is, without building
/// another graph, which matters where the whole solve is a fraction of a millisecond.
std::vector<int> rcmBlocks(const BlockGraph& g) {
  const int n = g.num_blocks;
  std::vector<int> degree(static_cast<std::size_t>(n), 0);
  for (int b = 0; b < n; ++b) {
    for (int k = g.ptr[b]; k < g.ptr[b + 1]; ++k) degree[b] += g.idx[k] != b ? 1 : 0;
  }
  const auto by_degree = [&](int a, int b) {
    return degree[a] < degree[b] || (degree[a] == degree[b] && a < b);
  };
  std::vector<int> level(static_cast<std::size_t>(n), -1);
  // Breadth-first search of root's component into `out` (n entries; each node's new
  // neighbours in increasing degree: the Cuthill-McKee order); returns the depth of the
  // last level and sets `size` and `last_level` (where it starts in `out`). Leaves `level`
  // as it found it. A neighbour is appended unconditionally and kept when it was new (no
  // branch on the visited test, which a dense graph makes unpredictable).
  std::size_t size = 0, last_level = 0;
  const auto search = [&](int root, std::vector<int>& out) {
    out[0] = root;
    size = 1;
    level[root] = 0;
    for (std::size_t h = 0; h < size; ++h) {
      const int v = out[h];
      const int next = level[v] + 1;
      const std::size_t added = size;
      for (int k = g.ptr[v]; k < g.ptr[v + 1]; ++k) {
        const int u = g.idx[k];
        const bool fresh = level[u] < 0;
        out[size] = u;
        level[u] = fresh ? next : level[u];
        size += fresh ? 1 : 0;
      }
      if (size - added > 1) {
        std::sort(out.begin() + static_cast<std::ptrdiff_t>(added),
                  out.begin() + static_cast<std::ptrdiff_t>(size), by_degree);
      }
    }
    const int depth = level[out[size - 1]];
    last_level = size - 1;
    while (last_level > 0 && level[out[last_level - 1]] == depth) --last_level;
    for (std::size_t k = 0; k < size; ++k) level[out[k]] = -1;
    return depth;
  };
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(n));
  // One spare entry: a search writes a neighbour at out[size] before it knows whether it
  // keeps it.
  std::vector<int> best(static_cast<std::size_t>(n) + 1), probe(best.size());
  std::vector<char> placed(static_cast<std::size_t>(n), 0);
  for (int seed = 0; seed < n; ++seed) {
    if (placed[seed]) continue;
    int depth = search(seed, best);
    std::size_t best_size = size, best_last = last_level;
    for (int attempt = 0; attempt < 8; ++attempt) {
      const int candidate =
          *std::min_element(best.begin() + static_cast<std::ptrdiff_t>(best_last),
                            best.begin() + static_cast<std::ptrdiff_t>(best_size), by_degree);
      const int d = search(candidate, probe);
      if (d < depth) break;
      best.swap(probe);
      best_last = last_level;
      if (d == depth) break;
      depth = d;
    }
    order.insert(order.end(), best.begin(), best.begin() + static_cast<std::ptrdiff_t>(best_size));
    for (std::size_t k = order.size() - best_size; k < order.size(); ++k) placed[order[k]] = 1;
  }
  std::reverse(order.begin(), order.end());
  return order;
}

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
      return metisBlockOrdering(g);
#else
      break;
#endif
    case Ordering::kRcm:
      return rcmBlocks(g);
  }
  throw Error(std::string("ordering '") + toString(ordering) +
              "' is not available in this build (it needs SuiteSparse)");
}

}  // namespace

namespace {

/// Calls f(r, b) for every block (r, b), r <= b, of H's upper triangle, block column by
/// block column, rows ascending (every column of a block has the same pattern: the first
/// is read). D: every block of dimension D (0: d at run time); D = -1: dimensions differ,
/// `block` maps a column to its block.
template <int D, typename F>
void forUpperBlocks(const SparseStructure& s, int d, const std::vector<int>& block, F&& f) {
  if constexpr (D > 0) d = D;
  for (int b = 0; b < s.num_blocks; ++b) {
    const int c = s.block_starts[b];
    const int end = s.col_ptr[c + 1];
    for (int k = s.col_ptr[c]; k < end;) {
      int rb;
      if constexpr (D < 0) {
        rb = block[s.row_idx[k]];
        k += s.block_starts[rb + 1] - s.block_starts[rb];
      } else {
        rb = s.row_idx[k] / d;
        k += d;
      }
      if (rb > b) break;  // entries below the diagonal block (not stored in upper form)
      f(rb, b);
    }
  }
}

/// blockGraph for blocks of dimension D (forUpperBlocks).
template <int D>
BlockGraph blockGraphOf(const SparseStructure& s, int d) {
  // Column b of the symmetric graph is the rows r <= b of H's upper block column b, then
  // every c > b whose column holds block (b, c), in increasing c. Filled block column by
  // block column, each column receives its own rows first, then the later columns in
  // increasing order: sorted, without a sort.
  const int nb = s.num_blocks;
  const std::vector<int> block =
      D < 0 ? blockOfColumn(s.block_starts, nb, s.n) : std::vector<int>();
  BlockGraph g;
  g.num_blocks = nb;
  g.ptr.assign(static_cast<std::size_t>(nb) + 1, 0);
  int* count = g.ptr.data() + 1;
  forUpperBlocks<D>(s, d, block, [count](int r, int b) {
    ++count[b];
    if (r != b) ++count[r];
  });
  for (int b = 0; b < nb; ++b) g.ptr[b + 1] += g.ptr[b];
  g.idx.resize(static_cast<std::size_t>(g.ptr[nb]));
  std::vector<int> next(g.ptr.begin(), g.ptr.end() - 1);
  int* idx = g.idx.data();
  int* at = next.data();
  forUpperBlocks<D>(s, d, block, [idx, at](int r, int b) {
    idx[at[b]++] = r;
    if (r != b) idx[at[r]++] = b;
  });
  return g;
}

}  // namespace

BlockGraph blockGraph(const SparseStructure& s) {
  const int nb = s.num_blocks;
  const int d = nb > 0 ? s.block_starts[1] - s.block_starts[0] : 1;
  bool uniform = true;  // every block of dimension d: fixed steps
  for (int b = 1; b < nb && uniform; ++b) uniform = s.block_starts[b + 1] - s.block_starts[b] == d;
  if (!uniform) return blockGraphOf<-1>(s, d);
  return withFixedSize(d, [&](auto size) { return blockGraphOf<decltype(size)::value>(s, d); });
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

std::vector<int> orderColumns(Ordering ordering, const SparseStructure& s, OrderingCache* cache) {
  if (ordering == Ordering::kNatural) {  // no graph needed
    std::vector<int> perm(static_cast<std::size_t>(s.n));
    std::iota(perm.begin(), perm.end(), 0);
    return perm;
  }
  return orderColumns(ordering, s, blockGraph(s), cache);
}

namespace {

/// 64-bit fingerprint of a block graph (splitmix64 steps over its arrays).
std::uint64_t fingerprint(const BlockGraph& g) {
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  auto mix = [&h](std::uint64_t v) {
    h += v + 0x9e3779b97f4a7c15ULL;
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
    h ^= h >> 31;
  };
  mix(static_cast<std::uint64_t>(g.num_blocks));
  for (int v : g.ptr) mix(static_cast<std::uint64_t>(v));
  for (int v : g.idx) mix(static_cast<std::uint64_t>(v));
  return h;
}

/// Whether `cache` keeps the `ordering` (AMD or METIS) of `g`.
bool cached(const OrderingCache* cache, const BlockGraph& g, Ordering ordering) {
  if (!cache) return false;
  return g.num_blocks >= (ordering == Ordering::kMetis ? cache->options().metis_min_blocks
                                                       : cache->options().min_blocks);
}

/// The AMD or METIS block ordering of `g`, looked up in `cache` and kept there.
std::vector<int> cachedBlockOrdering(Ordering ordering, const BlockGraph& g, OrderingCache& cache) {
  OrderingCache::Impl& impl = cache.impl();
  OrderingCache::Impl::Entry& entry = ordering == Ordering::kMetis ? impl.metis : impl.amd;
  const std::uint64_t key = fingerprint(g);
  {
    const std::lock_guard<std::mutex> lock(impl.mutex);
    if (entry.key == key && entry.perm.size() == static_cast<std::size_t>(g.num_blocks)) {
      return entry.perm;
    }
  }
  std::vector<int> perm = orderBlockGraph(ordering, g);
  const std::lock_guard<std::mutex> lock(impl.mutex);
  entry.key = key;
  entry.perm = perm;
  return perm;
}

}  // namespace

std::vector<int> orderColumns(Ordering ordering, const SparseStructure& s, const BlockGraph& g,
                              OrderingCache* cache) {
  const bool amd = ordering == Ordering::kAmd || ordering == Ordering::kDefault;
  if ((ordering == Ordering::kMetis || amd) && cached(cache, g, ordering)) {
    return expand(cachedBlockOrdering(amd ? Ordering::kAmd : ordering, g, *cache), s.block_starts,
                  s.n);
  }
  return expand(orderBlockGraph(ordering, g), s.block_starts, s.n);
}

std::vector<int> orderColumnsAmd(const SparseStructure& s, const BlockGraph& g, double* block_work,
                                 OrderingCache* cache) {
  if (cached(cache, g, Ordering::kAmd)) {
    if (block_work) *block_work = -1.0;
    return orderColumns(Ordering::kAmd, s, g, cache);
  }
  return expand(amdBlocks(g, block_work), s.block_starts, s.n);
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

LinearSolverResult OrderedSolver::analyze(const SparseStructure& s) {
  return analyzeOrdered(s, orderColumns(ordering(), s, ordering_cache_.get()), ordering());
}

std::vector<int> inversePermutation(const std::vector<int>& perm) {
  std::vector<int> inv(perm.size());
  for (std::size_t k = 0; k < perm.size(); ++k)
    inv[static_cast<std::size_t>(perm[k])] = static_cast<int>(k);
  return inv;
}

}  // namespace graphslam::solvers::detail
