// SPDX-License-Identifier: MIT
// Regression on the public benchmark graphs: the optimizer must reach the best known
// chi2 (to 1e-6 relative, or lower). Skipped when the dataset folder is absent.
#include <gtest/gtest.h>

#include "../common/test_util.h"
#include "graphslam/core/io_g2o.h"
#include "graphslam/core/logging.h"
#include "graphslam/core/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;

namespace {

struct DatasetCase {
  std::string file;
  double target_chi2;  ///< best known; we must reach it within 1e-6 relative or go lower
  Optimizer::Options options;
};

Optimizer::Options defaults() {
  Optimizer::Options o;
  return o;
}

std::ostream& operator<<(std::ostream& os, const DatasetCase& c) { return os << c.file; }

class Datasets_Regression : public ::testing::TestWithParam<DatasetCase> {};

TEST_P(Datasets_Regression, ReachesBestKnownChi2) {
  const DatasetCase& c = GetParam();
  const std::string path = test::dataDir() + "/" + c.file;
  if (!test::fileExists(path)) {
    GTEST_SKIP() << "dataset " << path << " not found (set GRAPHSLAM_DATA to the datasets folder)";
  }
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  auto loaded = io::loadG2o(path, types);
  ASSERT_TRUE(loaded.ok()) << loaded.diagnostics.at(0).str();
  setLogLevel(LogLevel::kError);
  Optimizer optimizer(loaded.graph, solvers, c.options);
  const Summary s = optimizer.optimize();
  std::printf("%s: chi2 %.10g -> %.10g in %d iterations, %.3f s (%s)\n", c.file.c_str(),
              s.initial_chi2, s.final_chi2, s.iterations, s.total_time, toString(s.status));
  EXPECT_TRUE(s.succeeded()) << s.message;
  EXPECT_LE(s.final_chi2, c.target_chi2 * (1 + 1e-6));
  // And the optimum is not suspiciously low either: these are the best known values.
  EXPECT_GE(s.final_chi2, c.target_chi2 * (1 - 1e-3));
}

std::vector<DatasetCase> cases() {
  return {
      {"intel.g2o", 45.004696, defaults()},
      {"m3500.g2o", 137.912951, defaults()},
      {"city10000.g2o", 511.985164, defaults()},
      {"ais2klinik.g2o", 172.81558, defaults()},
      {"csail.g2o", 38.956286, defaults()},
      {"fr079.g2o", 37.599116, defaults()},
      {"mit.g2o", 526.331038, defaults()},
      {"dlr.g2o", 56860.35, defaults()},
      {"victoria_park.g2o", 503457.85, defaults()},
  };
}

INSTANTIATE_TEST_SUITE_P(Public, Datasets_Regression, ::testing::ValuesIn(cases()),
                         [](const auto& info) {
                           std::string s = info.param.file.substr(0, info.param.file.find('.'));
                           return s;
                         });

}  // namespace
