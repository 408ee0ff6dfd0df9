// SPDX-License-Identifier: MIT
// The linear system: parallel linearisation, block patterns, H in a solver's block order.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/optimizer/linear_system.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/support/block_pattern.h"
#include "optimizer_test_graphs.h"

using namespace graphslam;
using test::allSolvers;
using test::mixedGraph;

namespace {

/// H as a dense symmetric matrix in the id order of the vertices (the order of the first
/// structure built), from any layout of `system`: `column_of` maps each active vertex to
/// its first column in that order.
Eigen::MatrixXd denseInIdOrder(const LinearSystem& system,
                               const std::map<const Vertex*, int>& column_of, int n) {
  const SparseStructure s = system.hessianStructure();
  std::vector<int> id_column(static_cast<std::size_t>(s.n));
  for (const Vertex* v : system.activeVertices()) {
    for (int j = 0; j < v->dimension(); ++j)
      id_column[system.columnOf(*v) + j] = column_of.at(v) + j;
  }
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  const auto& values = system.hessianValues();
  for (int c = 0; c < s.n; ++c) {
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      const int r = s.row_idx[k];
      if (s.lower ? r < c : r > c) continue;  // the other triangle of a diagonal block
      h(id_column[r], id_column[c]) = values[k];
      h(id_column[c], id_column[r]) = values[k];
    }
  }
  return h;
}

/// Eigen's simplicial LL^T (AMD) on H's stored triangle. With `shuffle`, it asks for H in a
/// shuffled block order (so gets the lower triangle), else it takes H as it is (the upper
/// one, id order), and checks that it gets what it asked for. It reports 24 non-zeros per
/// column in either case, so that the optimizer's chord steps get the same budget.
template <int UpLo>
class TriangleSolver final : public LinearSolver {
 public:
  explicit TriangleSolver(int* analyses) : analyses_(analyses) {}
  std::string name() const override { return UpLo == Eigen::Lower ? "shuffled-lower" : "upper"; }
  std::vector<int> preferredBlockOrder(const SparseStructure& s) override {
    EXPECT_FALSE(s.lower);
    if (UpLo != Eigen::Lower) return {};
    order_.resize(static_cast<std::size_t>(s.num_blocks));
    std::iota(order_.begin(), order_.end(), 0);
    std::shuffle(order_.begin(), order_.end(), std::mt19937(7));
    return order_;
  }
  LinearSolverResult analyze(const SparseStructure& s) override {
    EXPECT_EQ(s.lower, UpLo == Eigen::Lower);
    if (UpLo == Eigen::Lower) {
      EXPECT_EQ(static_cast<std::size_t>(s.num_blocks), order_.size());
    }
    s_ = s;
    ++*analyses_;
    return LinearSolverResult::success();
  }
  LinearSolverResult factorize(const double* values) override {
    const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::ColMajor, int>> h(
        s_.n, s_.n, static_cast<int>(s_.nnz()), s_.col_ptr, s_.row_idx, values);
    llt_.compute(h);  // reads the UpLo triangle only
    if (llt_.info() != Eigen::Success) {
      return LinearSolverResult::failure(LinearSolverStatus::kNotPositiveDefinite, "not SPD");
    }
    return LinearSolverResult::success();
  }
  LinearSolverResult solve(const double* rhs, double* x) override {
    Eigen::VectorXd sol = llt_.solve(Eigen::Map<const Eigen::VectorXd>(rhs, s_.n));
    std::copy(sol.data(), sol.data() + s_.n, x);
    return LinearSolverResult::success();
  }
  std::size_t factorNonZeros() const override { return 24 * static_cast<std::size_t>(s_.n); }

 private:
  int* analyses_;
  std::vector<int> order_;
  SparseStructure s_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double, Eigen::ColMajor, int>, UpLo> llt_;
};

}  // namespace

TEST(Optimizer_LinearSystem, ParallelLinearisationMatchesSerialPerEdge) {
  Graph serial = mixedGraph();
  Graph parallel = mixedGraph();
  LinearSystem a, b;
  b.setThreads(2);
  EXPECT_EQ(b.threads(), 2);
  a.update(serial);
  b.update(parallel);
  EXPECT_EQ(a.computeChi2(serial), b.computeChi2(parallel));
  EXPECT_EQ(a.computeChi2(serial), serial.chi2());
  for (int pass = 0; pass < 2; ++pass) {  // the first pass classifies the edges
    a.linearize();
    b.linearize();
  }
  a.assembleHessian();
  b.assembleHessian();
  EXPECT_TRUE(a.hessianValues() == b.hessianValues());
  EXPECT_TRUE(a.gradient() == b.gradient());
  // The in-place numeric edges were classified as serial and still give correct Jacobians.
  std::size_t in_place = 0;
  for (const auto& e : parallel.edges()) in_place += e->perturbsVerticesInPlace() ? 1 : 0;
  EXPECT_GT(in_place, 500u);
}

TEST(Optimizer_BlockPattern, PairsInAnyOrderGiveSortedUpperColumnsWithTheirDiagonal) {
  // Pairs in both orders, repeated, and a block (3) coupled to nothing.
  const std::vector<std::pair<int, int>> pairs = {{2, 0}, {0, 2}, {1, 2}, {4, 1}, {2, 1}, {0, 4}};
  const support::BlockPattern p = support::BlockPattern::fromPairs(5, pairs);
  ASSERT_EQ(p.numBlocks(), 5);
  const std::vector<std::vector<int>> want = {{0}, {1}, {0, 1, 2}, {3}, {0, 1, 4}};
  for (int c = 0; c < 5; ++c) {
    const std::vector<int> got(p.rows.begin() + p.ptr[c], p.rows.begin() + p.ptr[c + 1]);
    EXPECT_EQ(got, want[c]) << "column " << c;
    for (int r : want[c]) EXPECT_EQ(p.rows[p.find(r, c)], r);
  }
  EXPECT_EQ(p.ptr.back(), static_cast<int>(p.rows.size()));
}

// ------------------------------------------------ H in a solver's order (lower triangle)

// LinearSystem::reorder lays H out in a solver's block order as its lower triangle: the
// same matrix and gradient, vertex by vertex (vertices of dimension 2 and 3, a ternary
// edge); a list that is not a permutation is refused, and the empty one restores the id
// order.
TEST(Optimizer_LinearSystem, ReorderedHessianIsTheSameMatrixInTheLowerTriangle) {
  Graph g = mixedGraph();
  LinearSystem system;
  system.update(g);
  system.computeChi2(g);
  system.linearize();
  system.assembleHessian();
  const int n = system.dimension();
  std::map<const Vertex*, int> column_of;
  for (const Vertex* v : system.activeVertices()) column_of[v] = system.columnOf(*v);
  const Eigen::MatrixXd h_id = denseInIdOrder(system, column_of, n);
  const std::vector<double> g_id = system.gradient();
  const std::vector<Vertex*> by_id = system.activeVertices();
  const std::size_t nb = by_id.size();

  std::vector<int> order(nb);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(11));
  std::vector<int> bad = order;
  bad[1] = bad[0];
  EXPECT_FALSE(system.reorder(bad));
  EXPECT_FALSE(system.reorder(std::vector<int>(order.begin(), order.end() - 1)));
  EXPECT_FALSE(system.reordered());

  ASSERT_TRUE(system.reorder(order));
  EXPECT_TRUE(system.reordered());
  EXPECT_TRUE(system.hessianStructure().lower);
  EXPECT_EQ(system.activeVertices()[0], by_id[static_cast<std::size_t>(order[0])]);
  EXPECT_EQ(system.columnOf(*system.activeVertices()[0]), 0);
  EXPECT_EQ(system.blockStarts()[0], 0);
  system.assembleHessian();
  const Eigen::MatrixXd h_shuffled = denseInIdOrder(system, column_of, n);
  EXPECT_LT((h_shuffled - h_id).cwiseAbs().maxCoeff(), 1e-12 * h_id.cwiseAbs().maxCoeff());
  for (const Vertex* v : system.activeVertices()) {
    for (int j = 0; j < v->dimension(); ++j) {
      EXPECT_NEAR(system.gradient()[system.columnOf(*v) + j], g_id[column_of[v] + j],
                  1e-12 * std::max(1.0, std::abs(g_id[column_of[v] + j])));
    }
  }
  // Every stored entry of the lower layout lies on or below the diagonal, or in a diagonal
  // block.
  const SparseStructure s = system.hessianStructure();
  for (int c = 0; c < s.n; ++c) {
    for (int k = s.col_ptr[c]; k < s.col_ptr[c + 1]; ++k) {
      if (s.row_idx[k] < c) {
        const auto* first = std::upper_bound(s.block_starts, s.block_starts + s.num_blocks, c);
        EXPECT_GE(s.row_idx[k], *(first - 1)) << "column " << c;
      }
    }
  }

  ASSERT_TRUE(system.reorder({}));
  EXPECT_FALSE(system.reordered());
  for (const Vertex* v : system.activeVertices()) EXPECT_EQ(system.columnOf(*v), column_of[v]);
}

// A solver that asks for its own block order gets H's lower triangle in that order, and
// the optimizer takes the same steps as with H in the id order (chord steps included: their
// products with H read the lower triangle); a list that is not a permutation is a failure
// that says so.
TEST(Optimizer_Batch, SolverBlockOrderGivesTheSameSteps) {
  simulation::ManhattanOptions sim;
  sim.num_poses = 1500;
  sim.sigma_theta = 0.05;
  auto run = [&](const std::string& solver, SolverRegistry& registry, int* cg) {
    Graph g = std::move(simulation::simulateManhattan(sim).graph);
    g.vertex(0)->setFixed(true);
    auto init_solver = registry.create("auto");
    EXPECT_TRUE(init::initializeGlobal(g, init_solver.get()).message.empty());
    Optimizer::Options opt;
    opt.linear_solver = solver;
    Optimizer optimizer(g, registry, opt);
    const Summary s = optimizer.optimize();
    for (const auto& it : s.per_iteration) *cg += it.strategy.value("cg_iterations");
    std::vector<double> state, buf;
    for (const auto& [id, v] : g.vertices()) {
      buf.resize(static_cast<std::size_t>(v->estimateDataDimension()));
      v->getEstimateData(buf.data());
      state.insert(state.end(), buf.begin(), buf.end());
    }
    return std::make_pair(s, state);
  };
  SolverRegistry registry = allSolvers();
  int analyses = 0;
  registry.registerSolver("shuffled-lower", "test: H in a shuffled block order", [&analyses] {
    return std::make_unique<TriangleSolver<Eigen::Lower>>(&analyses);
  });
  registry.registerSolver("upper", "test: H in the id order", [&analyses] {
    return std::make_unique<TriangleSolver<Eigen::Upper>>(&analyses);
  });
  int cg_id = 0, cg_shuffled = 0;
  const auto [id_order, id_state] = run("upper", registry, &cg_id);
  const auto [shuffled, shuffled_state] = run("shuffled-lower", registry, &cg_shuffled);
  ASSERT_TRUE(id_order.succeeded()) << id_order.report();
  ASSERT_TRUE(shuffled.succeeded()) << shuffled.report();
  EXPECT_EQ(analyses, 2);
  EXPECT_GT(cg_shuffled, 0);
  EXPECT_EQ(cg_shuffled, cg_id);
  ASSERT_EQ(shuffled.per_iteration.size(), id_order.per_iteration.size());
  for (std::size_t k = 0; k < id_order.per_iteration.size(); ++k) {
    EXPECT_NEAR(shuffled.per_iteration[k].chi2, id_order.per_iteration[k].chi2,
                1e-9 * id_order.per_iteration[k].chi2)
        << "iteration " << k + 1;
  }
  ASSERT_EQ(shuffled_state.size(), id_state.size());
  for (std::size_t i = 0; i < id_state.size(); ++i)
    EXPECT_NEAR(shuffled_state[i], id_state[i], 1e-9);

  // A solver whose order is not a permutation.
  class BadOrder final : public LinearSolver {
   public:
    std::string name() const override { return "bad-order"; }
    std::vector<int> preferredBlockOrder(const SparseStructure& s) override {
      return std::vector<int>(static_cast<std::size_t>(s.num_blocks), 0);
    }
  };
  registry.registerSolver("bad-order", "test", [] { return std::make_unique<BadOrder>(); });
  int unused = 0;
  const auto [bad, bad_state] = run("bad-order", registry, &unused);
  EXPECT_EQ(bad.status, TerminationStatus::kNumericalFailure);
  EXPECT_NE(bad.message.find("not a permutation of the 1499 vertices"), std::string::npos)
      << bad.message;
}
