// SPDX-License-Identifier: MIT
// Parameters: shared constants defined once in a file and referred to by id from edges.
#include <gtest/gtest.h>

#include <sstream>

#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/parameterized_edge.h"
#include "graphslam/io/g2o.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using types_slam2d::VertexXY;

namespace {

/// A sensor offset added to a point.
class ParamOffset final : public BaseParameter<Eigen::Vector2d> {};
/// A scale factor; refuses non-positive values.
class ParamScale final : public BaseParameter<double> {
 public:
  void setValue(const double& s) override {
    if (!(s > 0)) throw Error("scale must be positive");
    BaseParameter<double>::setValue(s);
  }
};

/// e = scale * (p + offset) - z.
class EdgeOffsetPoint final : public ParameterizedEdge<BaseUnaryEdge<2, Eigen::Vector2d, VertexXY>,
                                                       ParamOffset, ParamScale> {
 public:
  ErrorVector evaluate(const Eigen::Vector2d& p) const override {
    return typedParameter<1>().value() * (p + typedParameter<0>().value()) - measurement();
  }
};

TypeRegistry registry() {
  TypeRegistry r;
  types_slam2d::registerTypes(r);
  r.registerParameter<ParamOffset>("TEST_OFFSET");
  r.registerParameter<ParamScale>("TEST_SCALE");
  r.registerEdge<EdgeOffsetPoint>("TEST_EDGE_OFFSET_POINT");
  return r;
}

io::LoadResult read(const std::string& text, const TypeRegistry& r) {
  std::istringstream in(text);
  return io::readG2o(in, "f.g2o", r);
}

const char* kGood =
    "TEST_OFFSET 3 1 2\n"
    "TEST_SCALE 7 2\n"
    "VERTEX_XY 0 1 1\n"
    "TEST_EDGE_OFFSET_POINT 0 3 7 4 6 1 0 1\n";

TEST(Io_Parameters, EdgesReadTheirParametersAndRoundTrip) {
  const TypeRegistry r = registry();
  auto res = read(kGood, r);
  ASSERT_TRUE(res.ok()) << res.diagnostics[0].str();
  ASSERT_EQ(res.graph.parameters().size(), 2u);
  Edge& e = *res.graph.edges()[0];
  EXPECT_EQ(e.numParameters(), 2);
  EXPECT_EQ(e.parameterId(0), 3);
  EXPECT_EQ(e.parameterId(1), 7);
  EXPECT_EQ(e.parameter(0), res.graph.parameter(3));
  // 2 * ((1, 1) + (1, 2)) - (4, 6) = (0, 0): the parameters are used.
  EXPECT_DOUBLE_EQ(res.graph.chi2(), 0.0);
  std::ostringstream out;
  io::writeG2o(out, res.graph, r);
  EXPECT_NE(out.str().find("TEST_OFFSET 3 1 2\n"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("TEST_EDGE_OFFSET_POINT 0 3 7 4 6 1 0 1\n"), std::string::npos)
      << out.str();
  auto again = read(out.str(), r);
  ASSERT_TRUE(again.ok()) << again.diagnostics[0].str();
  EXPECT_EQ(again.graph.parameters().size(), 2u);
  EXPECT_DOUBLE_EQ(again.graph.chi2(), 0.0);
}

TEST(Io_Parameters, BadParametersNameTheLineAndTheReason) {
  const TypeRegistry r = registry();
  const std::pair<std::string, std::string> cases[] = {
      {"TEST_OFFSET 3 1 2\nTEST_OFFSET 3 0 0\n", "f.g2o:2: TEST_OFFSET: duplicate parameter id 3"},
      {"TEST_SCALE 1 -2\n", "f.g2o:1: TEST_SCALE: scale must be positive"},
      {"TEST_SCALE x 2\n", "not a parameter id"},
      {"TEST_OFFSET 3 1\n", "TEST_OFFSET expects 3 numbers after the tag, found 2"},
      {"TEST_OFFSET 3 1 2\nVERTEX_XY 0 1 1\nTEST_EDGE_OFFSET_POINT 0 3 8 4 6 1 0 1\n",
       "f.g2o:3: TEST_EDGE_OFFSET_POINT: refers to parameter 8, which is not defined before "
       "this line"},
      {"TEST_OFFSET 3 1 2\nTEST_OFFSET 4 1 2\nVERTEX_XY 0 1 1\n"
       "TEST_EDGE_OFFSET_POINT 0 3 4 4 6 1 0 1\n",
       "f.g2o:4: TEST_EDGE_OFFSET_POINT: parameter 4 has the wrong type for parameter slot 1: it "
       "is a TEST_OFFSET, the slot takes TEST_SCALE"},
  };
  for (const auto& [text, expected] : cases) {
    auto res = read(text, r);
    ASSERT_FALSE(res.ok()) << text;
    EXPECT_NE(res.diagnostics[0].str().find(expected), std::string::npos)
        << res.diagnostics[0].str();
  }
}

TEST(Io_Parameters, GraphResolvesAndChecksIds) {
  Graph g;
  auto v = std::make_unique<VertexXY>();
  v->setId(0);
  g.addVertex(std::move(v));
  auto offset = std::make_unique<ParamOffset>();
  offset->setId(1);
  g.addParameter(std::move(offset));
  auto twice = std::make_unique<ParamOffset>();
  twice->setId(1);
  EXPECT_THROW(g.addParameter(std::move(twice)), Error);

  auto e = std::make_unique<EdgeOffsetPoint>();
  e->setVertexIds({0});
  e->setParameterId(0, 1);
  e->setParameterId(1, 1);  // an offset where a scale belongs
  EXPECT_THROW(g.addEdge(std::move(e)), Error);
  auto unknown = std::make_unique<EdgeOffsetPoint>();
  unknown->setVertexIds({0});
  unknown->setParameterId(0, 1);
  unknown->setParameterId(1, 5);
  EXPECT_THROW(g.addEdge(std::move(unknown)), Error);
  EXPECT_EQ(g.numEdges(), 0u);
  EXPECT_THROW(EdgeOffsetPoint().setParameterId(2, 0), Error);
}

}  // namespace
