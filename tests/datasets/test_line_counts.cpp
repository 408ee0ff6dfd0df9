// SPDX-License-Identifier: MIT
// Every reader over every file of the data folder: the lines it read equal the lines
// counted independently (line ends, plus one when the last byte is not a line end), so no
// reader holds back a line anywhere. Skips with a message when the folder is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../common/test_util.h"
#include "graphslam/drivebot/scenario.h"
#include "graphslam/io/g2o.h"
#include "graphslam/io/trajectory.h"
#include "graphslam/types_drivebot/register.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;
using namespace graphslam::io;
namespace fs = std::filesystem;

namespace {

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Lines of a text: its line ends, plus one for a last line without a line end.
std::size_t countLines(const std::string& text) {
  const auto ends = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  return ends + (!text.empty() && text.back() != '\n' ? 1 : 0);
}

/// Lines holding something other than white space and a comment.
struct DataLines {
  std::size_t total = 0;
  std::size_t fix = 0;
};

DataLines countDataLines(const std::string& text) {
  DataLines out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    line = line.substr(0, line.find('#'));
    const auto first = line.find_first_not_of(" \t\r\v\f");
    if (first == std::string::npos) continue;
    ++out.total;
    if (line.compare(first, 4, "FIX ") == 0) ++out.fix;
  }
  return out;
}

std::vector<fs::path> filesWithExtension(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().extension() == extension)
      out.push_back(entry.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(Datasets_LineCounts, G2oReaderReadsEveryLineOfEveryFile) {
  const fs::path dir = test::dataDir();
  if (!fs::is_directory(dir)) GTEST_SKIP() << dir << " not found (set GRAPHSLAM_DATA)";
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  types_drivebot::registerTypes(types);
  const auto files = filesWithExtension(dir, ".g2o");
  ASSERT_FALSE(files.empty());
  for (const auto& file : files) {
    const std::string text = readBytes(file);
    const DataLines data = countDataLines(text);
    for (int threads : {1, 2}) {
      io::LoadOptions options;
      options.strict = false;  // the tags no module registers yet (3D) are skipped, counted
      options.threads = threads;
      const auto r = io::loadG2o(file.string(), types, options);
      const std::string what = file.filename().string() + " threads " + std::to_string(threads);
      EXPECT_EQ(r.lines, countLines(text)) << what;
      EXPECT_EQ(r.graph.numVertices() + r.graph.numEdges() + data.fix + r.skipped_lines, data.total)
          << what;
    }
  }
}

TEST(Datasets_LineCounts, TumMatrixAndScenarioReadersReadEveryRow) {
  const fs::path seeds = fs::path(test::dataDir()) / "seeds";
  if (!fs::is_directory(seeds)) GTEST_SKIP() << seeds << " not found (set GRAPHSLAM_DATA)";
  const fs::path hw = seeds / "shanghaitech_slam2024_hw1";
  const std::string tum = readBytes(hw / "gt_tum_student_generated.txt");
  EXPECT_EQ(readTum((hw / "gt_tum_student_generated.txt").string()).size(),
            countDataLines(tum).total);
  // The relative-pose matrix: 3 rows; every number of the file is one entry.
  const std::string matrix_text = readBytes(hw / "hw1_data.txt");
  const Eigen::Matrix3Xd matrix = readMatrix3xN((hw / "hw1_data.txt").string());
  std::istringstream numbers(matrix_text);
  const auto count = static_cast<Eigen::Index>(std::distance(
      std::istream_iterator<std::string>(numbers), std::istream_iterator<std::string>()));
  EXPECT_EQ(countDataLines(matrix_text).total, 3u);
  EXPECT_EQ(matrix.size(), count);

  std::size_t scenarios = 0;
  for (const auto& x0 : filesWithExtension(seeds, ".txt")) {
    if (x0.filename() != "x0.txt") continue;
    const fs::path dir = x0.parent_path();
    const auto s = drivebot::loadScenario(dir.string());
    EXPECT_EQ(s.waypoints.size(), countDataLines(readBytes(dir / "wp.txt")).total) << dir;
    EXPECT_EQ(s.landmarks.size(), countDataLines(readBytes(dir / "lm.txt")).total) << dir;
    ++scenarios;
  }
  EXPECT_GE(scenarios, 9u);
}

TEST(Datasets_LineCounts, Pose2ExampleLoadsItsLastLoopClosure) {
  // The file's last line, the loop closure 3 -> 10, has no line end.
  const std::string path = test::dataDir() + "/pose2example.g2o";
  if (!test::fileExists(path)) GTEST_SKIP() << path << " not found (set GRAPHSLAM_DATA)";
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  for (int threads : {1, 2}) {
    io::LoadOptions options;
    options.threads = threads;
    const auto r = io::loadG2o(path, types, options);
    ASSERT_TRUE(r.ok());
    ASSERT_EQ(r.graph.numEdges(), 12u);
    EXPECT_EQ(r.graph.edges().back()->vertexId(0), 3);
    EXPECT_EQ(r.graph.edges().back()->vertexId(1), 10);
  }
}
