// SPDX-License-Identifier: MIT
#pragma once

#include <functional>
#include <iosfwd>
#include <string>

namespace graphslam {

/// Writes a file atomically: `write` fills a temporary file next to `path`, which is then
/// renamed over `path`. If `write` throws or the stream fails, the temporary file is
/// removed, `path` is left untouched and graphslam::Error (naming the path) is thrown.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

/// Shortest decimal text that reads back to exactly `value`.
[[nodiscard]] std::string formatDouble(double value);

/// Appends `separator`, then formatDouble(value), to `out` (no temporary string).
void appendDouble(std::string& out, double value, char separator = ' ');

}  // namespace graphslam
