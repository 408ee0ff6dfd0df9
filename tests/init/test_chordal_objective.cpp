// SPDX-License-Identifier: MIT
// SE-Sync's chordal objective: analytic Jacobians and the switch of a graph's edges.
#include <gtest/gtest.h>

#include <random>

#include "../common/edge_type_checks.h"
#include "../common/test_util.h"
#include "graphslam/init/chordal_edges.h"
#include "graphslam/init/chordal_objective.h"
#include "graphslam/io/g2o.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

using namespace graphslam;

namespace {

constexpr double kPi = 3.14159265358979323846;

template <typename V>
V& addVertex(Graph& g, VertexId id, const typename V::EstimateType& x) {
  auto v = std::make_unique<V>();
  v->setId(id);
  v->setEstimate(x);
  return static_cast<V&>(g.addVertex(std::move(v)));
}

init::EdgeSE2Chordal* makeSE2(Graph& g, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-5, 5), a(-kPi, kPi);
  addVertex<types_slam2d::VertexSE2>(g, 0, types_slam2d::SE2(u(rng), u(rng), a(rng)));
  addVertex<types_slam2d::VertexSE2>(g, 1, types_slam2d::SE2(u(rng), u(rng), a(rng)));
  auto e = std::make_unique<init::EdgeSE2Chordal>();
  e->setVertexIds({0, 1});
  e->setMeasurement(Eigen::Vector3d(u(rng), u(rng), a(rng)));
  e->setWeights(2.0, 3.0);
  return static_cast<init::EdgeSE2Chordal*>(&g.addEdge(std::move(e)));
}

init::EdgeSE3Chordal* makeSE3(Graph& g, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-5, 5);
  auto pose = [&] {
    return geometry::SE3(geometry::SO3::exp(Eigen::Vector3d(u(rng), u(rng), u(rng)) / 3.0),
                         Eigen::Vector3d(u(rng), u(rng), u(rng)));
  };
  addVertex<types_slam3d::VertexSE3>(g, 0, pose());
  addVertex<types_slam3d::VertexSE3>(g, 1, pose());
  const geometry::SE3 z = pose();
  Eigen::Matrix<double, 12, 1> m;
  const Eigen::Matrix3d r = z.rotation();
  m.head<9>() = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(r.data());
  m.tail<3>() = z.translation();
  auto e = std::make_unique<init::EdgeSE3Chordal>();
  e->setVertexIds({0, 1});
  e->setMeasurement(m);
  e->setWeights(2.0, 3.0);
  return static_cast<init::EdgeSE3Chordal*>(&g.addEdge(std::move(e)));
}

TEST(Init_Edges, AnalyticJacobiansMatchNumeric) {
  test::expectAnalyticJacobians<init::EdgeSE2Chordal>(makeSE2, 21, 300);
  test::expectAnalyticJacobians<init::EdgeSE3Chordal>(makeSE3, 22, 300);
}

TEST(Init_Edges, TermIsSeSyncs) {
  // R_j = R_i R~ and t_j = t_i + R_i t~: zero; a rotation off by 90 degrees in 2D:
  // |R(pi/2) - I|_F^2 = 4 (1 - cos(pi/2)) = 4, times kappa.
  Graph g;
  addVertex<types_slam2d::VertexSE2>(g, 0, types_slam2d::SE2(1, 2, 0.3));
  addVertex<types_slam2d::VertexSE2>(g, 1, types_slam2d::SE2(1, 2, 0.3 + kPi / 2));
  auto e = std::make_unique<init::EdgeSE2Chordal>();
  e->setVertexIds({0, 1});
  e->setMeasurement(Eigen::Vector3d::Zero());
  e->setWeights(5.0, 7.0);
  g.addEdge(std::move(e));
  EXPECT_NEAR(g.chi2(), 20.0, 1e-12);
}

TEST(Init_Objective, SwitchesRelativePoseEdgesAndRestoresThem) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  std::istringstream in(
      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_XY 2 1 1\n"
      "EDGE_SE2 0 1 1 0 1.5707963267948966 4 1 0 2 0 9\n"
      "EDGE_SE2_XY 0 2 1 1 1 0 1\n");
  auto res = io::readG2o(in, "f.g2o", types);
  ASSERT_TRUE(res.ok());
  Graph& g = res.graph;
  {
    init::ChordalObjective objective(g);
    EXPECT_EQ(objective.switched(), 1u);
    EXPECT_EQ(g.numEdges(), 3u);
    EXPECT_FALSE(g.edges()[0]->active());
    // kappa = 9, rotation off by 90 degrees: 4 * 9; tau = 2 / tr(Omega_t^-1) of
    // [4 1; 1 2] (inverse trace 6 / 7), translation exact.
    EXPECT_NEAR(objective.value(), 36.0, 1e-9);
  }
  EXPECT_EQ(g.numEdges(), 2u);
  EXPECT_TRUE(g.edges()[0]->active());
}

}  // namespace
