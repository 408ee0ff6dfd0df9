// SPDX-License-Identifier: MIT
#include "graphslam/io/text_tokens.h"

#include <charconv>
#include <cmath>
#include <limits>

namespace graphslam::io {

namespace {
/// The C locale's white space (std::isspace without the locale lookup per character).
constexpr bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}
}  // namespace

void tokenize(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    if (i >= line.size()) break;
    std::size_t j = i;
    while (j < line.size() && !isSpace(line[j])) ++j;
    tokens.push_back(line.substr(i, j - i));
    i = j;
  }
}

/// `token` in quotes for a message: bytes that would not show (control characters,
/// non-ASCII: binary or UTF-16 input, a byte-order mark) as \xHH, and at most
/// kQuotedBytes of it.
std::string quote(std::string_view token) {
  constexpr std::size_t kQuotedBytes = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kQuotedBytes; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      constexpr char kHex[] = "0123456789ABCDEF";
      out += {'\\', 'x', kHex[c >> 4], kHex[c & 15]};
    }
  }
  out += token.size() > kQuotedBytes ? "'..." : "'";
  if (token.substr(0, 3) == "\xEF\xBB\xBF") {
    out += " (a UTF-8 byte-order mark: save the file without one)";
  } else if (token.substr(0, 2) == "\xFF\xFE" || token.substr(0, 2) == "\xFE\xFF") {
    out += " (a UTF-16 byte-order mark: save the file as UTF-8 text)";
  }
  return out;
}

double parseDouble(std::string_view token, std::size_t index, std::string_view tag) {
  std::string_view t = token;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  double value = 0.0;
  auto res = std::from_chars(t.data(), t.data() + t.size(), value);
  if (res.ec == std::errc::result_out_of_range && res.ptr == t.data() + t.size()) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is out of the range of a double"};
  }
  if (res.ec != std::errc() || res.ptr != t.data() + t.size()) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is not a number"};
  }
  if (!std::isfinite(value)) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is not finite"};
  }
  return value;
}

/// An id (`what`: "vertex id" or "parameter id"; both are ints).
VertexId parseId(std::string_view token, std::size_t index, std::string_view tag,
                 const char* what) {
  long long value = 0;
  auto res = std::from_chars(token.data(), token.data() + token.size(), value);
  const bool whole = res.ptr == token.data() + token.size();
  if (whole && (res.ec == std::errc::result_out_of_range ||
                (res.ec == std::errc() && (value < std::numeric_limits<VertexId>::min() ||
                                           value > std::numeric_limits<VertexId>::max())))) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is out of the range of " + what + "s (" +
                    std::to_string(std::numeric_limits<VertexId>::min()) + " to " +
                    std::to_string(std::numeric_limits<VertexId>::max()) + ")"};
  }
  if (res.ec != std::errc() || !whole) {
    throw LineError{std::string(tag) + ": value " + std::to_string(index) + " " + quote(token) +
                    " is not a " + what + " (an integer)"};
  }
  return static_cast<VertexId>(value);
}

}  // namespace graphslam::io
