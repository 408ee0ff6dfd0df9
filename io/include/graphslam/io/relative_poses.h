// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "graphslam/core/graph.h"

namespace graphslam::io {

/// Options of poseGraphFromRelativePoses.
struct RelativePoseGraphOptions {
  /// Treat the last column as a loop closure from the last pose back to pose 0 (the
  /// pose it would create coincides with the first one), as in the SE(2) homework.
  bool last_column_closes_loop = true;
  /// Information of every edge (identity unless given).
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
};

/// Builds an SE(2) pose graph from a 3xN matrix of relative poses, column k =
/// (dx, dy, dtheta) of T_k^-1 T_{k+1}: vertices initialised by dead reckoning from the
/// identity, odometry edges k -> k+1, and (by default) the last column as the edge
/// N-1 -> 0. Nothing is fixed (the optimizer fixes the gauge).
[[nodiscard]] Graph poseGraphFromRelativePoses(const Eigen::Matrix3Xd& relative,
                                               const RelativePoseGraphOptions& options = {});

}  // namespace graphslam::io
