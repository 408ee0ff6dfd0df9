// SPDX-License-Identifier: MIT
// The tool's plotting path: it writes the data as CSV and runs a matplotlib script from
// tools/plot/ with a Python interpreter that can import matplotlib.
#pragma once

#include <Eigen/Core>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/eval/point_errors.h"

namespace graphslam::apps {

/// The first of $GRAPHSLAM_PYTHON, /usr/bin/python3, python3 that imports matplotlib;
/// empty when none does.
[[nodiscard]] std::string findPlotPython();

/// Runs argv (no shell; the program is looked up in PATH); `quiet` discards its output.
/// Returns its exit status, -1 if it could not run.
int runCommand(const std::vector<std::string>& argv, bool quiet);

/// Runs tools/plot/<script> with `args`. Throws graphslam::Error with install advice when
/// no interpreter has matplotlib, or naming the script when it fails.
void runPlotScript(const std::string& script, const std::vector<std::string>& args);

/// Removes a file when it goes out of scope (a plot's data file, whatever the plot did).
struct TemporaryFile {
  explicit TemporaryFile(std::string p) : path(std::move(p)) {}
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() { std::remove(path.c_str()); }
  std::string path;
};

/// Positions of the vertices that have one (see eval::vertexPosition), by id.
[[nodiscard]] std::map<VertexId, Eigen::Vector2d> positions(const Graph& graph);

/// Prints one line "what count rmse mean max -> rmse mean max".
void printErrors(const char* what, const eval::PositionErrorStats& before,
                 const eval::PositionErrorStats& after);

/// Writes the initial / final / ground-truth positions as CSV and draws them
/// (plot_points.py). Poses are the ground truth's pose ids, or else the VERTEX_SE2 vertices.
/// `shown`: the name the "wrote" line gives (default `png`; a staged output's final name);
/// `panels`: the titles of the left and right panels, "LEFT|RIGHT".
void plotPoints(const std::string& png, const std::string& title, const Graph& graph,
                const std::map<VertexId, Eigen::Vector2d>& initial,
                const io::PointGroundTruth& truth, const std::string& shown = {},
                const std::string& panels = "initial guess|optimised");

}  // namespace graphslam::apps
