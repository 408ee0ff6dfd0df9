// SPDX-License-Identifier: MIT
// Graph, registries and edge bases (fixed, g2o-style, multi).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <memory>
#include <utility>
#include <vector>

#include "../common/point_edges.h"
#include "../common/test_util.h"
#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using test::addDisplacement;
using test::addPoint;
using test::EdgeCentroid;
using test::EdgeDisplacement;
using test::EdgeDisplacementG2oStyle;
using types_slam2d::VertexSE2;
using types_slam2d::VertexXY;

namespace {

/// A type that forgot both hooks.
class EdgeBroken final : public BaseUnaryEdge<2, Eigen::Vector2d, VertexXY> {};

}  // namespace

// --------------------------------------------------------------------------- Graph

TEST(Core_Graph, AddRemoveAndIncidence) {
  Graph g;
  addPoint(g, 1, {0, 0});
  addPoint(g, 2, {1, 0});
  addPoint(g, 3, {2, 0});
  EXPECT_THROW(addPoint(g, 2, {0, 0}), Error);
  auto& e12 = addDisplacement<EdgeDisplacement>(g, 1, 2, {1, 0});
  addDisplacement<EdgeDisplacement>(g, 2, 3, {1, 0});
  EXPECT_EQ(g.vertex(2)->edges().size(), 2u);
  EXPECT_THROW(addDisplacement<EdgeDisplacement>(g, 1, 9, {1, 0}), Error);  // missing vertex
  EXPECT_THROW(addDisplacement<EdgeDisplacement>(g, 1, 1, {1, 0}), Error);  // same vertex twice
  const auto version = g.structureVersion();
  EXPECT_TRUE(g.removeEdge(&e12));
  EXPECT_NE(g.structureVersion(), version);
  EXPECT_EQ(g.vertex(2)->edges().size(), 1u);
  EXPECT_TRUE(g.removeVertex(3));
  EXPECT_EQ(g.numEdges(), 0u);
  EXPECT_TRUE(g.vertex(2)->edges().empty());
  EXPECT_FALSE(g.removeVertex(3));
}

TEST(Core_Graph, WrongVertexTypeIsRejected) {
  Graph g;
  addPoint(g, 0, {0, 0});
  auto pose = std::make_unique<VertexSE2>();
  pose->setId(1);
  g.addVertex(std::move(pose));
  EXPECT_THROW_MSG(addDisplacement<EdgeDisplacement>(g, 0, 1, {1, 0}), Error,
                   "vertex 1 has the wrong type for slot 1 (expected "
                   "graphslam::types_slam2d::VertexXY)");
}

// --------------------------------------------------------------------------- Registry

TEST(Core_Registry, RejectsDuplicatesWhitespaceAndUnknown) {
  TypeRegistry types;
  types.registerVertex<VertexXY>("VERTEX_XY");
  EXPECT_THROW(types.registerVertex<VertexXY>("VERTEX_XY"), RegistryError);
  EXPECT_THROW(types.registerVertex<VertexSE2>("VERTEX SE2"), RegistryError);
  EXPECT_THROW(types.registerVertex<VertexSE2>(""), RegistryError);
  EXPECT_THROW(types.registerVertex<VertexXY>("OTHER_NAME"), RegistryError);  // type twice
  EXPECT_THROW((void)types.createEdge("VERTEX_XY"), RegistryError);
  EXPECT_THROW((void)types.createVertex("NOPE"), RegistryError);
  auto v = types.createVertex("VERTEX_XY");
  ASSERT_NE(types.tagOf(*v), nullptr);
  EXPECT_EQ(*types.tagOf(*v), "VERTEX_XY");

  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  EXPECT_THROW(solvers::registerSolvers(solvers), RegistryError);
  EXPECT_THROW((void)solvers.create("no-such-solver"), RegistryError);
  EXPECT_THROW(solvers.registerSolver("x", "", nullptr), RegistryError);
}

// --------------------------------------------------------------------------- Edge bases

TEST(Core_Edge, NumericDefaultsAgreeForAllThreeStyles) {
  Graph g;
  addPoint(g, 0, {0.3, -1.2});
  addPoint(g, 1, {2.0, 0.7});
  addPoint(g, 2, {-1.0, 4.0});
  auto& a = addDisplacement<EdgeDisplacement>(g, 0, 1, {1, 1});
  auto& b = addDisplacement<EdgeDisplacementG2oStyle>(g, 0, 1, {1, 1});
  auto c = std::make_unique<EdgeCentroid>();
  c->setVertexIds({0, 1, 2});
  c->setMeasurement({0.5, 0.5});
  auto& centroid = static_cast<EdgeCentroid&>(g.addEdge(std::move(c)));
  for (Edge* e : std::vector<Edge*>{&a, &b}) {
    e->computeError();
    e->linearizeOplus();
    const Eigen::Map<const Eigen::Matrix2d> j0(e->jacobianData(0)), j1(e->jacobianData(1));
    EXPECT_TRUE(j0.isApprox(-Eigen::Matrix2d::Identity(), 1e-8));
    EXPECT_TRUE(j1.isApprox(Eigen::Matrix2d::Identity(), 1e-8));
  }
  EXPECT_TRUE(a.error().isApprox(b.error()));
  centroid.computeError();
  centroid.linearizeOplus();
  for (std::size_t s = 0; s < 3; ++s) {
    EXPECT_TRUE(centroid.jacobian(s).isApprox(Eigen::Matrix2d::Identity() / 3.0, 1e-8)) << s;
  }
  // A vertex's estimate is untouched by numeric differentiation.
  EXPECT_EQ(static_cast<VertexXY*>(g.vertex(0))->estimate(), Eigen::Vector2d(0.3, -1.2));
}

TEST(Core_Edge, MissingHooksAreReported) {
  Graph g;
  addPoint(g, 0, {0, 0});
  auto e = std::make_unique<EdgeBroken>();
  e->setVertexIds({0});
  auto& edge = g.addEdge(std::move(e));
  EXPECT_THROW_MSG(edge.computeError(), Error,
                   "edge type (anonymous namespace)::EdgeBroken overrides neither");
}
