// SPDX-License-Identifier: MIT
// block-llt: vertices of mixed dimensions, long columns, its kernels, dense trailing parts.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdlib>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/solvers/register.h"

using namespace graphslam;

namespace {

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

}  // namespace

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
  for (int d : {1, 2, 3, 6}) {
    std::mt19937 rng(40 + d);
    const int nb = 120;
    const MixedSystem sys(std::vector<int>(nb, d), chainAndRandomPairs(nb, rng), rng);
    for (const char* spec : {"block-llt:natural", "block-llt:amd"}) {
      EXPECT_LT(sys.solveError(registry, spec), 1e-12) << "dimension " << d << ", " << spec;
    }
  }
}

TEST(Solvers_BlockLlt, ThreeDimensionalPosesAndPointsTakeSixBySixBlocks) {
  // 3D poses (6) with points (3) and a few scalars: block-llt pads to 6 x 6 blocks; auto
  // takes it for such systems; a failing vertex is named by its first column.
  std::mt19937 rng(61);
  const std::vector<int> dims = {6, 3, 6, 6, 3, 3, 6, 1, 6, 6, 3, 6, 4, 5};
  const int nb = static_cast<int>(dims.size());
  const MixedSystem sys(dims, chainAndRandomPairs(nb, rng), rng);
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  for (const char* spec : {"block-llt:amd", "block-llt:natural", "auto"}) {
    EXPECT_LT(sys.solveError(registry, spec), 1e-12) << spec;
  }
  auto solver = registry.create("auto");
  ASSERT_TRUE(solver->analyze(sys.structure()).ok());
  EXPECT_NE(solver->name().find("block-llt"), std::string::npos) << solver->name();
  for (const int b : {0, 4, 7, nb - 1}) {
    const LinearSolverResult r = sys.negatedBlockFailure(registry, "block-llt:natural", b);
    EXPECT_EQ(r.status, LinearSolverStatus::kNotPositiveDefinite) << b;
    EXPECT_EQ(r.column, sys.starts[b]) << b;
  }
  // Beyond six dimensions block-llt refuses and says what to use instead.
  const MixedSystem wide(std::vector<int>{7, 7, 7}, {{0, 1}, {1, 2}}, rng);
  auto llt = registry.create("block-llt:natural");
  const LinearSolverResult refused = llt->analyze(wide.structure());
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.message.find("at most 6"), std::string::npos) << refused.message;
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
