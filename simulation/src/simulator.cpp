// SPDX-License-Identifier: MIT
#include "graphslam/simulation/simulator.h"

#include <cmath>
#include <memory>
#include <random>
#include <unordered_map>

#include "graphslam/core/error.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/edge_se2_xy.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::simulation {

using namespace graphslam::types_slam2d;

namespace {
constexpr double kHalfPi = 1.57079632679489661923;

std::int64_t cellKey(int x, int y) {
  return (static_cast<std::int64_t>(x) << 32) ^ static_cast<std::uint32_t>(y);
}
}  // namespace

SimulatedGraph simulateManhattan(const ManhattanOptions& o) {
  if (o.num_poses < 2) throw Error("simulateManhattan: num_poses must be at least 2");
  if (o.num_landmarks < 0) throw Error("simulateManhattan: num_landmarks must be >= 0");
  if (!(o.sigma_xy > 0) || !(o.sigma_theta > 0) || !(o.sigma_landmark > 0)) {
    throw Error("simulateManhattan: noise standard deviations must be positive");
  }
  const int size =
      o.world_size > 0 ? o.world_size : std::max(4, static_cast<int>(std::sqrt(o.num_poses) / 2));
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);

  SimulatedGraph out;
  // Ground-truth walk on the integer grid.
  int x = 0, y = 0, heading = 0;  // heading in quarter turns
  const int dx[4] = {1, 0, -1, 0};
  const int dy[4] = {0, 1, 0, -1};
  std::vector<std::pair<int, int>> cells;
  cells.reserve(static_cast<std::size_t>(o.num_poses));
  for (int i = 0; i < o.num_poses; ++i) {
    cells.emplace_back(x, y);
    out.true_poses.emplace_back(x, y, heading * kHalfPi);
    if (uni(rng) < o.turn_probability) heading = (heading + (uni(rng) < 0.5 ? 1 : 3)) % 4;
    for (int tries = 0; tries < 4; ++tries) {
      const int nx = x + dx[heading], ny = y + dy[heading];
      if (nx >= 0 && ny >= 0 && nx < size && ny < size) break;
      heading = (heading + 1) % 4;
    }
    x += dx[heading];
    y += dy[heading];
  }

  Eigen::Matrix3d pose_info = Eigen::Matrix3d::Zero();
  pose_info(0, 0) = pose_info(1, 1) = 1.0 / (o.sigma_xy * o.sigma_xy);
  pose_info(2, 2) = 1.0 / (o.sigma_theta * o.sigma_theta);
  auto noisy_relative = [&](const SE2& a, const SE2& b) {
    const SE2 rel = a.inverse() * b;
    return SE2(rel.translation().x() + o.sigma_xy * gauss(rng),
               rel.translation().y() + o.sigma_xy * gauss(rng),
               rel.angle() + o.sigma_theta * gauss(rng));
  };
  auto add_pose_edge = [&](int i, int j, const SE2& z) {
    auto e = std::make_unique<EdgeSE2>();
    e->setVertexIds({i, j});
    e->setMeasurement(z);
    e->setInformation(pose_info);
    out.graph.addEdge(std::move(e));
  };

  // Vertices initialised by composing the noisy odometry.
  SE2 guess;
  std::vector<SE2> guesses;
  guesses.reserve(cells.size());
  for (int i = 0; i < o.num_poses; ++i) {
    auto v = std::make_unique<VertexSE2>();
    v->setId(i);
    if (i > 0) {
      const SE2 z = noisy_relative(out.true_poses[i - 1], out.true_poses[i]);
      guess = guess * z;
      v->setEstimate(guess);
      out.graph.addVertex(std::move(v));
      add_pose_edge(i - 1, i, z);
    } else {
      v->setEstimate(guess);
      out.graph.addVertex(std::move(v));
    }
    guesses.push_back(guess);
  }

  // Loop closures to an earlier visit of the same cell.
  std::unordered_map<std::int64_t, std::vector<int>> visits;
  for (int i = 0; i < o.num_poses; ++i) {
    auto& seen = visits[cellKey(cells[i].first, cells[i].second)];
    std::vector<int> candidates;
    for (int j : seen) {
      if (i - j >= o.min_loop_gap) candidates.push_back(j);
    }
    if (!candidates.empty() && uni(rng) < o.loop_probability) {
      const int j =
          candidates[static_cast<std::size_t>(uni(rng) * candidates.size()) % candidates.size()];
      add_pose_edge(j, i, noisy_relative(out.true_poses[j], out.true_poses[i]));
      ++out.num_loop_closures;
    }
    seen.push_back(i);
  }

  // Landmarks scattered over the world, observed from poses within range.
  if (o.num_landmarks > 0) {
    Eigen::Matrix2d lm_info = Eigen::Matrix2d::Identity() / (o.sigma_landmark * o.sigma_landmark);
    std::unordered_map<std::int64_t, std::vector<int>> lm_cells;
    for (int k = 0; k < o.num_landmarks; ++k) {
      const Eigen::Vector2d p(uni(rng) * size - 0.5, uni(rng) * size - 0.5);
      out.true_landmarks.push_back(p);
      lm_cells[cellKey(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())))]
          .push_back(k);
    }
    std::vector<bool> initialised(static_cast<std::size_t>(o.num_landmarks), false);
    const int reach = static_cast<int>(std::ceil(o.landmark_range));
    for (int i = 0; i < o.num_poses; ++i) {
      const SE2& truth = out.true_poses[i];
      for (int cx = cells[i].first - reach - 1; cx <= cells[i].first + reach; ++cx) {
        for (int cy = cells[i].second - reach - 1; cy <= cells[i].second + reach; ++cy) {
          auto it = lm_cells.find(cellKey(cx, cy));
          if (it == lm_cells.end()) continue;
          for (int k : it->second) {
            const Eigen::Vector2d& p = out.true_landmarks[k];
            if ((p - truth.translation()).norm() > o.landmark_range) continue;
            Eigen::Vector2d z = truth.rotation().transpose() * (p - truth.translation());
            z += o.sigma_landmark * Eigen::Vector2d(gauss(rng), gauss(rng));
            const int lid = o.num_poses + k;
            if (!initialised[k]) {
              auto v = std::make_unique<VertexXY>();
              v->setId(lid);
              v->setEstimate(guesses[i] * z);
              out.graph.addVertex(std::move(v));
              initialised[k] = true;
            }
            auto e = std::make_unique<EdgeSE2XY>();
            e->setVertexIds({i, lid});
            e->setMeasurement(z);
            e->setInformation(lm_info);
            out.graph.addEdge(std::move(e));
            ++out.num_observations;
          }
        }
      }
    }
  }
  return out;
}

}  // namespace graphslam::simulation
