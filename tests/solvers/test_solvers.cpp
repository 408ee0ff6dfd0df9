// SPDX-License-Identifier: MIT
// Conformance suite run over every registered linear solver.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <set>

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

class Solvers_Conformance : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<LinearSolver> make() {
    SolverRegistry registry;
    solvers::registerSolvers(registry);
    return registry.create(GetParam());
  }
};

TEST_P(Solvers_Conformance, SolvesSpdSystemsRepeatedlyWithOneAnalysis) {
  std::mt19937 rng(17);
  BlockSystem sys(40, 3, rng);
  auto solver = make();
  EXPECT_EQ(solver->name(), GetParam());
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  for (int round = 0; round < 5; ++round) {
    const Eigen::MatrixXd m = sys.randomSpd(rng);
    const auto values = sys.values(m);
    const Eigen::VectorXd rhs = Eigen::VectorXd::Random(sys.n());
    ASSERT_TRUE(solver->factorize(values.data()).ok()) << "round " << round;
    Eigen::VectorXd x(sys.n());
    ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok());
    const Eigen::VectorXd ref = m.ldlt().solve(rhs);
    EXPECT_LT((x - ref).cwiseAbs().maxCoeff(), 1e-10) << "round " << round;
    EXPECT_LT((m * x - rhs).norm(), 1e-10 * rhs.norm());
  }
  EXPECT_GT(solver->factorNonZeros(), 0u);
}

TEST_P(Solvers_Conformance, EntriesBelowTheDiagonalAreIgnored) {
  std::mt19937 rng(23);
  BlockSystem sys(10, 2, rng);
  auto solver = make();
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  const Eigen::MatrixXd m = sys.randomSpd(rng);
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
  BlockSystem sys(12, 3, rng);
  auto solver = make();
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  Eigen::MatrixXd m = sys.randomSpd(rng);
  m(20, 20) = -50.0;  // column 20 belongs to block 6
  const auto values = sys.values(m);
  const LinearSolverResult r = solver->factorize(values.data());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite);
  if (GetParam() != "eigen-llt") {  // Eigen's LLT does not report where it failed
    EXPECT_GE(r.column, 0);
    EXPECT_LT(r.column, sys.n());
  }
}

TEST_P(Solvers_Conformance, SingularSystemIsAFailure) {
  std::mt19937 rng(31);
  BlockSystem sys(8, 3, rng);
  auto solver = make();
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  Eigen::MatrixXd m = sys.randomSpd(rng);
  // Zero out everything touching block 3: a vertex nothing constrains.
  m.middleRows(9, 3).setZero();
  m.middleCols(9, 3).setZero();
  const auto values = sys.values(m);
  const LinearSolverResult r = solver->factorize(values.data());
  ASSERT_FALSE(r.ok());
  if (GetParam() != "eigen-llt") {
    EXPECT_GE(r.column, 9);
    EXPECT_LT(r.column, 12);
  }
}

std::vector<std::string> registeredSolvers() {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  std::vector<std::string> names;
  for (const auto* e : registry.entries()) names.push_back(e->name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Registered, Solvers_Conformance, ::testing::ValuesIn(registeredSolvers()),
                         [](const auto& info) {
                           std::string s = info.param;
                           for (char& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

}  // namespace
