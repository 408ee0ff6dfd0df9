// SPDX-License-Identifier: MIT
// The auto solver: predicted factors, its orderings and paths (scalar, complex, block).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/solvers/register.h"
#include "solver_test_systems.h"

using namespace graphslam;
using test::BlockSystem;
using test::GridOfPairs;
using test::GridPattern;

namespace {

/// Solver options whose cost model makes supernodal CHOLMOD the fastest backend for every
/// system (no fixed cost, almost no cost per flop), to test that path on systems small
/// enough for a unit test; the measured model sends them to block-llt.
solvers::SolverOptions supernodalEverywhere() {
  auto model = std::make_shared<solvers::CostModel>(solvers::CostModel::builtIn());
  model->cholmod_supernodal = solvers::CostLine{0.0, 0.0, 1e-15};
  solvers::SolverOptions options;
  options.auto_solver.cost_model = model;
  return options;
}

/// Values on the pattern of `pairs` (the 2x2 blocks of `grid`): each diagonal block
/// diagonal(c) I (c the block column), each other block from off(v, len), which writes its
/// (0, 0) and (1, 0) entries at v[0], v[1] and its (0, 1) and (1, 1) at v[len], v[len + 1].
template <typename Diagonal, typename Off>
std::vector<double> pairValues(const GridPattern& grid, const GridOfPairs& pairs,
                               Diagonal&& diagonal, Off&& off) {
  std::vector<double> values(pairs.row_idx.size(), 0.0);
  for (int c = 0; c < grid.structure.n; ++c) {
    const int len = pairs.col_ptr[2 * c + 1] - pairs.col_ptr[2 * c];
    for (int k = grid.col_ptr[c]; k < grid.col_ptr[c + 1]; ++k) {
      double* v = values.data() + pairs.col_ptr[2 * c] + 2 * (k - grid.col_ptr[c]);
      if (grid.row_idx[k] == c) {
        v[0] = v[len + 1] = diagonal(c);
      } else {
        off(v, len);
      }
    }
  }
  return values;
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

}  // namespace

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

TEST(Solvers_Auto, IsotropicValuesTakeTheScalarPathAndOthersTheBlockOne) {
  AutoOnPairs t(41);
  const Eigen::MatrixXd iso = t.sys.isotropic(t.general);
  const auto nnz = solveInTurn(*t.solver, t.sys, {&t.general, &iso, &t.general, &iso});
  // L = L_s (x) I_2 stores d entries per non-zero of L_s, the block factor d^2 per block.
  EXPECT_LT(nnz[1], nnz[0]);
  EXPECT_LT(nnz[3], nnz[2]);
}

// Blocks [a -b; b a] are a Hermitian complex matrix: `auto` factorises it as such (half
// the flops and memory of the real 2x2 block factor) when its cost model sends the system
// to CHOLMOD's supernodal factorisation (here a model that always does; the measured one
// keeps block-llt up to large systems); a block of another form sends it back to the real
// factor.
TEST(Solvers_Auto, LargeConformalSystemsTakeTheComplexPath) {
  SolverRegistry registry;
  solvers::registerSolvers(registry, supernodalEverywhere());
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

// The SE(2) initial guess's two systems (orientations: blocks [a -b; b a]; positions:
// H_s (x) I_2) have one pattern: `auto` factorises both with one solver on one analysis,
// CHOLMOD's factor switching between complex and real values, and solves the positions'
// two components in one pass, once the complex path was taken (a system with only
// isotropic values keeps the scalar path's own solver). Alternating the two kinds (and a
// general block system between them) gives every solution right.
// `options` decide whether CHOLMOD's inner factor is supernodal or simplicial.
void checkComplexAndIsotropicValuesShareOneAnalysis(const solvers::SolverOptions& options) {
  SolverRegistry registry;
  solvers::registerSolvers(registry, options);
  if (!registry.contains("cholmod")) GTEST_SKIP() << "the complex path needs CHOLMOD";
  const GridPattern grid(120);  // 14400 blocks of 2x2
  const GridOfPairs pairs(grid);
  const SparseStructure& s = pairs.structure;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  auto fill = [&](auto&& off) {
    return pairValues(
        grid, pairs, [](int c) { return 5.0 + 0.01 * (c % 7); }, off);
  };
  const std::vector<double> conformal = fill([&](double* v, int len) {
    const double t = angle(rng);
    v[0] = v[len + 1] = std::cos(t);
    v[1] = std::sin(t);
    v[len] = -std::sin(t);
  });
  const std::vector<double> isotropic =
      fill([&](double* v, int len) { v[0] = v[len + 1] = -0.5 + 0.1 * angle(rng); });
  std::vector<double> general = conformal;
  general[pairs.col_ptr[2 * 100 + 1] - 2] = 5.5;  // vertex 100's diagonal block: diag(5.5, 5)
  std::vector<double> rhs(static_cast<std::size_t>(s.n)), x(rhs.size());
  for (double& r : rhs) r = angle(rng);
  auto solver = registry.create("auto");
  ASSERT_TRUE(solver->analyze(s).ok());
  // Isotropic values before any complex ones: the scalar path's own solver.
  const std::vector<std::pair<const std::vector<double>*, const char*>> cases = {
      {&isotropic, "(isotropic path)"},
      {&conformal, "(complex path)"},
      {&isotropic, "(isotropic path, on the complex path's analysis)"},
      {&conformal, "(complex path)"},
      {&general, nullptr},
      {&isotropic, "(isotropic path, on the complex path's analysis)"}};
  for (const auto& [values, path] : cases) {
    const LinearSolverResult f = solver->factorize(values->data());
    ASSERT_TRUE(f.ok()) << solver->name() << ": " << f.message;
    if (path) {
      EXPECT_NE(solver->name().find(path), std::string::npos) << solver->name();
    } else {
      EXPECT_EQ(solver->name().find("path"), std::string::npos) << solver->name();
    }
    ASSERT_TRUE(solver->solve(rhs.data(), x.data()).ok()) << solver->name();
    EXPECT_LT(pairs.residual(*values, x, rhs), 1e-9) << solver->name();
  }
  // The isotropic factor stores L_s once for both components, the complex one a 2x2 real
  // block per entry of L_s: the factor's size says which one was made.
  ASSERT_TRUE(solver->factorize(isotropic.data()).ok());
  const std::size_t isotropic_nnz = solver->factorNonZeros();
  ASSERT_TRUE(solver->factorize(conformal.data()).ok());
  EXPECT_GT(solver->factorNonZeros(), isotropic_nnz);
}

TEST(Solvers_Auto, ComplexAndIsotropicValuesShareOneAnalysis) {
  checkComplexAndIsotropicValuesShareOneAnalysis(supernodalEverywhere());
}

// The same with CHOLMOD's simplicial factor inside (the scalar paths' own model predicts
// the supernodal one slower for systems this small): its factor switches kinds too.
TEST(Solvers_Auto, ComplexAndIsotropicValuesShareOneSimplicialAnalysis) {
  auto model = std::make_shared<solvers::CostModel>(solvers::CostModel::builtIn());
  model->block_llt[1] = solvers::CostLine{1.0, 0.0, 0.0};  // the 2x2 plan: CHOLMOD
  model->eigen_ldlt = solvers::CostLine{1.0, 0.0, 0.0};
  model->cholmod_supernodal = solvers::CostLine{0.0, 1e-5, 1e-15};
  model->block_llt[0] = solvers::CostLine{0.0, 0.0, 1e-9};  // supernodal from 1e4 flops per unknown
  solvers::SolverOptions options;
  options.auto_solver.cost_model = model;
  checkComplexAndIsotropicValuesShareOneAnalysis(options);
}

// A block system the cost model sends to supernodal CHOLMOD makes `auto` ask for H in its
// fill-reducing order, postordered, as the lower triangle: CHOLMOD then factorises H's own arrays.
// Every path takes that layout: the complex one (blocks [a -b; b a]), the scalar one (H_s (x) I),
// and the real block factor; a failed pivot names its column in that order, and a lower
// triangle given without asking for it is refused.
TEST(Solvers_Auto, LargeBlockSystemsTakeTheirOrderAsTheLowerTriangleOnEveryPath) {
  SolverRegistry registry;
  solvers::registerSolvers(registry, supernodalEverywhere());
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
    return pairValues(
        grid, pairs, [](int) { return 5.0; }, off);
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
      {&conformal, "(complex path)"},
      {&isotropic, "(isotropic path, on the complex path's analysis)"},
      {&general, nullptr}};
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
