// SPDX-License-Identifier: MIT
// The tool's plotting path: it writes the data as CSV and runs a matplotlib script from
// tools/plot/ with a Python interpreter that can import matplotlib.
#pragma once

#include <string>
#include <vector>

namespace graphslam::apps {

/// The first of $GRAPHSLAM_PYTHON, /usr/bin/python3, python3 that imports matplotlib;
/// empty when none does.
[[nodiscard]] std::string findPlotPython();

/// Runs tools/plot/<script> with `args`. Throws graphslam::Error with install advice when
/// no interpreter has matplotlib, or naming the script when it fails.
void runPlotScript(const std::string& script, const std::vector<std::string>& args);

}  // namespace graphslam::apps
