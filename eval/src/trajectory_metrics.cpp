// SPDX-License-Identifier: MIT
#include "graphslam/eval/trajectory_metrics.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>

namespace graphslam::eval {

bool poseRelationFromName(const std::string& name, PoseRelation* relation) {
  static const std::map<std::string, PoseRelation> names = {
      {"trans_part", PoseRelation::kTranslationPart},
      {"rot_part", PoseRelation::kRotationPart},
      {"angle_deg", PoseRelation::kRotationAngleDeg},
      {"angle_rad", PoseRelation::kRotationAngleRad},
      {"full", PoseRelation::kFullTransformation},
      {"point_distance", PoseRelation::kPointDistance},
      {"point_distance_error_ratio", PoseRelation::kPointDistanceErrorRatio}};
  const auto it = names.find(name);
  if (it == names.end()) return false;
  *relation = it->second;
  return true;
}
namespace {

constexpr double kPi = 3.14159265358979323846;

/// SE(3) inverse through the transposed rotation block (evo's se3_inverse).
Eigen::Isometry3d se3Inverse(const Eigen::Isometry3d& p) {
  Eigen::Isometry3d inv = Eigen::Isometry3d::Identity();
  inv.linear() = p.linear().transpose();
  inv.translation() = -(inv.linear() * p.translation());
  return inv;
}

/// p1^{-1} * p2 (evo's relative_se3).
Eigen::Isometry3d relativeSe3(const Eigen::Isometry3d& p1, const Eigen::Isometry3d& p2) {
  return Eigen::Isometry3d(se3Inverse(p1).matrix() * p2.matrix());
}

/// Reference/estimate pair after the association step.
std::pair<Trajectory, Trajectory> associateIfRequested(const Trajectory& reference,
                                                       const Trajectory& estimate, bool associate,
                                                       const AssociationOptions& options) {
  if (reference.empty() || estimate.empty()) throw Error("trajectory evaluation: empty trajectory");
  if (associate) return associateTrajectories(reference, estimate, options);
  if (reference.size() != estimate.size()) {
    throw Error("trajectory evaluation: trajectories must have the same number of poses (" +
                std::to_string(reference.size()) + " vs " + std::to_string(estimate.size()) +
                "); enable association");
  }
  return {reference, estimate};
}

bool needsAlignment(const AlignmentOptions& options) {
  return options.mode != AlignmentMode::kNone || options.align_origin;
}

/// Pairs whose indices are `delta` apart (evo's filter_pairs_by_index).
std::vector<IdPair> pairsByIndex(std::size_t n, std::size_t delta, bool all_pairs) {
  std::vector<IdPair> pairs;
  if (all_pairs) {
    for (std::size_t i = 0; i + delta < n; ++i) pairs.emplace_back(i, i + delta);
  } else {
    for (std::size_t i = 0; i + delta < n; i += delta) pairs.emplace_back(i, i + delta);
  }
  return pairs;
}

/// Pairs `delta` metres of travelled path apart (evo's filter_pairs_by_path).
std::vector<IdPair> pairsByPath(const std::vector<Eigen::Isometry3d>& poses, double delta,
                                double tol, bool all_pairs) {
  std::vector<IdPair> pairs;
  const std::size_t n = poses.size();
  if (all_pairs) {
    std::vector<double> accumulated(n, 0.0);
    for (std::size_t i = 1; i < n; ++i) {
      accumulated[i] =
          accumulated[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
    }
    for (std::size_t i = 0; i + 1 < n; ++i) {
      std::size_t best = i + 1;
      double best_residual = std::numeric_limits<double>::infinity();
      for (std::size_t j = i + 1; j < n; ++j) {
        const double residual = std::abs((accumulated[j] - accumulated[i]) - delta);
        if (residual < best_residual) {  // first minimum, like numpy argmin
          best_residual = residual;
          best = j;
        }
      }
      if (best_residual > tol) continue;
      pairs.emplace_back(i, best);
    }
  } else {
    // evo's consecutive mode: a pose becomes a pair endpoint once the path travelled since
    // the previous endpoint (or since pose 0) reaches delta; pose 0 itself is not an endpoint.
    std::vector<std::size_t> ids;
    double current_path = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0) current_path += (poses[i].translation() - poses[i - 1].translation()).norm();
      if (current_path >= delta) {
        ids.push_back(i);
        current_path = 0.0;
      }
    }
    for (std::size_t k = 0; k + 1 < ids.size(); ++k) pairs.emplace_back(ids[k], ids[k + 1]);
  }
  return pairs;
}

/// Pairs `delta` radians of rotation apart (evo's filter_pairs_by_angle, in radians).
std::vector<IdPair> pairsByAngle(const std::vector<Eigen::Isometry3d>& poses, double delta,
                                 double tol, bool all_pairs) {
  std::vector<IdPair> pairs;
  const std::size_t n = poses.size();
  if (all_pairs) {
    for (std::size_t i = 0; i + 1 < n; ++i) {
      for (std::size_t j = i + 1; j < n; ++j) {
        const double angle = rotationAngle(poses[i].linear().transpose() * poses[j].linear());
        if (delta - tol <= angle && angle <= delta + tol) pairs.emplace_back(i, j);
      }
    }
  } else {
    double accumulated = 0.0;
    std::size_t start = 0;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      accumulated += rotationAngle(poses[i].linear().transpose() * poses[i + 1].linear());
      if (accumulated >= delta) {
        pairs.emplace_back(start, i + 1);
        accumulated = 0.0;
        start = i + 1;
      }
    }
  }
  return pairs;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Statistics

ErrorStatistics computeStatistics(const std::vector<double>& errors) {
  if (errors.empty()) throw Error("computeStatistics: empty error array");
  const double n = static_cast<double>(errors.size());
  ErrorStatistics s;
  double sum = 0.0;
  double sum_sq = 0.0;
  for (const double e : errors) {
    sum += e;
    sum_sq += e * e;
  }
  s.mean = sum / n;
  s.sse = sum_sq;
  s.rmse = std::sqrt(sum_sq / n);
  const auto [min_it, max_it] = std::minmax_element(errors.begin(), errors.end());
  s.min = *min_it;
  s.max = *max_it;
  double var = 0.0;
  for (const double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std_dev = std::sqrt(var / n);
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t mid = sorted.size() / 2;
  s.median = (sorted.size() % 2 == 1) ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  return s;
}

// ---------------------------------------------------------------------------------------
// Association

MatchingIndices matchingTimeIndices(const std::vector<double>& stamps_1,
                                    const std::vector<double>& stamps_2, double max_diff,
                                    double offset_2) {
  MatchingIndices matches;
  if (stamps_2.empty()) return matches;
  // Sorted stamps (every real trajectory): the nearest is next to the insertion point,
  // found in O(log n); otherwise a full scan. Both return numpy argmin's first minimum.
  const bool sorted = std::is_sorted(stamps_2.begin(), stamps_2.end());
  for (std::size_t i = 0; i < stamps_1.size(); ++i) {
    std::size_t best = 0;
    double best_diff = std::numeric_limits<double>::infinity();
    auto consider = [&](std::size_t j) {
      const double diff = std::abs((stamps_2[j] + offset_2) - stamps_1[i]);
      if (diff < best_diff || (diff == best_diff && j < best)) {
        best_diff = diff;
        best = j;
      }
    };
    if (sorted) {
      const double key = stamps_1[i] - offset_2;
      const auto it = std::lower_bound(stamps_2.begin(), stamps_2.end(), key);
      const auto j = static_cast<std::size_t>(it - stamps_2.begin());
      if (j < stamps_2.size()) {
        // First of a run of equal stamps: argmin's first minimum among equal values.
        consider(static_cast<std::size_t>(
            std::lower_bound(stamps_2.begin(), stamps_2.end(), stamps_2[j]) - stamps_2.begin()));
      }
      if (j > 0) {
        consider(static_cast<std::size_t>(
            std::lower_bound(stamps_2.begin(), stamps_2.end(), stamps_2[j - 1]) -
            stamps_2.begin()));
      }
    } else {
      for (std::size_t j = 0; j < stamps_2.size(); ++j) consider(j);
    }
    if (best_diff <= max_diff) {
      matches.first.push_back(i);
      matches.second.push_back(best);
    }
  }
  return matches;
}

std::pair<Trajectory, Trajectory> associateTrajectories(const Trajectory& first,
                                                        const Trajectory& second,
                                                        const AssociationOptions& options) {
  const bool second_longer = second.size() > first.size();
  const Trajectory& longer = second_longer ? second : first;
  const Trajectory& shorter = second_longer ? first : second;
  const MatchingIndices matches =
      matchingTimeIndices(shorter.timestamps(), longer.timestamps(), options.max_diff,
                          second_longer ? options.offset_2 : -options.offset_2);
  if (matches.first.empty()) {
    throw Error("associateTrajectories: found no matching timestamps with max. time diff " +
                std::to_string(options.max_diff) + " s and time offset " +
                std::to_string(options.offset_2) + " s");
  }
  Trajectory shorter_reduced = shorter.subset(matches.first);
  Trajectory longer_reduced = longer.subset(matches.second);
  if (second_longer) return {std::move(shorter_reduced), std::move(longer_reduced)};
  return {std::move(longer_reduced), std::move(shorter_reduced)};
}

// ---------------------------------------------------------------------------------------
// Alignment

UmeyamaResult umeyamaAlignment(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                               bool with_scale) {
  if (x.cols() != y.cols()) throw Error("umeyamaAlignment: data matrices must have the same shape");
  if (x.cols() == 0) throw Error("umeyamaAlignment: no points");
  const double n = static_cast<double>(x.cols());
  const Eigen::Vector3d mean_x = x.rowwise().mean();
  const Eigen::Vector3d mean_y = y.rowwise().mean();
  const Eigen::Matrix3Xd xc = x.colwise() - mean_x;
  const Eigen::Matrix3Xd yc = y.colwise() - mean_y;
  const double sigma_x = xc.squaredNorm() / n;               // eq. 36
  const Eigen::Matrix3d cov_xy = (yc * xc.transpose()) / n;  // eq. 38

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov_xy, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  const int rank = static_cast<int>((d.array() > std::numeric_limits<double>::epsilon()).count());
  if (rank < 2) throw Error("umeyamaAlignment: degenerate covariance rank, alignment not possible");

  Eigen::Matrix3d s = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) s(2, 2) = -1.0;  // eq. 43

  UmeyamaResult result;
  result.rotation = svd.matrixU() * s * svd.matrixV().transpose();           // eq. 40
  result.scale = with_scale ? (d.asDiagonal() * s).trace() / sigma_x : 1.0;  // eq. 42
  result.translation = mean_y - result.scale * (result.rotation * mean_x);   // eq. 41
  return result;
}

AlignmentResult alignTrajectory(const Trajectory& estimate, const Trajectory& reference,
                                const AlignmentOptions& options) {
  if (estimate.size() != reference.size()) {
    throw Error("alignTrajectory: trajectories must have the same number of poses");
  }
  if (estimate.empty()) throw Error("alignTrajectory: empty trajectory");
  if (options.num_poses == 0 || options.num_poses < -1) {
    throw Error("alignTrajectory: num_poses must be -1 (all) or positive");
  }
  AlignmentResult result;
  result.aligned = estimate;
  if (options.mode != AlignmentMode::kNone) {
    Eigen::Matrix3Xd x = estimate.positions();
    Eigen::Matrix3Xd y = reference.positions();
    if (options.num_poses > 0 && options.num_poses < x.cols()) {
      x = x.leftCols(options.num_poses).eval();
      y = y.leftCols(options.num_poses).eval();
    }
    const bool with_scale =
        options.mode == AlignmentMode::kSim3 || options.mode == AlignmentMode::kScaleOnly;
    result.umeyama = umeyamaAlignment(x, y, with_scale);
    if (options.mode == AlignmentMode::kScaleOnly) {
      result.aligned.scale(result.umeyama.scale);
      result.umeyama.rotation.setIdentity();  // only the scale was applied
      result.umeyama.translation.setZero();
    } else {
      if (with_scale) result.aligned.scale(result.umeyama.scale);
      Eigen::Isometry3d rigid = Eigen::Isometry3d::Identity();
      rigid.linear() = result.umeyama.rotation;
      rigid.translation() = result.umeyama.translation;
      result.aligned.transform(rigid);
    }
  }
  if (options.align_origin) {
    result.origin_transform =
        Eigen::Isometry3d(reference.pose(0).matrix() * se3Inverse(result.aligned.pose(0)).matrix());
    result.aligned.transform(result.origin_transform);
  }
  return result;
}

// ---------------------------------------------------------------------------------------
// Pose errors

double rotationAngle(const Eigen::Matrix3d& rotation) {
  Eigen::Quaterniond q(rotation);
  q.normalize();
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

double poseErrorMetric(const Eigen::Isometry3d& e, PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTranslationPart:
      return e.translation().norm();
    case PoseRelation::kRotationPart:
      return (e.linear() - Eigen::Matrix3d::Identity()).norm();
    case PoseRelation::kFullTransformation:
      return (e.matrix() - Eigen::Matrix4d::Identity()).norm();
    case PoseRelation::kRotationAngleRad:
      return rotationAngle(e.linear());
    case PoseRelation::kRotationAngleDeg:
      return rotationAngle(e.linear()) * 180.0 / kPi;
    case PoseRelation::kPointDistance:
    case PoseRelation::kPointDistanceErrorRatio:
      break;
  }
  throw Error("poseErrorMetric: the point-distance relations need positions, not an error pose");
}

std::vector<double> apeErrors(const Trajectory& reference, const Trajectory& estimate,
                              PoseRelation relation) {
  if (reference.size() != estimate.size()) {
    throw Error("apeErrors: trajectories must have the same number of poses");
  }
  if (relation == PoseRelation::kPointDistanceErrorRatio) {
    throw Error("APE: pose relation point_distance_error_ratio is not supported (RPE only)");
  }
  std::vector<double> errors(reference.size());
  for (std::size_t i = 0; i < reference.size(); ++i) {
    if (relation == PoseRelation::kTranslationPart || relation == PoseRelation::kPointDistance) {
      errors[i] = (estimate.pose(i).translation() - reference.pose(i).translation()).norm();
    } else {
      errors[i] = poseErrorMetric(relativeSe3(estimate.pose(i), reference.pose(i)), relation);
    }
  }
  return errors;
}

ApeResult computeApe(const Trajectory& reference, const Trajectory& estimate,
                     const ApeOptions& options) {
  auto [ref, est] =
      associateIfRequested(reference, estimate, options.associate, options.association);
  ApeResult result;
  if (needsAlignment(options.alignment)) {
    AlignmentResult aligned = alignTrajectory(est, ref, options.alignment);
    est = std::move(aligned.aligned);
    result.umeyama = aligned.umeyama;
    result.origin_transform = aligned.origin_transform;
  }
  result.errors = apeErrors(ref, est, options.pose_relation);
  result.statistics = computeStatistics(result.errors);
  result.reference = std::move(ref);
  result.estimate = std::move(est);
  return result;
}

// ---------------------------------------------------------------------------------------
// RPE

std::vector<IdPair> idPairsFromDelta(const std::vector<Eigen::Isometry3d>& poses, double delta,
                                     DeltaUnit unit, double rel_tol, bool all_pairs) {
  if (!(delta > 0.0) || !std::isfinite(delta)) {
    throw Error("RPE: delta must be a positive number");
  }
  std::vector<IdPair> pairs;
  switch (unit) {
    case DeltaUnit::kFrames: {
      if (delta != std::floor(delta)) throw Error("RPE: delta must be an integer for unit frames");
      pairs = pairsByIndex(poses.size(), static_cast<std::size_t>(delta), all_pairs);
      break;
    }
    case DeltaUnit::kMeters:
      pairs = pairsByPath(poses, delta, delta * rel_tol, all_pairs);
      break;
    case DeltaUnit::kRadians:
    case DeltaUnit::kDegrees: {
      const double bound = unit == DeltaUnit::kDegrees ? 180.0 : kPi;
      if (delta > bound)
        throw Error("RPE: delta angle must be within [0, " + std::to_string(bound) + "]");
      const double to_rad = unit == DeltaUnit::kDegrees ? kPi / 180.0 : 1.0;
      pairs = pairsByAngle(poses, delta * to_rad, delta * rel_tol * to_rad, all_pairs);
      break;
    }
  }
  if (pairs.empty()) {
    throw Error("RPE: delta = " + std::to_string(delta) +
                " produced an empty index list - try lower values or a less strict tolerance");
  }
  return pairs;
}

RpeResult computeRpe(const Trajectory& reference, const Trajectory& estimate,
                     const RpeOptions& options) {
  auto [ref, est] =
      associateIfRequested(reference, estimate, options.associate, options.association);
  RpeResult result;
  if (needsAlignment(options.alignment)) {
    AlignmentResult aligned = alignTrajectory(est, ref, options.alignment);
    est = std::move(aligned.aligned);
    result.umeyama = aligned.umeyama;
    result.origin_transform = aligned.origin_transform;
  }
  std::vector<IdPair> pairs =
      idPairsFromDelta(options.pairs_from_reference ? ref.poses() : est.poses(), options.delta,
                       options.delta_unit, options.rel_delta_tol, options.all_pairs);

  std::vector<double> errors;
  errors.reserve(pairs.size());
  if (options.pose_relation == PoseRelation::kPointDistance ||
      options.pose_relation == PoseRelation::kPointDistanceErrorRatio) {
    std::vector<IdPair> kept;
    for (const auto& [i, j] : pairs) {
      const double ref_distance = (ref.position(i) - ref.position(j)).norm();
      const double est_distance = (est.position(i) - est.position(j)).norm();
      const double error = std::abs(ref_distance - est_distance);
      if (options.pose_relation == PoseRelation::kPointDistance) {
        errors.push_back(error);
        kept.emplace_back(i, j);
      } else if (ref_distance != 0.0) {  // evo ignores zero divisions
        errors.push_back(error / ref_distance * 100.0);
        kept.emplace_back(i, j);
      }
    }
    pairs = std::move(kept);
  } else {
    for (const auto& [i, j] : pairs) {
      const Eigen::Isometry3d ref_rel = relativeSe3(ref.pose(i), ref.pose(j));
      const Eigen::Isometry3d est_rel = relativeSe3(est.pose(i), est.pose(j));
      errors.push_back(poseErrorMetric(relativeSe3(ref_rel, est_rel), options.pose_relation));
    }
  }
  result.errors = std::move(errors);
  result.statistics = computeStatistics(result.errors);
  result.id_pairs = std::move(pairs);
  result.reference = std::move(ref);
  result.estimate = std::move(est);
  return result;
}

}  // namespace graphslam::eval
