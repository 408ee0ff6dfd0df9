// SPDX-License-Identifier: MIT
// The CSV files graphslam eval --plot hands to tools/plot/plot_eval.py.
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "graphslam/eval/trajectory_metrics.h"
#include "graphslam/io/trajectory.h"

namespace graphslam::apps {

/// `t,x,y,z` per pose of `trajectory`.
void writePositionsCsv(const std::string& path, const io::Trajectory& trajectory);

/// `t,x,y,z` per pose of `trajectory` after the alignment an evaluation applied to its
/// associated poses, x -> origin * (s R x + t): the poses without a reference (e.g. a 13th
/// pose closing a loop of 12) are drawn where the compared ones are.
void writeAlignedPositionsCsv(const std::string& path, const io::Trajectory& trajectory,
                              const eval::UmeyamaResult& umeyama, const Eigen::Isometry3d& origin);

/// The unit in a pose-relation title, "translation part (m)" -> "m"; "unit-less" -> "-".
[[nodiscard]] std::string unitOf(const std::string& relation_title);

}  // namespace graphslam::apps
