// SPDX-License-Identifier: MIT
#include "graphslam/io/toro_isam.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "graphslam/geometry/so3.h"
#include "graphslam/support/error.h"
#include "line_translator.h"

namespace graphslam::io {

const char* toString(TextFormat format) {
  switch (format) {
    case TextFormat::kToro:
      return "toro";
    case TextFormat::kIsam:
      return "isam";
    case TextFormat::kG2o:
      break;
  }
  return "g2o";
}

const char* displayName(TextFormat format) {
  switch (format) {
    case TextFormat::kToro:
      return "TORO";
    case TextFormat::kIsam:
      return "iSAM";
    case TextFormat::kG2o:
      break;
  }
  return ".g2o";
}

namespace {
bool isVertexTag(std::string_view tag) {
  return tag == "VERTEX2" || tag == "VERTEX3" || tag == "VERTEX";
}

/// The first token of every non-comment line, in order, until `stop` returns true.
template <typename F>
void forEachTag(std::string_view text, F&& stop) {
  detail::forEachLine(
      text, [&](int, const detail::Tokens& tokens) { return tokens.empty() || !stop(tokens[0]); });
}
}  // namespace

TextFormat detectTextFormat(std::string_view text) {
  std::string_view first;
  forEachTag(text, [&](std::string_view tag) {
    first = tag;
    return true;
  });
  if (isVertexTag(first)) return TextFormat::kToro;
  if (first == "ODOMETRY" || first == "LANDMARK" || first == "Constraint2")
    return TextFormat::kIsam;
  if (first != "EDGE2" && first != "EDGE3" && first != "EDGE") return TextFormat::kG2o;
  bool has_vertices = false;
  forEachTag(text, [&](std::string_view tag) { return has_vertices = isVertexTag(tag); });
  return has_vertices ? TextFormat::kToro : TextFormat::kIsam;
}

TextFormat detectFileFormat(const std::string& path) {
  // The first tag is in the first lines; a file of comments longer than this is read whole.
  constexpr std::size_t kPrefixBytes = 1 << 16;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open: " + std::strerror(errno));
  std::string prefix(kPrefixBytes, '\0');
  in.read(prefix.data(), static_cast<std::streamsize>(prefix.size()));
  prefix.resize(static_cast<std::size_t>(in.gcount()));
  const TextFormat guess = detectTextFormat(prefix);
  if (in.eof() || guess == TextFormat::kToro) return guess;  // read whole, or settled by a vertex
  std::string_view first;
  forEachTag(prefix, [&](std::string_view tag) {
    first = tag;
    return true;
  });
  // No tag yet (a long comment), or EDGE2/EDGE3 whose vertex lines may come later.
  const bool open = first.empty() || first == "EDGE2" || first == "EDGE3" || first == "EDGE";
  return open ? detectTextFormat(readText(path)) : guess;
}

Translation translate(std::string_view text, const std::string& name, TextFormat format) {
  switch (format) {
    case TextFormat::kToro:
      return translateToro(text, name);
    case TextFormat::kIsam:
      return translateIsam(text, name);
    case TextFormat::kG2o:
      break;
  }
  Translation t;
  t.g2o = std::string(text);
  return t;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(path + ": read error: " + std::strerror(errno));
  return std::move(text).str();
}

Eigen::Quaterniond quaternionFromRollPitchYaw(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

Eigen::Matrix<double, 6, 6> eulerFromCompactQuaternionJacobian(const Eigen::Quaterniond& q_in) {
  const Eigen::Quaterniond q = geometry::positiveScalar(q_in.normalized());
  const double w = q.w();
  const Eigen::Vector3d v = q.vec();
  // A change dv of the compact quaternion (w follows from |q| = 1) rotates by
  // R(q + dq) = R(q) Exp(omega), omega = 2 (w I + v v^T / w - [v]x) dv.
  const Eigen::Matrix3d d_omega =
      2.0 * (w * Eigen::Matrix3d::Identity() + v * v.transpose() / w - geometry::hat(v));
  // Body rates of R = Rz(yaw) Ry(pitch) Rx(roll): omega = E d(roll pitch yaw).
  const Eigen::Matrix3d r = q.toRotationMatrix();
  const double roll = std::atan2(r(2, 1), r(2, 2));
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  const double sr = std::sin(roll), cr = std::cos(roll);
  const double sp = std::sin(pitch), cp = std::cos(pitch);
  Eigen::Matrix3d e;
  e << 1.0, 0.0, -sp, 0.0, cr, sr * cp, 0.0, -sr, cr * cp;
  Eigen::Matrix<double, 6, 6> j = Eigen::Matrix<double, 6, 6>::Zero();
  j.topLeftCorner<3, 3>().setIdentity();
  j.bottomRightCorner<3, 3>() = e.inverse() * d_omega;
  return j;
}

Eigen::Matrix<double, 6, 6> toroInformation3d(const Eigen::Quaterniond& measurement,
                                              const Eigen::Matrix<double, 6, 6>& information) {
  const Eigen::Matrix<double, 6, 6> j = eulerFromCompactQuaternionJacobian(measurement);
  return j.transpose() * information * j;
}

}  // namespace graphslam::io
