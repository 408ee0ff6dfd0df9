// SPDX-License-Identifier: MIT
// Internal to graphslam (installed with io's headers, not an API for programs): the
// token-level helpers of the text readers (the .g2o line parser, the TORO and iSAM
// translators), so that every reader splits lines, quotes bad bytes and reports numbers and
// ids the same way.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "graphslam/core/vertex.h"

namespace graphslam::io {

/// A bad line: what is wrong with it (the reader adds FILE:LINE).
struct LineError {
  std::string message;
};

/// Splits `line` at white space into `tokens` (cleared first; its storage is reused).
void tokenize(std::string_view line, std::vector<std::string_view>& tokens);

/// `token` in quotes for a message: bytes that would not show (control characters,
/// non-ASCII: binary or UTF-16 input, a byte-order mark) as `\xHH`, at most 40 of them, and
/// a UTF-8 or UTF-16 byte-order mark named as such.
[[nodiscard]] std::string quote(std::string_view token);

/// The finite double `token` (value number `index` after `tag`); throws LineError naming
/// the value when it is not a number, out of range or not finite.
[[nodiscard]] double parseDouble(std::string_view token, std::size_t index, std::string_view tag);

/// An id (`what`: "vertex id" or "parameter id"; both are ints); throws LineError when
/// `token` is not an integer or out of the range of ids.
[[nodiscard]] VertexId parseId(std::string_view token, std::size_t index, std::string_view tag,
                               const char* what = "vertex id");

}  // namespace graphslam::io
