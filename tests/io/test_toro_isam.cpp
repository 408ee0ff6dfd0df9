// SPDX-License-Identifier: MIT
// TORO and iSAM text as .g2o text (formats/text_format.h): format detection, each tag's
// translation against hand-computed values, the Euler-to-quaternion information mapping
// against numeric derivatives, and bad lines named by line.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "graphslam/io/toro_isam.h"

namespace graphslam::io {
namespace {

std::vector<std::vector<double>> numbersOfLines(const std::string& text) {
  std::vector<std::vector<double>> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    std::vector<double> v;
    for (double x; ls >> x;) v.push_back(x);
    lines.push_back(v);
  }
  return lines;
}

std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(Io_Detect, FromTheTags) {
  EXPECT_EQ(detectTextFormat("VERTEX_SE2 0 0 0 0\n"), TextFormat::kG2o);
  EXPECT_EQ(detectTextFormat("# comment\n\nVERTEX2 0 0 0 0\nEDGE2 0 1 1 0 0 1 0 1 1 0 0\n"),
            TextFormat::kToro);
  EXPECT_EQ(detectTextFormat("VERTEX3 0 0 0 0 0 0 0\n"), TextFormat::kToro);
  EXPECT_EQ(detectTextFormat("ODOMETRY 0 1 1 0 0 1 0 0 1 0 1\n"), TextFormat::kIsam);
  EXPECT_EQ(detectTextFormat("LANDMARK 0 1 1 0 1 0 1\n"), TextFormat::kIsam);
  // EDGE2 is both formats' tag: vertex lines (even after the edges) make it TORO.
  EXPECT_EQ(detectTextFormat("EDGE2 0 1 1 0 0 1 0 0 1 0 1\n"), TextFormat::kIsam);
  EXPECT_EQ(detectTextFormat("EDGE2 0 1 1 0 0 1 0 1 1 0 0\nVERTEX2 0 0 0 0\n"), TextFormat::kToro);
  EXPECT_EQ(detectTextFormat("1 2 3\n4 5 6\n"), TextFormat::kG2o);
}

TEST(Io_Toro, TwoDimensionalTagsAndInformationOrder) {
  // TORO's information order xx xy yy tt xt yt = 1 2 3 4 5 6 becomes g2o's xx xy xt yy yt tt.
  const std::string text =
      "VERTEX2 7 1.5 -2 0.25\n"
      "# a comment line stays a line\n"
      "EDGE2 7 8 1 0 0.5  1 2 3 4 5 6\n";
  const Translation t = translateToro(text, "t.graph");
  ASSERT_TRUE(t.ok()) << t.diagnostics.front().str();
  const auto lines = linesOf(t.g2o);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "VERTEX_SE2 7 1.5 -2 0.25");
  EXPECT_EQ(lines[1], "");
  EXPECT_EQ(lines[2], "EDGE_SE2 7 8 1 0 0.5 1 2 5 3 6 4");
  EXPECT_EQ(t.vertices, 1u);
  EXPECT_EQ(t.edges, 1u);
}

TEST(Io_Toro, VertexThreeFromRollPitchYaw) {
  // Yaw 90 degrees: q = (0, 0, sin 45, cos 45).
  const Translation t = translateToro("VERTEX3 3 1 2 3 0 0 1.5707963267948966\n", "t.graph");
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(linesOf(t.g2o)[0].rfind("VERTEX_SE3:QUAT 3 1 2 3 ", 0), 0u) << t.g2o;
  const auto v = numbersOfLines(t.g2o)[0];
  ASSERT_EQ(v.size(), 8u);
  EXPECT_NEAR(v[4], 0.0, 1e-15);
  EXPECT_NEAR(v[5], 0.0, 1e-15);
  EXPECT_NEAR(v[6], std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(v[7], std::sqrt(0.5), 1e-15);
  // R = Rz(yaw) Ry(pitch) Rx(roll), checked on the x axis for roll 0.3, pitch 0.2, yaw 0.1.
  const Eigen::Quaterniond q = quaternionFromRollPitchYaw(0.3, 0.2, 0.1);
  const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(x.x(), std::cos(0.1) * std::cos(0.2), 1e-15);
  EXPECT_NEAR(x.y(), std::sin(0.1) * std::cos(0.2), 1e-15);
  EXPECT_NEAR(x.z(), -std::sin(0.2), 1e-15);
}

/// Euler angles (roll, pitch, yaw) of the compact quaternion v (q_w = sqrt(1 - |v|^2)).
Eigen::Vector3d eulerOfCompact(const Eigen::Vector3d& v) {
  const Eigen::Quaterniond q(std::sqrt(1.0 - v.squaredNorm()), v.x(), v.y(), v.z());
  const Eigen::Matrix3d r = q.toRotationMatrix();
  return {std::atan2(r(2, 1), r(2, 2)), std::asin(-r(2, 0)), std::atan2(r(1, 0), r(0, 0))};
}

TEST(Io_Toro, EulerJacobianMatchesNumericDerivative) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-1.2, 1.2);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Quaterniond q = quaternionFromRollPitchYaw(angle(rng), angle(rng), angle(rng));
    const Eigen::Quaterniond qp = q.w() < 0 ? Eigen::Quaterniond(-q.coeffs()) : q;
    const Eigen::Matrix<double, 6, 6> j = eulerFromCompactQuaternionJacobian(q);
    EXPECT_TRUE((j.topLeftCorner<3, 3>().isIdentity(0.0)));
    EXPECT_TRUE((j.topRightCorner<3, 3>().isZero(0.0)));
    EXPECT_TRUE((j.bottomLeftCorner<3, 3>().isZero(0.0)));
    constexpr double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d a = qp.vec(), b = qp.vec();
      a[k] -= h;
      b[k] += h;
      const Eigen::Vector3d numeric = (eulerOfCompact(b) - eulerOfCompact(a)) / (2 * h);
      EXPECT_LT((j.block<3, 1>(3, 3 + k) - numeric).norm(), 1e-7 * (1 + numeric.norm()))
          << "trial " << trial << " column " << k << "\n"
          << j.bottomRightCorner<3, 3>() << "\nnumeric " << numeric.transpose();
    }
  }
}

TEST(Io_Toro, InformationAtTheIdentityWeighsTheHalfAngle) {
  // At the identity, Euler angles are the rotation vector, which is twice the compact
  // quaternion: the rotation block's information is 4 times TORO's, translation unchanged.
  Eigen::Matrix<double, 6, 6> info = Eigen::Matrix<double, 6, 6>::Identity();
  info(0, 3) = info(3, 0) = 0.5;
  const Eigen::Matrix<double, 6, 6> g = toroInformation3d(Eigen::Quaterniond::Identity(), info);
  Eigen::Matrix<double, 6, 6> expected = info;
  expected.bottomRightCorner<3, 3>() *= 4.0;
  expected(0, 3) = expected(3, 0) = 1.0;
  EXPECT_TRUE(g.isApprox(expected, 1e-14)) << g;
}

TEST(Io_Toro, EdgeThreeTranslated) {
  std::string line = "EDGE3 0 1 1 2 3 0 0 0";
  for (int r = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c) line += r == c ? " 10" : " 0";
  }
  const Translation t = translateToro(line + "\n", "t.graph");
  ASSERT_TRUE(t.ok()) << t.diagnostics.front().str();
  EXPECT_EQ(linesOf(t.g2o)[0].rfind("EDGE_SE3:QUAT 0 1 1 2 3 0 0 0 1 10 0 0 0 0 0 10", 0), 0u)
      << t.g2o;
  const auto v = numbersOfLines(t.g2o)[0];
  ASSERT_EQ(v.size(), 2u + 7u + 21u);
  EXPECT_DOUBLE_EQ(v[9 + 15], 40.0);  // first rotation diagonal entry (row 3 of the triangle)
  EXPECT_DOUBLE_EQ(v.back(), 40.0);
}

TEST(Io_Toro, BadLinesAreNamedByLine) {
  const Translation t = translateToro(
      "VERTEX2 0 0 0 0\nVERTEX2 1 x 0 0\nEDGE2 0 1 1 0 0 1 0 1\nPOINT 3\n", "bad.graph");
  ASSERT_EQ(t.diagnostics.size(), 3u);
  EXPECT_EQ(t.diagnostics[0].str(), "bad.graph:2: VERTEX2: value 2 'x' is not a number");
  EXPECT_EQ(t.diagnostics[1].str(), "bad.graph:3: EDGE2 expects 11 values after the tag, found 8");
  EXPECT_EQ(t.diagnostics[2].str(),
            "bad.graph:4: unknown TORO tag 'POINT' (TORO files hold VERTEX2, EDGE2, VERTEX3 and "
            "EDGE3 lines)");
  EXPECT_EQ(linesOf(t.g2o).size(), 4u);  // line for line, bad lines blank
}

TEST(Io_Toro, GimbalLockIsRefused) {
  std::string line = "EDGE3 0 1 0 0 0 0 1.5707963267948966 0";
  for (int r = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c) line += r == c ? " 1" : " 0";
  }
  const Translation t = translateToro(line + "\n", "g.graph");
  ASSERT_EQ(t.diagnostics.size(), 1u);
  EXPECT_NE(t.diagnostics[0].message.find("+-90 degrees"), std::string::npos);
}

TEST(Io_Isam, SquareRootInformationAndLandmarks) {
  // R = [2 1 0; 0 3 0; 0 0 4] -> R^T R = [4 2 0; 2 10 0; 0 0 16]; landmark R = [2 1; 0 1]
  // -> [4 2; 2 2]. Landmark 1 collides with pose 1: landmarks move past the last pose (2).
  const std::string text =
      "ODOMETRY 0 1 1 0 0  2 1 0 3 0 4\n"
      "EDGE2 1 2 1 0 0  2 1 0 3 0 4\n"
      "LANDMARK 2 1 0.5 -0.5  2 1 1\n";
  const Translation t = translateIsam(text, "i.txt");
  ASSERT_TRUE(t.ok()) << t.diagnostics.front().str();
  EXPECT_EQ(t.landmark_id_offset, 3);
  const auto lines = linesOf(t.g2o);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "EDGE_SE2 0 1 1 0 0 4 2 0 10 0 16");
  EXPECT_EQ(lines[1], "EDGE_SE2 1 2 1 0 0 4 2 0 10 0 16");
  EXPECT_EQ(lines[2], "EDGE_SE2_XY 2 4 0.5 -0.5 4 2 2");
  EXPECT_EQ(t.edges, 3u);
  // Ids that do not collide are kept (iSAM files whose poses and landmarks share a counter).
  const Translation shared =
      translateIsam("ODOMETRY 0 1 1 0 0 1 0 0 1 0 1\nLANDMARK 1 5 1 1 1 0 1\n", "s.txt");
  ASSERT_TRUE(shared.ok());
  EXPECT_EQ(shared.landmark_id_offset, 0);
  EXPECT_EQ(linesOf(shared.g2o)[1], "EDGE_SE2_XY 1 5 1 1 1 0 1");
}

TEST(Io_Isam, ThreeDimensionalAndUnknownLinesAreRefused) {
  const Translation t =
      translateIsam("ODOMETRY 0 1 1 0 0 1 0 0 1 0 1\nEDGE3 0 1\nFOO 1\n", "i.txt");
  ASSERT_EQ(t.diagnostics.size(), 2u);
  EXPECT_EQ(t.diagnostics[0].line, 2);
  EXPECT_NE(t.diagnostics[0].message.find("iSAM's 3D lines are not supported"), std::string::npos);
  EXPECT_EQ(t.diagnostics[1].str(),
            "i.txt:3: unknown iSAM tag 'FOO' (iSAM 2D files hold EDGE2, ODOMETRY, Constraint2 "
            "and LANDMARK lines)");
}

}  // namespace
}  // namespace graphslam::io
