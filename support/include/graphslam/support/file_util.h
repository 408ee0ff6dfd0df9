// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>

namespace graphslam::support {

/// Writes a file atomically: `write` fills a temporary file next to `path`, which is then
/// renamed over `path`. If `write` throws or the stream fails, the temporary file is
/// removed, `path` is left untouched and graphslam::Error (naming the path) is thrown.
/// A character device, a FIFO or "-" (standard output) is written in place instead
/// (isStreamOutput): renaming over a device node would replace it with a regular file.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

/// True for "-" and for an existing character device or FIFO: outputs that are streamed
/// into, never replaced.
[[nodiscard]] bool isStreamOutput(const std::string& path);

/// Shortest decimal text that reads back to exactly `value`.
[[nodiscard]] std::string formatDouble(double value);

/// Appends `separator`, then formatDouble(value), to `out` (no temporary string).
void appendDouble(std::string& out, double value, char separator = ' ');

/// The longest line the text readers (TUM, KITTI, the relative-pose matrix, DriveBot scenario
/// files) accept, in bytes: 1 MiB, thousands of times their longest legitimate line. The
/// .g2o reader's bound is io::LoadOptions::max_line_bytes.
inline constexpr std::size_t kMaxTextLineBytes = std::size_t{1} << 20;

/// What readBoundedLine found.
enum class LineRead { kLine, kEnd, kTooLong };

/// Reads the next line of `in` into `line` (without its '\n'): kLine, kEnd at the end of
/// the input, or kTooLong when the line has more than `max_bytes` bytes (then `line` holds
/// the first `max_bytes` of them and the rest is not read).
[[nodiscard]] LineRead readBoundedLine(std::istream& in, std::string& line, std::size_t max_bytes);

/// "PATH: cannot open: REASON" with the system's reason (errno after a failed open).
[[nodiscard]] std::string cannotOpenMessage(const std::string& path, int error_number);

}  // namespace graphslam::support
