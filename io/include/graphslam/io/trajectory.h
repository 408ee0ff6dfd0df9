// SPDX-License-Identifier: MIT
#pragma once

/// \file
/// Timestamped SE(3) trajectories and their file formats (TUM, KITTI), plus the planar
/// helpers used by the SE(2) examples (pose lists (x, y, theta), dead reckoning, 3xN
/// matrix files). The evaluation metrics (APE/RPE) live in trajectory_metrics.h.
///
/// Input validation (all reading functions): every malformed line throws
/// graphslam::InputError with the message `FILE:LINE: what is wrong` — wrong token
/// count, a token that is not a number, NaN or Inf. Quaternions (TUM) whose norm is
/// within kQuaternionNormTolerance of 1 are normalised (evo does the same, silently);
/// farther from 1 they are rejected. KITTI rotation blocks must be orthonormal within
/// kRotationTolerance (max-abs of R^T R - I) with det > 0; they are kept exactly as read
/// (no re-orthonormalisation), as evo does, so metrics match evo to the last digit.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/support/error.h"

namespace graphslam::io {

/// Largest accepted deviation of a TUM quaternion's norm from 1 before normalisation.
inline constexpr double kQuaternionNormTolerance = 1e-3;
/// Largest accepted max-abs entry of R^T R - I for a KITTI rotation block.
inline constexpr double kRotationTolerance = 1e-3;

/// A sequence of SE(3) poses with one timestamp each (seconds, or an index for
/// formats without time). Poses map body coordinates into the world frame.
class Trajectory {
 public:
  Trajectory() = default;
  /// Builds from parallel arrays; throws graphslam::Error if the sizes differ.
  Trajectory(std::vector<double> timestamps, std::vector<Eigen::Isometry3d> poses);

  /// Appends one pose at time `t`.
  void append(double t, const Eigen::Isometry3d& pose);

  /// Number of poses.
  [[nodiscard]] std::size_t size() const { return poses_.size(); }
  /// True if the trajectory holds no pose.
  [[nodiscard]] bool empty() const { return poses_.empty(); }
  /// All timestamps, in storage order.
  [[nodiscard]] const std::vector<double>& timestamps() const { return timestamps_; }
  /// All poses, in storage order.
  [[nodiscard]] const std::vector<Eigen::Isometry3d>& poses() const { return poses_; }
  /// Timestamp of pose `i` (bounds-checked, throws std::out_of_range).
  [[nodiscard]] double timestamp(std::size_t i) const { return timestamps_.at(i); }
  /// Pose `i` (bounds-checked, throws std::out_of_range).
  [[nodiscard]] const Eigen::Isometry3d& pose(std::size_t i) const { return poses_.at(i); }
  /// Translation of pose `i`.
  [[nodiscard]] Eigen::Vector3d position(std::size_t i) const { return poses_.at(i).translation(); }
  /// All positions as a 3xN matrix.
  [[nodiscard]] Eigen::Matrix3Xd positions() const;

  /// The poses with the given indices, in that order (evo's reduce_to_ids).
  [[nodiscard]] Trajectory subset(const std::vector<std::size_t>& ids) const;
  /// Arc length of the position sequence (evo's path_length).
  [[nodiscard]] double pathLength() const;

  /// Applies `t` to every pose: t * pose (default) or pose * t (`right_mul`).
  void transform(const Eigen::Isometry3d& t, bool right_mul = false);
  /// Scales every translation by `s`; rotations are unchanged (evo's scale()).
  void scale(double s);

 private:
  std::vector<double> timestamps_;
  std::vector<Eigen::Isometry3d> poses_;
};

/// Reads a TUM file: one pose per line `t x y z qx qy qz qw`, whitespace separated, in
/// strictly increasing time; blank lines and text after '#' are ignored. Throws
/// graphslam::InputError (FILE:LINE) for a malformed line, a quaternion that is not unit
/// length, or a timestamp not after the previous one.
[[nodiscard]] Trajectory readTum(const std::string& path);
/// Same as readTum(path) on a stream; `source_name` is used as FILE in error messages.
[[nodiscard]] Trajectory readTum(std::istream& in, const std::string& source_name);
/// Writes a TUM file (shortest decimal form that reads back bit-exactly, qw >= 0).
/// Throws graphslam::Error if the file cannot be written.
void writeTum(const std::string& path, const Trajectory& trajectory);
/// Writes TUM lines to a stream.
void writeTum(std::ostream& out, const Trajectory& trajectory);

/// Reads a KITTI odometry pose file: 12 numbers per line, the row-major 3x4 matrix
/// [R | t]; timestamps are the 0-based line index of the pose. Throws InputError.
[[nodiscard]] Trajectory readKitti(const std::string& path);
/// Same as readKitti(path) on a stream; `source_name` is used as FILE in error messages.
[[nodiscard]] Trajectory readKitti(std::istream& in, const std::string& source_name);
/// Writes a KITTI pose file (timestamps are not stored). Throws graphslam::Error.
void writeKitti(const std::string& path, const Trajectory& trajectory);
/// Writes KITTI lines to a stream.
void writeKitti(std::ostream& out, const Trajectory& trajectory);

/// SE(3) pose of a planar pose (x, y, theta): rotation about z by theta, z = 0.
[[nodiscard]] Eigen::Isometry3d se2ToIsometry3(double x, double y, double theta);
/// Trajectory from planar poses given as columns (x, y, theta); timestamps = index.
[[nodiscard]] Trajectory trajectoryFromSE2(const Eigen::Matrix3Xd& poses);
/// Trajectory from planar poses given as columns (x, y, theta) with explicit timestamps
/// (throws graphslam::Error if the counts differ).
[[nodiscard]] Trajectory trajectoryFromSE2(const Eigen::Matrix3Xd& poses,
                                           const std::vector<double>& timestamps);

/// Composes relative SE(2) poses: column k of `relative` = (dx, dy, dtheta) of
/// T_k^{-1} T_{k+1}; the first pose is the identity. Returns N+1 columns (x, y, theta)
/// with theta = atan2(R10, R00) in (-pi, pi].
[[nodiscard]] Eigen::Matrix3Xd deadReckonSE2(const Eigen::Matrix3Xd& relative);

/// Reads a matrix file with exactly 3 rows of N numbers each (tab/space separated,
/// CRLF tolerated, blank lines and '#' comments skipped), e.g. the ShanghaiTech
/// homework's relative-pose file. Throws graphslam::InputError.
[[nodiscard]] Eigen::Matrix3Xd readMatrix3xN(const std::string& path);
/// Same as readMatrix3xN(path) on a stream; `source_name` names it in error messages.
[[nodiscard]] Eigen::Matrix3Xd readMatrix3xN(std::istream& in, const std::string& source_name);

/// The VERTEX_SE2 and VERTEX_SE3:QUAT estimates of a graph as a trajectory, in id order,
/// timestamp = id. Other vertex types are skipped.
[[nodiscard]] Trajectory trajectoryFromGraph(const Graph& graph);

}  // namespace graphslam::io
