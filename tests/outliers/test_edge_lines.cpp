// SPDX-License-Identifier: MIT
// io::LoadResult::edge_lines: the file line of every edge in graph order (what
// --outliers reports), for one and several reader threads and chunks that split lines.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "graphslam/io/g2o.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;

namespace {

TEST(Outliers_EdgeLines, EveryEdgeKnowsItsFileLine) {
  std::string text = "# comment\nVERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n\n";
  std::vector<std::size_t> want;
  int line = 4;
  for (int k = 2; k < 40; ++k) {
    text += "VERTEX_SE2 " + std::to_string(k) + " " + std::to_string(k) + " 0 0\n";
    ++line;
    text += "EDGE_SE2 " + std::to_string(k - 1) + " " + std::to_string(k) + " 1 0 0 1 0 0 1 0 1\n";
    want.push_back(static_cast<std::size_t>(++line));
    if (k % 5 == 0) {
      text += "# between\nFIX 0\n";
      line += 2;
    }
  }
  text += "EDGE_SE2 0 39 1 0 0 1 0 0 1 0 1";  // last line without a line end
  want.push_back(static_cast<std::size_t>(++line));
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  for (int threads : {1, 2, 3}) {
    for (std::size_t chunk : {std::size_t{7}, std::size_t{100}, std::size_t{1} << 22}) {
      io::LoadOptions o;
      o.threads = threads;
      o.chunk_bytes = chunk;
      std::istringstream in(text);
      const auto r = io::readG2o(in, "lines.g2o", types, o);
      ASSERT_TRUE(r.ok());
      EXPECT_EQ(r.edge_lines, want) << threads << " threads, chunks of " << chunk;
      EXPECT_EQ(r.edge_lines.size(), r.graph.numEdges());
    }
  }
}

TEST(Outliers_EdgeLines, LenientLoadSkipsBadEdgesLines) {
  const std::string text =
      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
      "EDGE_SE2 0 7 1 0 0 1 0 0 1 0 1\nEDGE_SE2 1 0 1 0 0 1 0 0 1 0 1\n";
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  io::LoadOptions o;
  o.strict = false;
  std::istringstream in(text);
  const auto r = io::readG2o(in, "lenient.g2o", types, o);
  EXPECT_EQ(r.edge_lines, (std::vector<std::size_t>{3, 5}));
}

}  // namespace
