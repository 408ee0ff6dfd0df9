// SPDX-License-Identifier: MIT
// libFuzzer harness: the text readers of eval (TUM, KITTI, the 3xN relative-pose matrix
// with the pose graph built from it); the first byte chooses. Bad input must throw
// graphslam::InputError (or Error), never crash.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "graphslam/core/error.h"
#include "graphslam/eval/trajectory.h"
#include "graphslam/homework/pose_graph_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  try {
    switch (data[0] % 3) {
      case 0:
        (void)graphslam::eval::readTum(in, "fuzz.tum");
        break;
      case 1:
        (void)graphslam::eval::readKitti(in, "fuzz.kitti");
        break;
      default: {
        const Eigen::Matrix3Xd m = graphslam::eval::readMatrix3xN(in, "fuzz.txt");
        if (m.cols() <= 4096) (void)graphslam::homework::poseGraphFromRelativePoses(m);
      }
    }
  } catch (const graphslam::Error&) {
  }
  return 0;
}
