// SPDX-License-Identifier: MIT
// graphslam drivebot's output: the report it prints and the files it writes after a run.
#pragma once

#include <string>

#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/drivebot/run.h"
#include "graphslam/drivebot/scenario.h"

namespace graphslam::apps {

/// pi, for the angles of the presets, options and reports.
constexpr double kPi = 3.14159265358979323846;

/// Prints the report of a run: steps, graph, optimisation times, final state, errors
/// against the truth, covariances and the loop closure; `laser`: the observation counts.
void printDrivebotReport(const drivebot::Scenario& scenario, const drivebot::RunResult& r,
                         bool laser);

/// Writes steps.csv, landmarks.csv, scenario.csv, graph_stats.csv, summary.csv,
/// loop_closure.csv and loop_closure_vehicle.csv (after a loop-closure snapshot) and
/// final.g2o into `out_dir`.
void writeDrivebotResults(const std::string& out_dir, const drivebot::Scenario& scenario,
                          const drivebot::RunResult& r, const Graph& graph,
                          const TypeRegistry& types);

}  // namespace graphslam::apps
