// SPDX-License-Identifier: MIT
// DriveBot scenarios: the start state, the waypoints the controller drives to and the
// landmarks the laser sees (the coursework's x0.txt, wp.txt and lm.txt).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "graphslam/io/format_registry.h"

namespace graphslam::drivebot {

struct Scenario {
  std::string name;
  /// Where it came from: "built-in" or the directory it was read from.
  std::string source;
  /// x0.txt (x, y, psi). The coursework's simulator ignores it (it starts at 0, 0, 0).
  Eigen::Vector3d x0 = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector2d> waypoints;
  /// Landmark k (0-based here) has landmark id k + 1 in observations.
  std::vector<Eigen::Vector2d> landmarks;
};

/// Reads DIR/x0.txt (3 numbers), DIR/wp.txt (rows x y) and DIR/lm.txt (rows x y [z]; z
/// is dropped, as in the coursework). Blank lines are skipped. Throws InputError
/// (`FILE:LINE: what is wrong`) for a missing file, a wrong number of columns, a
/// non-number or NaN/Inf, or an empty waypoint list.
[[nodiscard]] Scenario loadScenario(const std::string& directory);

/// The coursework's small scenarios, built in so no data folder is needed: q1_b, q1_c,
/// q1_d, q1_e, q2_b, q2_c, q2_d (70 x 70 m square, 7 landmarks) and q3_a (13 landmarks:
/// its lm.txt has 13 rows, the last without a newline, so `wc -l` says 12).
[[nodiscard]] std::vector<std::string> builtinScenarioNames();
/// Throws InputError for an unknown name.
[[nodiscard]] Scenario builtinScenario(const std::string& name);

/// Resolves NAME: a path containing '/' is a scenario directory; a built-in name gives the
/// built-in scenario; otherwise DATA_DIR/NAME is read (e.g. q3-large-test). Throws
/// InputError naming what was tried when nothing matches.
[[nodiscard]] Scenario findScenario(const std::string& name, const std::string& data_dir);

/// Registers the scenario folder as the format "scenario" of data Scenario (loadScenario).
void registerFormats(io::FormatRegistry& formats);

}  // namespace graphslam::drivebot
