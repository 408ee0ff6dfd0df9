// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <sstream>

#include "../common/test_util.h"
#include "graphslam/core/io_g2o.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using namespace graphslam::types_slam2d;

namespace {

constexpr double kPi = 3.14159265358979323846;

SE2 randomPose(std::mt19937& rng) {
  std::uniform_real_distribution<double> t(-10, 10), a(-kPi, kPi);
  return SE2(t(rng), t(rng), a(rng));
}
Eigen::Vector2d randomPoint(std::mt19937& rng) {
  std::uniform_real_distribution<double> t(-10, 10);
  return {t(rng), t(rng)};
}
template <int D>
Eigen::Matrix<double, D, D> randomInformation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix<double, D, D> a;
  for (int i = 0; i < D * D; ++i) a.data()[i] = u(rng);
  const Eigen::Matrix<double, D, D> m = a * a.transpose() + Eigen::Matrix<double, D, D>::Identity();
  return 0.5 * (m + m.transpose());  // exactly symmetric, as a file's upper triangle gives
}

/// Builds a random graph holding one edge of type E and its vertices.
template <typename E>
struct EdgeFactory;

template <>
struct EdgeFactory<EdgeSE2> {
  static EdgeSE2* make(Graph& g, std::mt19937& rng) {
    auto a = std::make_unique<VertexSE2>();
    a->setId(0);
    a->setEstimate(randomPose(rng));
    auto b = std::make_unique<VertexSE2>();
    b->setId(1);
    b->setEstimate(randomPose(rng));
    g.addVertex(std::move(a));
    g.addVertex(std::move(b));
    auto e = std::make_unique<EdgeSE2>();
    e->setVertexIds({0, 1});
    e->setMeasurement(randomPose(rng));
    e->setInformation(randomInformation<3>(rng));
    return static_cast<EdgeSE2*>(&g.addEdge(std::move(e)));
  }
};

template <>
struct EdgeFactory<EdgeSE2XY> {
  static EdgeSE2XY* make(Graph& g, std::mt19937& rng) {
    auto a = std::make_unique<VertexSE2>();
    a->setId(0);
    a->setEstimate(randomPose(rng));
    auto b = std::make_unique<VertexXY>();
    b->setId(1);
    b->setEstimate(randomPoint(rng));
    g.addVertex(std::move(a));
    g.addVertex(std::move(b));
    auto e = std::make_unique<EdgeSE2XY>();
    e->setVertexIds({0, 1});
    e->setMeasurement(randomPoint(rng));
    e->setInformation(randomInformation<2>(rng));
    return static_cast<EdgeSE2XY*>(&g.addEdge(std::move(e)));
  }
};

template <>
struct EdgeFactory<EdgePriorSE2> {
  static EdgePriorSE2* make(Graph& g, std::mt19937& rng) {
    auto a = std::make_unique<VertexSE2>();
    a->setId(0);
    a->setEstimate(randomPose(rng));
    g.addVertex(std::move(a));
    auto e = std::make_unique<EdgePriorSE2>();
    e->setVertexIds({0});
    e->setMeasurement(randomPose(rng));
    e->setInformation(randomInformation<3>(rng));
    return static_cast<EdgePriorSE2*>(&g.addEdge(std::move(e)));
  }
};

template <typename E>
class TypesSlam2d_Edge : public ::testing::Test {};
using EdgeTypes = ::testing::Types<EdgeSE2, EdgeSE2XY, EdgePriorSE2>;
TYPED_TEST_SUITE(TypesSlam2d_Edge, EdgeTypes);

TYPED_TEST(TypesSlam2d_Edge, AnalyticJacobianMatchesNumeric) {
  std::mt19937 rng(1234);
  for (int trial = 0; trial < 500; ++trial) {
    Graph g;
    TypeParam* e = EdgeFactory<TypeParam>::make(g, rng);
    const std::string problem = graphslam::test::checkJacobians(*e, g, 1e-6);
    ASSERT_TRUE(problem.empty()) << "trial " << trial << ": " << problem;
  }
}

TYPED_TEST(TypesSlam2d_Edge, AnalyticJacobianMatchesBuiltInNumericDefault) {
  // The FixedEdge numeric default (central differences on copies) is what a type
  // without linearizeOplus() gets; it must agree with the analytic Jacobian too.
  std::mt19937 rng(99);
  for (int trial = 0; trial < 100; ++trial) {
    Graph g;
    TypeParam* e = EdgeFactory<TypeParam>::make(g, rng);
    e->computeError();
    e->linearizeOplus();
    std::vector<Eigen::MatrixXd> analytic;
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      analytic.emplace_back(Eigen::Map<const Eigen::MatrixXd>(e->jacobianData(s), e->dimension(),
                                                              e->vertex(s)->dimension()));
    }
    e->numericJacobians();
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      const Eigen::Map<const Eigen::MatrixXd> numeric(e->jacobianData(s), e->dimension(),
                                                      e->vertex(s)->dimension());
      EXPECT_LT((numeric - analytic[s]).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, analytic[s].cwiseAbs().maxCoeff()))
          << "slot " << s;
    }
  }
}

TYPED_TEST(TypesSlam2d_Edge, WriteReadRoundTripIsExact) {
  TypeRegistry types;
  registerTypes(types);
  std::mt19937 rng(7);
  Graph g;
  TypeParam* e = EdgeFactory<TypeParam>::make(g, rng);
  ASSERT_NE(types.tagOf(*e), nullptr) << "type not registered";
  std::stringstream text;
  io::writeG2o(text, g, types);
  auto loaded = io::readG2o(text, "roundtrip", types);
  ASSERT_TRUE(loaded.ok()) << loaded.diagnostics.at(0).str();
  ASSERT_EQ(loaded.graph.numEdges(), 1u);
  ASSERT_EQ(loaded.graph.numVertices(), g.numVertices());
  const Edge& back = *loaded.graph.edges()[0];
  std::vector<double> m1(static_cast<std::size_t>(e->measurementDataDimension())), m2(m1.size());
  e->getMeasurementData(m1.data());
  back.getMeasurementData(m2.data());
  EXPECT_EQ(m1, m2);
  const int d = e->dimension();
  for (int i = 0; i < d * d; ++i) EXPECT_EQ(e->informationData()[i], back.informationData()[i]);
  for (const auto& [id, v] : g.vertices()) {
    std::vector<double> a(static_cast<std::size_t>(v->estimateDataDimension())), b(a.size());
    v->getEstimateData(a.data());
    loaded.graph.vertex(id)->getEstimateData(b.data());
    EXPECT_EQ(a, b) << "vertex " << id;
  }
  EXPECT_NEAR(loaded.graph.chi2(), g.chi2(), 1e-12 * std::max(1.0, g.chi2()));
}

TEST(TypesSlam2d_SE2, GroupAxioms) {
  std::mt19937 rng(5);
  for (int i = 0; i < 100; ++i) {
    const SE2 a = randomPose(rng), b = randomPose(rng), c = randomPose(rng);
    const SE2 ident = a * a.inverse();
    EXPECT_NEAR(ident.translation().norm(), 0.0, 1e-12);
    EXPECT_NEAR(ident.angle(), 0.0, 1e-12);
    EXPECT_TRUE(((a * b) * c).matrix().isApprox((a * (b * c)).matrix(), 1e-12));
    EXPECT_TRUE((a * b).matrix().isApprox(a.matrix() * b.matrix(), 1e-12));
    EXPECT_GE(a.angle(), -kPi);
    EXPECT_LT(a.angle(), kPi);
  }
}

TEST(TypesSlam2d_SE2, NormalizeAngle) {
  EXPECT_NEAR(normalizeAngle(3 * kPi), -kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(-3 * kPi / 2), kPi / 2, 1e-12);
  EXPECT_NEAR(normalizeAngle(0.5), 0.5, 0);
  EXPECT_NEAR(normalizeAngle(2 * kPi + 0.25), 0.25, 1e-12);
}

TEST(TypesSlam2d_EdgeSE2, ErrorFollowsG2oConvention) {
  // Z^-1 (Xi^-1 Xj) for a hand-computed case.
  Graph g;
  auto a = std::make_unique<VertexSE2>();
  a->setId(0);
  a->setEstimate(SE2(1, 2, kPi / 2));
  auto b = std::make_unique<VertexSE2>();
  b->setId(1);
  b->setEstimate(SE2(1, 5, kPi));
  g.addVertex(std::move(a));
  g.addVertex(std::move(b));
  auto e = std::make_unique<EdgeSE2>();
  e->setVertexIds({0, 1});
  e->setMeasurement(SE2(3, 0, kPi / 2));  // exact: b is 3 m ahead of a, turned by 90 deg
  auto& edge = static_cast<EdgeSE2&>(g.addEdge(std::move(e)));
  edge.computeError();
  EXPECT_NEAR(edge.error().norm(), 0.0, 1e-12);
  // 1 m further than measured along a's x axis, expressed in the measurement's frame
  // (rotated by 90 degrees): e_t = R_z^T (1, 0) = (0, -1).
  edge.setMeasurement(SE2(2, 0, kPi / 2));
  edge.computeError();
  EXPECT_NEAR(edge.error()[0], 0.0, 1e-12);
  EXPECT_NEAR(edge.error()[1], -1.0, 1e-12);
  EXPECT_NEAR(edge.error()[2], 0.0, 1e-12);
}

TEST(TypesSlam2d_Register, AllTagsRegistered) {
  TypeRegistry types;
  registerTypes(types);
  for (const char* tag : {"VERTEX_SE2", "VERTEX_XY", "EDGE_SE2", "EDGE_SE2_XY", "EDGE_PRIOR_SE2"}) {
    EXPECT_TRUE(types.contains(tag)) << tag;
  }
  EXPECT_THROW(registerTypes(types), RegistryError);  // duplicates are refused
}

}  // namespace
