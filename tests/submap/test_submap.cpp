// SPDX-License-Identifier: MIT
// The submap solver reaches the direct path's optimum (Optimizer) on 2D and 3D graphs and
// refuses partitions it cannot use with messages that say why.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "../common/test_util.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/io/g2o.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/simulator3d.h"
#include "graphslam/solvers/register.h"
#include "graphslam/submap/submap_solver.h"
#include "graphslam/support/error.h"
#include "graphslam/support/logging.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam3d/register.h"

using namespace graphslam;

namespace {

/// Estimates of every vertex (Vertex::getEstimateData), in id order.
std::vector<std::vector<double>> estimates(const Graph& g) {
  std::vector<std::vector<double>> out;
  for (const auto& [id, v] : g.vertices()) {
    std::vector<double> x(static_cast<std::size_t>(v->estimateDataDimension()));
    v->getEstimateData(x.data());
    out.push_back(std::move(x));
  }
  return out;
}

/// Largest difference between two graphs' estimates; angles (3rd entry of a 3-vector) are
/// wrapped and a quaternion (entries 3..6 of a 7-vector) compared up to its sign.
double maxDifference(const std::vector<std::vector<double>>& a,
                     const std::vector<std::vector<double>>& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const auto& x = a[k];
    const auto& y = b[k];
    double flip = 1.0;
    if (x.size() == 7 && x[3] * y[3] + x[4] * y[4] + x[5] * y[5] + x[6] * y[6] < 0) flip = -1.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      double d = x[i] - ((x.size() == 7 && i >= 3) ? flip * y[i] : y[i]);
      if (x.size() == 3 && i == 2) d = std::remainder(d, 2 * M_PI);
      worst = std::max(worst, std::abs(d));
    }
  }
  return worst;
}

Optimizer::Options tightDirect() {
  Optimizer::Options o;
  o.function_tolerance = 1e-14;
  o.max_iterations = 200;
  return o;
}

submap::Options tightSubmaps(int k, int threads = 2) {
  submap::Options o;
  o.partition.num_submaps = k;
  o.threads = threads;
  o.function_tolerance = 1e-14;
  o.max_iterations = 200;
  return o;
}

/// Runs the direct path on a copy-by-rebuild (`make` twice) and the submap solver, and
/// checks the same optimum to 1e-6.
template <class Make>
void expectSameOptimum(const Make& make, int k, bool cholmod = false,
                       const std::function<void(submap::Options&)>& tweak = {}) {
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  support::setLogLevel(support::LogLevel::kError);
  Graph direct = make();
  Optimizer optimizer(direct, solvers, tightDirect());
  const Summary ds = optimizer.optimize();
  ASSERT_TRUE(ds.succeeded()) << ds.message;
  Graph split = make();
  submap::Options so = tightSubmaps(k);
  if (tweak) tweak(so);
  if (cholmod) {
    if (!solvers.contains("cholmod")) GTEST_SKIP() << "no cholmod in this build";
    so.solvers = &solvers;
  }
  const submap::Summary ss = submap::SubmapSolver(split, so).optimize();
  ASSERT_TRUE(ss.succeeded()) << ss.report();
  EXPECT_NEAR(ss.final_chi2, ds.final_chi2, 1e-6 * ds.final_chi2) << ss.report();
  EXPECT_LT(maxDifference(estimates(direct), estimates(split)), 1e-6);
  EXPECT_LT(ss.final_gradient_norm, 1e-4 * std::max(1.0, std::sqrt(ss.final_chi2)));
  EXPECT_EQ(ss.per_iteration.front().separator_vertices > 0, k > 1);
}

Graph manhattan(int poses, int landmarks = 0) {
  simulation::ManhattanOptions o;
  o.num_poses = poses;
  o.num_landmarks = landmarks;
  o.seed = 7;
  return simulation::simulateManhattan(o).graph;
}

}  // namespace

TEST(Submap_Solver, SameOptimumAsDirectPathOnSimulated2D) {
  expectSameOptimum([] { return manhattan(1500); }, 5);
}

TEST(Submap_Solver, SameOptimumWithTheSeparatorSystemByCholmod) {
  expectSameOptimum([] { return manhattan(1500); }, 5, true);
}

// Every preconditioner: block Jacobi alone, with the coarse level, with aggregates'
// chunks as local blocks, with both (the default).
TEST(Submap_Solver, SameOptimumWithTheSeparatorSystemByConjugateGradients) {
  for (const bool coarse : {false, true}) {
    for (const int local_dimension : {0, 300}) {
      int cg_iterations = 0;
      expectSameOptimum([] { return manhattan(1500); }, 5, false,
                        [&](submap::Options& o) {
                          o.separator_method =
                              submap::Options::SeparatorMethod::conjugate_gradients;
                          o.separator_cg_coarse = coarse;
                          o.separator_cg_local_dimension = local_dimension;
                          o.callback = [&](const submap::IterationStats& s) {
                            cg_iterations = std::max(cg_iterations, s.separator_iterations);
                          };
                        });
      EXPECT_GT(cg_iterations, 1) << "coarse " << coarse << ", local " << local_dimension;
    }
  }
}

// Aggregates of poses and landmarks (blocks of dimensions 3 and 2).
TEST(Submap_Solver, SameOptimumWithLandmarksByConjugateGradients) {
  expectSameOptimum([] { return manhattan(600, 150); }, 3, false,
                    [](submap::Options& o) {
                      o.separator_method = submap::Options::SeparatorMethod::conjugate_gradients;
                    });
}

TEST(Submap_Solver, SameOptimumWithLandmarks) {
  expectSameOptimum([] { return manhattan(600, 150); }, 3);
}

TEST(Submap_Solver, SameOptimumOnSimulated3DSphere) {
  expectSameOptimum(
      [] {
        simulation::PoseGraph3dOptions o;
        o.num_poses = 900;
        return simulation::simulatePoseGraph3d(o).graph;
      },
      4);
}

TEST(Submap_Solver, SameOptimumOnIntel) {
  const std::string path = test::dataDir() + "/intel.g2o";
  if (!test::fileExists(path)) GTEST_SKIP() << path << " not found (set GRAPHSLAM_DATA)";
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  expectSameOptimum(
      [&] {
        auto loaded = io::loadG2o(path, types);
        EXPECT_TRUE(loaded.ok());
        (void)init::initializeGlobal(loaded.graph);
        return std::move(loaded.graph);
      },
      6);
}

TEST(Submap_Solver, EachStepIsTheDirectGaussNewtonStep) {
  // One iteration from the dead-reckoned start (a step far from the optimum): the submap
  // step must be the direct path's Gauss-Newton step, not merely lead to the same optimum.
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Graph direct = manhattan(1000), split = manhattan(1000);
  Optimizer::Options gn;
  gn.algorithm = Algorithm::kGaussNewton;
  gn.max_iterations = 1;
  Optimizer optimizer(direct, solvers, gn);
  (void)optimizer.optimize();
  submap::Options so = tightSubmaps(6);
  so.max_iterations = 1;
  const auto s = submap::SubmapSolver(split, so).optimize();
  ASSERT_EQ(s.per_iteration.size(), 1u);
  ASSERT_TRUE(s.per_iteration[0].accepted && s.per_iteration[0].lambda == 0.0) << s.report();
  EXPECT_GT(s.per_iteration[0].step_norm, 1.0);
  EXPECT_LT(maxDifference(estimates(direct), estimates(split)), 1e-8);
}

TEST(Submap_Solver, ThreadsAndKeptFactorisationsGiveTheSameBits) {
  Graph a = manhattan(800), b = manhattan(800);
  submap::Options oa = tightSubmaps(4, 1);
  submap::Options ob = tightSubmaps(4, 3);
  ob.keep_factorizations = true;
  const auto sa = submap::SubmapSolver(a, oa).optimize();
  const auto sb = submap::SubmapSolver(b, ob).optimize();
  EXPECT_EQ(sa.final_chi2, sb.final_chi2);
  EXPECT_EQ(maxDifference(estimates(a), estimates(b)), 0.0);
}

TEST(Submap_Solver, OneSubmapIsTheDirectPath) {
  expectSameOptimum([] { return manhattan(300); }, 1);
}

TEST(Submap_Partition, RefusesAGraphWithoutASmallSeparator) {
  // Every pose joined to every other: any split puts most vertices in the separator.
  Graph g;
  for (int i = 0; i < 40; ++i) {
    auto v = std::make_unique<types_slam2d::VertexSE2>();
    v->setId(i);
    g.addVertex(std::move(v));
  }
  for (int i = 0; i < 40; ++i) {
    for (int j = i + 1; j < 40; ++j) {
      auto e = std::make_unique<types_slam2d::EdgeSE2>();
      e->setVertexIds({i, j});
      g.addEdge(std::move(e));
    }
  }
  submap::PartitionOptions o;
  o.num_submaps = 4;
  try {
    (void)submap::partitionGraph(g, o);
    FAIL() << "partition accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no good separator"), std::string::npos) << e.what();
  }
}

TEST(Submap_Solver, RefusesAFreeGaugeWhenNotAskedToFixIt) {
  Graph g = manhattan(200);
  submap::Options o = tightSubmaps(3);
  o.fix_gauge = false;  // the graph has no fixed vertex and no prior: its gauge is free
  try {
    (void)submap::SubmapSolver(g, o).optimize();
    FAIL() << "a free gauge was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gauge is free"), std::string::npos) << e.what();
  }
  o.fix_gauge = true;
  const auto s = submap::SubmapSolver(g, o).optimize();
  EXPECT_TRUE(s.succeeded()) << s.report();
  EXPECT_EQ(s.gauge_fixed, std::vector<VertexId>{0});
}

TEST(Submap_Partition, RefusesASubmapThatNothingAnchors) {
  // A second component (ids 1000-1002) that nothing anchors lands inside one submap.
  Graph g = manhattan(200);
  g.vertex(0)->setFixed(true);
  for (int i = 1000; i < 1003; ++i) {
    auto v = std::make_unique<types_slam2d::VertexSE2>();
    v->setId(i);
    g.addVertex(std::move(v));
    if (i == 1000) continue;
    auto e = std::make_unique<types_slam2d::EdgeSE2>();
    e->setVertexIds({i - 1, i});
    g.addEdge(std::move(e));
  }
  submap::PartitionOptions o;
  o.num_submaps = 3;
  try {
    (void)submap::partitionGraph(g, o);
    FAIL() << "an unanchored submap was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nothing anchors (1000-1002)"), std::string::npos)
        << e.what();
  }
  // The solver fixes that component's gauge as the Optimizer does.
  const auto s = submap::SubmapSolver(g, tightSubmaps(3)).optimize();
  EXPECT_TRUE(s.succeeded()) << s.report();
  EXPECT_EQ(s.gauge_fixed, std::vector<VertexId>{1000});
}

TEST(Submap_Partition, EveryEdgeInOneSubmapAndSeparatorsBetween) {
  Graph g = manhattan(1000);
  submap::PartitionOptions o;
  o.num_submaps = 6;
  const auto p = submap::partitionGraph(g, o);
  std::size_t edges = 0, interior = 0;
  for (const auto& s : p.submaps) {
    edges += s.edges.size();
    interior += s.interior.size();
    EXPECT_FALSE(s.interior.empty());
  }
  EXPECT_EQ(edges, g.numEdges());
  EXPECT_EQ(interior + p.separators.size(), g.numVertices());
  EXPECT_LT(p.separators.size(), g.numVertices() / 5) << p.describe();
}

namespace {

/// Checks that every edge's vertices are fixed, separator vertices or interior vertices of
/// the submap that holds the edge; returns the number of separator vertices.
std::size_t expectEdgesInsideSubmaps(const submap::Partition& p) {
  std::set<const Vertex*> separators(p.separators.begin(), p.separators.end());
  for (const auto& s : p.submaps) {
    std::set<const Vertex*> interior(s.interior.begin(), s.interior.end());
    for (const Edge* e : s.edges) {
      for (std::size_t k = 0; k < e->numVertices(); ++k) {
        const Vertex* v = e->vertex(k);
        EXPECT_TRUE(v->fixed() || separators.count(v) || interior.count(v))
            << "vertex " << v->id() << " of an edge in another submap's interior";
      }
    }
  }
  return p.separators.size();
}

}  // namespace

TEST(Submap_Partition, NodeBisectionCutsSmallerSeparatorsThanBreadthFirst) {
  if (submap::PartitionOptions::defaultMethod() !=
      submap::PartitionOptions::Method::node_bisection) {
    GTEST_SKIP() << "built without CHOLMOD: no node bisection";
  }
  Graph g = manhattan(4000);
  submap::PartitionOptions o;
  o.num_submaps = 8;
  o.method = submap::PartitionOptions::Method::breadth_first;
  const auto bfs = submap::partitionGraph(g, o);
  o.method = submap::PartitionOptions::Method::node_bisection;
  const auto nodes = submap::partitionGraph(g, o);
  const std::size_t bfs_size = expectEdgesInsideSubmaps(bfs);
  const std::size_t node_size = expectEdgesInsideSubmaps(nodes);
  EXPECT_LT(3 * node_size, 2 * bfs_size) << nodes.describe() << " against " << bfs.describe();
  const std::size_t mean = (g.numVertices() - node_size) / 8;
  for (const auto& s : nodes.submaps) {  // a power of two: about halves of halves
    EXPECT_GT(2 * s.interior.size(), mean) << nodes.describe();
    EXPECT_LT(2 * s.interior.size(), 3 * mean) << nodes.describe();
  }
}

TEST(Submap_Solver, SameOptimumWithSimplicialInteriorsAndTheBreadthFirstPartition) {
  // The paths of a build without CHOLMOD.
  expectSameOptimum([] { return manhattan(600, 100); }, 4, false,
                    [](submap::Options& o) {
                      o.partition.method = submap::PartitionOptions::Method::breadth_first;
                      o.supernodal_interiors = false;
                    });
}

TEST(Submap_Partition, RefusesMoreSubmapsThanVertices) {
  Graph g = manhattan(10);
  submap::PartitionOptions o;
  o.num_submaps = 50;
  EXPECT_THROW((void)submap::partitionGraph(g, o), Error);
  o.num_submaps = 0;
  EXPECT_THROW((void)submap::partitionGraph(g, o), Error);
}
