// SPDX-License-Identifier: MIT
// Conformance suite run over every registered linear solver; the registry's solvers.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"
#include "solver_test_systems.h"

using namespace graphslam;
using test::BlockSystem;

namespace {

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

std::vector<std::string> registeredSolvers() {
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  std::vector<std::string> specs;
  for (const auto* e : registry.entries()) {
    for (Ordering o : e->orderings) specs.push_back(e->name + ":" + toString(o));
  }
  return specs;
}

}  // namespace

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
