// SPDX-License-Identifier: MIT
// certify on SE-Sync's public files: every one certified, at SE-Sync's certified optimum f*.
#include <gtest/gtest.h>

#include "../common/test_util.h"
#include "graphslam/certify/certify.h"
#include "graphslam/io/g2o.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

using namespace graphslam;

namespace {

struct CertifyCase {
  const char* file;
  double f_star;  ///< SE-Sync's certified optimum (MANIFEST.md, IJRR 2019 Tables 1, 2), 4 digits
  InformationRepair information;
};

class Certify_SeSync : public ::testing::TestWithParam<CertifyCase> {};

TEST_P(Certify_SeSync, CertifiesSeSyncsOptimum) {
  const CertifyCase& c = GetParam();
  const std::string path = test::dataDir() + "/" + c.file;
  if (!test::fileExists(path)) GTEST_SKIP() << path << " not found (set GRAPHSLAM_DATA)";
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  types_slam3d::registerTypes(types);
  io::LoadOptions load;
  load.information = c.information;
  load.create_missing_vertices = true;  // the edges-only *_sesync files
  auto res = io::loadG2o(path, types, load);
  ASSERT_TRUE(res.ok()) << res.diagnostics.at(0).str();
  const certify::CertificateReport report = certify::certify(res.graph);
  std::printf("%s", report.report().c_str());
  EXPECT_TRUE(report.certified) << report.reason;
  EXPECT_TRUE(report.eigensolver_converged);
  EXPECT_GE(report.lambda_min, -report.tolerance);
  EXPECT_LE(report.suboptimality, 1e-6);
  EXPECT_LE(report.dual_bound, report.objective * (1 + 1e-12));
  // f* is published to 4 significant digits.
  EXPECT_NEAR(report.objective, c.f_star, 5e-4 * c.f_star);
}

INSTANTIATE_TEST_SUITE_P(
    Public, Certify_SeSync,
    ::testing::Values(CertifyCase{"intel.g2o", 52.35, InformationRepair::kRefuse},
                      CertifyCase{"city10000.g2o", 638.6, InformationRepair::kRefuse},
                      CertifyCase{"ais2klinik.g2o", 188.5, InformationRepair::kRefuse},
                      CertifyCase{"csail_sesync.g2o", 31.70, InformationRepair::kRefuse},
                      CertifyCase{"manhattan_sesync.g2o", 6432, InformationRepair::kRefuse},
                      CertifyCase{"sphere2500.g2o", 1687, InformationRepair::kRefuse},
                      CertifyCase{"torus3d.g2o", 24230, InformationRepair::kRefuse},
                      CertifyCase{"garage.g2o", 1.263, InformationRepair::kRefuse},
                      CertifyCase{"cubicle.g2o", 717.1, InformationRepair::kIsotropic}),
    [](const auto& info) {
      std::string s = info.param.file;
      return s.substr(0, s.find('.'));
    });

}  // namespace
