// SPDX-License-Identifier: MIT
// Every reader takes a complete last line that has no line end, and reports an incomplete
// one with its file and line: `.g2o` with one and two threads and with the last line on a
// chunk boundary, TUM, KITTI, the relative-pose matrix and DriveBot scenario files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../common/test_util.h"
#include "graphslam/io/g2o.h"
#include "graphslam/io/trajectory.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;
using namespace graphslam::io;

namespace {

const std::string kVertices = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";
const std::string kEdge = "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1";

io::LoadResult readText(const std::string& text, int threads, std::size_t chunk_bytes) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  io::LoadOptions options;
  options.threads = threads;
  options.chunk_bytes = chunk_bytes;
  std::istringstream in(text);
  return io::readG2o(in, "last.g2o", types, options);
}

/// The chunk sizes that put the input's end in every position relative to a chunk: one
/// byte per chunk, the last line's end exactly on a boundary, the whole text in one chunk.
std::vector<std::size_t> chunkSizes(const std::string& text) {
  return {1,
          7,
          text.size() - kEdge.size(),
          text.size() - 1,
          text.size(),
          text.size() + 1,
          std::size_t{1} << 22};
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("graphslam_last_line_" + name);
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

}  // namespace

TEST(Io_LastLine, G2oCompleteLastLineWithoutLineEndIsRead) {
  const std::string text = kVertices + kEdge;  // no final '\n'
  for (int threads : {1, 2}) {
    for (std::size_t chunk : chunkSizes(text)) {
      const auto r = readText(text, threads, chunk);
      ASSERT_TRUE(r.ok()) << "threads " << threads << " chunk " << chunk << ": "
                          << (r.diagnostics.empty() ? "" : r.diagnostics[0].str());
      EXPECT_EQ(r.graph.numVertices(), 2u) << "threads " << threads << " chunk " << chunk;
      EXPECT_EQ(r.graph.numEdges(), 1u) << "threads " << threads << " chunk " << chunk;
      EXPECT_EQ(r.lines, 3u) << "threads " << threads << " chunk " << chunk;
    }
  }
}

TEST(Io_LastLine, G2oLastVertexWithoutLineEndIsRead) {
  const std::string text = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0";
  for (int threads : {1, 2}) {
    for (std::size_t chunk : chunkSizes(text)) {
      const auto r = readText(text, threads, chunk);
      ASSERT_TRUE(r.ok());
      EXPECT_EQ(r.graph.numVertices(), 3u) << "threads " << threads << " chunk " << chunk;
    }
  }
}

TEST(Io_LastLine, G2oTruncatedLastLineIsReportedWithItsLine) {
  const std::string text = kVertices + "EDGE_SE2 0 1 1 0";
  for (int threads : {1, 2}) {
    for (std::size_t chunk : chunkSizes(text)) {
      const auto r = readText(text, threads, chunk);
      ASSERT_FALSE(r.ok()) << "threads " << threads << " chunk " << chunk;
      ASSERT_EQ(r.diagnostics.size(), 1u);
      EXPECT_EQ(r.diagnostics[0].str(),
                "last.g2o:3: EDGE_SE2 expects 11 numbers after the tag, found 4");
    }
  }
}

TEST(Io_LastLine, G2oLinesEndingExactlyOnChunkBoundaries) {
  // Every line is 20 bytes, so a chunk of 20 or 40 bytes ends exactly at a line end; the
  // last line (no line end) is 19 bytes and ends exactly where the input does.
  std::string text;
  for (int i = 0; i < 9; ++i) text += "VERTEX_SE2 " + std::to_string(i) + " 0 0 0  \n";
  text += "VERTEX_SE2 9 0 0 0  ";
  for (int threads : {1, 2}) {
    for (std::size_t chunk : {std::size_t{19}, std::size_t{20}, std::size_t{21}, std::size_t{40},
                              text.size(), text.size() + 1}) {
      const auto r = readText(text, threads, chunk);
      ASSERT_TRUE(r.ok());
      EXPECT_EQ(r.graph.numVertices(), 10u) << "threads " << threads << " chunk " << chunk;
      EXPECT_EQ(r.lines, 10u);
    }
  }
}

TEST(Io_LastLine, G2oFileOnDiskWithoutFinalLineEnd) {
  const std::string path = writeTemp("file.g2o", kVertices + kEdge);
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  const auto r = io::loadG2o(path, types);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.graph.numEdges(), 1u);
  std::filesystem::remove(path);
}

TEST(Io_LastLine, TumAndKittiReadTheLastLineAndReportATruncatedOne) {
  const std::string tum = "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1";
  std::istringstream tum_in(tum);
  EXPECT_EQ(readTum(tum_in, "t.tum").size(), 2u);
  std::istringstream tum_bad("0 0 0 0 0 0 0 1\n1 1 0 0 0");
  EXPECT_THROW_MSG(static_cast<void>(readTum(tum_bad, "t.tum")), InputError, "t.tum:2: ");

  const std::string row = "1 0 0 0 0 1 0 0 0 0 1 0";
  std::istringstream kitti_in(row + "\n" + row);
  EXPECT_EQ(readKitti(kitti_in, "k.txt").size(), 2u);
  std::istringstream kitti_bad(row + "\n1 0 0 0 0 1");
  EXPECT_THROW_MSG(static_cast<void>(readKitti(kitti_bad, "k.txt")), InputError, "k.txt:2: ");
}

TEST(Io_LastLine, RelativePoseMatrixReadsTheLastRowAndReportsATruncatedOne) {
  std::istringstream in("1 2\n3 4\n5 6");
  const Eigen::Matrix3Xd m = readMatrix3xN(in, "m.txt");
  ASSERT_EQ(m.cols(), 2);
  EXPECT_EQ(m(2, 1), 6.0);
  std::istringstream bad("1 2\n3 4\n5");
  EXPECT_THROW_MSG(static_cast<void>(readMatrix3xN(bad, "m.txt")), InputError, "m.txt:3: ");
}
