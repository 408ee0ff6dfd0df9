// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "graphslam/solvers/cost_model.h"
#include "graphslam/support/error.h"

using namespace graphslam;
using solvers::CostLine;
using solvers::CostModel;
using solvers::CostSample;

namespace {
const char* const kLines[] = {"block-llt-1", "block-llt-2", "block-llt-3",       "block-llt-6",
                              "eigen-ldlt",  "metis",       "cholmod-supernodal"};
}  // namespace

// The fit recovers the constants that made the samples, per line, with the terms a line
// does not need at zero (non-negative least squares on relative errors).
TEST(Solvers_CostModel, FitRecoversTheConstantsOfEachLine) {
  const CostLine truth{2e-4, 3e-7, 5e-10};
  std::vector<CostSample> samples;
  for (const char* line : kLines) {
    for (double n : {1e3, 1e4, 1e5}) {
      for (double flops : {1e6, 1e8, 1e10}) {
        const bool cholmod = std::string(line) == "cholmod-supernodal";
        const double seconds = cholmod ? truth.predict(n, flops) : 1e-9 * flops;
        samples.push_back({line, n, flops, seconds});
      }
    }
  }
  const CostModel model = solvers::fitCostModel(samples, "synthetic");
  EXPECT_EQ(model.source, "synthetic");
  EXPECT_NEAR(model.cholmod_supernodal.seconds, truth.seconds, 1e-9);
  EXPECT_NEAR(model.cholmod_supernodal.per_unknown, truth.per_unknown, 1e-12);
  EXPECT_NEAR(model.cholmod_supernodal.per_flop, truth.per_flop, 1e-15);
  EXPECT_NEAR(model.eigen_ldlt.per_flop, 1e-9, 1e-15);
  EXPECT_EQ(model.eigen_ldlt.seconds, 0.0);
  EXPECT_EQ(model.eigen_ldlt.per_unknown, 0.0);
  // Block sizes map to their lines: 4 to 6 share the 6x6 kernels' line.
  EXPECT_EQ(CostModel::blockClass(1), 0);
  EXPECT_EQ(CostModel::blockClass(3), 2);
  EXPECT_EQ(CostModel::blockClass(5), 3);
  samples.erase(samples.begin(), samples.begin() + 9);  // block-llt-1's
  EXPECT_THROW((void)solvers::fitCostModel(samples, "partial"), Error);
}

TEST(Solvers_CostModel, WrittenModelsReadBackAndBadFilesNameTheLine) {
  const CostModel& built_in = CostModel::builtIn();
  EXPECT_GT(built_in.cholmod_supernodal.per_flop + built_in.cholmod_supernodal.per_unknown, 0.0);
  std::ostringstream out;
  built_in.write(out);
  std::istringstream in(out.str());
  const CostModel back = CostModel::read(in, "m.txt");
  EXPECT_EQ(back.source, built_in.source);
  EXPECT_EQ(back.block_llt[2].per_flop, built_in.block_llt[2].per_flop);
  EXPECT_EQ(back.metis.per_flop, built_in.metis.per_flop);

  const std::string good = out.str();
  const std::pair<std::string, std::string> bad[] = {
      {good + "eigen-ldlt 0 0 1e-9\n", "eigen-ldlt given twice"},
      {"# x\nblock-llt-9 0 0 1\n", "m.txt:2: expected NAME SECONDS PER_UNKNOWN PER_FLOP"},
      {"eigen-ldlt 0 0 -1\n", "m.txt:1: expected"},
      {"eigen-ldlt 0 0 1 7\n", "m.txt:1: expected"},
      {"eigen-ldlt 0 0 1\n", "m.txt: expected 7 lines of constants, found 1"},
  };
  for (const auto& [text, expected] : bad) {
    std::istringstream bad_in(text);
    try {
      (void)CostModel::read(bad_in, "m.txt");
      FAIL() << "accepted:\n" << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}
