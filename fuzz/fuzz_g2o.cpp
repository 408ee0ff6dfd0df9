// SPDX-License-Identifier: MIT
// libFuzzer harness: the .g2o reader with every built-in type, on one thread or two, strict
// or lenient, with and without vertices created from edges (the first byte chooses). Bad
// input must come back as diagnostics, never as a crash, a leak or an exception.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "graphslam/core/type_registry.h"
#include "graphslam/diagnostics/information.h"
#include "graphslam/io/g2o.h"
#include "graphslam/types_drivebot/register.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

namespace {
const graphslam::TypeRegistry& types() {
  static const graphslam::TypeRegistry* registry = [] {
    auto* r = new graphslam::TypeRegistry;  // lives for the process, like the tool's
    graphslam::types_slam2d::registerTypes(*r);
    graphslam::types_slam3d::registerTypes(*r);
    graphslam::types_drivebot::registerTypes(*r);
    return r;
  }();
  return *registry;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t mode = data[0];
  graphslam::io::LoadOptions options;
  options.threads = (mode & 1) ? 2 : 1;
  options.strict = (mode & 2) == 0;
  options.create_missing_vertices = (mode & 4) != 0;
  options.information =
      (mode & 8) ? graphslam::InformationRepair::kNearestPd : graphslam::InformationRepair::kRefuse;
  // 7 bytes: line ends on chunk ends; 4 KiB rather than the default 4 MiB, which each run
  // would allocate and clear.
  options.chunk_bytes = (mode & 16) ? 7 : 4096;
  options.max_line_bytes = 4096;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  const auto result = graphslam::io::readG2o(in, "fuzz.g2o", types(), options);
  for (const auto& d : result.diagnostics) (void)d.str();
  return 0;
}
