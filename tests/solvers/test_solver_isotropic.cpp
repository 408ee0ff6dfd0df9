// SPDX-License-Identifier: MIT
// The isotropic solver (H = H_s (x) I) and pcg on such systems.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/solvers/register.h"
#include "solver_test_systems.h"

using namespace graphslam;
using test::BlockSystem;
using test::GridOfPairs;
using test::GridPattern;

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
