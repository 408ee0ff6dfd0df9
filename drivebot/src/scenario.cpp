// SPDX-License-Identifier: MIT
#include "graphslam/drivebot/scenario.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>
#include <system_error>

#include "graphslam/io/text_tokens.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"

namespace graphslam::drivebot {

namespace {

/// One number of a scenario file (locale independent); `where` is "FILE:LINE: ".
double parseValue(const std::string& token, const std::string& where) {
  std::string_view digits = token;
  if (digits.size() > 1 && digits.front() == '+') digits.remove_prefix(1);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
  if (ec == std::errc::result_out_of_range && ptr == digits.data() + digits.size()) {
    throw InputError(where + io::quote(token) + " is out of the range of a double");
  }
  if (ec != std::errc() || ptr != digits.data() + digits.size()) {
    throw InputError(where + io::quote(token) + " is not a number");
  }
  if (!std::isfinite(v)) throw InputError(where + io::quote(token) + " is not finite");
  return v;
}

/// Rows of numbers of a whitespace-separated text file, each with min_cols..max_cols
/// values. Blank lines are skipped.
std::vector<std::vector<double>> readRows(const std::string& path, int min_cols, int max_cols) {
  errno = 0;
  std::ifstream in(path);
  if (!in) throw InputError(support::cannotOpenMessage(path, errno));
  std::vector<std::vector<double>> rows;
  std::string line;
  int line_no = 0;
  while (true) {
    const support::LineRead read = support::readBoundedLine(in, line, support::kMaxTextLineBytes);
    if (read == support::LineRead::kEnd) break;
    ++line_no;
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    if (read == support::LineRead::kTooLong) {
      throw InputError(where + "the line is longer than " +
                       std::to_string(support::kMaxTextLineBytes) +
                       " bytes: not a line of numbers");
    }
    std::istringstream fields(line);
    std::vector<double> row;
    std::string token;
    while (fields >> token) row.push_back(parseValue(token, where));
    if (row.empty()) continue;
    const int n = static_cast<int>(row.size());
    if (n < min_cols || n > max_cols) {
      const std::string expected =
          min_cols == max_cols ? std::to_string(min_cols)
                               : std::to_string(min_cols) + " or " + std::to_string(max_cols);
      throw InputError(path + ":" + std::to_string(line_no) + ": expected " + expected +
                       " numbers, found " + std::to_string(n));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<Eigen::Vector2d> points(std::initializer_list<std::pair<double, double>> xy) {
  std::vector<Eigen::Vector2d> out;
  for (const auto& [x, y] : xy) out.emplace_back(x, y);
  return out;
}

std::vector<Eigen::Vector2d> repeat(const std::vector<Eigen::Vector2d>& v, int times) {
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i < times; ++i) out.insert(out.end(), v.begin(), v.end());
  return out;
}

}  // namespace

Scenario loadScenario(const std::string& directory) {
  Scenario s;
  std::string dir = directory;
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  s.source = dir;
  const auto slash = dir.find_last_of('/');
  s.name = slash == std::string::npos ? dir : dir.substr(slash + 1);

  const auto x0 = readRows(dir + "/x0.txt", 3, 3);
  if (x0.size() != 1) {
    throw InputError(dir + "/x0.txt: expected one row (x y psi), found " +
                     std::to_string(x0.size()));
  }
  s.x0 = Eigen::Vector3d(x0[0][0], x0[0][1], x0[0][2]);
  for (const auto& r : readRows(dir + "/wp.txt", 2, 2)) s.waypoints.emplace_back(r[0], r[1]);
  if (s.waypoints.empty()) throw InputError(dir + "/wp.txt: no waypoints");
  for (const auto& r : readRows(dir + "/lm.txt", 2, 3)) s.landmarks.emplace_back(r[0], r[1]);
  return s;
}

std::vector<std::string> builtinScenarioNames() {
  return {"q1_b", "q1_c", "q1_d", "q1_e", "q2_b", "q2_c", "q2_d", "q3_a"};
}

Scenario builtinScenario(const std::string& name) {
  const auto lm7 = points({{2, 2}, {5, 3}, {42, 3}, {60, 2}, {73, 10}, {66, 68}, {3, 27}});
  auto lm12 = lm7;
  const auto extra = points({{67, 48}, {71, 35}, {49, 71}, {18, 58}, {21, 17}, {10, 45}});
  lm12.insert(lm12.end(), extra.begin(), extra.end());
  const auto square = points({{70, 0}, {70, 70}, {0, 70}, {0, 0}});

  Scenario s;
  s.name = name;
  s.source = "built-in";
  s.landmarks = lm7;
  if (name == "q1_b" || name == "q1_c") {
    s.waypoints = points({{70, 0}, {70, 70}});
  } else if (name == "q1_e") {
    s.waypoints = points({{70, 0}});
  } else if (name == "q2_b" || name == "q2_d") {
    s.waypoints = square;
  } else if (name == "q1_d" || name == "q2_c") {
    s.waypoints = repeat(square, 4);
  } else if (name == "q3_a") {
    s.waypoints = repeat(square, 4);
    s.landmarks = lm12;
  } else {
    std::string known;
    for (const auto& n : builtinScenarioNames()) known += " " + n;
    throw InputError("unknown built-in scenario '" + name + "' (built in:" + known + ")");
  }
  return s;
}

Scenario findScenario(const std::string& name, const std::string& data_dir) {
  if (name.find('/') != std::string::npos) return loadScenario(name);
  for (const auto& n : builtinScenarioNames()) {
    if (n == name) return builtinScenario(name);
  }
  const std::string dir = data_dir + "/" + name;
  if (std::ifstream(dir + "/wp.txt").good()) return loadScenario(dir);
  std::string known;
  for (const auto& n : builtinScenarioNames()) known += " " + n;
  throw InputError("scenario '" + name + "' is neither built in (" + known.substr(1) +
                   ") nor a directory with x0.txt, wp.txt, lm.txt at " + dir);
}

void registerFormats(io::FormatRegistry& formats) {
  io::Format<Scenario> scenario;
  scenario.name = "scenario";
  scenario.description = "DriveBot scenario folder: x0.txt, wp.txt, lm.txt";
  scenario.read_folder = [](const std::string& folder, const io::ReadContext&) {
    return loadScenario(folder);
  };
  formats.add(std::move(scenario));
}

}  // namespace graphslam::drivebot
