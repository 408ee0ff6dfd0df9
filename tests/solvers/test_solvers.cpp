// SPDX-License-Identifier: MIT
// Conformance suite run over every registered linear solver.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <random>
#include <set>
#include <string>

#include "graphslam/core/error.h"
#include "graphslam/solvers/ordering.h"
#include "graphslam/solvers/register.h"

using namespace graphslam;

namespace {

/// A random symmetric block-sparse matrix stored as the optimizer stores H: upper
/// triangle, diagonal blocks full.
struct BlockSystem {
  int nb = 0;
  int bs = 3;
  std::vector<int> block_starts, col_ptr, row_idx;
  std::set<std::pair<int, int>> blocks;  // (row block <= col block)

  BlockSystem(int num_blocks, int block_size, std::mt19937& rng) : nb(num_blocks), bs(block_size) {
    std::uniform_int_distribution<int> pick(0, nb - 1);
    for (int b = 0; b < nb; ++b) blocks.insert({b, b});
    for (int b = 0; b + 1 < nb; ++b) blocks.insert({b, b + 1});
    for (int k = 0; k < nb; ++k) {
      int a = pick(rng), c = pick(rng);
      if (a != c) blocks.insert({std::min(a, c), std::max(a, c)});
    }
    layOut();
  }
  /// The pattern of `upper_blocks` (row block <= column block; the diagonal is added).
  BlockSystem(int num_blocks, int block_size, std::set<std::pair<int, int>> upper_blocks)
      : nb(num_blocks), bs(block_size), blocks(std::move(upper_blocks)) {
    for (int b = 0; b < nb; ++b) blocks.insert({b, b});
    layOut();
  }

  void layOut() {
    for (int b = 0; b <= nb; ++b) block_starts.push_back(b * bs);
    col_ptr.push_back(0);
    for (int cb = 0; cb < nb; ++cb) {
      for (int k = 0; k < bs; ++k) {
        for (const auto& [rb, c] : blocks) {
          if (c != cb) continue;
          for (int r = 0; r < bs; ++r) row_idx.push_back(rb * bs + r);
        }
        col_ptr.push_back(static_cast<int>(row_idx.size()));
      }
    }
  }
  int n() const { return nb * bs; }
  SparseStructure structure() const {
    SparseStructure s;
    s.n = n();
    s.col_ptr = col_ptr.data();
    s.row_idx = row_idx.data();
    s.block_starts = block_starts.data();
    s.num_blocks = nb;
    return s;
  }
  /// Values of the dense symmetric matrix M in this pattern.
  std::vector<double> values(const Eigen::MatrixXd& m) const {
    std::vector<double> v;
    for (int c = 0; c < n(); ++c) {
      for (int k = col_ptr[c]; k < col_ptr[c + 1]; ++k) v.push_back(m(row_idx[k], c));
    }
    return v;
  }
  /// H_s (x) I from the (0, 0) entries of m's blocks (positive definite when m is
  /// diagonally dominant, as randomSpd makes it).
  Eigen::MatrixXd isotropic(const Eigen::MatrixXd& m) const {
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n(), n());
    for (int r = 0; r < nb; ++r) {
      for (int c = 0; c < nb; ++c) {
        for (int i = 0; i < bs; ++i) k(r * bs + i, c * bs + i) = m(r * bs, c * bs);
      }
    }
    return k;
  }
  /// The real form of a Hermitian complex matrix (2x2 blocks [a -b; b a], a from m's
  /// block (0, 0), b from its (1, 0); diagonal blocks a I), made diagonally dominant.
  Eigen::MatrixXd conformal(const Eigen::MatrixXd& m) const {
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n(), n());
    Eigen::VectorXd row_sum = Eigen::VectorXd::Zero(nb);
    for (const auto& [rb, cb] : blocks) {
      if (rb == cb) continue;
      const double a = m(rb * 2, cb * 2), b = m(rb * 2 + 1, cb * 2);
      k.block<2, 2>(rb * 2, cb * 2) << a, -b, b, a;
      k.block<2, 2>(cb * 2, rb * 2) = k.block<2, 2>(rb * 2, cb * 2).transpose();
      row_sum[rb] += std::abs(a) + std::abs(b);
      row_sum[cb] += std::abs(a) + std::abs(b);
    }
    for (int b = 0; b < nb; ++b)
      k.block<2, 2>(b * 2, b * 2) = (row_sum[b] + 1.0) * Eigen::Matrix2d::Identity();
    return k;
  }
  /// A random SPD matrix with this block pattern.
  Eigen::MatrixXd randomSpd(std::mt19937& rng) const {
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n(), n());
    for (const auto& [rb, cb] : blocks) {
      for (int r = 0; r < bs; ++r)
        for (int c = 0; c < bs; ++c) {
          const double x = u(rng);
          m(rb * bs + r, cb * bs + c) += x;
          if (rb != cb) m(cb * bs + c, rb * bs + r) += x;
        }
    }
    m = (m + m.transpose()).eval() * 0.5;
    // Diagonal dominance makes it SPD.
    for (int i = 0; i < n(); ++i) m(i, i) = m.row(i).cwiseAbs().sum() + 1.0;
    return m;
  }
};

/// A random block-sparse least-squares system stored as the optimizer stores the
/// whitened Jacobian: one 3-row residual block per "edge" touching one or two variable
/// blocks, then one damping row per column.
struct JacobianSystem {
  int nb = 0;
  int bs = 3;
  int residual_rows = 0;
  std::vector<std::vector<int>> edges;  // blocks of every edge
  std::vector<int> block_starts, col_ptr, row_idx;

  JacobianSystem(int num_blocks, int block_size, std::mt19937& rng)
      : nb(num_blocks), bs(block_size) {
    std::uniform_int_distribution<int> pick(0, nb - 1);
    edges.push_back({0});  // a prior
    for (int b = 0; b + 1 < nb; ++b) edges.push_back({b, b + 1});
    for (int k = 0; k < nb; ++k) {
      const int a = pick(rng), c = pick(rng);
      if (a != c) edges.push_back({a, c});
    }
    residual_rows = static_cast<int>(edges.size()) * bs;
    for (int b = 0; b <= nb; ++b) block_starts.push_back(b * bs);
    col_ptr.push_back(0);
    for (int b = 0; b < nb; ++b) {
      for (int k = 0; k < bs; ++k) {
        for (std::size_t e = 0; e < edges.size(); ++e) {
          if (std::find(edges[e].begin(), edges[e].end(), b) == edges[e].end()) continue;
          for (int r = 0; r < bs; ++r) row_idx.push_back(static_cast<int>(e) * bs + r);
        }
        row_idx.push_back(residual_rows + b * bs + k);  // damping row
        col_ptr.push_back(static_cast<int>(row_idx.size()));
      }
    }
  }
  int n() const { return nb * bs; }
  int rows() const { return residual_rows + n(); }
  JacobianStructure structure() const {
    JacobianStructure s;
    s.rows = rows();
    s.cols = n();
    s.damping_row = residual_rows;
    s.col_ptr = col_ptr.data();
    s.row_idx = row_idx.data();
    s.block_starts = block_starts.data();
    s.num_blocks = nb;
    return s;
  }
  /// Random dense J in this pattern (damping rows zero unless `lambda` > 0).
  Eigen::MatrixXd random(std::mt19937& rng, double lambda = 0.0) const {
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(rows(), n());
    for (std::size_t e = 0; e < edges.size(); ++e) {
      for (int b : edges[e]) {
        for (int r = 0; r < bs; ++r)
          for (int c = 0; c < bs; ++c) j(static_cast<int>(e) * bs + r, b * bs + c) = u(rng);
      }
    }
    for (int c = 0; c < n(); ++c) j(residual_rows + c, c) = std::sqrt(lambda);
    return j;
  }
  std::vector<double> values(const Eigen::MatrixXd& j) const {
    std::vector<double> v;
    for (int c = 0; c < n(); ++c) {
      for (int k = col_ptr[c]; k < col_ptr[c + 1]; ++k) v.push_back(j(row_idx[k], c));
    }
    return v;
  }
};

/// Parameter: "solver:ordering" for every registered solver and every ordering it offers.
class Solvers_Conformance : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<LinearSolver> make() {
    SolverRegistry registry;
    solvers::registerSolvers(registry);
    return registry.create(GetParam());
  }
  static bool jacobianForm(const LinearSolver& s) { return s.form() == SystemForm::kJacobian; }
  std::string name() const { return GetParam().substr(0, GetParam().find(':')); }
  /// The isotropic solver takes only H = H_s (x) I: its systems are made so.
  bool isotropicOnly() const { return name() == "isotropic"; }
  Eigen::MatrixXd adapt(const Eigen::MatrixXd& m, const BlockSystem& sys) const {
    return isotropicOnly() ? sys.isotropic(m) : m;
  }
};

TEST_P(Solvers_Conformance, SolvesRepeatedlyWithOneAnalysis) {
  std::mt19937 rng(17);
  auto solver = make();
  EXPECT_EQ(solver->name(), name());
  EXPECT_EQ(std::string(toString(solver->ordering())), GetParam().substr(GetParam().find(':') + 1));
  if (jacobianForm(*solver)) {
    JacobianSystem sys(40, 3, rng);
    ASSERT_TRUE(solver->analyzeJacobian(sys.structure()).ok());
    for (int round = 0; round < 5; ++round) {
      const double lambda = round % 2 ? 0.5 : 0.0;  // damping rows in use on odd rounds
      const Eigen::MatrixXd j = sys.random(rng, lambda);
      const auto values = sys.values(j);
      const Eigen::VectorXd rhs = Eigen::VectorXd::Random(sys.rows());
      ASSERT_TRUE(solver->factorizeJacobian(values.data()).ok()) << "round " << round;
      Eigen::VectorXd x(sys.n());
      ASSERT_TRUE(solver->solveJacobian(rhs.data(), x.data()).ok());
      // Reference by dense QR (the normal equations would square the condition number).
      const Eigen::VectorXd ref = j.colPivHouseholderQr().solve(rhs);
      EXPECT_LT((x - ref).cwiseAbs().maxCoeff(), 1e-10) << "round " << round;
      EXPECT_LT((j.transpose() * (j * x - rhs)).norm(), 1e-10 * rhs.norm());
    }
  } else {
    BlockSystem sys(40, 3, rng);
    ASSERT_TRUE(solver->analyze(sys.structure()).ok());
    for (int round = 0; round < 5; ++round) {
      const Eigen::MatrixXd m = adapt(sys.randomSpd(rng), sys);
      const auto values = sys.values(m);
      const Eigen::VectorXd rhs = Eigen::VectorXd::Random(sys.n());
      ASSERT_TRUE(solver->factorize(values.data()).ok()) << "round " << round;
      Eigen::VectorXd x(sys.n());
      ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
      const Eigen::VectorXd ref = m.ldlt().solve(rhs);
      EXPECT_LT((x - ref).cwiseAbs().maxCoeff(), 1e-10) << "round " << round;
      EXPECT_LT((m * x - rhs).norm(), 1e-10 * rhs.norm());
    }
  }
  EXPECT_GT(solver->factorNonZeros(), 0u);
}

TEST_P(Solvers_Conformance, RhsAndSolutionMayAlias) {
  std::mt19937 rng(19);
  auto solver = make();
  if (jacobianForm(*solver)) GTEST_SKIP() << "rhs (rows) and x (cols) differ in size in J form";
  BlockSystem sys(15, 3, rng);
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  const Eigen::MatrixXd m = adapt(sys.randomSpd(rng), sys);
  const auto values = sys.values(m);
  ASSERT_TRUE(solver->factorize(values.data()).ok());
  Eigen::VectorXd x = Eigen::VectorXd::Random(sys.n());
  const Eigen::VectorXd ref = m.ldlt().solve(x);
  ASSERT_TRUE(solver->solve(x.data(), x.data()).ok());
  EXPECT_LT((x - ref).cwiseAbs().maxCoeff(), 1e-10);
}

TEST_P(Solvers_Conformance, EntriesBelowTheDiagonalAreIgnored) {
  std::mt19937 rng(23);
  auto solver = make();
  if (jacobianForm(*solver)) GTEST_SKIP() << "J has no triangle to ignore";
  BlockSystem sys(10, 2, rng);
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  const Eigen::MatrixXd m = adapt(sys.randomSpd(rng), sys);
  Eigen::MatrixXd garbage = m;
  garbage.triangularView<Eigen::StrictlyLower>().setConstant(1e6);
  const auto values = sys.values(garbage);
  ASSERT_TRUE(solver->factorize(values.data()).ok());
  const Eigen::VectorXd rhs = Eigen::VectorXd::Ones(sys.n());
  Eigen::VectorXd x(sys.n());
  ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
  EXPECT_LT((x - m.ldlt().solve(rhs)).cwiseAbs().maxCoeff(), 1e-10);
}

TEST_P(Solvers_Conformance, IndefiniteSystemIsAFailureNamingAColumn) {
  std::mt19937 rng(29);
  auto solver = make();
  if (jacobianForm(*solver)) GTEST_SKIP() << "J^T J cannot be indefinite";
  BlockSystem sys(12, 3, rng);
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  Eigen::MatrixXd m = adapt(sys.randomSpd(rng), sys);
  m(20, 20) = -50.0;                                   // column 20 belongs to block 6
  if (isotropicOnly()) m(18, 18) = m(19, 19) = -50.0;  // still a multiple of I
  const auto values = sys.values(m);
  LinearSolverResult r = solver->factorize(values.data());
  if (r.ok() && name() == "pcg") {  // conjugate gradients meet the negative curvature later
    Eigen::VectorXd x(sys.n());
    r = solver->solve(Eigen::VectorXd::Ones(sys.n()).eval().data(), x.data());
  }
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite);
  if (name() != "eigen-llt" && name() != "pcg") {  // these do not say where
    EXPECT_GE(r.column, 0);
    EXPECT_LT(r.column, sys.n());
  }
}

TEST_P(Solvers_Conformance, SingularSystemIsAFailure) {
  std::mt19937 rng(31);
  auto solver = make();
  LinearSolverResult r;
  if (jacobianForm(*solver)) {
    JacobianSystem sys(8, 3, rng);
    ASSERT_TRUE(solver->analyzeJacobian(sys.structure()).ok());
    Eigen::MatrixXd j = sys.random(rng);
    j.middleCols(9, 3).setZero();  // block 3: nothing constrains it
    const auto values = sys.values(j);
    r = solver->factorizeJacobian(values.data());
  } else {
    BlockSystem sys(8, 3, rng);
    ASSERT_TRUE(solver->analyze(sys.structure()).ok());
    Eigen::MatrixXd m = adapt(sys.randomSpd(rng), sys);
    // Zero out everything touching block 3: a vertex nothing constrains.
    m.middleRows(9, 3).setZero();
    m.middleCols(9, 3).setZero();
    const auto values = sys.values(m);
    r = solver->factorize(values.data());
  }
  ASSERT_FALSE(r.ok());
  if (name() != "eigen-llt") {
    EXPECT_GE(r.column, 9);
    EXPECT_LT(r.column, 12);
  }
}

std::vector<std::string> registeredSolvers() {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  std::vector<std::string> specs;
  for (const auto* e : registry.entries()) {
    for (Ordering o : e->orderings) specs.push_back(e->name + ":" + toString(o));
  }
  return specs;
}

INSTANTIATE_TEST_SUITE_P(Registered, Solvers_Conformance, ::testing::ValuesIn(registeredSolvers()),
                         [](const auto& info) {
                           std::string s = info.param;
                           for (char& c : s)
                             if (c == '-' || c == ':') c = '_';
                           return s;
                         });

TEST(Solvers_Registry, EveryBackendAndOrderingIsRegistered) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  for (const char* name :
       {"eigen-ldlt", "eigen-llt", "eigen-qr", "dense-ldlt", "dense-pinv", "pcg"}) {
    EXPECT_TRUE(registry.contains(name)) << name;
  }
  if (solvers::haveSuiteSparse()) {
    for (const char* name : {"cholmod", "cholmod-simplicial", "csparse", "umfpack", "spqr"}) {
      EXPECT_TRUE(registry.contains(name)) << name;
    }
    EXPECT_TRUE(registry.contains("cholmod:metis"));
    EXPECT_TRUE(registry.contains("spqr:colamd"));
    EXPECT_EQ(registry.find("spqr")->form, SystemForm::kJacobian);
  }
  EXPECT_FALSE(registry.contains("dense-ldlt:amd"));
  EXPECT_FALSE(registry.contains("eigen-ldlt:nonsense"));
  EXPECT_THROW((void)registry.create("dense-ldlt:amd"), RegistryError);
  EXPECT_THROW((void)registry.create("eigen-ldlt:nonsense"), RegistryError);
  EXPECT_EQ(registry.create("eigen-ldlt")->ordering(), Ordering::kAmd);
}

/// Predicted factor size and work parsed from the auto solver's name after analyze().
struct AutoChoice {
  std::string backend;
  double nnz = 0, flops = 0;
};
AutoChoice parseAuto(const std::string& name) {
  AutoChoice c;
  char backend[64] = {0};
  EXPECT_EQ(std::sscanf(name.c_str(), "auto: %63[^,], predicted nnz(L) %lf, %lf flops", backend,
                        &c.nnz, &c.flops),
            3)
      << name;
  c.backend = backend;
  return c;
}

TEST(Solvers_Auto, PredictsTheFactorExactly) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  std::mt19937 rng(5);
  const BlockSystem sys(300, 3, rng);
  auto solver = registry.create("auto");
  EXPECT_EQ(solver->name(), "auto");
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  const AutoChoice c = parseAuto(solver->name());
  EXPECT_EQ(c.backend, "block-llt:amd");  // a small system of 3x3 blocks
  EXPECT_EQ(solver->ordering(), Ordering::kAmd);
  const auto values = sys.values(sys.randomSpd(rng));
  ASSERT_TRUE(solver->factorize(values.data()).ok());
  EXPECT_EQ(static_cast<double>(solver->factorNonZeros()), c.nnz);
  // A small system's figures are not computed at analysis: named before its first
  // factorisation, auto computes them (above); after it, they are block-llt's own. The same.
  auto named_late = registry.create("auto");
  ASSERT_TRUE(named_late->analyze(sys.structure()).ok());
  ASSERT_TRUE(named_late->factorize(values.data()).ok());
  EXPECT_EQ(named_late->name(), solver->name());
  auto eigen = registry.create("eigen-ldlt:amd");
  ASSERT_TRUE(eigen->analyze(sys.structure()).ok());
  ASSERT_TRUE(eigen->factorize(values.data()).ok());
  // Eigen's L of LDL^T leaves out the unit diagonal.
  EXPECT_EQ(static_cast<double>(eigen->factorNonZeros() + sys.n()), c.nnz);
  if (solvers::haveSuiteSparse()) {
    auto cholmod = registry.create("cholmod-simplicial:amd");
    ASSERT_TRUE(cholmod->analyze(sys.structure()).ok());
    ASSERT_TRUE(cholmod->factorize(values.data()).ok());
    EXPECT_EQ(static_cast<double>(cholmod->factorNonZeros()), c.nnz);
  }
}

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

TEST(Solvers_Auto, LargeGridGetsNestedDissectionAndSupernodes) {
  if (!solvers::haveSuiteSparse()) GTEST_SKIP() << "built without SuiteSparse (no METIS)";
  // A 2D grid of 3x3 blocks (a pose graph revisiting a city): AMD fills it badly.
  const int side = 130, bs = 3, nb = side * side, n = nb * bs;
  auto id = [&](int x, int y) { return y * side + x; };
  std::vector<int> block_starts, col_ptr{0}, row_idx;
  std::vector<double> values;
  for (int b = 0; b <= nb; ++b) block_starts.push_back(b * bs);
  for (int cb = 0; cb < nb; ++cb) {
    const int x = cb % side, y = cb / side;
    std::vector<int> rows;  // row blocks <= cb
    if (y > 0) rows.push_back(id(x, y - 1));
    if (x > 0) rows.push_back(id(x - 1, y));
    rows.push_back(cb);
    for (int k = 0; k < bs; ++k) {
      for (int rb : rows) {
        for (int r = 0; r < bs; ++r) {
          row_idx.push_back(rb * bs + r);
          values.push_back(rb == cb ? (r == k ? 5.0 : 0.1) : (r == k ? -1.0 : 0.0));
        }
      }
      col_ptr.push_back(static_cast<int>(row_idx.size()));
    }
  }
  SparseStructure s;
  s.n = n;
  s.col_ptr = col_ptr.data();
  s.row_idx = row_idx.data();
  s.block_starts = block_starts.data();
  s.num_blocks = nb;
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  auto solver = registry.create("auto");
  ASSERT_TRUE(solver->analyze(s).ok());
  const AutoChoice c = parseAuto(solver->name());
  EXPECT_GT(c.flops, 2e8);  // large enough to try METIS
  EXPECT_NE(c.backend.find(":metis"), std::string::npos) << solver->name();
  ASSERT_TRUE(solver->factorize(values.data()).ok());
  Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0), x(n);
  ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
  Eigen::VectorXd hx = Eigen::VectorXd::Zero(n);  // H x from the upper triangle
  for (int col = 0; col < n; ++col) {
    for (int k = col_ptr[col]; k < col_ptr[col + 1]; ++k) {
      const int r = row_idx[k];
      if (r > col) continue;
      hx[r] += values[k] * x[col];
      if (r != col) hx[col] += values[k] * x[r];
    }
  }
  EXPECT_LT((hx - rhs).norm(), 1e-10 * rhs.norm());
}

/// A random SPD system over vertices of the given dimensions with the given blocks
/// (row block <= column block; the diagonal ones are added), stored as the optimizer
/// stores H: upper triangle, complete blocks.
struct MixedSystem {
  std::vector<int> starts{0}, col_ptr{0}, row_idx;
  std::set<std::pair<int, int>> blocks;
  Eigen::MatrixXd m;

  MixedSystem(const std::vector<int>& dims, std::set<std::pair<int, int>> pairs, std::mt19937& rng)
      : blocks(std::move(pairs)) {
    const int nb = static_cast<int>(dims.size());
    for (int d : dims) starts.push_back(starts.back() + d);
    for (int b = 0; b < nb; ++b) blocks.insert({b, b});
    const int n = starts.back();
    std::uniform_real_distribution<double> u(-1, 1);
    m = Eigen::MatrixXd::Zero(n, n);
    for (const auto& [rb, cb] : blocks) {
      for (int r = starts[rb]; r < starts[rb + 1]; ++r) {
        for (int c = starts[cb]; c < starts[cb + 1]; ++c) {
          const double x = u(rng);
          m(r, c) += x;
          if (rb != cb) m(c, r) += x;
        }
      }
    }
    m = (m + m.transpose()).eval() * 0.5;
    for (int i = 0; i < n; ++i) m(i, i) = m.row(i).cwiseAbs().sum() + 1.0;
    for (int cb = 0; cb < nb; ++cb) {
      for (int c = starts[cb]; c < starts[cb + 1]; ++c) {
        for (const auto& [rb, cb2] : blocks) {
          if (cb2 != cb) continue;
          for (int r = starts[rb]; r < starts[rb + 1]; ++r) row_idx.push_back(r);
        }
        col_ptr.push_back(static_cast<int>(row_idx.size()));
      }
    }
  }
  SparseStructure structure() const {
    SparseStructure s;
    s.n = starts.back();
    s.col_ptr = col_ptr.data();
    s.row_idx = row_idx.data();
    s.block_starts = starts.data();
    s.num_blocks = static_cast<int>(starts.size()) - 1;
    return s;
  }
  /// Stored values of the symmetric matrix a.
  std::vector<double> values(const Eigen::MatrixXd& a) const {
    std::vector<double> v;
    for (int c = 0; c < starts.back(); ++c) {
      for (int k = col_ptr[c]; k < col_ptr[c + 1]; ++k) v.push_back(a(row_idx[k], c));
    }
    return v;
  }
  /// max |x - m^-1 rhs| of spec's solution for a random rhs (ADD_FAILURE on failure).
  double solveError(const SolverRegistry& registry, const std::string& spec) const {
    auto solver = registry.create(spec);
    const std::vector<double> v = values(m);
    if (!solver->analyze(structure()).ok() || !solver->factorize(v.data()).ok()) {
      ADD_FAILURE() << spec << " failed";
      return 1.0;
    }
    const Eigen::VectorXd rhs = Eigen::VectorXd::Random(starts.back());
    Eigen::VectorXd x(starts.back());
    if (!solver->solve(rhs.data(), x.data()).ok()) {
      ADD_FAILURE() << spec << " failed to solve";
      return 1.0;
    }
    return (x - m.ldlt().solve(rhs)).cwiseAbs().maxCoeff();
  }
  /// The failure of spec when vertex b's diagonal block is negated.
  LinearSolverResult negatedBlockFailure(const SolverRegistry& registry, const std::string& spec,
                                         int b) const {
    Eigen::MatrixXd bad = m;
    const int d = starts[b + 1] - starts[b];
    bad.block(starts[b], starts[b], d, d) *= -1.0;
    const std::vector<double> v = values(bad);
    auto solver = registry.create(spec);
    if (!solver->analyze(structure()).ok()) return LinearSolverResult::success();
    return solver->factorize(v.data());
  }
};

/// Block pairs (a, b), a < b, of a chain over nb vertices and 2 nb random pairs.
std::set<std::pair<int, int>> chainAndRandomPairs(int nb, std::mt19937& rng) {
  std::set<std::pair<int, int>> blocks;
  std::uniform_int_distribution<int> pick(0, nb - 1);
  for (int b = 0; b + 1 < nb; ++b) blocks.insert({b, b + 1});
  for (int k = 0; k < 2 * nb; ++k) {
    const int a = pick(rng), c = pick(rng);
    blocks.insert({std::min(a, c), std::max(a, c)});
  }
  return blocks;
}

TEST(Solvers_BlockLlt, MixedVertexDimensionsArePadded) {
  // Poses (3) and landmarks (2) mixed, as in landmark SLAM: block-llt pads the 2s to 3.
  std::mt19937 rng(9);
  const std::vector<int> dims = {3, 2, 3, 3, 2, 2, 3, 2, 3, 3, 2, 3, 1};
  const int nb = static_cast<int>(dims.size());
  const MixedSystem sys(dims, chainAndRandomPairs(nb, rng), rng);
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  for (const char* spec : {"block-llt:amd", "block-llt:natural", "auto"}) {
    EXPECT_LT(sys.solveError(registry, spec), 1e-12) << spec;
  }
  // Not positive definite: the failing vertex's first column is named.
  const LinearSolverResult r = sys.negatedBlockFailure(registry, "block-llt:natural", 4);
  EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite);
  EXPECT_EQ(r.column, sys.starts[4]);
}

TEST(Solvers_BlockLlt, LongColumnsOfEveryBlockSizeAreExact) {
  // 120 vertices coupled at random: under the natural order L's columns hold dozens of
  // blocks, and each entry of a row is a long run of the elimination kernel. Runs on the
  // AVX2/FMA kernels where the CPU has them, and on the portable ones in the ctest entry
  // Solvers_PortableBlockKernels (GRAPHSLAM_SIMD=portable).
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  for (int d : {1, 2, 3}) {
    std::mt19937 rng(40 + d);
    const int nb = 120;
    const MixedSystem sys(std::vector<int>(nb, d), chainAndRandomPairs(nb, rng), rng);
    for (const char* spec : {"block-llt:natural", "block-llt:amd"}) {
      EXPECT_LT(sys.solveError(registry, spec), 1e-12) << "dimension " << d << ", " << spec;
    }
  }
}

TEST(Solvers_BlockLlt, KernelPathFollowsTheCpuAndTheEnvironment) {
  const char* env = std::getenv("GRAPHSLAM_SIMD");
  const bool portable = env && std::string(env) == "portable";
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  const bool avx2 = false;
#endif
  EXPECT_STREQ(solvers::blockKernelPath(), avx2 && !portable ? "avx2-fma" : "portable");
}

TEST(Solvers_BlockLlt, ScalarUnknownsTakeOneByOneBlocks) {
  // Every vertex of dimension 1 (the scalar systems of the isotropic solver): 1 x 1 blocks,
  // nothing padded.
  std::mt19937 rng(17);
  const int nb = 40;
  const std::vector<int> dims(nb, 1);
  const MixedSystem sys(dims, chainAndRandomPairs(nb, rng), rng);
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  for (const char* spec : {"block-llt:natural", "block-llt:amd", "block-llt:colamd"}) {
    EXPECT_LT(sys.solveError(registry, spec), 1e-12) << spec;
    auto solver = registry.create(spec);
    ASSERT_TRUE(solver->analyze(sys.structure()).ok());
    // Without padding, L stores exactly the lower triangle's non-zeros: at least H's.
    const std::vector<double> v = sys.values(sys.m);
    ASSERT_TRUE(solver->factorize(v.data()).ok());
    EXPECT_GE(solver->factorNonZeros(), sys.blocks.size()) << spec;
    EXPECT_LE(solver->factorNonZeros(), static_cast<std::size_t>(nb * (nb + 1) / 2)) << spec;
  }
  for (const int b : {0, 23, nb - 1}) {
    const LinearSolverResult r = sys.negatedBlockFailure(registry, "block-llt:natural", b);
    EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite) << b;
    EXPECT_EQ(r.column, b) << b;
  }
}

TEST(Solvers_BlockLlt, DenseTrailingPartIsFactorisedDenselyAndNamesItsFailures) {
  // 60 poses (3) in a chain, then 30 landmarks (2), each seen from 6 poses: eliminating
  // the poses first (natural order) connects every landmark with every other, so the last
  // 30+ block columns of L are dense and block-llt factorises them as one dense matrix.
  std::mt19937 rng(21);
  const int poses = 60, landmarks = 30;
  std::vector<int> dims(poses, 3);
  dims.insert(dims.end(), landmarks, 2);
  std::set<std::pair<int, int>> blocks;
  for (int b = 0; b + 1 < poses; ++b) blocks.insert({b, b + 1});
  std::uniform_int_distribution<int> pick(0, poses - 1);
  for (int l = 0; l < landmarks; ++l) {
    for (int k = 0; k < 6; ++k) blocks.insert({pick(rng), poses + l});
  }
  const MixedSystem sys(dims, blocks, rng);
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  for (const char* spec : {"block-llt:natural", "block-llt:amd", "block-llt:metis"}) {
    EXPECT_LT(sys.solveError(registry, spec), 1e-12) << spec;
  }
  // A landmark in the dense part, a pose before it: each named by its first column.
  for (const int b : {poses + 17, poses + landmarks - 1, 5}) {
    const LinearSolverResult r = sys.negatedBlockFailure(registry, "block-llt:natural", b);
    EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite) << b;
    EXPECT_EQ(r.column, sys.starts[b]) << b;
  }
}

}  // namespace

TEST(Solvers_Isotropic, RejectsSystemsThatAreNotAMultipleOfTheIdentityPerBlock) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  std::mt19937 rng(37);
  BlockSystem sys(12, 2, rng);
  auto solver = registry.create("isotropic:amd");
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  // A general SPD matrix: its blocks have off-diagonal entries.
  const Eigen::MatrixXd m = sys.randomSpd(rng);
  const auto values = sys.values(m);
  const LinearSolverResult r = solver->factorize(values.data());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status, LinearSolverStatus::kFailure);
  EXPECT_NE(r.message.find("not a multiple of the identity"), std::string::npos) << r.message;
  EXPECT_GE(r.column, 0);
  EXPECT_LT(r.column, sys.n());
  // Unequal diagonal entries in one block are rejected too.
  Eigen::MatrixXd k = sys.isotropic(m);
  const auto good = sys.values(k);
  EXPECT_TRUE(solver->factorize(good.data()).ok());
  k(7, 7) *= 1.5;  // block 3: diagonal (d, 1.5 d)
  const auto bad = sys.values(k);
  const LinearSolverResult r2 = solver->factorize(bad.data());
  ASSERT_FALSE(r2.ok());
  EXPECT_EQ(r2.column, 7);
}

TEST(Solvers_Isotropic, SmallSystemsAreSolvedAndNameTheFailingVertex) {
  // Below the supernodal threshold the scalar matrix goes to tail-llt's loop (with BLAS /
  // LAPACK; no dense tail here) or block-llt's 1 x 1 blocks.
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  std::mt19937 rng(43);
  BlockSystem sys(30, 2, rng);
  const Eigen::MatrixXd iso = sys.isotropic(sys.randomSpd(rng));
  const Eigen::VectorXd rhs = Eigen::VectorXd::Random(sys.n());
  const Eigen::VectorXd expected = iso.ldlt().solve(rhs);
  for (const char* spec : {"isotropic:natural", "isotropic:amd", "isotropic:colamd"}) {
    auto solver = registry.create(spec);
    ASSERT_TRUE(solver->analyze(sys.structure()).ok()) << spec;
    const auto values = sys.values(iso);
    ASSERT_TRUE(solver->factorize(values.data()).ok()) << spec;
    Eigen::VectorXd x(sys.n());
    ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok()) << spec;
    EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-10) << spec;
    for (const int b : {0, 11, 29}) {  // its diagonal block negated: still isotropic
      Eigen::MatrixXd bad = iso;
      bad.block(2 * b, 2 * b, 2, 2) *= -1.0;
      const auto bad_values = sys.values(bad);
      const LinearSolverResult r = solver->factorize(bad_values.data());
      EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite) << spec << " " << b;
      EXPECT_EQ(r.column, 2 * b) << spec << " " << b;
    }
  }
}

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

// Poses in a chain, then landmarks each seen from most poses: in the natural order the
// landmarks' columns of L are dense. The isotropic solver then factorises the columns
// before them one by one and the landmarks' Schur complement with BLAS (tail-llt, when
// BLAS / LAPACK were found at the build); a failed pivot names its vertex either way.
TEST(Solvers_Isotropic, DenseLandmarkTailsAreSolvedAndNameTheFailingVertex) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  std::mt19937 rng(17);
  const int poses = 200, landmarks = 48;
  std::set<std::pair<int, int>> upper;
  std::bernoulli_distribution seen(0.7);
  for (int p = 0; p < poses; ++p) {
    if (p + 1 < poses) upper.insert({p, p + 1});
    for (int l = 0; l < landmarks; ++l) {
      if (seen(rng)) upper.insert({p, poses + l});
    }
  }
  BlockSystem sys(poses + landmarks, 2, upper);
  const Eigen::MatrixXd iso = sys.isotropic(sys.randomSpd(rng));
  const Eigen::VectorXd rhs = Eigen::VectorXd::Random(sys.n());
  const Eigen::VectorXd expected = iso.ldlt().solve(rhs);
  auto solver = registry.create("isotropic:natural");
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  const auto values = sys.values(iso);
  for (int repeat = 0; repeat < 2; ++repeat) {  // the pattern analysed once
    ASSERT_TRUE(solver->factorize(values.data()).ok());
    Eigen::VectorXd x(sys.n());
    ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
    EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-10);
  }
  // L's non-zeros: the dense tail holds every landmark, and the pose columns.
  EXPECT_GE(solver->factorNonZeros(), static_cast<std::size_t>(landmarks * (landmarks + 1)));
  for (const int b : {0, 17, poses - 1, poses, poses + 30, poses + landmarks - 1}) {
    Eigen::MatrixXd bad = iso;
    bad.block(2 * b, 2 * b, 2, 2) *= -1.0;
    const auto bad_values = sys.values(bad);
    const LinearSolverResult r = solver->factorize(bad_values.data());
    EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite) << b;
    EXPECT_EQ(r.column, 2 * b) << b << ": " << r.message;
#ifdef GRAPHSLAM_TEST_HAVE_LAPACK
    EXPECT_NE(r.message.find(b >= poses ? "tail-llt, dense tail" : "tail-llt"), std::string::npos)
        << b << ": " << r.message;
#endif
  }
  ASSERT_TRUE(solver->factorize(values.data()).ok());  // and it recovers
  Eigen::VectorXd x(sys.n());
  ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
  EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-10);
}

// Linear SLAM's H = H_s (x) I_d with H_s a weighted graph Laplacian (a pose chain and
// landmarks, weights 1e4) plus a weak prior (1) on the first pose: pcg iterates on H_s
// with the d coordinates as right-hand sides (its preconditioner then has one entry
// per vertex) and converges although the prior leaves H's condition number near 1e8.
TEST(Solvers_Pcg, IsotropicLaplacianWithAWeakPriorConverges) {
  for (const int dim : {2, 3, 4}) {  // the pair kernel, a fixed size, any size
    SCOPED_TRACE(dim);
    SolverRegistry registry;
    solvers::registerSolvers(registry);
    std::mt19937 rng(5);
    const int poses = 120, landmarks = 40;
    std::set<std::pair<int, int>> upper;
    std::uniform_int_distribution<int> pose(0, poses - 1);
    for (int p = 0; p + 1 < poses; ++p) upper.insert({p, p + 1});
    for (int l = 0; l < landmarks; ++l) {
      for (int k = 0; k < 4; ++k) upper.insert({pose(rng), poses + l});
    }
    BlockSystem sys(poses + landmarks, dim, upper);
    const int nb = poses + landmarks;
    Eigen::MatrixXd hs = Eigen::MatrixXd::Zero(nb, nb);
    for (const auto& [a, b] : upper) {
      hs(a, a) += 1e4;
      hs(b, b) += 1e4;
      hs(a, b) -= 1e4;
      hs(b, a) -= 1e4;
    }
    hs(0, 0) += 1.0;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(sys.n(), sys.n());
    for (int r = 0; r < nb; ++r) {
      for (int c = 0; c < nb; ++c)
        h.block(dim * r, dim * c, dim, dim) = hs(r, c) * Eigen::MatrixXd::Identity(dim, dim);
    }
    Eigen::VectorXd truth(sys.n());
    std::uniform_real_distribution<double> u(-10, 10);
    for (int i = 0; i < sys.n(); ++i) truth[i] = u(rng);
    const Eigen::VectorXd rhs = h * truth;
    auto solver = registry.create("pcg");
    ASSERT_TRUE(solver->analyze(sys.structure()).ok());
    const auto values = sys.values(h);
    ASSERT_TRUE(solver->factorize(values.data()).ok());
    EXPECT_EQ(solver->factorNonZeros(), static_cast<std::size_t>(nb));  // H_s's diagonal
    Eigen::VectorXd x(sys.n());
    const LinearSolverResult r = solver->solve(rhs.data(), x.data());
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_LT((x - truth).cwiseAbs().maxCoeff(), 1e-6);
    // A vertex whose diagonal block is negative: named before any iteration.
    Eigen::MatrixXd bad = h;
    bad.block(dim * 37, dim * 37, dim, dim) *= -1.0;
    const auto bad_values = sys.values(bad);
    const LinearSolverResult rb = solver->factorize(bad_values.data());
    EXPECT_EQ(rb.status, LinearSolverStatus::kNotPositiveDefinite);
    EXPECT_EQ(rb.column, dim * 37);
    // Not isotropic: the block-Jacobi iteration on H itself.
    Eigen::MatrixXd skew = h;
    skew(dim * 5, dim * 5) += 3.0;
    const auto skew_values = sys.values(skew);
    ASSERT_TRUE(solver->factorize(skew_values.data()).ok());
    EXPECT_EQ(solver->factorNonZeros(), static_cast<std::size_t>(dim * dim * nb));
    const Eigen::VectorXd skew_rhs = skew * truth;
    ASSERT_TRUE(solver->solve(skew_rhs.data(), x.data()).ok());
    EXPECT_LT((x - truth).cwiseAbs().maxCoeff(), 1e-6);
  }
}

TEST(Solvers_Isotropic, NeedsVerticesOfOneDimension) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  // Two vertices of dimension 3 and 2, one block between them.
  const std::vector<int> starts{0, 3, 5};
  std::vector<int> col_ptr{0}, row_idx;
  for (int c = 0; c < 5; ++c) {
    const int last = c < 3 ? 3 : 5;
    for (int r = 0; r < last; ++r) row_idx.push_back(r);
    col_ptr.push_back(static_cast<int>(row_idx.size()));
  }
  SparseStructure s;
  s.n = 5;
  s.col_ptr = col_ptr.data();
  s.row_idx = row_idx.data();
  s.block_starts = starts.data();
  s.num_blocks = 2;
  auto solver = registry.create("isotropic:natural");
  const LinearSolverResult r = solver->analyze(s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message.find("same dimension"), std::string::npos) << r.message;
}

/// Factorises and solves each matrix in turn on one analysis of `sys`; each solution must
/// be exact for its own matrix. Returns factorNonZeros() after each.
std::vector<std::size_t> solveInTurn(LinearSolver& solver, const BlockSystem& sys,
                                     std::initializer_list<const Eigen::MatrixXd*> matrices) {
  const Eigen::VectorXd rhs = Eigen::VectorXd::Random(sys.n());
  std::vector<std::size_t> nnz;
  for (const Eigen::MatrixXd* m : matrices) {
    const auto values = sys.values(*m);
    EXPECT_TRUE(solver.factorize(values.data()).ok());
    Eigen::VectorXd x(sys.n());
    EXPECT_TRUE(solver.solve(rhs.data(), x.data()).ok());
    EXPECT_LT((*m * x - rhs).norm(), 1e-10 * rhs.norm());
    EXPECT_LT((x - m->ldlt().solve(rhs)).cwiseAbs().maxCoeff(), 1e-10);
    nnz.push_back(solver.factorNonZeros());
  }
  return nnz;
}

/// `auto` analysed on a random pattern of 30 vertices of dimension 2, and a random SPD
/// matrix in that pattern.
struct AutoOnPairs {
  SolverRegistry registry;
  std::mt19937 rng;
  BlockSystem sys;
  std::unique_ptr<LinearSolver> solver;
  Eigen::MatrixXd general;

  explicit AutoOnPairs(unsigned seed) : rng(seed), sys(30, 2, rng) {
    solvers::registerSolvers(registry);
    solver = registry.create("auto");
    EXPECT_TRUE(solver->analyze(sys.structure()).ok());
    general = sys.randomSpd(rng);
  }
};

TEST(Solvers_Auto, IsotropicValuesTakeTheScalarPathAndOthersTheBlockOne) {
  AutoOnPairs t(41);
  const Eigen::MatrixXd iso = t.sys.isotropic(t.general);
  const auto nnz = solveInTurn(*t.solver, t.sys, {&t.general, &iso, &t.general, &iso});
  // L = L_s (x) I_2 stores d entries per non-zero of L_s, the block factor d^2 per block.
  EXPECT_LT(nnz[1], nnz[0]);
  EXPECT_LT(nnz[3], nnz[2]);
}

/// The upper CSC pattern of a side x side grid graph (one scalar unknown per node,
/// 4-neighbours), with its diagonal.
struct GridPattern {
  std::vector<int> col_ptr{0}, row_idx, block_starts;
  SparseStructure structure;

  explicit GridPattern(int side) {
    const int n = side * side;
    for (int c = 0; c < n; ++c) {
      if (c - side >= 0) row_idx.push_back(c - side);
      if (c % side > 0) row_idx.push_back(c - 1);
      row_idx.push_back(c);
      col_ptr.push_back(static_cast<int>(row_idx.size()));
    }
    for (int b = 0; b <= n; ++b) block_starts.push_back(b);
    structure.n = n;
    structure.col_ptr = col_ptr.data();
    structure.row_idx = row_idx.data();
    structure.block_starts = block_starts.data();
    structure.num_blocks = n;
  }
};

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

// Blocks [a -b; b a] are a Hermitian complex matrix: `auto` factorises it as such (half
// the flops and memory of the real 2x2 block factor) when the factorisation is large
// enough for CHOLMOD's supernodal one (on small systems block-llt is faster than CHOLMOD's
// complex factorisation); a block of another form sends it back to the real factor.
/// A grid's pattern with 2x2 blocks, stored complete: columns 2c and 2c+1 hold rows 2r,
/// 2r+1 for every row r of grid column c.
struct GridOfPairs {
  std::vector<int> col_ptr{0}, row_idx, block_starts;
  SparseStructure structure;

  explicit GridOfPairs(const GridPattern& grid) {
    for (int c = 0; c < grid.structure.n; ++c) {
      for (int j = 0; j < 2; ++j) {
        for (int k = grid.col_ptr[c]; k < grid.col_ptr[c + 1]; ++k) {
          row_idx.push_back(2 * grid.row_idx[k]);
          row_idx.push_back(2 * grid.row_idx[k] + 1);
        }
        col_ptr.push_back(static_cast<int>(row_idx.size()));
      }
    }
    for (int b = 0; b <= grid.structure.n; ++b) block_starts.push_back(2 * b);
    structure.n = 2 * grid.structure.n;
    structure.col_ptr = col_ptr.data();
    structure.row_idx = row_idx.data();
    structure.block_starts = block_starts.data();
    structure.num_blocks = grid.structure.n;
  }

  /// max |H x - rhs| with H from the upper triangle and complete diagonal blocks.
  [[nodiscard]] double residual(const std::vector<double>& values, const std::vector<double>& x,
                                const std::vector<double>& rhs) const {
    std::vector<double> hx(rhs.size(), 0.0);
    for (int c = 0; c < structure.n; ++c) {
      for (int k = col_ptr[c]; k < col_ptr[c + 1]; ++k) {
        const int r = row_idx[k];
        hx[r] += values[k] * x[c];
        if (r / 2 != c / 2) hx[c] += values[k] * x[r];  // the mirrored off-diagonal block
      }
    }
    double err = 0.0;
    for (std::size_t i = 0; i < rhs.size(); ++i) err = std::max(err, std::abs(hx[i] - rhs[i]));
    return err;
  }
};

// The isotropic solver lays H_s out in its (postordered) fill-reducing order itself and
// hands CHOLMOD the lower triangle, which CHOLMOD factorises without a permuted copy. Every
// ordering must give the exact solution, and a failed pivot must name its vertex's first
// column of H, through that order.
TEST(Solvers_Isotropic, LargeSystemsAreFactorisedInTheirOrderAndNameTheFailingVertex) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  if (!registry.contains("cholmod")) GTEST_SKIP() << "the supernodal path needs CHOLMOD";
  const GridPattern grid(120);  // 14400 vertices of dimension 2: supernodal in every order
  const GridOfPairs pairs(grid);
  const SparseStructure& s = pairs.structure;
  // H = H_s (x) I_2: off-diagonal blocks -I, diagonal blocks 5 I (diagonally dominant).
  std::vector<double> values(pairs.row_idx.size(), 0.0);
  for (int c = 0; c < s.n; ++c) {
    for (int k = pairs.col_ptr[c]; k < pairs.col_ptr[c + 1]; ++k) {
      const int r = pairs.row_idx[k];
      if (r % 2 == c % 2) values[k] = r / 2 == c / 2 ? 5.0 : -1.0;
    }
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> rhs(static_cast<std::size_t>(s.n)), x(rhs.size());
  for (double& r : rhs) r = uniform(rng);
  const int bad_vertex = 7001;
  for (const char* name : {"isotropic:natural", "isotropic:amd", "isotropic:metis"}) {
    auto solver = registry.create(name);
    ASSERT_TRUE(solver->analyze(s).ok()) << name;
    ASSERT_TRUE(solver->factorize(values.data()).ok()) << name;
    ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok()) << name;
    EXPECT_LT(pairs.residual(values, x, rhs), 1e-10) << name;
    std::vector<double> indefinite = values;
    for (int j = 0; j < 2; ++j) {  // the vertex's diagonal block becomes -50 I
      const int col = 2 * bad_vertex + j;
      for (int k = pairs.col_ptr[col]; k < pairs.col_ptr[col + 1]; ++k) {
        if (pairs.row_idx[k] == col) indefinite[k] = -50.0;
      }
    }
    const LinearSolverResult r = solver->factorize(indefinite.data());
    ASSERT_FALSE(r.ok()) << name;
    EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite) << name;
    EXPECT_EQ(r.column, 2 * bad_vertex) << name << ": " << r.message;
  }
}

TEST(Solvers_Auto, LargeConformalSystemsTakeTheComplexPath) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  if (!registry.contains("cholmod")) GTEST_SKIP() << "the complex path needs CHOLMOD";
  const GridPattern grid(300);  // 90000 blocks of 2x2
  const GridOfPairs pairs(grid);
  const std::vector<int>& col_ptr = pairs.col_ptr;
  const std::vector<int>& row_idx = pairs.row_idx;
  const SparseStructure& s = pairs.structure;
  // Off-diagonal blocks: rotations; diagonal blocks: (degree + 1) I (diagonally dominant).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  std::vector<double> values(row_idx.size(), 0.0);
  for (int c = 0; c < grid.structure.n; ++c) {
    const int len = col_ptr[2 * c + 1] - col_ptr[2 * c];
    for (int k = grid.col_ptr[c]; k < grid.col_ptr[c + 1]; ++k) {
      const int at = col_ptr[2 * c] + 2 * (k - grid.col_ptr[c]);
      double* v = values.data() + at;  // v[0], v[1]: column 2c; v[len], v[len + 1]: 2c + 1
      if (grid.row_idx[k] == c) {
        v[0] = v[len + 1] = 5.0;
      } else {
        const double t = angle(rng);
        v[0] = v[len + 1] = std::cos(t);
        v[1] = std::sin(t);
        v[len] = -std::sin(t);
      }
    }
  }
  auto solver = registry.create("auto");
  ASSERT_TRUE(solver->analyze(s).ok());
  ASSERT_TRUE(solver->factorize(values.data()).ok());
  EXPECT_NE(solver->name().find("(complex path)"), std::string::npos) << solver->name();
  std::vector<double> rhs(static_cast<std::size_t>(s.n)), x(rhs.size());
  for (double& r : rhs) r = angle(rng);
  ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
  EXPECT_LT(pairs.residual(values, x, rhs), 1e-9);
  // One block of another form: the real factor.
  values[col_ptr[2 * 200 + 1] - 2] = 5.5;  // a diagonal block 5.5, 5 on its diagonal
  ASSERT_TRUE(solver->factorize(values.data()).ok());
  EXPECT_EQ(solver->name().find("path)"), std::string::npos) << solver->name();
  std::printf("%s\n", solver->name().c_str());
}

/// H of a GridOfPairs laid out in a block order (order[k]: the block at position k) as its
/// lower triangle, complete 2x2 blocks, as the optimizer lays it out for a solver that asks
/// for that order (LinearSolver::preferredBlockOrder).
struct LowerLayout {
  std::vector<int> col_ptr, row_idx, source, block_starts, new_column;
  SparseStructure structure;

  LowerLayout(const GridOfPairs& pairs, const std::vector<int>& order) {
    const SparseStructure& s = pairs.structure;
    std::vector<int> pos(order.size());
    for (std::size_t k = 0; k < order.size(); ++k) pos[order[k]] = static_cast<int>(k);
    new_column.resize(static_cast<std::size_t>(s.n));
    for (int c = 0; c < s.n; ++c) new_column[c] = 2 * pos[c / 2] + c % 2;
    std::vector<std::vector<std::pair<int, int>>> columns(static_cast<std::size_t>(s.n));
    for (int c = 0; c < s.n; ++c) {
      for (int k = pairs.col_ptr[c]; k < pairs.col_ptr[c + 1]; ++k) {
        const int r = pairs.row_idx[k];
        const int nr = new_column[r], nc = new_column[c];
        if (r / 2 == c / 2) {
          columns[nc].emplace_back(nr, k);  // the diagonal block, complete
        } else {
          columns[std::min(nr, nc)].emplace_back(std::max(nr, nc), k);
        }
      }
    }
    col_ptr.assign(1, 0);
    for (auto& column : columns) {
      std::sort(column.begin(), column.end());
      for (const auto& [r, k] : column) {
        row_idx.push_back(r);
        source.push_back(k);
      }
      col_ptr.push_back(static_cast<int>(row_idx.size()));
    }
    for (int b = 0; b <= s.num_blocks; ++b) block_starts.push_back(2 * b);
    structure = s;
    structure.col_ptr = col_ptr.data();
    structure.row_idx = row_idx.data();
    structure.block_starts = block_starts.data();
    structure.lower = true;
  }
  [[nodiscard]] std::vector<double> values(const std::vector<double>& id_values) const {
    std::vector<double> v(source.size());
    for (std::size_t k = 0; k < source.size(); ++k) v[k] = id_values[source[k]];
    return v;
  }
  /// Solves with `solver` in this layout and returns x in the id order.
  std::vector<double> solve(LinearSolver& solver, const std::vector<double>& rhs) const {
    std::vector<double> b(rhs.size()), x(rhs.size()), out(rhs.size());
    for (std::size_t c = 0; c < rhs.size(); ++c) b[new_column[c]] = rhs[c];
    EXPECT_TRUE(solver.solve(b.data(), x.data()).ok());
    for (std::size_t c = 0; c < rhs.size(); ++c) out[c] = x[new_column[c]];
    return out;
  }
};

// A large block system (supernodal CHOLMOD) makes `auto` ask for H in its fill-reducing
// order, postordered, as the lower triangle: CHOLMOD then factorises H's own arrays. Every
// path takes that layout: the complex one (blocks [a -b; b a]), the scalar one (H_s (x) I),
// and the real block factor; a failed pivot names its column in that order, and a lower
// triangle given without asking for it is refused.
TEST(Solvers_Auto, LargeBlockSystemsTakeTheirOrderAsTheLowerTriangleOnEveryPath) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  if (!registry.contains("cholmod")) GTEST_SKIP() << "the supernodal path needs CHOLMOD";
  const GridPattern grid(300);  // 90000 blocks of 2x2
  const GridOfPairs pairs(grid);
  const SparseStructure& s = pairs.structure;
  std::vector<int> identity(static_cast<std::size_t>(s.num_blocks));
  std::iota(identity.begin(), identity.end(), 0);
  {
    auto unasked = registry.create("auto");
    const LowerLayout layout(pairs, identity);
    EXPECT_FALSE(unasked->analyze(layout.structure).ok());
  }
  auto solver = registry.create("auto");
  const std::vector<int> order = solver->preferredBlockOrder(s);
  ASSERT_EQ(order.size(), identity.size());
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  ASSERT_EQ(sorted, identity);
  EXPECT_NE(order, identity);  // METIS or AMD
  const LowerLayout layout(pairs, order);
  ASSERT_TRUE(solver->analyze(layout.structure).ok());

  // Values per block column: off-diagonal blocks from `off`, diagonal blocks 5 I.
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  auto fill = [&](auto&& off) {
    std::vector<double> values(pairs.row_idx.size(), 0.0);
    for (int c = 0; c < grid.structure.n; ++c) {
      const int len = pairs.col_ptr[2 * c + 1] - pairs.col_ptr[2 * c];
      for (int k = grid.col_ptr[c]; k < grid.col_ptr[c + 1]; ++k) {
        double* v = values.data() + pairs.col_ptr[2 * c] + 2 * (k - grid.col_ptr[c]);
        if (grid.row_idx[k] == c) {
          v[0] = v[len + 1] = 5.0;
        } else {
          off(v, len);
        }
      }
    }
    return values;
  };
  const std::vector<double> conformal = fill([&](double* v, int len) {
    const double t = angle(rng);
    v[0] = v[len + 1] = std::cos(t);
    v[1] = std::sin(t);
    v[len] = -std::sin(t);
  });
  const std::vector<double> isotropic = fill([](double* v, int len) { v[0] = v[len + 1] = -1.0; });
  std::vector<double> general = conformal;
  // Vertex 200's diagonal block (the last of its upper columns) becomes diag(5.5, 5): the
  // real block factor.
  general[pairs.col_ptr[2 * 200 + 1] - 2] = 5.5;
  std::vector<double> rhs(static_cast<std::size_t>(s.n));
  for (double& r : rhs) r = angle(rng);
  const std::vector<std::pair<const std::vector<double>*, const char*>> cases = {
      {&conformal, "(complex path)"}, {&isotropic, "(isotropic path)"}, {&general, nullptr}};
  for (const auto& [values, path] : cases) {
    const LinearSolverResult f = solver->factorize(layout.values(*values).data());
    ASSERT_TRUE(f.ok()) << solver->name() << ": " << f.message;
    if (path) {
      EXPECT_NE(solver->name().find(path), std::string::npos) << solver->name();
    } else {
      EXPECT_EQ(solver->name().find("path)"), std::string::npos) << solver->name();
    }
    EXPECT_LT(pairs.residual(*values, layout.solve(*solver, rhs), rhs), 1e-9) << solver->name();
  }
  // An indefinite diagonal block: the failure names the vertex's first column in the order.
  const int bad_vertex = 4321;
  std::vector<double> indefinite = general;
  for (int j = 0; j < 2; ++j) {
    const int col = 2 * bad_vertex + j;
    for (int k = pairs.col_ptr[col]; k < pairs.col_ptr[col + 1]; ++k) {
      if (pairs.row_idx[k] == col) indefinite[k] = -50.0;
    }
  }
  const LinearSolverResult r = solver->factorize(layout.values(indefinite).data());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite);
  EXPECT_EQ(r.column, layout.new_column[2 * bad_vertex]) << r.message;
}

// A factor of tens of MB: CHOLMOD's large allocations (the factor's values here) are
// faulted in on two threads by graphslam's SuiteSparse allocation hooks; the
// factorisation must stay exact and the process intact.
TEST(Solvers_Cholmod, LargeSupernodalFactorIsExact) {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  if (!registry.contains("cholmod")) GTEST_SKIP() << "needs CHOLMOD";
  const int side = 500;
  const GridPattern grid(side);
  const SparseStructure& s = grid.structure;
  // The grid Laplacian plus the identity (SPD), as stored: upper triangle.
  std::vector<double> values(grid.row_idx.size());
  std::vector<double> degree(static_cast<std::size_t>(s.n), 1.0);
  for (int c = 0; c < s.n; ++c) {
    for (int k = grid.col_ptr[c]; k < grid.col_ptr[c + 1]; ++k) {
      const int r = grid.row_idx[k];
      if (r != c) {
        values[k] = -1.0;
        degree[r] += 1.0;
        degree[c] += 1.0;
      }
    }
  }
  for (int c = 0; c < s.n; ++c) values[grid.col_ptr[c + 1] - 1] = degree[c];  // diagonal last
  auto solver = registry.create("cholmod:metis");
  ASSERT_TRUE(solver->analyze(s).ok());
  ASSERT_TRUE(solver->factorize(values.data()).ok());
  EXPECT_GT(solver->factorNonZeros() * sizeof(double), std::size_t{32} << 20);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> rhs(static_cast<std::size_t>(s.n)), x(rhs.size()), ax(rhs.size(), 0.0);
  for (double& v : rhs) v = u(rng);
  ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
  for (int c = 0; c < s.n; ++c) {  // A x from the upper triangle
    for (int k = grid.col_ptr[c]; k < grid.col_ptr[c + 1]; ++k) {
      const int r = grid.row_idx[k];
      ax[r] += values[k] * x[c];
      if (r != c) ax[c] += values[k] * x[r];
    }
  }
  double worst = 0.0;
  for (int i = 0; i < s.n; ++i) worst = std::max(worst, std::abs(ax[i] - rhs[i]));
  EXPECT_LT(worst, 1e-10);
}
