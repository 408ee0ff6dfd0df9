// SPDX-License-Identifier: MIT
// libFuzzer harness: DriveBot scenario folders. The input is split at the first two
// bytes '|' into x0.txt, wp.txt and lm.txt of a folder that loadScenario reads. Bad input
// must throw graphslam::Error, never crash.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "graphslam/drivebot/scenario.h"
#include "graphslam/support/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string dir = "/tmp/graphslam-fuzz-scenario-" + std::to_string(::getpid());
  static const bool made = std::filesystem::create_directories(dir) || true;
  (void)made;
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  for (const char* name : {"x0.txt", "wp.txt", "lm.txt"}) {
    const std::size_t bar = rest.find('|');
    const std::string_view part = rest.substr(0, bar);
    std::ofstream(dir + "/" + name, std::ios::binary | std::ios::trunc)
        .write(part.data(), static_cast<std::streamsize>(part.size()));
    rest = bar == std::string_view::npos ? std::string_view() : rest.substr(bar + 1);
  }
  try {
    (void)graphslam::drivebot::loadScenario(dir);
  } catch (const graphslam::Error&) {
  }
  return 0;
}
