// SPDX-License-Identifier: MIT
// libFuzzer harness: the text readers of eval (TUM, KITTI, the 3xN relative-pose matrix
// with the pose graph built from it); the first byte chooses. Bad input must throw
// graphslam::InputError (or Error), never crash.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "graphslam/io/relative_poses.h"
#include "graphslam/io/trajectory.h"
#include "graphslam/support/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  try {
    switch (data[0] % 3) {
      case 0:
        (void)graphslam::io::readTum(in, "fuzz.tum");
        break;
      case 1:
        (void)graphslam::io::readKitti(in, "fuzz.kitti");
        break;
      default: {
        const Eigen::Matrix3Xd m = graphslam::io::readMatrix3xN(in, "fuzz.txt");
        if (m.cols() <= 4096) (void)graphslam::io::poseGraphFromRelativePoses(m);
      }
    }
  } catch (const graphslam::Error&) {
  }
  return 0;
}
