// SPDX-License-Identifier: MIT
// checkConstraints and checkObservability (which vertices the edges cannot determine, and
// why), the optimizer's failure message naming the failing vertex's edges, and its stop at
// an optimum it starts from.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "../common/range_bearing_edges.h"
#include "../common/small_se2_graphs.h"
#include "graphslam/diagnostics/graph_checks.h"
#include "graphslam/diagnostics/observability.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using namespace graphslam::types_slam2d;

using namespace graphslam::test;

TEST(Diagnostics_GraphChecks, FindsUnanchoredIsolatedAndUnderMeasuredVertices) {
  Graph g;
  add<VertexSE2>(g, 0, true);
  add<VertexSE2>(g, 1);
  add<VertexSE2>(g, 2);
  odometry(g, 0, 1);
  odometry(g, 1, 2);  // 1, 2 anchored by the fixed 0
  add<VertexSE2>(g, 5);
  add<VertexSE2>(g, 6);
  add<VertexSE2>(g, 7);
  odometry(g, 5, 6);
  odometry(g, 6, 7);     // 5-7 float
  add<VertexSE2>(g, 8);  // no edge
  add<VertexXY>(g, 9, true);
  add<VertexSE2>(g, 10);
  observation(g, 10, 9);  // anchored, but 2 measured dimensions for 3 unknowns
  add<VertexXY>(g, 11);
  observation(g, 2, 11);  // a point seen once: 2 of 2, fine

  const ConstraintReport r = checkConstraints(g);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.without_edges, (std::vector<VertexId>{8}));
  ASSERT_EQ(r.unanchored.size(), 1u);
  EXPECT_EQ(r.unanchored[0], (std::vector<VertexId>{5, 6, 7}));
  EXPECT_EQ(r.too_few_measurements, (std::vector<VertexId>{10}));
  const std::string text = r.describe();
  EXPECT_NE(text.find("no edge at all: 8"), std::string::npos) << text;
  EXPECT_NE(text.find("can move freely together): 5-7"), std::string::npos) << text;
  EXPECT_NE(text.find("fewer measured dimensions than unknowns: 10"), std::string::npos) << text;

  g.removeVertex(8);
  g.removeVertex(10);
  odometry(g, 2, 5);
  EXPECT_TRUE(checkConstraints(g).ok()) << checkConstraints(g).describe();
}

TEST(Diagnostics_GraphChecks, IdRanges) {
  EXPECT_EQ(formatIdRanges({}), "");
  EXPECT_EQ(formatIdRanges({4}), "4");
  EXPECT_EQ(formatIdRanges({1, 2, 3, 4, 7, 9, 10}), "1-4, 7, 9-10");
  std::vector<VertexId> many;
  for (int i = 0; i < 100; i += 2) many.push_back(i);
  const std::string s = formatIdRanges(many, 5);
  EXPECT_EQ(s, "0, 2, 4, 6, 8, ... (50 in total)");
}

TEST(Diagnostics_Observability, DeterminedGraphIsOk) {
  Graph g = threePoses();
  point(g, 10, 1, 3);  // two bearings from different directions
  observe<test::EdgeBearingSE2XY>(g, 0, 10);
  observe<test::EdgeBearingSE2XY>(g, 2, 10);
  point(g, 11, 5, 1);  // a range and a bearing from one pose
  observe<test::EdgeRangeSE2XY>(g, 1, 11);
  observe<test::EdgeBearingSE2XY>(g, 1, 11);
  point(g, 12, 3, 3);  // one relative position
  observe<EdgeSE2XY>(g, 2, 12);
  const ObservabilityReport r = checkObservability(g);
  EXPECT_TRUE(r.ok()) << r.describe();
  EXPECT_TRUE(r.unanchored.empty());
}

TEST(Diagnostics_Observability, NamesEachUndeterminedVertexWithItsReason) {
  Graph g = threePoses();
  point(g, 9, 7, 7);  // no edges
  point(g, 10, 4, 1);
  observe<test::EdgeRangeSE2XY>(g, 1, 10);
  point(g, 11, 4, 2);  // two bearings from one pose
  observe<test::EdgeBearingSE2XY>(g, 1, 11);
  observe<test::EdgeBearingSE2XY>(g, 1, 11);
  point(g, 12, 6, 0);  // bearings from poses on the line through it
  observe<test::EdgeBearingSE2XY>(g, 0, 12);
  observe<test::EdgeBearingSE2XY>(g, 2, 12);
  point(g, 13, -3, 0);  // ranges from poses on the line through it
  observe<test::EdgeRangeSE2XY>(g, 0, 13);
  observe<test::EdgeRangeSE2XY>(g, 2, 13);
  pose(g, 20, 5, 5);  // a pose seen from one landmark: 2 of its 3 directions
  point(g, 21, 6, 5);
  observe<EdgeSE2XY>(g, 2, 21);
  observe<EdgeSE2XY>(g, 20, 21);

  TypeRegistry types;
  types_slam2d::registerTypes(types);
  ObservabilityOptions options;
  options.types = &types;
  const ObservabilityReport r = checkObservability(g, options);
  EXPECT_EQ(r.undeterminedIds(), (std::vector<VertexId>{9, 10, 11, 12, 13, 20}));
  const auto reason = [&](VertexId id) { return find(r, id) ? find(r, id)->reason : ""; };
  EXPECT_EQ(reason(9), "no edges");
  EXPECT_EQ(reason(10),
            "one range-only edge (from vertex 1): it can move on a circle around vertex 1");
  EXPECT_EQ(reason(11),
            "seen from one vertex (1) by bearing only: it can slide along the line of sight");
  EXPECT_EQ(reason(12),
            "bearing-only edges all along one line (parallel bearings) from vertices 0 and 2: it "
            "can slide along that line");
  EXPECT_EQ(reason(13),
            "range-only edges from vertices 0 and 2 that all lie along one line through it: it can "
            "move across that line");
  EXPECT_EQ(reason(20), "its one edge (from vertex 21) determines only 2 of its 3 directions");
  EXPECT_EQ(find(r, 10)->tag, "VERTEX_XY");
  EXPECT_EQ(find(r, 10)->rank, 1);
  EXPECT_EQ(find(r, 20)->neighbours, (std::vector<VertexId>{21}));
  // The edges of each vertex, as indices into graph.edges().
  ASSERT_EQ(find(r, 12)->edges.size(), 2u);
  for (std::size_t k : find(r, 12)->edges) {
    EXPECT_EQ(g.edges()[k]->vertexId(1), 12);
  }
  const std::string text = r.describe();
  EXPECT_NE(
      text.find("6 vertices are not determined by the edges:\n  vertex 9 (VERTEX_XY): no edges"),
      std::string::npos)
      << text;
  // The estimates are where they were.
  EXPECT_EQ(static_cast<const VertexXY*>(g.vertex(10))->estimate(), Eigen::Vector2d(4, 1));
}

TEST(Diagnostics_Observability, UnanchoredComponentIsInformationOnly) {
  Graph g = threePoses();
  pose(g, 5, 0, 0);
  pose(g, 6, 1, 0);
  odometry(g, 5, 6);
  const ObservabilityReport r = checkObservability(g);
  EXPECT_TRUE(r.ok());
  ASSERT_EQ(r.unanchored.size(), 1u);
  EXPECT_EQ(r.unanchored[0], (std::vector<VertexId>{5, 6}));
  EXPECT_NE(r.describe().find("information: 1 component has no anchor"), std::string::npos)
      << r.describe();
}

TEST(Diagnostics_Observability, ThreadCountDoesNotChangeTheReport) {
  Graph g;
  pose(g, 0, 0, 0, true);
  for (int i = 1; i < 3000; ++i) {
    pose(g, i, i, 0);
    odometry(g, i - 1, i);
  }
  point(g, 5000, 10, 4);
  observe<test::EdgeRangeSE2XY>(g, 10, 5000);
  ObservabilityOptions one, two;
  two.threads = 2;
  const auto a = checkObservability(g, one), b = checkObservability(g, two);
  EXPECT_EQ(a.undeterminedIds(), (std::vector<VertexId>{5000}));
  EXPECT_EQ(a.describe(), b.describe());
}
