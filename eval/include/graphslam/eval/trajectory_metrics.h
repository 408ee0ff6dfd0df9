// SPDX-License-Identifier: MIT
#pragma once

/// \file
/// Trajectory evaluation with the semantics of evo (Michael Grupp, github.com/MichaelGrupp/evo):
/// timestamp association (evo.core.sync), Umeyama alignment (evo.core.geometry /
/// PosePath3D.align, align_origin), the absolute and relative pose errors (evo.core.metrics
/// APE / RPE with their PoseRelation) and the error statistics evo reports. Numbers are meant
/// to be quoted side by side with `evo_ape` / `evo_rpe`.
///
/// Conventions reproduced from evo:
///  - APE pose error E_i = est_i^{-1} * ref_i (evo's ape_base(x_t, x_t_star)); the
///    translation-part and point-distance errors are |p_est - p_ref|.
///  - RPE pose error E = (ref_i^{-1} ref_j)^{-1} (est_i^{-1} est_j).
///  - rotation_part = ||R(E) - I||_F, full_transformation = ||E - I||_F (4x4),
///    rotation_angle = |log(R(E))| (angle of the rotation vector).
///  - Statistics: mean, numpy median (mean of the two middle values for even N), min, max,
///    rmse = sqrt(mean(e^2)), sse = sum(e^2), std = population standard deviation.
///  - Alignment is applied to the estimate only: Sim(3) = scale translations, then the
///    rigid transform; align_origin left-multiplies by ref_0 * est_0^{-1} (after Umeyama).
///
/// Misuse (unequal sizes, empty input, unsupported combination, no matching timestamps,
/// degenerate Umeyama data) throws graphslam::Error.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/io/trajectory.h"
#include "graphslam/support/error.h"

namespace graphslam::eval {

using io::Trajectory;

/// What part of the pose error is measured (evo's PoseRelation).
enum class PoseRelation {
  kTranslationPart,         ///< |t(E)| in metres (APE: |p_est - p_ref|); evo's default
  kRotationPart,            ///< ||R(E) - I||_F, dimensionless
  kRotationAngleRad,        ///< rotation angle of R(E), radians
  kRotationAngleDeg,        ///< rotation angle of R(E), degrees
  kFullTransformation,      ///< ||E - I_4||_F, dimensionless
  kPointDistance,           ///< APE: |p_est - p_ref|; RPE: | |dp_ref| - |dp_est| |
  kPointDistanceErrorRatio  ///< RPE only: point distance / |dp_ref| * 100 (percent)
};

/// evo's names of the pose relations, as its `-r` takes them, in a message's words.
inline constexpr const char* kPoseRelationNames =
    "trans_part, rot_part, angle_deg, angle_rad, full, point_distance or "
    "point_distance_error_ratio";
/// The relation evo calls `name` ("trans_part", ...); false when there is none.
[[nodiscard]] bool poseRelationFromName(const std::string& name, PoseRelation* relation);

/// Alignment of the estimate to the reference before computing errors.
enum class AlignmentMode {
  kNone,      ///< no alignment (evo default)
  kSE3,       ///< Umeyama rotation + translation (evo `-a`)
  kSim3,      ///< Umeyama rotation + translation + scale (evo `-as`)
  kScaleOnly  ///< Umeyama scale only (evo `-s` without `-a`)
};

/// Unit of the RPE delta (evo's delta_unit).
enum class DeltaUnit {
  kFrames,   ///< index distance (evo 'f')
  kMeters,   ///< travelled path length (evo 'm')
  kRadians,  ///< accumulated rotation angle (evo 'rad')
  kDegrees   ///< accumulated rotation angle (evo 'deg')
};

/// The seven statistics evo reports for an error array.
struct ErrorStatistics {
  double max = 0.0;      ///< largest error
  double mean = 0.0;     ///< arithmetic mean
  double median = 0.0;   ///< numpy median (average of the middle pair for even N)
  double min = 0.0;      ///< smallest error
  double rmse = 0.0;     ///< sqrt(mean(e^2))
  double sse = 0.0;      ///< sum(e^2)
  double std_dev = 0.0;  ///< population standard deviation (evo's "std", numpy ddof=0)
};

/// Computes the statistics of `errors` (throws graphslam::Error if empty).
[[nodiscard]] ErrorStatistics computeStatistics(const std::vector<double>& errors);

/// Index pairs (first, second) of matched timestamps.
struct MatchingIndices {
  std::vector<std::size_t> first;   ///< indices into the first stamp list
  std::vector<std::size_t> second;  ///< indices into the second stamp list
};

/// evo's sync.matching_time_indices: for each stamp of `stamps_1` in order, the first
/// index of the nearest `stamps_2 + offset_2`, kept if |difference| <= max_diff.
[[nodiscard]] MatchingIndices matchingTimeIndices(const std::vector<double>& stamps_1,
                                                  const std::vector<double>& stamps_2,
                                                  double max_diff = 0.01, double offset_2 = 0.0);

/// Options of associateTrajectories (evo_ape/evo_rpe `--t_max_diff`, `--t_offset`).
struct AssociationOptions {
  double max_diff = 0.01;  ///< max. absolute time difference, seconds
  double offset_2 = 0.0;   ///< time offset added to the second trajectory's stamps
};

/// evo's sync.associate_trajectories: the shorter trajectory is matched against the longer
/// one and both are reduced to the matched pairs (order preserved, returned as
/// (first, second)). As in evo: if `second` has strictly more poses, each stamp of `first`
/// looks up its nearest in `second + offset_2`; otherwise (also on equal sizes) each stamp
/// of `second` looks up its nearest in `first - offset_2`. A pose of the longer trajectory
/// may be matched twice. Throws graphslam::Error if nothing matches.
[[nodiscard]] std::pair<Trajectory, Trajectory> associateTrajectories(
    const Trajectory& first, const Trajectory& second, const AssociationOptions& options = {});

/// Result of umeyamaAlignment: y ~ scale * rotation * x + translation.
struct UmeyamaResult {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< proper rotation
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();   ///< translation
  double scale = 1.0;                                      ///< 1 unless with_scale
};

/// Least-squares Sim(3)/SE(3) between point sets (columns), Umeyama 1991, as evo's
/// geometry.umeyama_alignment. Throws graphslam::Error on shape mismatch, fewer than one
/// point, or a covariance with fewer than 2 singular values above machine epsilon.
[[nodiscard]] UmeyamaResult umeyamaAlignment(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                                             bool with_scale = false);

/// Alignment settings shared by APE and RPE.
struct AlignmentOptions {
  AlignmentMode mode = AlignmentMode::kNone;  ///< Umeyama variant
  bool align_origin = false;                  ///< evo `--align_origin`
  int num_poses = -1;  ///< use only the first N poses for Umeyama (-1: all; evo `--n_to_align`)
};

/// The aligned estimate and the transformation that was applied.
struct AlignmentResult {
  Trajectory aligned;     ///< the estimate after alignment
  UmeyamaResult umeyama;  ///< Umeyama parameters (identity/1 if not used)
  Eigen::Isometry3d origin_transform = Eigen::Isometry3d::Identity();  ///< align_origin part
};

/// Aligns `estimate` to `reference` (same size, already associated) as evo_ape/evo_rpe do:
/// Umeyama first (per mode), then align_origin if requested.
[[nodiscard]] AlignmentResult alignTrajectory(const Trajectory& estimate,
                                              const Trajectory& reference,
                                              const AlignmentOptions& options);

/// Rotation angle |log(R)| in radians (evo's so3_log_angle), via the rotation quaternion.
[[nodiscard]] double rotationAngle(const Eigen::Matrix3d& rotation);

/// Scalar error of one SE(3) error pose `e` under `relation` (not for the point-distance
/// relations, which need positions; those throw graphslam::Error).
[[nodiscard]] double poseErrorMetric(const Eigen::Isometry3d& e, PoseRelation relation);

/// Options of computeApe.
struct ApeOptions {
  PoseRelation pose_relation = PoseRelation::kTranslationPart;  ///< evo `-r`
  bool associate = true;           ///< match timestamps first (evo does for TUM/bag input)
  AssociationOptions association;  ///< used if `associate`
  AlignmentOptions alignment;      ///< alignment of the estimate
};

/// APE result.
struct ApeResult {
  std::vector<double> errors;  ///< one error per associated pose
  ErrorStatistics statistics;  ///< statistics of `errors`
  Trajectory reference;        ///< associated reference
  Trajectory estimate;         ///< associated, aligned estimate
  UmeyamaResult umeyama;       ///< applied Umeyama parameters
  Eigen::Isometry3d origin_transform = Eigen::Isometry3d::Identity();  ///< applied origin alignment
};

/// Per-pose APE errors of two equally long trajectories (no association/alignment).
/// kPointDistanceErrorRatio is unsupported for APE (as in evo) and throws.
[[nodiscard]] std::vector<double> apeErrors(const Trajectory& reference, const Trajectory& estimate,
                                            PoseRelation relation);

/// Absolute pose error as `evo_ape ref est` with the given options.
[[nodiscard]] ApeResult computeApe(const Trajectory& reference, const Trajectory& estimate,
                                   const ApeOptions& options = {});

/// Options of computeRpe.
struct RpeOptions {
  PoseRelation pose_relation = PoseRelation::kTranslationPart;  ///< evo `-r`
  double delta = 1.0;                                           ///< evo `-d`
  DeltaUnit delta_unit = DeltaUnit::kFrames;                    ///< evo `-u`
  double rel_delta_tol = 0.1;         ///< relative tolerance for all_pairs in m/rad/deg units
  bool all_pairs = false;             ///< evo `--all_pairs`
  bool pairs_from_reference = false;  ///< evo `--pairs_from_reference`
  bool associate = true;              ///< match timestamps first
  AssociationOptions association;     ///< used if `associate`
  AlignmentOptions alignment;         ///< alignment of the estimate
};

/// Index pair (i, j), i < j, of one relative-pose comparison.
using IdPair = std::pair<std::size_t, std::size_t>;

/// RPE result.
struct RpeResult {
  std::vector<double> errors;    ///< one error per pair
  ErrorStatistics statistics;    ///< statistics of `errors`
  std::vector<IdPair> id_pairs;  ///< the compared pairs (after dropping zero-distance
                                 ///< pairs for kPointDistanceErrorRatio)
  Trajectory reference;          ///< associated reference
  Trajectory estimate;           ///< associated, aligned estimate
  UmeyamaResult umeyama;         ///< applied Umeyama parameters
  Eigen::Isometry3d origin_transform = Eigen::Isometry3d::Identity();  ///< applied origin alignment
};

/// evo's metrics.id_pairs_from_delta: pairs by index step (frames), travelled path (metres;
/// tolerance delta * rel_tol in all_pairs mode) or rotation angle. Throws graphslam::Error
/// if no pair results or the delta is invalid.
[[nodiscard]] std::vector<IdPair> idPairsFromDelta(const std::vector<Eigen::Isometry3d>& poses,
                                                   double delta, DeltaUnit unit,
                                                   double rel_tol = 0.1, bool all_pairs = false);

/// Relative pose error as `evo_rpe ref est` with the given options.
[[nodiscard]] RpeResult computeRpe(const Trajectory& reference, const Trajectory& estimate,
                                   const RpeOptions& options = {});

}  // namespace graphslam::eval
