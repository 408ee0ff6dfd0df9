// SPDX-License-Identifier: MIT
// Reading files whose vertices are not all defined (io::LoadOptions::create_missing_vertices):
// edges-only files, the vertex type chosen per slot, and the errors that remain.
#include <gtest/gtest.h>

#include <sstream>

#include "graphslam/core/base_multi_edge.h"
#include "graphslam/core/base_vertex.h"
#include "graphslam/core/fixed_edge.h"
#include "graphslam/io/g2o.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using types_slam2d::VertexSE2;
using types_slam2d::VertexXY;

namespace {

io::LoadResult read(const std::string& text, const TypeRegistry& types, bool create,
                    bool strict = true) {
  std::istringstream in(text);
  io::LoadOptions options;
  options.create_missing_vertices = create;
  options.strict = strict;
  return io::readG2o(in, "f.g2o", types, options);
}

TypeRegistry slam2d() {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  return types;
}

const std::string kOdometry = " 1 0 0 1 0 0 1 0 1\n";

/// Any number of vertices of any type (a slot that several registered types fit).
class EdgeAnyVertices final : public BaseMultiEdge<1, double> {
 public:
  void computeError() override { mutableError()[0] = 0.0; }
};

/// A slot whose vertex type is not registered.
class VertexUnregistered final : public BaseVertex<1, Eigen::Matrix<double, 1, 1>> {
 public:
  [[nodiscard]] EstimateType plus(const EstimateType& x, const TangentVector& d) const override {
    return x + d;
  }
};
class EdgeToUnregistered final
    : public BaseBinaryEdge<1, double, types_slam2d::VertexSE2, VertexUnregistered> {
 public:
  [[nodiscard]] ErrorVector evaluate(const types_slam2d::SE2&,
                                     const VertexUnregistered::EstimateType& x) const override {
    return x;
  }
};

}  // namespace

TEST(Io_EdgesOnly, VerticesAreCreatedFromTheEdgesOnRequest) {
  const TypeRegistry types = slam2d();
  const std::string text = "EDGE_SE2 0 1" + kOdometry + "EDGE_SE2 1 2" + kOdometry +
                           "EDGE_SE2_XY 2 7 1 0 1 0 1\nEDGE_SE2 2 0" + kOdometry;
  const auto strict = read(text, types, false);
  ASSERT_FALSE(strict.ok());
  EXPECT_EQ(strict.diagnostics.at(0).str(),
            "f.g2o:1: EDGE_SE2: refers to vertex 0, which is not defined before this line");

  const auto r = read(text, types, true);
  ASSERT_TRUE(r.ok()) << r.diagnostics.at(0).str();
  EXPECT_EQ(r.created_vertices, 4u);
  EXPECT_EQ(r.graph.numVertices(), 4u);
  EXPECT_EQ(r.graph.numEdges(), 4u);
  EXPECT_EQ(r.edge_lines, (std::vector<std::size_t>{1, 2, 3, 4}));
  for (VertexId id : {0, 1, 2}) {
    const auto* v = dynamic_cast<const VertexSE2*>(r.graph.vertex(id));
    ASSERT_NE(v, nullptr) << id;
    EXPECT_EQ(v->estimate().translation(), Eigen::Vector2d::Zero());
    EXPECT_EQ(v->estimate().angle(), 0.0);
  }
  ASSERT_NE(dynamic_cast<const VertexXY*>(r.graph.vertex(7)), nullptr);

  // The same on three threads, with line ends on chunk boundaries.
  std::istringstream in(text);
  io::LoadOptions threaded;
  threaded.create_missing_vertices = true;
  threaded.threads = 3;
  threaded.chunk_bytes = 7;
  const auto t = io::readG2o(in, "f.g2o", types, threaded);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t.created_vertices, 4u);
  EXPECT_EQ(t.edge_lines, r.edge_lines);
  EXPECT_TRUE(r.vertex_lines.empty());  // no line defines a vertex
}

TEST(Io_EdgesOnly, VertexLinesAreRecordedForTheLinesThatDefineThem) {
  const TypeRegistry types = slam2d();
  const std::string text = "# two poses\nVERTEX_SE2 4 0 0 0\n\nVERTEX_SE2 2 1 0 0\nEDGE_SE2 4 2" +
                           kOdometry + "EDGE_SE2 2 9" + kOdometry;
  for (int threads : {1, 3}) {
    std::istringstream in(text);
    io::LoadOptions options;
    options.create_missing_vertices = true;  // vertex 9 has no line
    options.threads = threads;
    options.chunk_bytes = 7;
    const auto r = io::readG2o(in, "f.g2o", types, options);
    ASSERT_TRUE(r.ok());
    using Line = std::pair<VertexId, std::size_t>;
    EXPECT_EQ(r.vertex_lines, (std::vector<Line>{{4, 2}, {2, 4}})) << threads;
  }
}

TEST(Io_EdgesOnly, VertexDefinedAfterAnEdgeIsStillAnError) {
  const TypeRegistry types = slam2d();
  const std::string text = "VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1" + kOdometry +
                           "VERTEX_SE2 1 1 0 0\nEDGE_SE2 1 2" + kOdometry;
  const auto r = read(text, types, true);
  ASSERT_FALSE(r.ok());
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_EQ(r.diagnostics[0].str(),
            "f.g2o:2: EDGE_SE2: refers to vertex 1, which is not defined before this line "
            "(VERTEX_SE2 defines it on line 3)");
  // Lenient: the vertex line is skipped, the vertex made from the edge stays; 2 is created.
  const auto lenient = read(text, types, true, false);
  ASSERT_TRUE(lenient.ok());
  EXPECT_EQ(lenient.skipped_lines, 1u);
  EXPECT_EQ(lenient.created_vertices, 2u);
  EXPECT_EQ(lenient.graph.numEdges(), 2u);
  EXPECT_EQ(static_cast<const VertexSE2*>(lenient.graph.vertex(1))->estimate().translation(),
            Eigen::Vector2d::Zero());
}

TEST(Io_EdgesOnly, WrongTypeOfACreatedVertexNamesTheEdgeThatMadeIt) {
  const TypeRegistry types = slam2d();
  const auto r = read("EDGE_SE2 0 1" + kOdometry + "EDGE_SE2_XY 0 1 1 0 1 0 1\n", types, true);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.diagnostics.at(0).str(),
            "f.g2o:2: EDGE_SE2_XY: vertex 1 has the wrong type for slot 1: it is a VERTEX_SE2 "
            "(created for the EDGE_SE2 on line 1), the slot takes VERTEX_XY");
}

TEST(Io_EdgesOnly, RefusedEdgeLeavesNoCreatedVertex) {
  const TypeRegistry types = slam2d();
  // 5 appears twice in one edge: the edge is refused, and the 5 it created goes with it.
  const auto r = read("EDGE_SE2 0 1" + kOdometry + "EDGE_SE2 5 5" + kOdometry, types, true, false);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.skipped_lines, 1u);
  EXPECT_NE(r.diagnostics.at(0).message.find("vertex 5 appears twice"), std::string::npos)
      << r.diagnostics.at(0).message;
  EXPECT_FALSE(r.graph.hasVertex(5));
  EXPECT_EQ(r.created_vertices, 2u);
  // A bad information matrix creates nothing either.
  const auto bad = read("EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n", types, true, false);
  EXPECT_EQ(bad.graph.numVertices(), 0u);
  EXPECT_NE(bad.diagnostics.at(0).message.find("not positive definite"), std::string::npos);
}

TEST(Io_EdgesOnly, SlotTypeIsTheFirstAcceptedTagOrNoneFits) {
  TypeRegistry types = slam2d();
  types.registerEdge<EdgeAnyVertices>("EDGE_ANY");
  types.registerEdge<EdgeToUnregistered>("EDGE_TO_UNREGISTERED");
  // Every vertex tag fits: the first in tag order (VERTEX_SE2 before VERTEX_XY).
  const auto any = read("EDGE_ANY 3 4 0 1\n", types, true);
  ASSERT_TRUE(any.ok()) << any.diagnostics.at(0).str();
  EXPECT_NE(dynamic_cast<const VertexSE2*>(any.graph.vertex(3)), nullptr);
  EXPECT_NE(dynamic_cast<const VertexSE2*>(any.graph.vertex(4)), nullptr);
  const auto none = read("EDGE_TO_UNREGISTERED 0 1 0 1\n", types, true);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.diagnostics.at(0).str(),
            "f.g2o:1: EDGE_TO_UNREGISTERED: refers to vertex 1, which no line defines, and no "
            "registered vertex type fits its slot 1 (so it cannot be created)");
  EXPECT_EQ(none.graph.numVertices(), 0u);
  EXPECT_EQ(none.created_vertices, 0u);
}
