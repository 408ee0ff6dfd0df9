// SPDX-License-Identifier: MIT
// libFuzzer harness: the TORO and iSAM readers (translation into .g2o text, then the .g2o
// reader with the 2D and 3D types, as the tool loads them). The first byte chooses the
// format (detected from the text, TORO or iSAM), the reader's threads and whether vertices
// are created from edges. Bad input must come back as diagnostics, never as a crash, a
// leak or an exception; a translation that succeeds must be one the .g2o reader can take
// line for line.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <string_view>

#include "graphslam/core/type_registry.h"
#include "graphslam/io/g2o.h"
#include "graphslam/io/toro_isam.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

namespace {
const graphslam::TypeRegistry& types() {
  static const graphslam::TypeRegistry* registry = [] {
    auto* r = new graphslam::TypeRegistry;  // lives for the process, like the tool's
    graphslam::types_slam2d::registerTypes(*r);
    graphslam::types_slam3d::registerTypes(*r);
    return r;
  }();
  return *registry;
}

/// Lines of `text`: its line ends, plus a last line without one.
std::size_t countLines(std::string_view text) {
  std::size_t lines = 0;
  for (char c : text) lines += c == '\n' ? 1 : 0;
  return lines + (!text.empty() && text.back() != '\n' ? 1 : 0);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace io = graphslam::io;
  if (size == 0) return 0;
  const std::uint8_t mode = data[0];
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  io::TextFormat format = io::detectTextFormat(text);
  if ((mode & 3) == 1) format = io::TextFormat::kToro;
  if ((mode & 3) == 2) format = io::TextFormat::kIsam;
  const io::Translation t = io::translate(text, "fuzz.graph", format);
  for (const auto& d : t.diagnostics) (void)d.str();
  if (!t.ok()) return 0;
  // Line for line: the .g2o reader's FILE:LINE diagnostics point into the source text.
  if (format != io::TextFormat::kG2o && countLines(t.g2o) != countLines(text)) std::abort();
  graphslam::io::LoadOptions options;
  options.threads = (mode & 4) ? 2 : 1;
  options.create_missing_vertices = format == io::TextFormat::kIsam || (mode & 8) != 0;
  options.chunk_bytes = 4096;
  options.max_line_bytes = 4096;
  std::istringstream in(t.g2o);
  const auto result = graphslam::io::readG2o(in, "fuzz.graph", types(), options);
  for (const auto& d : result.diagnostics) (void)d.str();
  return 0;
}
