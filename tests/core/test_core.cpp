// SPDX-License-Identifier: MIT
// Graph, registries, edge bases (fixed, g2o-style, multi), .g2o I/O and the optimizer.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <sstream>

#include "../common/se2_graphs.h"
#include "../common/test_util.h"
#include "graphslam/core/base_multi_edge.h"
#include "graphslam/core/error.h"
#include "graphslam/core/fixed_edge.h"
#include "graphslam/core/internal/block_pattern.h"
#include "graphslam/core/internal/file_util.h"
#include "graphslam/core/io_g2o.h"
#include "graphslam/core/large_array.h"
#include "graphslam/core/linear_system.h"
#include "graphslam/core/logging.h"
#include "graphslam/core/optimizer.h"
#include "graphslam/init/initialization.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using types_slam2d::EdgeSE2;
using types_slam2d::SE2;
using types_slam2d::VertexSE2;
using types_slam2d::VertexXY;

namespace {

/// Linear displacement between two points: e = (b - a) - z. Numeric Jacobian (no
/// linearizeOplus), exercising the FixedEdge default on copies.
class EdgeDisplacement final : public BaseBinaryEdge<2, Eigen::Vector2d, VertexXY, VertexXY> {
 public:
  ErrorVector evaluate(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const override {
    return (b - a) - measurement();
  }
};

/// The same, written g2o style: overrides computeError() only.
class EdgeDisplacementG2oStyle final
    : public BaseBinaryEdge<2, Eigen::Vector2d, VertexXY, VertexXY> {
 public:
  void computeError() override {
    mutableError() = (vertexXi<1>().estimate() - vertexXi<0>().estimate()) - measurement();
  }
};

/// Absolute position of one point: e = p - z.
class EdgePointPrior final : public BaseUnaryEdge<2, Eigen::Vector2d, VertexXY> {
 public:
  ErrorVector evaluate(const Eigen::Vector2d& p) const override { return p - measurement(); }
};

/// Dynamic arity: the centroid of any number of points equals z.
class EdgeCentroid final : public BaseMultiEdge<2, Eigen::Vector2d> {
 public:
  void computeError() override {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < numVertices(); ++i) {
      sum += static_cast<const VertexXY*>(vertex(i))->estimate();
    }
    mutableError() = sum / static_cast<double>(numVertices()) - measurement();
  }
};

/// A type that forgot both hooks.
class EdgeBroken final : public BaseUnaryEdge<2, Eigen::Vector2d, VertexXY> {};

SolverRegistry allSolvers() {
  SolverRegistry s;
  solvers::registerSolvers(s);
  return s;
}

VertexXY& addPoint(Graph& g, VertexId id, const Eigen::Vector2d& p) {
  auto v = std::make_unique<VertexXY>();
  v->setId(id);
  v->setEstimate(p);
  return static_cast<VertexXY&>(g.addVertex(std::move(v)));
}

template <typename E>
E& addDisplacement(Graph& g, VertexId a, VertexId b, const Eigen::Vector2d& z, double w = 1.0) {
  auto e = std::make_unique<E>();
  e->setVertexIds({a, b});
  e->setMeasurement(z);
  e->setInformation(Eigen::Matrix2d::Identity() * w);
  return static_cast<E&>(g.addEdge(std::move(e)));
}

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

TEST(Core_Edge, MissingHooksAreReportedFromWorkerThreads) {
  // An edge that throws in a worker thread reaches the caller as the same exception.
  Graph g;
  for (int i = 0; i < 3000; ++i) {
    addPoint(g, i, {0, 0});
    auto e = std::make_unique<EdgeBroken>();
    e->setVertexIds({i});
    g.addEdge(std::move(e));
  }
  LinearSystem system;
  system.setThreads(3);
  system.update(g);
  EXPECT_THROW((void)system.computeChi2(g), Error);
}

// --------------------------------------------------------------------------- I/O

TEST(Core_IoG2o, MalformedInputNamesFileAndLine) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  const std::string header = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";
  struct Case {
    std::string body;
    int line;
    std::string fragment;
  };
  const std::vector<Case> cases = {
      {"EDGE_SE2 0 1 1 0 0 1 0 0 1 0\n", 3, "EDGE_SE2 expects 11 numbers after the tag, found 10"},
      {"EDGE_SE2 0 1 1 0 zero 1 0 0 1 0 1\n", 3, "'zero' is not a number"},
      {"EDGE_SE2 0 1 1 0 nan 1 0 0 1 0 1\n", 3, "is not finite"},
      {"# comment\nEDGE_FOO 0 1\n", 4, "unknown tag 'EDGE_FOO'"},
      {"\xEF\xBB\xBFVERTEX_SE2 2 0 0 0\n", 3,
       "unknown tag '\\xEF\\xBB\\xBFVERTEX_SE2' (a UTF-8 byte-order mark: save the file without "
       "one)"},
      {std::string("\x01\x02\x7f\x80\0z", 6) + "\n", 3, "unknown tag '\\x01\\x02\\x7F\\x80\\x00z'"},
      {"VERTEX_SE2 1 5 5 0\n", 3, "duplicate vertex id 1 (first defined on line 2)"},
      {"EDGE_SE2 0 7 1 0 0 1 0 0 1 0 1\n", 3, "refers to vertex 7"},
      {"EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n", 3, "information matrix is not positive definite"},
      {"EDGE_SE2 0 1.5 1 0 0 1 0 0 1 0 1\n", 3, "'1.5' is not a vertex id"},
      {"FIX 42\n", 3, "FIX: vertex 42 is not defined"},
      {"EDGE_SE2 0 2147483648 1 0 0 1 0 0 1 0 1\n", 3,
       "value 2 '2147483648' is out of the range of vertex ids (-2147483648 to 2147483647)"},
      {"EDGE_SE2 0 999999999999999999999 1 0 0 1 0 0 1 0 1\n", 3,
       "is out of the range of vertex ids"},
      {"EDGE_SE2 0 1 1e400 0 0 1 0 0 1 0 1\n", 3,
       "value 3 '1e400' is out of the range of a double"},
      {"EDGE_SE2_XY 0 1 1 0 1 0 1\n", 3,
       "EDGE_SE2_XY: vertex 1 has the wrong type for slot 1: it is a VERTEX_SE2, the slot takes "
       "VERTEX_XY"},
  };
  for (const auto& c : cases) {
    std::istringstream in(header + c.body);
    auto r = io::readG2o(in, "bad.g2o", types);
    ASSERT_FALSE(r.ok()) << c.body;
    // Refused information matrices are counted to the end of the file and summed up.
    const bool information = c.fragment.find("information") != std::string::npos;
    ASSERT_EQ(r.diagnostics.size(), information ? 2u : 1u);
    EXPECT_EQ(r.diagnostics[0].line, c.line) << c.body;
    EXPECT_NE(r.diagnostics[0].str().find("bad.g2o:" + std::to_string(c.line) + ": "),
              std::string::npos);
    EXPECT_NE(r.diagnostics[0].message.find(c.fragment), std::string::npos)
        << "got: " << r.diagnostics[0].message;
  }
}

TEST(Core_IoG2o, LenientModeSkipsAndCounts) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  std::istringstream in(
      "VERTEX_SE2 0 0 0 0\nBOGUS 1\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
  io::LoadOptions opt;
  opt.strict = false;
  auto r = io::readG2o(in, "x.g2o", types, opt);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.skipped_lines, 1u);
  EXPECT_EQ(r.graph.numVertices(), 2u);
  EXPECT_EQ(r.graph.numEdges(), 1u);
}

TEST(Core_IoG2o, FixLinesRoundTrip) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  std::istringstream in(
      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0.1\nFIX 1\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
  auto r = io::readG2o(in, "x.g2o", types);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.graph.vertex(1)->fixed());
  EXPECT_FALSE(r.graph.vertex(0)->fixed());
  std::stringstream out;
  io::writeG2o(out, r.graph, types);
  EXPECT_NE(out.str().find("FIX 1\n"), std::string::npos);
  auto back = io::readG2o(out, "y.g2o", types);
  ASSERT_TRUE(back.ok());
  EXPECT_TRUE(back.graph.vertex(1)->fixed());
}

TEST(Core_IoG2o, LargeGraphsAreWrittenInOrderAndNameUnregisteredTypes) {
  // Enough lines for several batches formatted on two threads.
  constexpr int kPoses = 70000;
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  Graph g;
  std::vector<types_slam2d::SE2> truth;
  for (int i = 0; i < kPoses; ++i) {
    truth.emplace_back(0.5 * i, std::sin(0.01 * i), 0.001 * i);
    auto v = std::make_unique<types_slam2d::VertexSE2>();
    v->setId(i);
    v->setEstimate(truth.back());
    g.addVertex(std::move(v));
  }
  for (int i = 0; i + 1 < kPoses; ++i) test::addExactSE2Edge(g, truth, i, i + 1);
  for (int i = 0; i + 7 < kPoses; i += 5) test::addExactSE2Edge(g, truth, i + 7, i);
  g.vertex(kPoses / 2)->setFixed(true);

  std::stringstream out;
  io::writeG2o(out, g, types);
  const std::string text = out.str();
  // Line k + 1 + kPoses (after the vertices and the FIX line) is edge k, in the graph's
  // order, and vertex lines follow the ids.
  std::istringstream lines(text);
  std::string line;
  for (int i = 0; i < kPoses; ++i) {
    ASSERT_TRUE(std::getline(lines, line));
    ASSERT_EQ(line.rfind("VERTEX_SE2 " + std::to_string(i) + " ", 0), 0u) << line;
  }
  ASSERT_TRUE(std::getline(lines, line));
  EXPECT_EQ(line, "FIX " + std::to_string(kPoses / 2));
  for (const auto& e : g.edges()) {
    ASSERT_TRUE(std::getline(lines, line));
    const std::string head =
        "EDGE_SE2 " + std::to_string(e->vertexId(0)) + " " + std::to_string(e->vertexId(1)) + " ";
    ASSERT_EQ(line.rfind(head, 0), 0u) << line;
  }
  EXPECT_FALSE(std::getline(lines, line));
  // Reading it back and writing again gives the same text.
  std::istringstream in(text);
  auto back = io::readG2o(in, "big.g2o", types);
  ASSERT_TRUE(back.ok());
  std::stringstream again;
  io::writeG2o(again, back.graph, types);
  EXPECT_EQ(again.str(), text);

  // An edge of a type the registry does not know, at a position that the second thread
  // formats (items [98304, 131072) of the list: batches of 32768 per thread): the error
  // reaches the caller and names the edge's vertex.
  while (g.numEdges() < 100000) test::addExactSE2Edge(g, truth, 3, 10 + g.numEdges() % 1000);
  auto prior = std::make_unique<types_slam2d::EdgePriorSE2>();
  prior->setVertexIds({4321});
  prior->setMeasurement(truth[4321]);
  g.addEdge(std::move(prior));
  TypeRegistry without_priors;
  without_priors.registerVertex<types_slam2d::VertexSE2>("VERTEX_SE2");
  without_priors.registerEdge<types_slam2d::EdgeSE2>("EDGE_SE2");
  std::stringstream failed;
  try {
    io::writeG2o(failed, g, without_priors);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write an edge on vertex 4321"), std::string::npos)
        << e.what();
  }
}

TEST(Core_IoG2o, ThreadedReadingGivesTheSameGraphAndDiagnostics) {
  // A text of several 4 MiB chunks (lines cross their boundaries), with bad lines in
  // different chunks: every thread count gives the same graph, the same diagnostics and
  // the same line numbers, and strict reading stops at the first bad line.
  constexpr int kPoses = 60000;
  std::string text;
  std::vector<int> bad_lines;
  int line = 0;
  auto add = [&](const std::string& l) {
    text += l;
    text += '\n';
    ++line;
  };
  for (int i = 0; i < kPoses; ++i) {
    add("VERTEX_SE2 " + std::to_string(i) + " " + std::to_string(0.5 * i) +
        " 0.25000000000000011 0.0010000000000000009  # pose " + std::to_string(i));
    if (i == 20000) {
      add("VERTEX_SE2 17 1 2 3");  // duplicate id: names the first line of vertex 17
      bad_lines.push_back(line);
    }
  }
  add("FIX 3");
  for (int i = 0; i + 1 < kPoses; ++i) {
    add("EDGE_SE2 " + std::to_string(i) + " " + std::to_string(i + 1) +
        " 0.5 0.0 0.0 500.00000000000011 0.0 0.0 500.00000000000011 0.0 1000.0000000000002");
    if (i == 30000) {
      add("EDGE_SE2 1 99999999 1 0 0 1 0 0 1 0 1");
      bad_lines.push_back(line);
    }
    if (i == 45000) {
      add("EDGE_SE2 1 2 1 0 0 1 0 0 -1 0 1");
      bad_lines.push_back(line);
    }
  }
  ASSERT_GT(text.size(), std::size_t{10} << 20);  // three chunks or more
  TypeRegistry types;
  types_slam2d::registerTypes(types);

  std::string first_written;
  for (int threads : {1, 2, 3}) {
    io::LoadOptions lenient;
    lenient.strict = false;
    lenient.threads = threads;
    std::istringstream in(text);
    auto r = io::readG2o(in, "t.g2o", types, lenient);
    ASSERT_TRUE(r.ok()) << threads;
    EXPECT_EQ(r.graph.numVertices(), static_cast<std::size_t>(kPoses));
    EXPECT_EQ(r.graph.numEdges(), static_cast<std::size_t>(kPoses - 1));
    EXPECT_TRUE(r.graph.vertex(3)->fixed());
    ASSERT_EQ(r.diagnostics.size(), bad_lines.size()) << threads;
    EXPECT_EQ(r.skipped_lines, bad_lines.size());
    for (std::size_t k = 0; k < bad_lines.size(); ++k) {
      EXPECT_EQ(r.diagnostics[k].line, bad_lines[k]) << threads << ": " << r.diagnostics[k].str();
    }
    EXPECT_NE(r.diagnostics[0].message.find("duplicate vertex id 17 (first defined on line 18)"),
              std::string::npos)
        << r.diagnostics[0].message;
    EXPECT_NE(r.diagnostics[1].message.find("refers to vertex 99999999"), std::string::npos);
    EXPECT_NE(r.diagnostics[2].message.find("not positive definite"), std::string::npos);
    std::stringstream out;
    io::writeG2o(out, r.graph, types);
    if (threads == 1) {
      first_written = out.str();
    } else {
      EXPECT_EQ(out.str(), first_written) << threads;
    }

    io::LoadOptions strict;
    strict.threads = threads;
    std::istringstream again(text);
    auto s = io::readG2o(again, "t.g2o", types, strict);
    ASSERT_FALSE(s.ok());
    ASSERT_EQ(s.diagnostics.size(), 1u);
    EXPECT_EQ(s.diagnostics[0].line, bad_lines[0]);
    EXPECT_EQ(s.graph.numVertices(), 20001u);  // the lines before it
  }
}

TEST(Core_IoG2o, AtomicWriteLeavesNoPartialFile) {
  const std::string path = ::testing::TempDir() + "atomic_out.g2o";
  std::remove(path.c_str());
  EXPECT_THROW(writeFileAtomically(path,
                                   [](std::ostream& out) {
                                     out << "half a line";
                                     throw Error("simulated failure");
                                   }),
               Error);
  EXPECT_FALSE(test::fileExists(path));
  writeFileAtomically(path, [](std::ostream& out) { out << "ok\n"; });
  EXPECT_TRUE(test::fileExists(path));
  // An existing file survives a failed rewrite unchanged.
  EXPECT_THROW(writeFileAtomically(path, [](std::ostream&) { throw Error("again"); }), Error);
  std::ifstream in(path);
  std::string content;
  std::getline(in, content);
  EXPECT_EQ(content, "ok");
}

TEST(Core_IoG2o, MissingFileIsADiagnostic) {
  TypeRegistry types;
  auto r = io::loadG2o("/nonexistent/file.g2o", types);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.diagnostics[0].str(),
            "/nonexistent/file.g2o: cannot open: No such file or directory");
}

// --------------------------------------------------------------------------- Optimizer

class Core_Optimizer : public ::testing::TestWithParam<std::string> {};

/// A linear problem: GN must land on the exact least-squares solution in one step.
TEST_P(Core_Optimizer, LinearProblemSolvedExactlyInOneStep) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.1);
  Graph g;
  const int n = 30;
  for (int i = 0; i < n; ++i) addPoint(g, i, {noise(rng) * 10, noise(rng) * 10});
  auto prior = std::make_unique<EdgePointPrior>();
  prior->setVertexIds({0});
  prior->setMeasurement({0, 0});
  g.addEdge(std::move(prior));
  for (int i = 0; i + 1 < n; ++i) {
    addDisplacement<EdgeDisplacement>(g, i, i + 1, {1 + noise(rng), noise(rng)}, 1.0 + i % 3);
  }
  for (int i = 0; i + 5 < n; i += 4)
    addDisplacement<EdgeDisplacement>(g, i, i + 5, {5 + noise(rng), noise(rng)}, 2.0);

  // Dense reference: stack the whitened linear system.
  const int dim = 2 * n;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(dim, dim);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(dim);
  for (const auto& e : g.edges()) {
    e->computeError();
    e->linearizeOplus();
    const Eigen::Map<const Eigen::Matrix2d> W(e->informationData());
    const Eigen::Map<const Eigen::Vector2d> err(e->errorData());
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      const int ci = 2 * e->vertexId(s);
      const Eigen::Map<const Eigen::Matrix2d> Ji(e->jacobianData(s));
      b.segment<2>(ci) += Ji.transpose() * W * err;
      for (std::size_t t = 0; t < e->numVertices(); ++t) {
        const Eigen::Map<const Eigen::Matrix2d> Jj(e->jacobianData(t));
        H.block<2, 2>(ci, 2 * e->vertexId(t)) += Ji.transpose() * W * Jj;
      }
    }
  }
  Eigen::VectorXd x0(dim);
  for (int i = 0; i < n; ++i)
    x0.segment<2>(2 * i) = static_cast<VertexXY*>(g.vertex(i))->estimate();
  const Eigen::VectorXd expected = x0 + H.ldlt().solve(-b);

  auto solvers = allSolvers();
  Optimizer::Options opt;
  opt.algorithm = Algorithm::kGaussNewton;
  opt.linear_solver = GetParam();
  opt.max_iterations = 5;
  Optimizer optimizer(g, solvers, opt);
  const Summary s = optimizer.optimize();
  EXPECT_EQ(s.status, TerminationStatus::kConverged) << s.message;
  EXPECT_LE(s.iterations, 2);
  EXPECT_TRUE(s.gauge_fixed.empty());  // the prior anchors the graph
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d got = static_cast<VertexXY*>(g.vertex(i))->estimate();
    EXPECT_NEAR((got - expected.segment<2>(2 * i)).norm(), 0.0, 1e-7) << "vertex " << i;
  }
}

/// A noise-free SE(2) pose graph from a perturbed start converges back to the truth.
TEST_P(Core_Optimizer, NoiseFreePoseGraphRecoversTruth) {
  for (Algorithm algorithm : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt}) {
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0, 0.05);
    Graph g;
    std::vector<SE2> truth;
    const int n = 40;
    for (int i = 0; i < n; ++i) {
      truth.emplace_back(std::cos(i * 0.3) * 5, std::sin(i * 0.3) * 5, i * 0.3 + 1.57);
      auto v = std::make_unique<VertexSE2>();
      v->setId(i);
      v->setEstimate(i == 0 ? truth[0]
                            : SE2(truth[i].translation().x() + noise(rng),
                                  truth[i].translation().y() + noise(rng),
                                  truth[i].angle() + noise(rng)));
      g.addVertex(std::move(v));
    }
    auto link = [&](int i, int j) { test::addExactSE2Edge(g, truth, i, j); };
    for (int i = 0; i + 1 < n; ++i) link(i, i + 1);
    for (int i = 0; i + 21 < n; i += 3) link(i, i + 21);
    auto solvers = allSolvers();
    Optimizer::Options opt;
    opt.algorithm = algorithm;
    opt.linear_solver = GetParam();
    Optimizer optimizer(g, solvers, opt);
    const Summary s = optimizer.optimize();
    EXPECT_EQ(s.status, TerminationStatus::kConverged) << toString(algorithm) << ": " << s.message;
    EXPECT_LT(s.final_chi2, 1e-12);
    ASSERT_EQ(s.gauge_fixed, std::vector<VertexId>{0});
    EXPECT_FALSE(g.vertex(0)->fixed()) << "gauge fix must be undone after optimize()";
    for (int i = 0; i < n; ++i) {
      const SE2& got = static_cast<VertexSE2*>(g.vertex(i))->estimate();
      EXPECT_NEAR((got.translation() - truth[i].translation()).norm(), 0.0, 1e-7) << i;
      EXPECT_NEAR(types_slam2d::normalizeAngle(got.angle() - truth[i].angle()), 0.0, 1e-8) << i;
    }
    EXPECT_EQ(static_cast<int>(s.per_iteration.size()), s.iterations);
  }
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, Core_Optimizer,
                         ::testing::Values("eigen-ldlt", "eigen-llt", "cholmod",
                                           "cholmod-simplicial"));

/// Two components: 0-1 anchored by the fixed vertex 0, 5-6 by nothing.
Graph twoComponents() {
  Graph g;
  addPoint(g, 0, {0, 0}).setFixed(true);
  addPoint(g, 1, {1, 0});
  addPoint(g, 5, {5, 0});
  addPoint(g, 6, {6, 0.5});
  addDisplacement<EdgeDisplacement>(g, 0, 1, {1, 0});
  addDisplacement<EdgeDisplacement>(g, 5, 6, {1, 0});  // floats: nothing anchors 5-6
  return g;
}

TEST(Core_OptimizerDiagnostics, UnanchoredComponentIsAnchoredAtItsLowestId) {
  for (Algorithm algorithm : {Algorithm::kGaussNewton, Algorithm::kGaussNewtonFallback,
                              Algorithm::kLevenbergMarquardt, Algorithm::kDogleg}) {
    Graph g = twoComponents();
    auto solvers = allSolvers();
    Optimizer::Options opt;
    opt.algorithm = algorithm;
    opt.linear_solver = "cholmod";
    std::vector<std::string> logged;
    setLogSink([&](LogLevel, const std::string& m) { logged.push_back(m); });
    setLogLevel(LogLevel::kInfo);
    Optimizer optimizer(g, solvers, opt);
    const Summary s = optimizer.optimize();
    setLogLevel(LogLevel::kWarning);
    setLogSink(nullptr);
    SCOPED_TRACE(toString(algorithm));
    ASSERT_EQ(s.unanchored.size(), 1u);
    EXPECT_EQ(s.unanchored[0], (std::vector<VertexId>{5, 6}));
    EXPECT_EQ(s.gauge_fixed, (std::vector<VertexId>{5}));
    EXPECT_EQ(s.status, TerminationStatus::kConverged) << s.message;
    EXPECT_NEAR(s.final_chi2, 0.0, 1e-12);
    EXPECT_FALSE(g.vertex(5)->fixed());  // released after optimize()
    ASSERT_FALSE(logged.empty());
    EXPECT_NE(logged[0].find("fixing vertex 5"), std::string::npos) << logged[0];
  }
}

TEST(Core_OptimizerDiagnostics, UnanchoredComponentFailureNamesVertexAndCause) {
  Graph g = twoComponents();
  auto solvers = allSolvers();
  Optimizer::Options opt;
  opt.algorithm = Algorithm::kGaussNewton;
  opt.linear_solver = "cholmod";
  opt.fix_gauge = false;
  std::vector<std::string> logged;
  setLogSink([&](LogLevel, const std::string& m) { logged.push_back(m); });
  Optimizer optimizer(g, solvers, opt);
  const Summary s = optimizer.optimize();
  setLogSink(nullptr);
  ASSERT_EQ(s.unanchored.size(), 1u);
  EXPECT_EQ(s.status, TerminationStatus::kNumericalFailure);
  EXPECT_NE(s.message.find("(at vertex 6)"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("component without an anchor"), std::string::npos) << s.message;
  ASSERT_FALSE(logged.empty());
  EXPECT_NE(logged[0].find("5 6"), std::string::npos) << logged[0];
}

TEST(Core_OptimizerDiagnostics, CallbackAndRebuildAfterGraphChange) {
  Graph g;
  addPoint(g, 0, {0, 0}).setFixed(true);
  for (int i = 1; i < 5; ++i) {
    addPoint(g, i, {0, 0});
    addDisplacement<EdgeDisplacement>(g, i - 1, i, {1, 0});
  }
  auto solvers = allSolvers();
  Optimizer::Options opt;
  opt.linear_solver = "eigen-ldlt";
  int calls = 0;
  opt.callback = [&](const IterationStats&) { ++calls; };
  Optimizer optimizer(g, solvers, opt);
  Summary s = optimizer.optimize();
  EXPECT_EQ(calls, s.iterations);
  EXPECT_NEAR(static_cast<VertexXY*>(g.vertex(4))->estimate().x(), 4.0, 1e-6);
  // Grow the graph online and re-optimise with the same optimizer.
  addPoint(g, 5, {0, 0});
  addDisplacement<EdgeDisplacement>(g, 4, 5, {1, 0});
  s = optimizer.optimize();
  EXPECT_TRUE(s.succeeded());
  EXPECT_NEAR(static_cast<VertexXY*>(g.vertex(5))->estimate().x(), 5.0, 1e-6);
  g.removeVertex(5);
  s = optimizer.optimize();
  EXPECT_TRUE(s.succeeded());
  EXPECT_EQ(s.system_dimension, 8);
}

/// A graph mixing every way of linearising: an SE(2) pose graph (analytic Jacobians) and
/// points with numeric Jacobians on copies, in place (g2o style) and of a multi-edge.
Graph mixedGraph() {
  simulation::ManhattanOptions sim;
  sim.num_poses = 1500;
  Graph g = std::move(simulation::simulateManhattan(sim).graph);
  g.vertex(0)->setFixed(true);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.1);
  const VertexId p0 = 100000;
  const int points = 1200;
  for (int i = 0; i < points; ++i) addPoint(g, p0 + i, {noise(rng), noise(rng)});
  g.vertex(p0)->setFixed(true);
  for (int i = 1; i < points; ++i) {
    const Eigen::Vector2d z(1.0 + noise(rng), noise(rng));
    if (i % 2) {
      addDisplacement<EdgeDisplacement>(g, p0 + i - 1, p0 + i, z);
    } else {
      addDisplacement<EdgeDisplacementG2oStyle>(g, p0 + i - 1, p0 + i, z);
    }
    if (i % 7 == 0) {
      auto c = std::make_unique<EdgeCentroid>();
      c->setVertexIds({p0 + i - 2, p0 + i - 1, p0 + i});
      c->setMeasurement(Eigen::Vector2d(i - 1.0 + noise(rng), noise(rng)));
      g.addEdge(std::move(c));
    }
  }
  return g;
}

TEST(Core_Optimizer, ThreadsGiveTheSameBits) {
  auto solvers = allSolvers();
  std::vector<std::vector<double>> chi2s;
  std::vector<std::vector<double>> states;
  for (int threads : {1, 2, 3}) {
    Graph g = mixedGraph();
    Optimizer::Options opt;
    opt.threads = threads;
    std::vector<double> chi2;
    opt.callback = [&](const IterationStats& st) { chi2.push_back(st.chi2); };
    Optimizer optimizer(g, solvers, opt);
    const Summary s = optimizer.optimize();
    ASSERT_TRUE(s.succeeded()) << s.report();
    EXPECT_GE(s.iterations, 3);
    chi2.push_back(s.final_chi2);
    chi2s.push_back(chi2);
    std::vector<double> state, buf;
    for (const auto& [id, v] : g.vertices()) {
      buf.resize(static_cast<std::size_t>(v->estimateDataDimension()));
      v->getEstimateData(buf.data());
      state.insert(state.end(), buf.begin(), buf.end());
    }
    states.push_back(state);
  }
  for (std::size_t k = 1; k < states.size(); ++k) {
    EXPECT_EQ(chi2s[k], chi2s[0]) << "thread count " << k + 1;  // bit for bit
    EXPECT_TRUE(states[k] == states[0]) << "thread count " << k + 1;
  }
}

TEST(Core_LinearSystem, ParallelLinearisationMatchesSerialPerEdge) {
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

}  // namespace

namespace {

/// Optimises a simulated Manhattan graph (vertex 0 fixed) with `algorithm`, from the
/// simulator's estimates or from the global initial guess.
Summary optimizeSimulated(const simulation::ManhattanOptions& sim, Algorithm algorithm,
                          bool global_init) {
  auto solvers = allSolvers();
  Graph g = std::move(simulation::simulateManhattan(sim).graph);
  g.vertex(0)->setFixed(true);
  if (global_init) {
    auto init_solver = solvers.create("auto");
    EXPECT_TRUE(init::initializeGlobal(g, init_solver.get()).message.empty());
  }
  Optimizer::Options opt;
  opt.algorithm = algorithm;
  Optimizer optimizer(g, solvers, opt);
  return optimizer.optimize();
}

}  // namespace

// Near convergence the default algorithm reuses the last Gauss-Newton factorisation for
// one step (a chord step); it must end where plain Gauss-Newton ends, with fewer
// factorisations, and plain Gauss-Newton must factorise at every iteration.
TEST(Core_Optimizer, ChordStepsSaveFactorisationsAndReachTheSameMinimum) {
  simulation::ManhattanOptions sim;
  sim.num_poses = 1500;
  const Summary fallback = optimizeSimulated(sim, Algorithm::kGaussNewtonFallback, false);
  const Summary gn = optimizeSimulated(sim, Algorithm::kGaussNewton, false);
  ASSERT_EQ(fallback.status, TerminationStatus::kConverged) << fallback.message;
  ASSERT_EQ(gn.status, TerminationStatus::kConverged) << gn.message;
  auto factorisations = [](const Summary& s) {
    int n = 0;
    for (const auto& it : s.per_iteration) n += it.attempts;
    return n;
  };
  for (const auto& it : gn.per_iteration) EXPECT_GE(it.attempts, 1) << "iteration " << it.iteration;
  EXPECT_EQ(fallback.per_iteration.back().attempts, 0);  // the converging step was a chord
  EXPECT_LT(factorisations(fallback), factorisations(gn));
  EXPECT_NEAR(fallback.final_chi2, gn.final_chi2, 1e-8 * gn.final_chi2);
  std::printf("chi2 %.10g (default, %d factorisations) and %.10g (gn, %d)\n", fallback.final_chi2,
              factorisations(fallback), gn.final_chi2, factorisations(gn));
}

// Chord steps iterate conjugate gradients preconditioned with the last factorisation.
// Away from convergence one is taken when the last step agreed with its model and the
// factor is dense enough for a few iterations to cost less than a factorisation
// (nnz(L)/n >= 24); chord steps that reach their tolerance follow one another. On a
// simulated graph started at the global initial guess (what `graphslam optimize` does)
// one factorisation serves every step, and the optimizer ends where Gauss-Newton ends.
TEST(Core_Optimizer, ChordStepsIterateConjugateGradientsOnTheLastFactorisation) {
  simulation::ManhattanOptions sim;
  sim.num_poses = 2000;
  sim.sigma_theta = 0.05;  // the first step lowers chi2 by 16 %
  const Summary fallback = optimizeSimulated(sim, Algorithm::kGaussNewtonFallback, true);
  const Summary gn = optimizeSimulated(sim, Algorithm::kGaussNewton, true);
  ASSERT_EQ(fallback.status, TerminationStatus::kConverged) << fallback.message;
  ASSERT_EQ(gn.status, TerminationStatus::kConverged) << gn.message;
  int factorisations = 0;
  int cg = 0;
  for (const auto& it : fallback.per_iteration) {
    std::printf("iteration %d: chi2 %.10g, %d factorisations, %d CG iterations\n", it.iteration,
                it.chi2, it.attempts, it.cg_iterations);
    factorisations += it.attempts;
    cg += it.cg_iterations;
    EXPECT_EQ(it.cg_iterations > 0, it.attempts == 0) << "iteration " << it.iteration;
  }
  EXPECT_EQ(factorisations, 1);
  EXPECT_GE(fallback.iterations, 3);
  // The first step lowered chi2 by far more than the near-convergence trigger (1e-4 of
  // it): the second is a chord step because the first agreed with its model.
  ASSERT_GE(fallback.per_iteration.size(), 2u);
  EXPECT_GT(fallback.initial_chi2 - fallback.per_iteration[0].chi2, 0.01 * fallback.initial_chi2);
  EXPECT_EQ(fallback.per_iteration[1].attempts, 0);
  EXPECT_GT(cg, fallback.iterations - 1);  // some chord step took more than one iteration
  EXPECT_NEAR(fallback.final_chi2, gn.final_chi2, 1e-8 * gn.final_chi2);
  std::printf("chi2 %.10g -> %.10g (default) and %.10g (gn, %d iterations)\n",
              fallback.initial_chi2, fallback.final_chi2, gn.final_chi2, gn.iterations);
}

TEST(Core_BlockPattern, PairsInAnyOrderGiveSortedUpperColumnsWithTheirDiagonal) {
  // Pairs in both orders, repeated, and a block (3) coupled to nothing.
  const std::vector<std::pair<int, int>> pairs = {{2, 0}, {0, 2}, {1, 2}, {4, 1}, {2, 1}, {0, 4}};
  const BlockPattern p = BlockPattern::fromPairs(5, pairs);
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

// LinearSystem::reorder lays H out in a solver's block order as its lower triangle: the
// same matrix and gradient, vertex by vertex (vertices of dimension 2 and 3, a ternary
// edge); a list that is not a permutation is refused, and the empty one restores the id
// order.
TEST(Core_LinearSystem, ReorderedHessianIsTheSameMatrixInTheLowerTriangle) {
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
TEST(Core_Optimizer, SolverBlockOrderGivesTheSameSteps) {
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
    for (const auto& it : s.per_iteration) *cg += it.cg_iterations;
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

namespace {
/// Whether the mapping of this process that holds `p` carries the transparent huge page
/// advice ("hg" among its VmFlags in /proc/self/smaps); false when it is not found.
bool advisedForHugePages(const void* p) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(p);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    unsigned long long from = 0, to = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> from >> dash >> to && dash == '-') {
      inside = at >= from && at < to;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return (" " + line + " ").find(" hg ") != std::string::npos;
    }
  }
  return false;
}

struct alignas(32) Wide {
  double v[4];
};
}  // namespace

#if defined(__linux__)
// By default a freed huge-page array is unmapped: the library keeps nothing for itself.
TEST(Core_LargeArray, FreedMappingsAreNotKeptWithoutTheApplicationsOptIn) {
  const std::size_t n = LargeArrayAllocator<double>::kHugePageMinBytes / sizeof(double) + 10;
  { const LargeVector<double> a(n, 1.0); }
  EXPECT_EQ(detail::retainedLargeArrayBytes(), 0u);
}

// With the application's opt-in, a freed huge-page array's mapping serves the next array of
// the same rounded length (its pages are faulted in already); the mappings kept stay within
// their bound, and turning retention off releases them.
TEST(Core_LargeArray, FreedMappingsServeTheNextArrayOfTheSameRoundedLength) {
  const LargeArrayRetention retention;
  setLargeArrayRetention(retention);
  constexpr std::size_t kLarge = LargeArrayAllocator<double>::kHugePageMinBytes;
  const std::size_t n = kLarge / sizeof(double) + 10;  // rounded to 2 MiB
  const double* first = nullptr;
  {
    LargeVector<double> a(n, 1.0);
    first = a.data();
  }
  EXPECT_GE(detail::retainedLargeArrayBytes(), std::size_t{2} << 20);
  LargeVector<double> b(n + 1000, 2.0);  // the same rounded length
  EXPECT_EQ(b.data(), first);
  EXPECT_EQ(b.front(), 2.0);
  EXPECT_EQ(b.back(), 2.0);
  const LargeVector<double> c((std::size_t{3} << 20) / sizeof(double));  // 4 MiB rounded
  EXPECT_NE(c.data(), first);
  {
    std::vector<LargeVector<char>> many;
    for (int i = 0; i < 20; ++i) many.emplace_back(std::size_t{3} << 20);
  }
  EXPECT_LE(detail::retainedLargeArrayBytes(), retention.max_bytes);
  setLargeArrayRetention(LargeArrayRetention{0, 0});
  EXPECT_EQ(detail::retainedLargeArrayBytes(), 0u);
}
#endif

TEST(Core_LargeArray, SmallArraysAreOrdinaryLargeOnesAlignedAndAdvisedForHugePages) {
  constexpr std::size_t kLarge = LargeArrayAllocator<double>::kHugePageMinBytes;
  constexpr std::size_t kHuge = LargeArrayAllocator<double>::kHugePageMaxBytes;
  // Below the threshold: operator new with the element's alignment.
  LargeVector<Wide> small(10);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % alignof(Wide), 0u);
  // Growing across the threshold keeps the contents; the large array is zero-initialised
  // where resize() says so.
  LargeVector<double> v;
  for (std::size_t i = 0; i < kLarge / sizeof(double) + 1000; ++i) v.push_back(0.5 * i);
  for (std::size_t i = 0; i < v.size(); i += 997) ASSERT_EQ(v[i], 0.5 * i);
  v.resize(3 * kLarge / sizeof(double), 0.0);
  EXPECT_EQ(v.back(), 0.0);
  EXPECT_EQ(v[kLarge / sizeof(double)], 0.5 * (kLarge / sizeof(double)));
  const LargeVector<double> copy = v;
  EXPECT_TRUE(copy == v);
#if defined(__linux__)
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % (std::uintptr_t{2} << 20), 0u);
  std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string setting;
  std::getline(thp, setting);
  if (!setting.empty() && setting.find("[never]") == std::string::npos) {
    EXPECT_TRUE(advisedForHugePages(v.data())) << "THP setting: " << setting;
    EXPECT_FALSE(advisedForHugePages(small.data()));
    const LargeVector<char> beyond(kHuge + 1);
    EXPECT_FALSE(advisedForHugePages(beyond.data()));
  }
#endif
}
