// SPDX-License-Identifier: MIT
// The 3D types: g2o's errors, analytic Jacobians against numeric ones, exact round trips.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <sstream>

#include "../common/edge_type_checks.h"
#include "graphslam/io/g2o.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam3d/edges.h"
#include "graphslam/types_slam3d/register.h"

using namespace graphslam;
using namespace graphslam::types_slam3d;
using geometry::SO3;
using geometry::Vector6d;

namespace {

SE3 randomPose(std::mt19937& rng, double rot = 3.0) {
  std::uniform_real_distribution<double> t(-10, 10), a(-1, 1);
  const Eigen::Vector3d w(a(rng), a(rng), a(rng));
  return {SO3::exp(w.normalized() * rot * std::abs(a(rng))),
          Eigen::Vector3d(t(rng), t(rng), t(rng))};
}
/// A small perturbation: measurements near what the estimates predict.
SE3 noise(std::mt19937& rng) {
  std::uniform_real_distribution<double> a(-0.3, 0.3);
  Vector6d xi;
  for (int i = 0; i < 6; ++i) xi[i] = a(rng);
  return SE3::exp(xi);
}
Eigen::Vector3d randomPoint(std::mt19937& rng) {
  std::uniform_real_distribution<double> t(-10, 10);
  return {t(rng), t(rng), t(rng)};
}
template <int D>
Eigen::Matrix<double, D, D> randomInformation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix<double, D, D> a;
  for (int i = 0; i < D * D; ++i) a.data()[i] = u(rng);
  const Eigen::Matrix<double, D, D> m = a * a.transpose() + Eigen::Matrix<double, D, D>::Identity();
  return 0.5 * (m + m.transpose());
}

VertexSE3& addPose(Graph& g, VertexId id, const SE3& x) {
  auto v = std::make_unique<VertexSE3>();
  v->setId(id);
  v->setEstimate(x);
  return static_cast<VertexSE3&>(g.addVertex(std::move(v)));
}
VertexPointXYZ& addPoint(Graph& g, VertexId id, const Eigen::Vector3d& p) {
  auto v = std::make_unique<VertexPointXYZ>();
  v->setId(id);
  v->setEstimate(p);
  return static_cast<VertexPointXYZ&>(g.addVertex(std::move(v)));
}
const ParameterSE3Offset& addOffset(Graph& g, ParameterId id, const SE3& offset) {
  auto p = std::make_unique<ParameterSE3Offset>();
  p->setId(id);
  p->setValue(offset);
  return static_cast<const ParameterSE3Offset&>(g.addParameter(std::move(p)));
}
template <typename E>
E* add(Graph& g, std::unique_ptr<E> e, std::mt19937& rng) {
  e->setInformation(randomInformation<E::ErrorVector::RowsAtCompileTime>(rng));
  return static_cast<E*>(&g.addEdge(std::move(e)));
}

template <typename E>
struct EdgeFactory;

template <>
struct EdgeFactory<EdgeSE3> {
  static EdgeSE3* make(Graph& g, std::mt19937& rng) {
    const SE3& a = addPose(g, 0, randomPose(rng)).estimate();
    const SE3& b = addPose(g, 1, randomPose(rng)).estimate();
    auto e = std::make_unique<EdgeSE3>();
    e->setVertexIds({0, 1});
    e->setMeasurement(a.inverse() * b * noise(rng));
    return add(g, std::move(e), rng);
  }
};
template <>
struct EdgeFactory<EdgeSE3Offset> {
  static EdgeSE3Offset* make(Graph& g, std::mt19937& rng) {
    const SE3& a = addPose(g, 0, randomPose(rng)).estimate();
    const SE3& b = addPose(g, 1, randomPose(rng)).estimate();
    const SE3 pa = addOffset(g, 4, randomPose(rng)).offset();
    const SE3 pb = addOffset(g, 5, randomPose(rng)).offset();
    auto e = std::make_unique<EdgeSE3Offset>();
    e->setVertexIds({0, 1});
    e->setParameterId(0, 4);
    e->setParameterId(1, 5);
    e->setMeasurement((a * pa).inverse() * (b * pb) * noise(rng));
    return add(g, std::move(e), rng);
  }
};
template <>
struct EdgeFactory<EdgeSE3Prior> {
  static EdgeSE3Prior* make(Graph& g, std::mt19937& rng) {
    const SE3& a = addPose(g, 0, randomPose(rng)).estimate();
    const SE3 p = addOffset(g, 2, randomPose(rng)).offset();
    auto e = std::make_unique<EdgeSE3Prior>();
    e->setVertexIds({0});
    e->setParameterId(0, 2);
    e->setMeasurement(a * p * noise(rng));
    return add(g, std::move(e), rng);
  }
};
template <>
struct EdgeFactory<EdgeSE3XYZPrior> {
  static EdgeSE3XYZPrior* make(Graph& g, std::mt19937& rng) {
    addPose(g, 0, randomPose(rng));
    addOffset(g, 0, randomPose(rng));
    auto e = std::make_unique<EdgeSE3XYZPrior>();
    e->setVertexIds({0});
    e->setParameterId(0, 0);
    e->setMeasurement(randomPoint(rng));
    return add(g, std::move(e), rng);
  }
};
template <>
struct EdgeFactory<EdgeSE3PointXYZ> {
  static EdgeSE3PointXYZ* make(Graph& g, std::mt19937& rng) {
    addPose(g, 0, randomPose(rng));
    addPoint(g, 1, randomPoint(rng));
    addOffset(g, 3, randomPose(rng));
    auto e = std::make_unique<EdgeSE3PointXYZ>();
    e->setVertexIds({0, 1});
    e->setParameterId(0, 3);
    e->setMeasurement(randomPoint(rng));
    return add(g, std::move(e), rng);
  }
};
template <>
struct EdgeFactory<EdgePointXYZ> {
  static EdgePointXYZ* make(Graph& g, std::mt19937& rng) {
    addPoint(g, 0, randomPoint(rng));
    addPoint(g, 1, randomPoint(rng));
    auto e = std::make_unique<EdgePointXYZ>();
    e->setVertexIds({0, 1});
    e->setMeasurement(randomPoint(rng));
    return add(g, std::move(e), rng);
  }
};
template <>
struct EdgeFactory<EdgeXYZPrior> {
  static EdgeXYZPrior* make(Graph& g, std::mt19937& rng) {
    addPoint(g, 0, randomPoint(rng));
    auto e = std::make_unique<EdgeXYZPrior>();
    e->setVertexIds({0});
    e->setMeasurement(randomPoint(rng));
    return add(g, std::move(e), rng);
  }
};

template <typename E>
class TypesSlam3d_Edge : public ::testing::Test {};
using EdgeTypes = ::testing::Types<EdgeSE3, EdgeSE3Offset, EdgeSE3Prior, EdgeSE3XYZPrior,
                                   EdgeSE3PointXYZ, EdgePointXYZ, EdgeXYZPrior>;
TYPED_TEST_SUITE(TypesSlam3d_Edge, EdgeTypes, ::testing::internal::DefaultNameGenerator);

TYPED_TEST(TypesSlam3d_Edge, AnalyticJacobianMatchesNumeric) {
  graphslam::test::expectAnalyticJacobians<TypeParam>(EdgeFactory<TypeParam>::make, 4321, 300);
}

TYPED_TEST(TypesSlam3d_Edge, WriteReadRoundTripIsExact) {
  TypeRegistry types;
  registerTypes(types);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    Graph g;
    EdgeFactory<TypeParam>::make(g, rng);
    graphslam::test::expectExactRoundTrip(g, types);
  }
}

/// One line of each tag, read through the registry; errors computed by hand.
TEST(TypesSlam3d_Io, G2oLinesGiveHandComputedErrors) {
  TypeRegistry types;
  registerTypes(types);
  // Pose 1 is pose 0 moved 1 along x and turned 90 degrees about z; q(90 deg about z) =
  // (0, 0, sin 45, cos 45). The measurement says 1.5 along x and no turn.
  const std::string info6 = " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1";
  const std::string text =
      "PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n"
      "PARAMS_SE3OFFSET 1 0 0 1 0 0 0 1\n"
      "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n"
      "VERTEX_SE3:QUAT 1 1 0 0 0 0 0.70710678118654752 0.70710678118654752\n"
      "VERTEX_TRACKXYZ 2 1 2 3\n"
      "VERTEX_TRACKXYZ 3 2 2 3\n"
      "EDGE_SE3:QUAT 0 1 1.5 0 0 0 0 0 1" +
      info6 +
      "\n"
      "EDGE_SE3_PRIOR 1 0 1 0 0 0 0 0 1" +
      info6 +
      "\n"
      "EDGE_SE3_OFFSET 0 1 0 1 1 0 0 0 0 0 1" +
      info6 +
      "\n"
      "EDGE_SE3_TRACKXYZ 0 2 1 1 2 2 1 0 0 1 0 1\n"
      "EDGE_SE3_XYZ_PRIOR 1 0 1 0.5 0 1 0 0 1 0 1\n"
      "EDGE_POINTXYZ 2 3 1 0 0 1 0 0 1 0 1\n"
      "EDGE_POINTXYZ_PRIOR 2 1 2 2 1 0 0 1 0 1\n";
  std::istringstream in(text);
  auto res = io::readG2o(in, "t.g2o", types);
  ASSERT_TRUE(res.ok()) << res.diagnostics[0].str();
  const auto& edges = res.graph.edges();
  ASSERT_EQ(edges.size(), 7u);
  EXPECT_GT(res.graph.chi2(), 0.0);
  auto error = [&](std::size_t k) {
    return Eigen::Map<const Eigen::VectorXd>(edges[k]->errorData(), edges[k]->dimension());
  };
  const double s = std::sqrt(0.5);
  Eigen::VectorXd expected(6);
  expected << -0.5, 0, 0, 0, 0, s;  // Z^-1 X0^-1 X1 = (-0.5, 0, 0; 90 deg about z)
  EXPECT_LT((error(0) - expected).norm(), 1e-15);
  expected << 0, 0, 0, 0, 0, s;  // the prior: X1 (offset identity) against (1, 0, 0)
  EXPECT_LT((error(1) - expected).norm(), 1e-15);
  // Offset: (X0 P0)^-1 (X1 P1), P1 = 1 along z: (1, 0, 1; 90 deg about z) against (1, 0, 0).
  expected << 0, 0, 1, 0, 0, s;
  EXPECT_LT((error(2) - expected).norm(), 1e-15);
  // Track: sensor at (0, 0, 1) on pose 0 sees point (1, 2, 3) at (1, 2, 2); measured (1, 2, 2).
  EXPECT_LT(error(3).norm(), 1e-15);
  EXPECT_LT((error(4) - Eigen::Vector3d(0, -0.5, 0)).norm(), 1e-15);  // t - z
  EXPECT_LT(error(5).norm(), 1e-15);                                  // (2,2,3)-(1,2,3) = z
  EXPECT_LT((error(6) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-15);     // (1,2,3) - (1,2,2)
}

TEST(TypesSlam3d_Register, AllTagsRegistered) {
  TypeRegistry types;
  registerTypes(types);
  for (const char* tag : {"VERTEX_SE3:QUAT", "VERTEX_TRACKXYZ", "PARAMS_SE3OFFSET", "EDGE_SE3:QUAT",
                          "EDGE_SE3_OFFSET", "EDGE_SE3_PRIOR", "EDGE_SE3_XYZ_PRIOR",
                          "EDGE_SE3_TRACKXYZ", "EDGE_POINTXYZ", "EDGE_POINTXYZ_PRIOR"}) {
    EXPECT_TRUE(types.contains(tag)) << tag;
  }
}

/// A noise-free 3D pose graph with points, perturbed: the optimizer returns to chi2 0.
TEST(TypesSlam3d_Optimizer, NoiseFreeGraphConvergesFromPerturbedEstimates) {
  std::mt19937 rng(11);
  Graph g;
  std::vector<SE3> truth;
  for (int i = 0; i < 30; ++i) {
    truth.push_back(i == 0 ? SE3()
                           : truth.back() *
                                 SE3::exp((Vector6d() << 1, 0, 0.1, 0.05, 0.1, 0.2).finished()));
    addPose(g, i, truth.back() * (i == 0 ? SE3() : noise(rng)));
  }
  addOffset(g, 0, SE3(SO3::exp(Eigen::Vector3d(0.1, 0.2, 0.3)), Eigen::Vector3d(0.2, 0, 0.5)));
  for (int i = 0; i + 1 < 30; ++i) {
    for (int j : {i + 1, i + 5}) {
      if (j >= 30) continue;
      auto e = std::make_unique<EdgeSE3>();
      e->setVertexIds({i, j});
      e->setMeasurement(truth[i].inverse() * truth[j]);
      e->setInformation(geometry::Matrix6d::Identity());
      g.addEdge(std::move(e));
    }
  }
  const SE3& sensor = static_cast<const ParameterSE3Offset*>(g.parameter(0))->offset();
  for (int l = 0; l < 10; ++l) {
    const Eigen::Vector3d p = truth[3 * l].translation() + Eigen::Vector3d(1, 2, 1);
    addPoint(g, 100 + l, p + Eigen::Vector3d(0.3, -0.2, 0.1));
    for (int i : {3 * l, 3 * l + 1, 3 * l + 2}) {
      auto e = std::make_unique<EdgeSE3PointXYZ>();
      e->setVertexIds({i, 100 + l});
      e->setParameterId(0, 0);
      e->setMeasurement((truth[i] * sensor).inverse() * p);
      e->setInformation(Eigen::Matrix3d::Identity());
      g.addEdge(std::move(e));
    }
  }
  g.vertex(0)->setFixed(true);
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Optimizer::Options options;
  options.max_iterations = 50;
  Optimizer opt(g, solvers, options);
  const double initial = g.chi2();
  const Summary s = opt.optimize();
  EXPECT_GT(initial, 1.0);
  EXPECT_LT(s.final_chi2, 1e-16) << s.message;
}

}  // namespace
