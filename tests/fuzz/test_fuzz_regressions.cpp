// SPDX-License-Identifier: MIT
// The fuzz harnesses' regression inputs (fuzz/regressions/<harness>/), replayed through the
// harnesses themselves in every build (the harness sources are compiled here under other
// names): each must be read or refused, never crash (and, in a sanitizer build, never
// touch memory it does not own).
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int graphslamFuzzG2o(const std::uint8_t* data, std::size_t size);
extern "C" int graphslamFuzzTrajectory(const std::uint8_t* data, std::size_t size);
extern "C" int graphslamFuzzNpz(const std::uint8_t* data, std::size_t size);
extern "C" int graphslamFuzzScenario(const std::uint8_t* data, std::size_t size);
extern "C" int graphslamFuzzFormats(const std::uint8_t* data, std::size_t size);
extern "C" int graphslamFuzzPipe(const std::uint8_t* data, std::size_t size);

namespace {

using Harness = int (*)(const std::uint8_t*, std::size_t);

/// Runs every file of fuzz/regressions/<name>/ through `harness`; returns how many.
std::size_t replay(const std::string& name, Harness harness) {
  const std::filesystem::path dir = std::filesystem::path(GRAPHSLAM_FUZZ_REGRESSIONS_DIR) / name;
  std::size_t count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    SCOPED_TRACE(entry.path().string());
    EXPECT_EQ(harness(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), 0);
    ++count;
  }
  return count;
}

}  // namespace

TEST(Fuzz_Regressions, G2oInputsAreReadOrRefused) {
  EXPECT_GT(replay("g2o", graphslamFuzzG2o), 0u);
}

TEST(Fuzz_Regressions, TrajectoryInputsAreReadOrRefused) {
  EXPECT_GT(replay("trajectory", graphslamFuzzTrajectory), 0u);
}

TEST(Fuzz_Regressions, NpzInputsAreReadOrRefused) {
  EXPECT_GT(replay("npz", graphslamFuzzNpz), 0u);
}

TEST(Fuzz_Regressions, ScenarioInputsAreReadOrRefused) {
  EXPECT_GT(replay("scenario", graphslamFuzzScenario), 0u);
}

TEST(Fuzz_Regressions, ToroAndIsamInputsAreReadOrRefused) {
  EXPECT_GT(replay("formats", graphslamFuzzFormats), 0u);
}

TEST(Fuzz_Regressions, PipeInputsReadAsFromMemory) {
  EXPECT_GT(replay("pipe", graphslamFuzzPipe), 0u);
  // Larger than a pipe's 64 KiB and than the format detection's look at the head: the
  // reader must get every line through the pipe (the harness aborts on a difference).
  std::string big;
  for (int k = 0; k < 4000; ++k) {
    big += "VERTEX_SE2 " + std::to_string(k) + " " + std::to_string(k) + " 0 0\n";
    if (k > 0) {
      big += "EDGE_SE2 " + std::to_string(k - 1) + " " + std::to_string(k) +
             " 1 0 0 1 0 0 1 0 1\n";
    }
  }
  ASSERT_GT(big.size(), 200000u);
  EXPECT_EQ(graphslamFuzzPipe(reinterpret_cast<const std::uint8_t*>(big.data()), big.size()), 0);
}
