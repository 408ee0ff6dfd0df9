// SPDX-License-Identifier: MIT
// TORO's 2D and 3D text as .g2o text (text_format.h).
#include "graphslam/geometry/so3.h"
#include "line_translator.h"

namespace graphslam::io {

namespace {
using detail::Tokens;

/// |cos(pitch)| below which the Euler rates matrix is singular to rounding (gimbal lock).
constexpr double kGimbalLockCosine = 1e-9;

void vertex2(const Tokens& t, std::string& out) {
  detail::expectValues(t, 4);
  const Eigen::Vector3d pose = detail::parseValues<3>(t, 2);
  out += "VERTEX_SE2";
  detail::appendTokens(out, t, 1, 1);
  for (int k = 0; k < 3; ++k) support::appendDouble(out, pose[k]);
}

/// TORO's information order is xx xy yy tt xt yt; g2o's xx xy xt yy yt tt.
void edge2(const Tokens& t, std::string& out) {
  detail::expectValues(t, 11);
  const Eigen::Matrix<double, 9, 1> v = detail::parseValues<9>(t, 3);
  out += "EDGE_SE2";
  detail::appendTokens(out, t, 1, 2);
  for (int k : {0, 1, 2, 3, 4, 7, 5, 8, 6}) support::appendDouble(out, v[k]);
}

void appendPose3(std::string& out, const Eigen::Matrix<double, 6, 1>& p) {
  const Eigen::Quaterniond q =
      geometry::positiveScalar(quaternionFromRollPitchYaw(p[3], p[4], p[5]));
  for (int k = 0; k < 3; ++k) support::appendDouble(out, p[k]);
  for (double c : {q.x(), q.y(), q.z(), q.w()}) support::appendDouble(out, c);
}

void vertex3(const Tokens& t, std::string& out) {
  detail::expectValues(t, 7);
  out += "VERTEX_SE3:QUAT";
  detail::appendTokens(out, t, 1, 1);
  appendPose3(out, detail::parseValues<6>(t, 2));
}

void edge3(const Tokens& t, std::string& out) {
  detail::expectValues(t, 2 + 6 + 21);
  const Eigen::Matrix<double, 6, 1> pose = detail::parseValues<6>(t, 3);
  const Eigen::Matrix<double, 6, 6> info = detail::parseUpperTriangle<6>(t, 9);
  const Eigen::Quaterniond q = quaternionFromRollPitchYaw(pose[3], pose[4], pose[5]);
  if (std::abs(std::cos(pose[4])) < kGimbalLockCosine) {
    throw io::LineError{
        "EDGE3: pitch " + support::formatDouble(pose[4]) +
        " is +-90 degrees, where roll and yaw are one angle: the Euler information cannot be "
        "mapped to the quaternion error"};
  }
  out += "EDGE_SE3:QUAT";
  detail::appendTokens(out, t, 1, 2);
  appendPose3(out, pose);
  detail::appendUpperTriangle(out, toroInformation3d(q, info));
}
}  // namespace

Translation translateToro(std::string_view text, const std::string& name) {
  Translation result;
  detail::translateLines(text, name, result, [&](const Tokens& t, std::string& out) {
    if (t[0] == "VERTEX2" || t[0] == "VERTEX") {
      vertex2(t, out);
      ++result.vertices;
    } else if (t[0] == "EDGE2" || t[0] == "EDGE") {
      edge2(t, out);
      ++result.edges;
    } else if (t[0] == "VERTEX3") {
      vertex3(t, out);
      ++result.vertices;
    } else if (t[0] == "EDGE3") {
      edge3(t, out);
      ++result.edges;
    } else {
      throw io::LineError{"unknown TORO tag " + graphslam::io::quote(t[0]) +
                          " (TORO files hold VERTEX2, EDGE2, VERTEX3 and EDGE3 lines)"};
    }
  });
  return result;
}

}  // namespace graphslam::io
