// SPDX-License-Identifier: MIT
// SE-Sync's chordal objective on the public files: the certified optima of SE-Sync's paper
// reached from the default initialisation.
#include <gtest/gtest.h>

#include "../common/test_util.h"
#include "graphslam/init/chordal_objective.h"
#include "graphslam/init/chordal_se3.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/io/g2o.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/logging.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

using namespace graphslam;

namespace {

struct SeSyncCase {
  const char* file;
  double f_star;  ///< SE-Sync's certified optimum (MANIFEST.md, IJRR 2019 Tables 1, 2)
  InformationRepair information;
};

class Chordal_SeSync : public ::testing::TestWithParam<SeSyncCase> {};

TEST_P(Chordal_SeSync, ReachesTheCertifiedOptimumFromTheDefaultInitialisation) {
  const SeSyncCase& c = GetParam();
  const std::string path = test::dataDir() + "/" + c.file;
  if (!test::fileExists(path)) GTEST_SKIP() << path << " not found (set GRAPHSLAM_DATA)";
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  types_slam3d::registerTypes(types);
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  io::LoadOptions load;
  load.information = c.information;
  load.create_missing_vertices = true;  // the edges-only *_sesync files
  auto res = io::loadG2o(path, types, load);
  ASSERT_TRUE(res.ok()) << res.diagnostics.at(0).str();
  init::initializeGlobal(res.graph);
  init::initializeChordal3d(res.graph);
  support::setLogLevel(support::LogLevel::kError);
  init::ChordalObjective objective(res.graph);
  ASSERT_EQ(objective.skipped(), 0u);
  Optimizer optimizer(res.graph, solvers);
  const Summary s = optimizer.optimize();
  std::printf("%s: f %.10g (certified %.4g), %d iterations, %.3f s\n", c.file, s.final_chi2,
              c.f_star, s.iterations, s.total_time);
  EXPECT_TRUE(s.succeeded()) << s.message;
  EXPECT_NEAR(s.final_chi2, c.f_star, 1e-3 * c.f_star);
}

INSTANTIATE_TEST_SUITE_P(
    Public, Chordal_SeSync,
    ::testing::Values(SeSyncCase{"intel.g2o", 52.35, InformationRepair::kRefuse},
                      SeSyncCase{"city10000.g2o", 638.6, InformationRepair::kRefuse},
                      SeSyncCase{"ais2klinik.g2o", 188.5, InformationRepair::kRefuse},
                      SeSyncCase{"csail_sesync.g2o", 31.70, InformationRepair::kRefuse},
                      SeSyncCase{"manhattan_sesync.g2o", 6432, InformationRepair::kRefuse},
                      SeSyncCase{"sphere2500.g2o", 1687, InformationRepair::kRefuse},
                      SeSyncCase{"torus3d.g2o", 24230, InformationRepair::kRefuse},
                      SeSyncCase{"garage.g2o", 1.263, InformationRepair::kRefuse},
                      SeSyncCase{"cubicle.g2o", 717.1, InformationRepair::kIsotropic}),
    [](const auto& info) {
      std::string s = info.param.file;
      return s.substr(0, s.find('.'));
    });

}  // namespace
