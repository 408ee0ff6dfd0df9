// SPDX-License-Identifier: MIT
// .g2o I/O: diagnostics, lenient reading, FIX lines, large and threaded files, atomic writes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "../common/se2_graphs.h"
#include "../common/test_util.h"
#include "graphslam/core/graph.h"
#include "graphslam/io/g2o.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam3d/register.h"

using namespace graphslam;

TEST(Io_G2o, MalformedInputNamesFileAndLine) {
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

TEST(Io_G2o, LenientModeSkipsAndCounts) {
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

TEST(Io_G2o, FixLinesRoundTrip) {
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

TEST(Io_G2o, LargeGraphsAreWrittenInOrderAndNameUnregisteredTypes) {
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

TEST(Io_G2o, ThreadedReadingGivesTheSameGraphAndDiagnostics) {
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

TEST(Io_G2o, AtomicWriteLeavesNoPartialFile) {
  const std::string path = ::testing::TempDir() + "atomic_out.g2o";
  std::remove(path.c_str());
  EXPECT_THROW(support::writeFileAtomically(path,
                                            [](std::ostream& out) {
                                              out << "half a line";
                                              throw Error("simulated failure");
                                            }),
               Error);
  EXPECT_FALSE(test::fileExists(path));
  support::writeFileAtomically(path, [](std::ostream& out) { out << "ok\n"; });
  EXPECT_TRUE(test::fileExists(path));
  // An existing file survives a failed rewrite unchanged.
  EXPECT_THROW(support::writeFileAtomically(path, [](std::ostream&) { throw Error("again"); }),
               Error);
  std::ifstream in(path);
  std::string content;
  std::getline(in, content);
  EXPECT_EQ(content, "ok");
}

TEST(Io_G2o, MissingFileIsADiagnostic) {
  TypeRegistry types;
  auto r = io::loadG2o("/nonexistent/file.g2o", types);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.diagnostics[0].str(),
            "/nonexistent/file.g2o: cannot open: No such file or directory");
}

// A quaternion far from unit norm (zero, denormal, a typo) is refused at its line: normalised,
// a zero one would drop the rotation term from the error (a ring of four poses reached chi2
// 0 instead of 1). One written with a few digits is normalised.
TEST(Io_G2o, QuaternionsFarFromUnitNormAreRefusedAtTheLine) {
  TypeRegistry types;
  types_slam3d::registerTypes(types);
  const std::string v0 = "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n";
  const std::string info = " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n";
  const std::pair<std::string, std::string> refused[] = {
      {v0 + "VERTEX_SE3:QUAT 1 1 0 0 1e-300 0 0 0\n", "f.g2o:2: VERTEX_SE3:QUAT: the quaternion"},
      {v0 + "VERTEX_SE3:QUAT 1 1 0 0 0 0 0 0\n", "has norm 0, not 1"},
      {v0 + "VERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\nEDGE_SE3:QUAT 0 1 1 0 0 0 0 0 2" + info,
       "f.g2o:3: EDGE_SE3:QUAT: the quaternion (qx qy qz qw) = (0 0 0 2) has norm 2"},
      {"PARAMS_SE3OFFSET 0 0 0 0 0 0 0 0\n", "f.g2o:1: PARAMS_SE3OFFSET: the quaternion"},
  };
  for (const auto& [text, expected] : refused) {
    std::istringstream in(text);
    const auto res = io::readG2o(in, "f.g2o", types);
    ASSERT_FALSE(res.ok()) << text;
    EXPECT_NE(res.diagnostics[0].str().find(expected), std::string::npos)
        << res.diagnostics[0].str();
  }
  std::istringstream rounded(v0 + "VERTEX_SE3:QUAT 1 1 0 0 0 0 0.7071 0.7071\n");
  const auto res = io::readG2o(rounded, "f.g2o", types);
  ASSERT_TRUE(res.ok());
  double data[7];
  res.graph.vertex(1)->getEstimateData(data);
  EXPECT_NEAR(data[6], std::sqrt(0.5), 1e-15);
}
