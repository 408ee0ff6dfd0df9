// SPDX-License-Identifier: MIT
#include "eval_plot_data.h"

#include "graphslam/support/file_util.h"

namespace graphslam::apps {

namespace {

void writeRows(const std::string& path, const io::Trajectory& t, const Eigen::Isometry3d& transform,
               const eval::UmeyamaResult& u) {
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "t,x,y,z\n";
    for (std::size_t i = 0; i < t.size(); ++i) {
      const Eigen::Vector3d p = transform * (u.scale * u.rotation * t.position(i) + u.translation);
      out << support::formatDouble(t.timestamp(i)) << ',' << support::formatDouble(p.x()) << ','
          << support::formatDouble(p.y()) << ',' << support::formatDouble(p.z()) << '\n';
    }
  });
}

}  // namespace

void writePositionsCsv(const std::string& path, const io::Trajectory& trajectory) {
  writeRows(path, trajectory, Eigen::Isometry3d::Identity(), eval::UmeyamaResult{});
}

void writeAlignedPositionsCsv(const std::string& path, const io::Trajectory& trajectory,
                              const eval::UmeyamaResult& umeyama, const Eigen::Isometry3d& origin) {
  writeRows(path, trajectory, origin, umeyama);
}

std::string unitOf(const std::string& relation_title) {
  const auto open = relation_title.rfind('('), close = relation_title.rfind(')');
  if (open == std::string::npos || close == std::string::npos || close < open) return "-";
  const std::string unit = relation_title.substr(open + 1, close - open - 1);
  return unit == "unit-less" ? "-" : unit;
}

}  // namespace graphslam::apps
