// SPDX-License-Identifier: MIT
// Fill-reducing orderings: block orderings kept across block sizes, AMD's fill, auto's choice.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "graphslam/solvers/ordering.h"
#include "graphslam/solvers/register.h"
#include "solver_test_systems.h"

using namespace graphslam;
using test::GridPattern;

namespace {

/// The block pattern with the row blocks `rows[c]` (each <= c; sorted and made unique
/// here) in block column c: upper triangle, complete bs x bs blocks.
struct BlockRowsPattern {
  int nb, bs;
  std::vector<int> block_starts, col_ptr{0}, row_idx;
  BlockRowsPattern(std::vector<std::vector<int>> rows, int block_size)
      : nb(static_cast<int>(rows.size())), bs(block_size) {
    for (int b = 0; b <= nb; ++b) block_starts.push_back(b * bs);
    for (int cb = 0; cb < nb; ++cb) {
      auto& r = rows[cb];
      std::sort(r.begin(), r.end());
      r.erase(std::unique(r.begin(), r.end()), r.end());
      for (int k = 0; k < bs; ++k) {
        for (int rb : r) {
          for (int i = 0; i < bs; ++i) row_idx.push_back(rb * bs + i);
        }
        col_ptr.push_back(static_cast<int>(row_idx.size()));
      }
    }
  }
  SparseStructure structure() const {
    SparseStructure s;
    s.n = nb * bs;
    s.col_ptr = col_ptr.data();
    s.row_idx = row_idx.data();
    s.block_starts = block_starts.data();
    s.num_blocks = nb;
    return s;
  }
};

/// A random block pattern (a chain plus one random link per block) built in linear time.
BlockRowsPattern largeBlockPattern(int nb, int bs, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, nb - 1);
  std::vector<std::vector<int>> rows(static_cast<std::size_t>(nb));  // row blocks <= column
  for (int b = 0; b < nb; ++b) {
    rows[b].push_back(b);
    if (b > 0) rows[b].push_back(b - 1);
    const int a = pick(rng), c = pick(rng);
    if (a != c) rows[std::max(a, c)].push_back(std::min(a, c));
  }
  return BlockRowsPattern(std::move(rows), bs);
}

/// Off-diagonal blocks of L when the block graph of `pairs` (nb blocks) is eliminated in
/// `order`: each block's neighbours not yet eliminated, which then become adjacent.
int eliminationFill(int nb, const std::vector<std::pair<int, int>>& pairs,
                    const std::vector<int>& order) {
  std::vector<std::set<int>> adj(static_cast<std::size_t>(nb));
  for (const auto& [a, b] : pairs) {
    adj[a].insert(b);
    adj[b].insert(a);
  }
  std::vector<char> done(static_cast<std::size_t>(nb), 0);
  int fill = 0;
  for (int v : order) {
    std::vector<int> left;
    for (int u : adj[v]) {
      if (!done[u]) left.push_back(u);
    }
    fill += static_cast<int>(left.size());
    for (int a : left) {
      for (int b : left) {
        if (a != b) adj[a].insert(b);
      }
    }
    done[v] = 1;
  }
  return fill;
}

}  // namespace

TEST(Solvers_Ordering, LargeBlockGraphsKeepTheirOrderingAcrossBlockSizes) {
  // The global initial guess (2x2 blocks) and the optimizer (3x3) order one pose graph;
  // with a shared OrderingCache, from its min_blocks on, the block ordering is kept for the
  // next request with the same block graph. Each must still get the ordering of its own
  // graph.
  std::vector<Ordering> orderings{Ordering::kAmd};
  if (solvers::haveSuiteSparse()) orderings.push_back(Ordering::kMetis);
  for (Ordering o : orderings) {
    SCOPED_TRACE(toString(o));
    const BlockRowsPattern two = largeBlockPattern(60000, 2, 5),
                           three = largeBlockPattern(60000, 3, 5),
                           other = largeBlockPattern(60000, 3, 6);
    const auto blocks_of = [](const std::vector<int>& perm, int bs) {
      std::vector<int> order;
      for (std::size_t k = 0; k < perm.size(); k += static_cast<std::size_t>(bs)) {
        EXPECT_EQ(perm[k] % bs, 0);
        order.push_back(perm[k] / bs);
      }
      return order;
    };
    solvers::OrderingCache cache;
    ASSERT_LE(cache.options().min_blocks, 60000);
    const auto p2 = blocks_of(solvers::fillReducingOrdering(o, two.structure(), &cache), 2);
    const auto p3 = blocks_of(solvers::fillReducingOrdering(o, three.structure(), &cache), 3);
    const auto po = blocks_of(solvers::fillReducingOrdering(o, other.structure(), &cache), 3);
    // Without a cache, the same orderings.
    EXPECT_EQ(blocks_of(solvers::fillReducingOrdering(o, three.structure()), 3), p3);
    EXPECT_EQ(p2, p3);
    EXPECT_NE(po, p3);  // another graph of the same size is ordered anew
    for (const auto* p : {&p3, &po}) {
      std::vector<int> sorted = *p;
      std::sort(sorted.begin(), sorted.end());
      std::vector<int> iota(sorted.size());
      std::iota(iota.begin(), iota.end(), 0);
      EXPECT_EQ(sorted, iota);
    }
  }
}

TEST(Solvers_Ordering, MetisOrderingsOfSmallerGraphsAreKeptToo) {
  // METIS costs tens of milliseconds from a few thousand blocks on: the initial guess and
  // the optimizer of a 10000-pose graph share it from metis_min_blocks on (AMD's orderings
  // only from min_blocks). Each block size still gets its own graph's ordering.
  if (!solvers::haveSuiteSparse()) GTEST_SKIP() << "METIS needs SuiteSparse";
  solvers::OrderingCache cache;
  ASSERT_LE(cache.options().metis_min_blocks, 3000);
  ASSERT_GT(cache.options().min_blocks, 3000);
  const BlockRowsPattern two = largeBlockPattern(3000, 2, 7), three = largeBlockPattern(3000, 3, 7),
                         other = largeBlockPattern(3000, 3, 8);
  const auto blocks_of = [](const std::vector<int>& perm, int bs) {
    std::vector<int> order;
    for (std::size_t k = 0; k < perm.size(); k += static_cast<std::size_t>(bs)) {
      order.push_back(perm[k] / bs);
    }
    return order;
  };
  const auto metis = [&](const BlockRowsPattern& p, int bs, solvers::OrderingCache* c) {
    return blocks_of(solvers::fillReducingOrdering(Ordering::kMetis, p.structure(), c), bs);
  };
  const auto p2 = metis(two, 2, &cache);
  EXPECT_EQ(metis(three, 3, &cache), p2);
  EXPECT_EQ(metis(three, 3, nullptr), p2);
  EXPECT_NE(metis(other, 3, &cache), p2);
  EXPECT_EQ(metis(other, 3, &cache), metis(other, 3, nullptr));
}

TEST(Solvers_Ordering, AmdEliminatesChainsRingsAndLeavesWithoutExtraFill) {
  // Blocks of at most two neighbours are eliminated before AMD orders the rest. Components:
  // a ring of 30 with a chain of 10 hanging from it (fill 2 * 30 - 3 + 10), a triangle
  // (3), and a complete graph of 5 (AMD's part, renumbered: 4 + 3 + 2 + 1) with a chain of
  // 3 (3). Each figure is the least fill of its component.
  std::vector<std::pair<int, int>> pairs;
  for (int k = 0; k < 30; ++k) pairs.emplace_back(k, (k + 1) % 30);
  for (int k = 30; k < 40; ++k) pairs.emplace_back(k, k == 30 ? 5 : k - 1);
  pairs.insert(pairs.end(), {{40, 41}, {41, 42}, {40, 42}});
  for (int a = 43; a < 48; ++a) {
    for (int b = a + 1; b < 48; ++b) pairs.emplace_back(a, b);
  }
  pairs.insert(pairs.end(), {{45, 48}, {48, 49}, {49, 50}});
  const int nb = 51, bs = 3;
  std::vector<std::vector<int>> rows(static_cast<std::size_t>(nb));
  for (int b = 0; b < nb; ++b) rows[b].push_back(b);
  for (const auto& [a, b] : pairs) rows[std::max(a, b)].push_back(std::min(a, b));
  const BlockRowsPattern pattern(std::move(rows), bs);
  const SparseStructure s = pattern.structure();
  const std::vector<int> perm = solvers::fillReducingOrdering(Ordering::kAmd, s);
  ASSERT_EQ(perm.size(), static_cast<std::size_t>(s.n));
  std::vector<int> order;
  for (std::size_t k = 0; k < perm.size(); k += bs) {
    for (int i = 0; i < bs; ++i) ASSERT_EQ(perm[k + i], perm[k] + i);  // whole blocks
    order.push_back(perm[k] / bs);
  }
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int b = 0; b < nb; ++b) ASSERT_EQ(sorted[b], b);
  EXPECT_EQ(eliminationFill(nb, pairs, order), (2 * 30 - 3 + 10) + 3 + (4 + 3 + 2 + 1) + 3);
}

// auto's ordering: METIS is tried when AMD predicts more than 2e8 flops and kept when it
// predicts fewer; from 200000 blocks on it is computed on a second thread next to AMD. Both
// paths must choose as the rule says (grids: nested dissection wins).
TEST(Solvers_ChooseOrdering, MetisWinsOnLargeGridsSequentialAndConcurrent) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  if (!registry.contains("cholmod")) GTEST_SKIP() << "METIS needs CHOLMOD";
  for (int side : {300, 480}) {  // 90000 blocks (sequential), 230400 (concurrent)
    const GridPattern grid(side);
    const SparseStructure& s = grid.structure;
    const solvers::ChosenOrdering chosen = solvers::chooseOrdering(s);
    const solvers::CholeskyPrediction amd =
        solvers::predictCholesky(s, solvers::fillReducingOrdering(Ordering::kAmd, s));
    const std::vector<int> metis_perm = solvers::fillReducingOrdering(Ordering::kMetis, s);
    const solvers::CholeskyPrediction metis = solvers::predictCholesky(s, metis_perm);
    std::printf("grid %d x %d: AMD %.3g flops, METIS %.3g flops\n", side, side, amd.flops,
                metis.flops);
    ASSERT_GT(amd.flops, 2e8);
    ASSERT_LT(metis.flops, amd.flops);
    EXPECT_EQ(chosen.ordering, Ordering::kMetis) << side;
    EXPECT_EQ(chosen.perm, metis_perm) << side;
    EXPECT_EQ(chosen.prediction.flops, metis.flops) << side;
  }
}
