// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/io/npz.h"

namespace graphslam::io {

/// True 2D positions of some vertices of a graph, split into the robot's trajectory (in
/// order) and landmarks.
struct PointGroundTruth {
  std::vector<VertexId> pose_ids;
  std::vector<Eigen::Vector2d> poses;
  std::vector<VertexId> landmark_ids;
  std::vector<Eigen::Vector2d> landmarks;
  [[nodiscard]] bool empty() const { return pose_ids.empty() && landmark_ids.empty(); }
};

/// How the landmark observations of a CMU 16-833 HW3 file are to be read.
enum class PointObservationModel {
  kAuto,          ///< decide from the file (see loadCourseworkNpz)
  kLinear,        ///< (dx, dy) = landmark - pose, world frame: EDGE_POINTXY
  kBearingRange,  ///< (bearing, range), world-frame bearing: EDGE_XY_BEARING_RANGE
};

[[nodiscard]] const char* toString(PointObservationModel model);

struct CourseworkNpzOptions {
  PointObservationModel model = PointObservationModel::kAuto;
  /// Information of the prior on the first pose (the homework's A[0:2, 0:2] = I).
  Eigen::Matrix2d prior_information = Eigen::Matrix2d::Identity();
};

/// A point-robot SLAM problem of the CMU 16-833 HW3 "linear and nonlinear SLAM solvers"
/// homework, as a graph.
struct CourseworkProblem {
  Graph graph;
  PointObservationModel model = PointObservationModel::kLinear;  ///< never kAuto
  std::string model_reason;                                      ///< why this model (for the user)
  int num_poses = 0;
  int num_landmarks = 0;
  std::size_t num_odometry = 0;
  std::size_t num_observations = 0;
  Eigen::Matrix2d sigma_odom = Eigen::Matrix2d::Identity();
  Eigen::Matrix2d sigma_landmark = Eigen::Matrix2d::Identity();
  PointGroundTruth ground_truth;   ///< from gt_traj / gt_landmarks; empty if absent
  std::vector<std::string> notes;  ///< e.g. landmarks that are never observed

  [[nodiscard]] static VertexId poseId(int i) { return i; }
  [[nodiscard]] VertexId landmarkId(int j) const { return num_poses + j; }
};

/// Reads a homework `.npz` (keys odom (P-1, 2), observations (K, 4) rows
/// [pose, landmark, m1, m2], sigma_odom and sigma_landmark (2, 2), optional gt_traj (P, 2)
/// and gt_landmarks (L, 2)) and builds the graph of the homework's least-squares problem:
///  - vertices (VertexXY): poses 0..P-1, then landmarks P..P+L-1 — the homework's state
///    order [r_0, ..., r_{P-1}, l_0, ...], so the optimizer's columns match its A;
///  - EDGE_PRIOR_XY on pose 0 at (0, 0) with `prior_information`;
///  - EDGE_POINTXY i -> i+1 per odometry row, information sigma_odom^-1;
///  - per observation, EDGE_POINTXY (linear) or EDGE_XY_BEARING_RANGE (bearing-range)
///    pose -> landmark, information sigma_landmark^-1;
///  - initial estimates: all zero for the linear model (the system is linear, so any
///    start gives the same solution); for bearing-range the homework's init_states: poses
///    by summing the odometry from (0, 0), each landmark from its first observation.
/// kAuto picks the model whose residuals at the ground truth are smaller (the two
/// files of each kind share keys and shapes); without ground truth, a file name
/// containing "nonlinear" means bearing-range. P is the number of odometry rows + 1 (and
/// must equal gt_traj's rows); L is gt_landmarks' rows, else the largest landmark
/// index + 1. Indices are stored as floats: each must be an integer in range.
/// Throws graphslam::InputError naming the file, the array and the row for missing or
/// malformed arrays, non-finite values, bad indices and covariances that are not
/// symmetric positive definite.
[[nodiscard]] CourseworkProblem loadCourseworkNpz(const std::string& path,
                                                  const CourseworkNpzOptions& options = {});
/// Same, from an archive already opened (NpzArchive::fromBytes for a pipe).
[[nodiscard]] CourseworkProblem loadCourseworkNpz(const NpzArchive& npz,
                                                  const CourseworkNpzOptions& options = {});

}  // namespace graphslam::io
