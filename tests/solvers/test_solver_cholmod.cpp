// SPDX-License-Identifier: MIT
// CHOLMOD's supernodal factor of tens of MB (SuiteSparse allocation hooks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include "graphslam/solvers/register.h"
#include "solver_test_systems.h"

using namespace graphslam;
using test::GridPattern;

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
