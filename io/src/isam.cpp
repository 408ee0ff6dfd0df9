// SPDX-License-Identifier: MIT
// iSAM's 2D text as .g2o text (text_format.h).
#include <algorithm>
#include <limits>
#include <set>

#include "line_translator.h"

namespace graphslam::io {

namespace {
using detail::Tokens;

bool isOdometryTag(std::string_view tag) {
  return tag == "EDGE2" || tag == "ODOMETRY" || tag == "Constraint2";
}

/// The landmark id offset: 0 when no landmark id is also a pose id, else max pose id + 1.
/// Lines whose ids do not parse are skipped here (the translation reports them).
VertexId landmarkIdOffset(std::string_view text, const std::string& name) {
  std::set<long long> poses, landmarks;
  Translation scratch;
  detail::translateLines(text, name, scratch, [&](const Tokens& t, std::string&) {
    if (isOdometryTag(t[0]) && t.size() >= 3) {
      poses.insert(graphslam::io::parseId(t[1], 1, t[0]));
      poses.insert(graphslam::io::parseId(t[2], 2, t[0]));
    } else if (t[0] == "LANDMARK" && t.size() >= 3) {
      poses.insert(graphslam::io::parseId(t[1], 1, t[0]));
      landmarks.insert(graphslam::io::parseId(t[2], 2, t[0]));
    }
  });
  const bool collide = std::any_of(landmarks.begin(), landmarks.end(),
                                   [&](long long l) { return poses.count(l) > 0; });
  if (!collide || poses.empty()) return 0;
  return static_cast<VertexId>(*poses.rbegin() + 1);
}

/// iSAM's square-root information R (upper triangle, row by row) as R^T R.
template <int N>
Eigen::Matrix<double, N, N> informationFromSquareRoot(const Tokens& t, std::size_t first) {
  const Eigen::Matrix<double, N, N> sym = detail::parseUpperTriangle<N>(t, first);
  const Eigen::Matrix<double, N, N> r = sym.template triangularView<Eigen::Upper>();
  return r.transpose() * r;
}

void odometry(const Tokens& t, std::string& out) {
  detail::expectValues(t, 11);
  const Eigen::Vector3d z = detail::parseValues<3>(t, 3);
  out += "EDGE_SE2";
  detail::appendTokens(out, t, 1, 2);
  for (int k = 0; k < 3; ++k) support::appendDouble(out, z[k]);
  detail::appendUpperTriangle(out, informationFromSquareRoot<3>(t, 6));
}

void landmark(const Tokens& t, VertexId offset, std::string& out) {
  detail::expectValues(t, 7);
  const VertexId l = graphslam::io::parseId(t[2], 2, t[0], "landmark id");
  if (static_cast<long long>(l) + offset > std::numeric_limits<VertexId>::max()) {
    throw io::LineError{"LANDMARK: landmark " + std::to_string(l) + " + offset " +
                        std::to_string(offset) + " is out of the range of vertex ids"};
  }
  const Eigen::Vector2d z = detail::parseValues<2>(t, 3);
  out += "EDGE_SE2_XY";
  detail::appendTokens(out, t, 1, 1);
  out += ' ' + std::to_string(l + offset);
  for (int k = 0; k < 2; ++k) support::appendDouble(out, z[k]);
  detail::appendUpperTriangle(out, informationFromSquareRoot<2>(t, 5));
}
}  // namespace

Translation translateIsam(std::string_view text, const std::string& name) {
  Translation result;
  result.landmark_id_offset = landmarkIdOffset(text, name);
  detail::translateLines(text, name, result, [&](const Tokens& t, std::string& out) {
    if (isOdometryTag(t[0])) {
      odometry(t, out);
    } else if (t[0] == "LANDMARK") {
      landmark(t, result.landmark_id_offset, out);
    } else if (t[0] == "EDGE3") {
      throw io::LineError{
          "EDGE3 in an iSAM file (no vertex lines): iSAM's 3D lines are not supported; a TORO "
          "3D file holds VERTEX3 lines too"};
    } else {
      throw io::LineError{"unknown iSAM tag " + graphslam::io::quote(t[0]) +
                          " (iSAM 2D files hold EDGE2, ODOMETRY, Constraint2 and LANDMARK lines)"};
    }
    ++result.edges;
  });
  return result;
}

}  // namespace graphslam::io
