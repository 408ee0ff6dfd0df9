// SPDX-License-Identifier: MIT
// libFuzzer harness: the .npy parser on the bytes (first byte even), or the whole CMU
// homework .npz reader (archive, arrays, graph) on them written to a file (first byte
// odd). Bad input must throw graphslam::Error, never crash.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "graphslam/io/coursework_npz.h"
#include "graphslam/io/npz.h"
#include "graphslam/support/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  try {
    if ((data[0] & 1) == 0) {
      (void)graphslam::io::parseNpy(data + 1, size - 1, "fuzz.npy");
      return 0;
    }
    static const std::string path = "/tmp/graphslam-fuzz-" + std::to_string(::getpid()) + ".npz";
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
    graphslam::io::CourseworkNpzOptions options;
    options.model = (data[0] & 2) ? graphslam::io::PointObservationModel::kLinear
                                  : graphslam::io::PointObservationModel::kAuto;
    (void)graphslam::io::loadCourseworkNpz(path, options);
  } catch (const graphslam::Error&) {
  }
  return 0;
}
