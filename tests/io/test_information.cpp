// SPDX-License-Identifier: MIT
// Information matrices that are not positive definite: refused with a count, or repaired.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <sstream>

#include "graphslam/io/g2o.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;

namespace {

/// Six edges; lines 4, 5 and 7 have indefinite information (an xy entry of 5 > sqrt(1 * 1)).
const char* kFile =
    "VERTEX_SE2 0 0 0 0\n"
    "VERTEX_SE2 1 1 0 0\n"
    "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
    "EDGE_SE2 0 1 1 0 0 1 5 0 1 0 1\n"
    "EDGE_SE2 0 1 1 0 0 1 5 0 1 0 1\n"
    "EDGE_SE2 0 1 1 0 0 4 0 0 9 0 2\n"
    "EDGE_SE2 0 1 1 0 0 -1 0 0 1 0 1\n"
    "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n";

io::LoadResult read(InformationRepair how) {
  TypeRegistry types;
  types_slam2d::registerTypes(types);
  io::LoadOptions options;
  options.information = how;
  std::istringstream in(kFile);
  return io::readG2o(in, "f.g2o", types, options);
}

TEST(Io_Information, RefusedMatricesAreAllCountedAndListed) {
  const auto res = read(InformationRepair::kRefuse);
  ASSERT_FALSE(res.ok());
  EXPECT_EQ(res.refused_information, 3u);
  ASSERT_EQ(res.diagnostics.size(), 4u);
  EXPECT_EQ(res.diagnostics[0].str(),
            "f.g2o:4: EDGE_SE2: information matrix is not positive definite");
  EXPECT_EQ(res.diagnostics[2].line, 7);
  EXPECT_EQ(res.diagnostics[3].str(),
            "f.g2o: 3 of 6 edges have an information matrix that is not positive definite; "
            "--information nearest-pd or --information isotropic repairs them");
}

TEST(Io_Information, RepairsGivePositiveDefiniteMatricesAndCountThem) {
  for (InformationRepair how : {InformationRepair::kNearestPd, InformationRepair::kIsotropic}) {
    const auto res = read(how);
    ASSERT_TRUE(res.ok()) << res.diagnostics[0].str();
    EXPECT_EQ(res.repaired_information, 3u);
    ASSERT_EQ(res.graph.numEdges(), 6u);
    for (const auto& e : res.graph.edges()) {
      const Eigen::Map<const Eigen::Matrix3d> omega(e->informationData());
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(omega).eigenvalues().minCoeff(),
                0.0);
    }
    // A positive definite matrix is kept as it is.
    const Eigen::Map<const Eigen::Matrix3d> kept(res.graph.edges()[3]->informationData());
    EXPECT_EQ(kept(0, 0), 4.0);
    EXPECT_EQ(kept(1, 1), 9.0);
  }
}

TEST(Io_Information, IsotropicWeightsAreTheBlocksInverseTraces) {
  // Translation block diag(1, 4) with a coupling: 2 / tr(B^-1); rotation block: its value.
  Eigen::MatrixXd omega(3, 3);
  omega << 1, 0, 7, 0, 4, 0, 7, 0, 2;
  ASSERT_TRUE(repairInformation(omega, InformationRepair::kIsotropic));
  EXPECT_DOUBLE_EQ(omega(0, 0), 2.0 / (1.0 + 0.25));
  EXPECT_DOUBLE_EQ(omega(1, 1), omega(0, 0));
  EXPECT_DOUBLE_EQ(omega(2, 2), 2.0);
  EXPECT_EQ(omega(0, 2), 0.0);
  // Nearest PD: the negative eigenvalue is raised to the floor, the others kept.
  Eigen::MatrixXd m(2, 2);
  m << 1, 3, 3, 1;  // eigenvalues 4 and -2
  ASSERT_TRUE(repairInformation(m, InformationRepair::kNearestPd, 1e-3));
  const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m).eigenvalues();
  EXPECT_NEAR(ev[0], 4e-3, 1e-12);
  EXPECT_NEAR(ev[1], 4.0, 1e-12);
}

}  // namespace
