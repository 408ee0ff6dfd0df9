// SPDX-License-Identifier: MIT
#include "g2o_parse.h"

#include <charconv>
#include <cmath>
#include <limits>

#include "graphslam/diagnostics/information.h"
#include "graphslam/io/text_tokens.h"
#include "graphslam/support/error.h"

namespace graphslam::io::detail {

namespace {

/// Runs `set` (a setParameterData call); the message when the type refuses the value,
/// else empty.
template <typename F>
std::string refusal(const std::string& tag, F&& set) {
  try {
    set();
  } catch (const Error& err) {
    return tag + ": " + err.what();
  }
  return {};
}

std::string countMessage(const std::string& tag, std::size_t expected, std::size_t found) {
  return tag + " expects " + std::to_string(expected) + " numbers after the tag, found " +
         std::to_string(found);
}

}  // namespace

void LineParser::parse(Chunk& chunk) {
  chunk.lines.clear();
  const std::string_view text(chunk.text);
  int line_no = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view view = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (view.size() > options_.max_line_bytes) {
      ParsedLine& out = chunk.lines.emplace_back();
      out.line = line_no;
      out.bad = out.fatal = true;
      out.error = "the line is longer than " + std::to_string(options_.max_line_bytes) +
                  " bytes: not a .g2o line";
      break;
    }
    if (auto hash = view.find('#'); hash != std::string_view::npos) view = view.substr(0, hash);
    tokenize(view, tokens_);
    if (tokens_.empty()) continue;
    ParsedLine& out = chunk.lines.emplace_back();
    out.line = line_no;
    try {
      parseLine(tokens_, out);
    } catch (const LineError& err) {
      out = ParsedLine{};
      out.line = line_no;
      out.bad = true;
      out.error = err.message;
    }
  }
  chunk.line_count = line_no;
}

void LineParser::parseLine(const std::vector<std::string_view>& tokens, ParsedLine& out) {
  const std::string tag(tokens[0]);
  if (tag == "FIX") {
    if (tokens.size() < 2) throw LineError{"FIX expects at least one vertex id"};
    for (std::size_t i = 1; i < tokens.size(); ++i) out.fix.push_back(parseId(tokens[i], i, tag));
    return;
  }
  const TypeRegistry::Entry* entry = types_.find(tag);
  if (!entry) {
    throw LineError{"unknown tag " + quote(tag) +
                    " (graphslam list-types shows the known ones; --plugin loads more)"};
  }
  const std::size_t found = tokens.size() - 1;
  if (entry->kind == TypeRegistry::Kind::kParameter) {
    auto p = entry->make_parameter();
    const std::size_t expected = 1 + static_cast<std::size_t>(p->dataDimension());
    if (found != expected) throw LineError{countMessage(tag, expected, found)};
    p->setId(parseId(tokens[1], 1, tag, "parameter id"));
    values_.resize(expected - 1);
    for (std::size_t i = 0; i + 1 < expected; ++i)
      values_[i] = parseDouble(tokens[i + 2], i + 2, tag);
    out.error = refusal(tag, [&] { p->setData(values_.data()); });
    out.parameter = std::move(p);
    out.tag = &entry->tag;
    return;
  }
  if (entry->kind == TypeRegistry::Kind::kVertex) {
    auto v = entry->make_vertex();
    const std::size_t est = static_cast<std::size_t>(v->estimateDataDimension());
    const std::size_t expected = 1 + est + static_cast<std::size_t>(v->parameterDataDimension());
    if (found != expected) throw LineError{countMessage(tag, expected, found)};
    const VertexId id = parseId(tokens[1], 1, tag);
    values_.resize(expected - 1);
    for (std::size_t i = 0; i + 1 < expected; ++i)
      values_[i] = parseDouble(tokens[i + 2], i + 2, tag);
    v->setId(id);
    // Reported after the duplicate-id check (at commit), as a serial reader would.
    out.error = refusal(tag, [&] { v->setEstimateData(values_.data()); });
    if (out.error.empty()) {
      out.error = refusal(tag, [&] { v->setParameterData(values_.data() + est); });
    }
    out.vertex = std::move(v);
    out.tag = &entry->tag;
    return;
  }
  parseEdge(tokens, *entry, out);
}

void LineParser::parseEdge(const std::vector<std::string_view>& tokens,
                           const TypeRegistry::Entry& entry, ParsedLine& out) {
  const std::string& tag = entry.tag;
  auto e = entry.make_edge();
  const std::size_t found = tokens.size() - 1;
  // In the separated layout the ids come first: they size the edge.
  const bool separated = e->arity() < 0 && e->separatedCount(0) >= 0;
  const std::size_t first = separated ? readSeparatedIds(tokens, tag, *e) : 1;
  const int d = e->dimension();
  const std::size_t meas = static_cast<std::size_t>(e->measurementDataDimension()) +
                           static_cast<std::size_t>(e->parameterDataDimension());
  const std::size_t info = static_cast<std::size_t>(d * (d + 1) / 2);
  // Parameter ids follow the vertex ids (g2o's layout).
  const std::size_t num_params = static_cast<std::size_t>(e->numParameters());
  const std::size_t rest = num_params + meas + info;
  std::size_t num_ids = 0;
  if (separated) {
    if (found != first - 1 + rest) throw LineError{countMessage(tag, first - 1 + rest, found)};
  } else if (e->arity() > 0) {
    num_ids = static_cast<std::size_t>(e->arity());
    if (found != num_ids + rest) throw LineError{countMessage(tag, num_ids + rest, found)};
  } else {
    if (found < 1 + rest) {
      throw LineError{tag + " expects at least " + std::to_string(1 + rest) +
                      " numbers after the tag (vertex ids, " +
                      (num_params ? std::to_string(num_params) + " parameter ids, " : "") +
                      std::to_string(meas) + " measurement and parameter values, " +
                      std::to_string(info) + " information values), found " +
                      std::to_string(found)};
    }
    num_ids = found - rest;
  }
  if (!separated) setVertexIds(*e, tokens, num_ids, tag);
  const std::size_t first_param = separated ? first : 1 + num_ids;
  for (std::size_t i = 0; i < num_params; ++i) {
    const std::size_t at = first_param + i;
    e->setParameterId(i, parseId(tokens[at], at, tag, "parameter id"));
  }
  values_.resize(meas + info);
  const std::size_t first_value = first_param + num_params;
  for (std::size_t i = 0; i < meas + info; ++i) {
    values_[i] = parseDouble(tokens[first_value + i], first_value + i, tag);
  }
  Eigen::MatrixXd& omega = omega_;  // storage reused from line to line
  omega.resize(d, d);
  std::size_t k = meas;
  for (int r = 0; r < d; ++r) {
    for (int c = r; c < d; ++c) {
      omega(r, c) = values_[k];
      omega(c, r) = values_[k];
      ++k;
    }
  }
  // Checked after the edge's vertices are known to be defined (at commit), in this
  // order: the information matrix, then the parameters.
  if (llt_.compute(omega).info() != Eigen::Success) {
    out.repaired = repairInformation(omega, options_.information, options_.nearest_pd_floor) &&
                   llt_.compute(omega).info() == Eigen::Success;
    out.indefinite = !out.repaired;
  }
  if (out.indefinite) {
    out.error = tag + ": information matrix is not positive definite";
  } else {
    out.error = refusal(tag, [&] { e->setMeasurementData(values_.data()); });
    if (out.error.empty()) {
      out.error = refusal(
          tag, [&] { e->setParameterData(values_.data() + e->measurementDataDimension()); });
    }
    e->setInformationData(omega.data());
  }
  out.edge = std::move(e);
  out.tag = &entry.tag;
}

std::size_t LineParser::readSeparatedIds(const std::vector<std::string_view>& tokens,
                                         const std::string& tag, Edge& e) {
  std::size_t sep = 1;
  while (sep < tokens.size() && tokens[sep] != "||") ++sep;
  if (sep == 1 || sep + 1 >= tokens.size()) {
    throw LineError{tag + " expects its vertex ids to be followed by '||' and a count"};
  }
  setVertexIds(e, tokens, sep - 1, tag);
  const int expected = e.separatedCount(sep - 1);
  if (parseId(tokens[sep + 1], sep + 1, tag, "count") != expected) {
    throw LineError{tag + ": the count " + quote(tokens[sep + 1]) + " after '||' does not " +
                    "match its " + std::to_string(sep - 1) + " vertex ids (" +
                    std::to_string(expected) + " expected)"};
  }
  return sep + 2;
}

void LineParser::setVertexIds(Edge& e, const std::vector<std::string_view>& tokens,
                              std::size_t count, const std::string& tag) {
  std::vector<VertexId> ids(count);  // moved into the edge
  for (std::size_t i = 0; i < count; ++i) ids[i] = parseId(tokens[1 + i], 1 + i, tag);
  try {
    e.setVertexIds(std::move(ids));
  } catch (const Error& err) {
    throw LineError{tag + ": " + err.what()};
  }
}

}  // namespace graphslam::io::detail
