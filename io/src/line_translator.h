// SPDX-License-Identifier: MIT
// Private to graphslam::formats: the line loop shared by the TORO and iSAM translators.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "graphslam/io/text_tokens.h"
#include "graphslam/io/toro_isam.h"
#include "graphslam/support/file_util.h"

namespace graphslam::io::detail {

using graphslam::io::LineError;
using Tokens = std::vector<std::string_view>;

/// Calls `f(line_number, tokens)` for each line of `text` (1-based; a `#` comment cut off,
/// so a blank or comment line has no tokens) until `f` returns false.
template <typename F>
void forEachLine(std::string_view text, F&& f) {
  Tokens tokens;
  int line_no = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    graphslam::io::tokenize(line, tokens);
    if (!f(++line_no, tokens)) return;
  }
}

/// For each line of `text`: a blank line stays blank; otherwise `translateLine(tokens, out)`
/// appends its .g2o translation to `out` (without the line end). A LineError becomes a
/// diagnostic `name:LINE: message` and a blank line, so the output keeps one line per input
/// line.
template <typename F>
void translateLines(std::string_view text, const std::string& name, Translation& result,
                    F&& translateLine) {
  std::string line_out;
  forEachLine(text, [&](int line_no, const Tokens& tokens) {
    line_out.clear();
    if (!tokens.empty()) {
      try {
        translateLine(tokens, line_out);
      } catch (const LineError& err) {
        result.diagnostics.push_back(io::Diagnostic{name, line_no, err.message});
        line_out.clear();
      }
    }
    result.g2o += line_out;
    result.g2o += '\n';
    return true;
  });
}

/// Throws LineError unless `tokens` holds the tag and exactly `count` values.
inline void expectValues(const Tokens& tokens, std::size_t count) {
  if (tokens.size() != count + 1) {
    throw LineError{std::string(tokens[0]) + " expects " + std::to_string(count) +
                    " values after the tag, found " + std::to_string(tokens.size() - 1)};
  }
}

/// Values first..first+n-1 of the line (1-based value numbers in messages) as doubles.
template <int N>
Eigen::Matrix<double, N, 1> parseValues(const Tokens& tokens, std::size_t first) {
  Eigen::Matrix<double, N, 1> v;
  for (int k = 0; k < N; ++k) {
    const std::size_t index = first + static_cast<std::size_t>(k);
    v[k] = graphslam::io::parseDouble(tokens[index], index, tokens[0]);
  }
  return v;
}

/// The upper triangle of a symmetric n x n matrix, row by row, from values first...
template <int N>
Eigen::Matrix<double, N, N> parseUpperTriangle(const Tokens& tokens, std::size_t first) {
  Eigen::Matrix<double, N, N> m;
  std::size_t index = first;
  for (int r = 0; r < N; ++r) {
    for (int c = r; c < N; ++c, ++index) {
      m(r, c) = m(c, r) = graphslam::io::parseDouble(tokens[index], index, tokens[0]);
    }
  }
  return m;
}

/// Appends the upper triangle of `m`, row by row (.g2o's information layout).
template <typename Derived>
void appendUpperTriangle(std::string& out, const Eigen::MatrixBase<Derived>& m) {
  for (int r = 0; r < m.rows(); ++r) {
    for (int c = r; c < m.cols(); ++c) support::appendDouble(out, m(r, c));
  }
}

/// Appends the vertex id tokens as they are (the .g2o reader checks them).
inline void appendTokens(std::string& out, const Tokens& tokens, std::size_t first,
                         std::size_t count) {
  for (std::size_t k = first; k < first + count; ++k) {
    out += ' ';
    out += tokens[k];
  }
}

}  // namespace graphslam::io::detail
