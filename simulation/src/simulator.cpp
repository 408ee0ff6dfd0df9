// SPDX-License-Identifier: MIT
#include "graphslam/simulation/simulator.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <unordered_map>

#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::simulation {

using namespace graphslam::types_slam2d;

namespace {
constexpr double kHalfPi = 1.57079632679489661923;

std::int64_t cellKey(int x, int y) {
  // Shifted as unsigned: a left shift of a negative value is undefined (UBSan reports it);
  // the bits are the same.
  return static_cast<std::int64_t>((static_cast<std::uint64_t>(x) << 32) ^
                                   static_cast<std::uint32_t>(y));
}

/// The simulation's state, its phases in the order they draw from the random generator
/// (the same seed gives the same graph).
class ManhattanWorld {
 public:
  explicit ManhattanWorld(const ManhattanOptions& o)
      : o_(o),
        size_(o.world_size > 0 ? o.world_size
                               : std::max(4, static_cast<int>(std::sqrt(o.num_poses) / 2))),
        rng_(o.seed) {
    pose_info_(0, 0) = pose_info_(1, 1) = 1.0 / (o.sigma_xy * o.sigma_xy);
    pose_info_(2, 2) = 1.0 / (o.sigma_theta * o.sigma_theta);
  }

  /// Ground-truth walk on the integer grid: straight on, turning at random and at the
  /// world's border.
  void walk() {
    int x = 0, y = 0, heading = 0;  // heading in quarter turns
    const int dx[4] = {1, 0, -1, 0};
    const int dy[4] = {0, 1, 0, -1};
    cells_.reserve(static_cast<std::size_t>(o_.num_poses));
    for (int i = 0; i < o_.num_poses; ++i) {
      cells_.emplace_back(x, y);
      out_.true_poses.emplace_back(x, y, heading * kHalfPi);
      if (uni_(rng_) < o_.turn_probability) heading = (heading + (uni_(rng_) < 0.5 ? 1 : 3)) % 4;
      for (int tries = 0; tries < 4; ++tries) {
        const int nx = x + dx[heading], ny = y + dy[heading];
        if (nx >= 0 && ny >= 0 && nx < size_ && ny < size_) break;
        heading = (heading + 1) % 4;
      }
      x += dx[heading];
      y += dy[heading];
    }
  }

  /// Pose vertices initialised by composing the noisy odometry, and the odometry edges.
  void addOdometry() {
    SE2 guess;
    guesses_.reserve(cells_.size());
    for (int i = 0; i < o_.num_poses; ++i) {
      auto v = std::make_unique<VertexSE2>();
      v->setId(i);
      if (i > 0) {
        const SE2 z = noisyRelative(out_.true_poses[i - 1], out_.true_poses[i]);
        guess = guess * z;
        v->setEstimate(guess);
        out_.graph.addVertex(std::move(v));
        addPoseEdge(i - 1, i, z);
      } else {
        v->setEstimate(guess);
        out_.graph.addVertex(std::move(v));
      }
      guesses_.push_back(guess);
    }
  }

  /// Loop closures to an earlier visit of the same cell.
  void addLoopClosures() {
    std::unordered_map<std::int64_t, std::vector<int>> visits;
    for (int i = 0; i < o_.num_poses; ++i) {
      auto& seen = visits[cellKey(cells_[i].first, cells_[i].second)];
      std::vector<int> candidates;
      for (int j : seen) {
        if (i - j >= o_.min_loop_gap) candidates.push_back(j);
      }
      if (!candidates.empty() && uni_(rng_) < o_.loop_probability) {
        const int j = candidates[static_cast<std::size_t>(uni_(rng_) * candidates.size()) %
                                 candidates.size()];
        addPoseEdge(j, i, noisyRelative(out_.true_poses[j], out_.true_poses[i]));
        ++out_.num_loop_closures;
      }
      seen.push_back(i);
    }
  }

  /// Landmarks scattered over the world, observed from the poses within range; each is
  /// initialised from its first observation.
  void addLandmarks() {
    std::unordered_map<std::int64_t, std::vector<int>> lm_cells;
    for (int k = 0; k < o_.num_landmarks; ++k) {
      const Eigen::Vector2d p(uni_(rng_) * size_ - 0.5, uni_(rng_) * size_ - 0.5);
      out_.true_landmarks.push_back(p);
      lm_cells[cellKey(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())))]
          .push_back(k);
    }
    initialised_.assign(static_cast<std::size_t>(o_.num_landmarks), false);
    const int reach = static_cast<int>(std::ceil(o_.landmark_range));
    for (int i = 0; i < o_.num_poses; ++i) {
      for (int cx = cells_[i].first - reach - 1; cx <= cells_[i].first + reach; ++cx) {
        for (int cy = cells_[i].second - reach - 1; cy <= cells_[i].second + reach; ++cy) {
          auto it = lm_cells.find(cellKey(cx, cy));
          if (it == lm_cells.end()) continue;
          for (int k : it->second) observe(i, k);
        }
      }
    }
  }

  SimulatedGraph take() { return std::move(out_); }

 private:
  SE2 noisyRelative(const SE2& a, const SE2& b) {
    const SE2 rel = a.inverse() * b;
    return SE2(rel.translation().x() + o_.sigma_xy * gauss_(rng_),
               rel.translation().y() + o_.sigma_xy * gauss_(rng_),
               rel.angle() + o_.sigma_theta * gauss_(rng_));
  }

  void addPoseEdge(int i, int j, const SE2& z) {
    auto e = std::make_unique<EdgeSE2>();
    e->setVertexIds({i, j});
    e->setMeasurement(z);
    e->setInformation(pose_info_);
    out_.graph.addEdge(std::move(e));
  }

  /// Landmark k seen from pose i, when within range.
  void observe(int i, int k) {
    const SE2& truth = out_.true_poses[i];
    const Eigen::Vector2d& p = out_.true_landmarks[k];
    if ((p - truth.translation()).norm() > o_.landmark_range) return;
    Eigen::Vector2d z = truth.rotation().transpose() * (p - truth.translation());
    z += o_.sigma_landmark * Eigen::Vector2d(gauss_(rng_), gauss_(rng_));
    const int lid = o_.num_poses + k;
    if (!initialised_[k]) {
      auto v = std::make_unique<VertexXY>();
      v->setId(lid);
      v->setEstimate(guesses_[i] * z);
      out_.graph.addVertex(std::move(v));
      initialised_[k] = true;
    }
    auto e = std::make_unique<EdgeSE2XY>();
    e->setVertexIds({i, lid});
    e->setMeasurement(z);
    e->setInformation(Eigen::Matrix2d::Identity() / (o_.sigma_landmark * o_.sigma_landmark));
    out_.graph.addEdge(std::move(e));
    ++out_.num_observations;
  }

  const ManhattanOptions& o_;
  const int size_;
  std::mt19937 rng_;
  std::uniform_real_distribution<double> uni_{0.0, 1.0};
  std::normal_distribution<double> gauss_{0.0, 1.0};
  Eigen::Matrix3d pose_info_ = Eigen::Matrix3d::Zero();
  SimulatedGraph out_;
  std::vector<std::pair<int, int>> cells_;  ///< grid cell of each pose
  std::vector<SE2> guesses_;                ///< odometry estimate of each pose
  std::vector<bool> initialised_;           ///< per landmark: has its vertex
};

}  // namespace

SimulatedGraph simulateManhattan(const ManhattanOptions& o) {
  if (o.num_poses < 2) throw Error("simulateManhattan: num_poses must be at least 2");
  if (o.num_landmarks < 0) throw Error("simulateManhattan: num_landmarks must be >= 0");
  if (!(o.sigma_xy > 0) || !(o.sigma_theta > 0) || !(o.sigma_landmark > 0)) {
    throw Error("simulateManhattan: noise standard deviations must be positive");
  }
  ManhattanWorld world(o);
  world.walk();
  world.addOdometry();
  world.addLoopClosures();
  if (o.num_landmarks > 0) world.addLandmarks();
  return world.take();
}

ManhattanSize estimateSize(const ManhattanOptions& o) {
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kBytesPerPose = 1200.0;
  constexpr double kBytesPerObservation = 260.0;
  const double side =
      o.world_size > 0 ? o.world_size
                       : std::max(4.0, std::floor(std::sqrt(static_cast<double>(o.num_poses)) / 2));
  const double seen = std::min(1.0, kPi * o.landmark_range * o.landmark_range / (side * side));
  ManhattanSize size;
  size.observations = static_cast<double>(o.num_poses) * o.num_landmarks * seen;
  size.bytes = kBytesPerPose * o.num_poses + kBytesPerObservation * size.observations;
  return size;
}

}  // namespace graphslam::simulation
