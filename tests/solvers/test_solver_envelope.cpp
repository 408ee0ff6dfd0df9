// SPDX-License-Identifier: MIT
// The envelope (skyline) solver: rings in any order, vertices of mixed dimensions.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/solvers/register.h"
#include "solver_test_systems.h"

using namespace graphslam;
using test::BlockSystem;

// A ring of vertices with a few chords (a loop), its vertices numbered at random: in that
// order the envelope is wide, reverse Cuthill-McKee brings it back to a band. Every
// ordering solves it (AMD and COLAMD give rows whose first columns are not increasing:
// the kernel's rows j and j + 1 then start apart), for vertices of 1, 2 and 3 dimensions
// and 123 vertices (a last, partial group of four rows), whether H = H_s (x) I (the
// scalar H_s factorised) or not (H itself), the two alternating on one analysis; a
// negated diagonal block is a failure at its vertex's first column.
TEST(Solvers_Envelope, RingsInAnyOrderAreSolvedAndNameTheFailingVertex) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  std::mt19937 rng(5);
  const int nb = 123;
  std::vector<int> label(nb);
  std::iota(label.begin(), label.end(), 0);
  std::shuffle(label.begin(), label.end(), rng);
  std::set<std::pair<int, int>> upper;
  auto connect = [&](int a, int b) {
    upper.insert({std::min(label[a], label[b]), std::max(label[a], label[b])});
  };
  for (int v = 0; v < nb; ++v) connect(v, (v + 1) % nb);
  for (int v = 0; v < nb; v += 10) connect(v, (v + 3) % nb);
  EXPECT_EQ(registry.create("envelope")->ordering(), Ordering::kRcm);
  for (const int d : {1, 2, 3}) {
    BlockSystem sys(nb, d, upper);
    const Eigen::MatrixXd general = sys.randomSpd(rng);
    const Eigen::MatrixXd iso = sys.isotropic(general);
    const Eigen::VectorXd rhs = Eigen::VectorXd::Random(sys.n());
    std::size_t rcm_entries[2] = {}, natural_entries[2] = {};
    for (const char* spec : {"envelope:rcm", "envelope:natural", "envelope:amd", "envelope:colamd",
                             "envelope:metis"}) {
      if (!registry.contains(spec)) continue;  // METIS and COLAMD need SuiteSparse
      auto solver = registry.create(spec);
      EXPECT_EQ(solver->name(), "envelope");
      ASSERT_TRUE(solver->analyze(sys.structure()).ok());
      for (const int pass : {0, 1, 2}) {  // H_s (x) I, H, H_s (x) I again
        const Eigen::MatrixXd& m = pass == 1 ? general : iso;
        SCOPED_TRACE(std::string(spec) + " d = " + std::to_string(d) +
                     (pass == 1 ? " general" : " isotropic"));
        const Eigen::VectorXd expected = m.ldlt().solve(rhs);
        const auto values = sys.values(m);
        ASSERT_TRUE(solver->factorize(values.data()).ok());
        Eigen::VectorXd x(sys.n());
        ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
        EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-10);
        // L_s (x) I has d entries per entry of L_s; H's own factor has d^2 per block.
        const std::size_t entries = solver->factorNonZeros();
        if (std::string(spec) == "envelope:rcm") rcm_entries[pass % 2] = entries;
        if (std::string(spec) == "envelope:natural") natural_entries[pass % 2] = entries;
        for (const int b : {0, 61, 122}) {  // block b negated (an isotropic H stays so)
          Eigen::MatrixXd bad = m;
          bad.block(d * b, d * b, d, d) *= -1.0;
          const auto bad_values = sys.values(bad);
          const LinearSolverResult r = solver->factorize(bad_values.data());
          EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite) << b;
          EXPECT_EQ(r.column, d * b) << b;
        }
        // The factor of a good system again after a failure.
        ASSERT_TRUE(solver->factorize(values.data()).ok());
        ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
        EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-10);
      }
    }
    // A ring's band: each row of L starts at most a few vertices back (chords of three
    // steps widen it); at random, rows reach far back.
    for (const int general_h : {0, 1}) {
      const std::size_t per_block = general_h ? static_cast<std::size_t>(d * d) : d;
      EXPECT_LE(rcm_entries[general_h], per_block * nb * 10) << general_h;
      EXPECT_GT(natural_entries[general_h], 3 * rcm_entries[general_h]) << general_h;
    }
  }
}

// Vertices of 3 and 2 dimensions (poses and landmarks) in a ring with chords: H's own
// envelope, whose rows start at the first column of a vertex, in every ordering.
TEST(Solvers_Envelope, VerticesOfMixedDimensionsAreSolved) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  std::mt19937 rng(8);
  const int nb = 61;
  std::vector<int> starts{0};
  for (int b = 0; b < nb; ++b) starts.push_back(starts.back() + (b % 3 == 2 ? 2 : 3));
  const int n = starts.back();
  std::set<std::pair<int, int>> blocks;
  for (int b = 0; b < nb; ++b) {
    blocks.insert({b, b});
    blocks.insert({std::min(b, (b + 1) % nb), std::max(b, (b + 1) % nb)});
    if (b % 7 == 0) blocks.insert({std::min(b, (b + 5) % nb), std::max(b, (b + 5) % nb)});
  }
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (const auto& [rb, cb] : blocks) {
    for (int r = starts[rb]; r < starts[rb + 1]; ++r) {
      for (int c = starts[cb]; c < starts[cb + 1]; ++c) {
        const double x = u(rng);
        m(r, c) += x;
        m(c, r) += rb == cb ? 0.0 : x;
      }
    }
  }
  m = (m + m.transpose()).eval() * 0.5;
  for (int i = 0; i < n; ++i) m(i, i) = m.row(i).cwiseAbs().sum() + 1.0;
  // The upper triangle with complete diagonal blocks, rows sorted.
  std::vector<int> col_ptr{0}, row_idx;
  for (int cb = 0; cb < nb; ++cb) {
    for (int c = starts[cb]; c < starts[cb + 1]; ++c) {
      for (const auto& [rb, b] : blocks) {
        if (b != cb) continue;
        for (int r = starts[rb]; r < starts[rb + 1]; ++r) row_idx.push_back(r);
      }
      col_ptr.push_back(static_cast<int>(row_idx.size()));
    }
  }
  SparseStructure s;
  s.n = n;
  s.col_ptr = col_ptr.data();
  s.row_idx = row_idx.data();
  s.block_starts = starts.data();
  s.num_blocks = nb;
  const auto values_of = [&](const Eigen::MatrixXd& a) {
    std::vector<double> v;
    for (int c = 0; c < n; ++c) {
      for (int k = col_ptr[c]; k < col_ptr[c + 1]; ++k) v.push_back(a(row_idx[k], c));
    }
    return v;
  };
  const std::vector<double> values = values_of(m);
  const Eigen::VectorXd rhs = Eigen::VectorXd::Random(n);
  const Eigen::VectorXd expected = m.ldlt().solve(rhs);
  for (const char* spec : {"envelope:rcm", "envelope:natural", "envelope:amd"}) {
    SCOPED_TRACE(spec);
    auto solver = registry.create(spec);
    ASSERT_TRUE(solver->analyze(s).ok());
    ASSERT_TRUE(solver->factorize(values.data()).ok());
    Eigen::VectorXd x(n);
    ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
    EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-10);
    for (const int b : {0, 29, 60}) {
      Eigen::MatrixXd bad = m;
      const int dim = starts[b + 1] - starts[b];
      bad.block(starts[b], starts[b], dim, dim) *= -1.0;
      const std::vector<double> bad_values = values_of(bad);
      const LinearSolverResult r = solver->factorize(bad_values.data());
      EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite) << b;
      EXPECT_EQ(r.column, starts[b]) << b;
    }
  }
}
