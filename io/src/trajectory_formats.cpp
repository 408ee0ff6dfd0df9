// SPDX-License-Identifier: MIT
// The trajectory formats of the io module: TUM and KITTI, each one registry entry.
#include "graph_formats.h"
#include "graphslam/io/register.h"
#include "graphslam/io/trajectory.h"

namespace graphslam::io {

void registerTrajectoryFormats(FormatRegistry& formats) {
  Format<Trajectory> tum;
  tum.name = "tum";
  tum.description = "TUM RGB-D: timestamp x y z qx qy qz qw per line";
  tum.extensions = {".tum", ".txt"};
  tum.read = [](Source& source, const ReadContext&) {
    return readTum(source.stream(), source.name());
  };
  tum.write = [](const Trajectory& t, std::ostream& out, const WriteContext&) { writeTum(out, t); };
  formats.add(std::move(tum));

  Format<Trajectory> kitti;
  kitti.name = "kitti";
  kitti.description = "KITTI odometry: the 3x4 pose matrix row by row per line, no timestamps";
  kitti.extensions = {".kitti"};
  kitti.read = [](Source& source, const ReadContext&) {
    return readKitti(source.stream(), source.name());
  };
  kitti.write = [](const Trajectory& t, std::ostream& out, const WriteContext&) {
    writeKitti(out, t);
  };
  formats.add(std::move(kitti));
}

void registerFormats(FormatRegistry& formats) {
  registerGraphFormats(formats);
  registerTrajectoryFormats(formats);
}

}  // namespace graphslam::io
