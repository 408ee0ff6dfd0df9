// SPDX-License-Identifier: MIT
#include "graphslam/simulation/simulator3d.h"

#include <array>
#include <cmath>
#include <map>
#include <random>

#include "graphslam/support/error.h"
#include "graphslam/types_slam3d/edges.h"
#include "graphslam/types_slam3d/parameter_se3_offset.h"

namespace graphslam::simulation {

namespace {

using geometry::SE3;
using geometry::SO3;
using Pair = std::pair<int, int>;

constexpr double kPi = 3.14159265358979323846;

/// A rotation whose columns are the given forward (x) and up (z) directions (made
/// orthonormal).
SO3 frame(const Eigen::Vector3d& forward, const Eigen::Vector3d& up) {
  const Eigen::Vector3d x = forward.normalized();
  const Eigen::Vector3d y = up.cross(x).normalized();
  Eigen::Matrix3d r;
  r << x, y, x.cross(y);
  return SO3::fromMatrix(r);
}

/// True poses and candidate loop-closure pairs (i < j) of a sphere of rings.
void spherePoses(const PoseGraph3dOptions& o, std::vector<SE3>& poses, std::vector<Pair>& loops) {
  const int per_ring = std::max(3, static_cast<int>(std::lround(std::sqrt(o.num_poses))));
  const int rings = (o.num_poses + per_ring - 1) / per_ring;
  for (int k = 0; k < o.num_poses; ++k) {
    const int ring = k / per_ring, slot = k % per_ring;
    const double lat = kPi * (ring + 0.5) / (rings + 1) - kPi / 2;
    const double lon = 2 * kPi * slot / per_ring;
    const Eigen::Vector3d up(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon),
                             std::sin(lat));
    const Eigen::Vector3d forward(-std::sin(lon), std::cos(lon), 0.0);
    poses.emplace_back(frame(forward, up), o.scale * up);
    if (ring > 0) loops.emplace_back(k - per_ring, k);
  }
}

/// True poses and candidate loop-closure pairs of a snake through a cubic lattice.
void gridPoses(const PoseGraph3dOptions& o, std::vector<SE3>& poses, std::vector<Pair>& loops) {
  const int side = std::max(2, static_cast<int>(std::ceil(std::cbrt(o.num_poses))));
  std::map<std::array<int, 3>, int> visited;
  Eigen::Vector3d last_forward = Eigen::Vector3d::UnitX();
  std::vector<std::array<int, 3>> cells;
  for (int k = 0; k < o.num_poses; ++k) {
    const int layer = k / (side * side), in_layer = k % (side * side);
    int row = in_layer / side, col = in_layer % side;
    if (row % 2 == 1) col = side - 1 - col;    // boustrophedon within a layer
    if (layer % 2 == 1) row = side - 1 - row;  // and back across layers
    cells.push_back({col, row, layer});
  }
  for (int k = 0; k < o.num_poses; ++k) {
    const auto& c = cells[static_cast<std::size_t>(k)];
    const Eigen::Vector3d p = o.scale * Eigen::Vector3d(c[0], c[1], c[2]);
    if (k + 1 < o.num_poses) {
      const auto& n = cells[static_cast<std::size_t>(k + 1)];
      const Eigen::Vector3d step(n[0] - c[0], n[1] - c[1], n[2] - c[2]);
      if (step.z() == 0.0) last_forward = step;  // vertical steps keep the heading
    }
    poses.emplace_back(frame(last_forward, Eigen::Vector3d::UnitZ()), p);
    for (const auto& d :
         {std::array<int, 3>{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}) {
      auto it = visited.find({c[0] + d[0], c[1] + d[1], c[2] + d[2]});
      if (it != visited.end() && it->second != k - 1) loops.emplace_back(it->second, k);
    }
    visited[c] = k;
  }
}

/// The poses within `range` of `p`, by id.
std::vector<int> posesInRange(const std::vector<SE3>& poses, const Eigen::Vector3d& p,
                              double range) {
  std::vector<int> near;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if ((poses[k].translation() - p).norm() <= range) near.push_back(static_cast<int>(k));
  }
  return near;
}

/// Adds the points of PoseGraph3dOptions::num_points, their observations and the sensor
/// offset parameter they refer to.
void addPoints(const PoseGraph3dOptions& o, std::mt19937& rng, SimulatedGraph3d& out) {
  if (o.num_points <= 0) return;
  Eigen::Vector3d lo = out.true_poses[0].translation(), hi = lo;
  for (const SE3& x : out.true_poses) {
    lo = lo.cwiseMin(x.translation());
    hi = hi.cwiseMax(x.translation());
  }
  lo.array() -= o.point_range;
  hi.array() += o.point_range;
  auto sensor = std::make_unique<types_slam3d::ParameterSE3Offset>();
  sensor->setId(0);
  sensor->setValue(SE3());
  out.graph.addParameter(std::move(sensor));
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, o.sigma_point);
  const Eigen::Matrix3d info = Eigen::Matrix3d::Identity() / (o.sigma_point * o.sigma_point);
  const int first_id = static_cast<int>(out.true_poses.size());
  for (int m = 0; m < o.num_points; ++m) {
    Eigen::Vector3d p;
    std::vector<int> seen_from;
    for (int draw = 0;; ++draw) {
      if (draw == o.max_point_draws) {
        throw Error("simulatePoseGraph3d: no place for point " + std::to_string(m) + " seen from " +
                    std::to_string(o.min_observations) + " poses within " +
                    std::to_string(o.point_range) + " m after " +
                    std::to_string(o.max_point_draws) + " draws (raise point_range)");
      }
      for (int k = 0; k < 3; ++k) p[k] = lo[k] + (hi[k] - lo[k]) * u01(rng);
      seen_from = posesInRange(out.true_poses, p, o.point_range);
      if (static_cast<int>(seen_from.size()) >= o.min_observations) break;
    }
    out.true_points.push_back(p);
    const VertexId id = first_id + m;
    auto v = std::make_unique<types_slam3d::VertexPointXYZ>();
    v->setId(id);
    bool placed = false;
    std::vector<std::unique_ptr<Edge>> edges;
    for (int k : seen_from) {
      const SE3& x = out.true_poses[static_cast<std::size_t>(k)];
      const Eigen::Vector3d z =
          x.inverse() * p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      if (!placed) {  // from the first observation, seen from the pose's estimate
        const auto& pose = static_cast<const types_slam3d::VertexSE3&>(*out.graph.vertex(k));
        v->setEstimate(pose.estimate() * z);
        placed = true;
      }
      auto e = std::make_unique<types_slam3d::EdgeSE3PointXYZ>();
      e->setVertexIds({k, id});
      e->setParameterId(0, 0);
      e->setMeasurement(z);
      e->setInformation(info);
      edges.push_back(std::move(e));
    }
    out.graph.addVertex(std::move(v));
    for (auto& e : edges) out.graph.addEdge(std::move(e));
    out.num_point_observations += edges.size();
  }
}

}  // namespace

SimulatedGraph3d simulatePoseGraph3d(const PoseGraph3dOptions& o) {
  if (o.num_poses < 2) throw Error("simulatePoseGraph3d: at least 2 poses");
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  SimulatedGraph3d out;
  std::vector<Pair> loops;
  if (o.shape == PoseGraph3dOptions::Shape::kSphere) {
    spherePoses(o, out.true_poses, loops);
  } else {
    gridPoses(o, out.true_poses, loops);
  }
  geometry::Matrix6d info = geometry::Matrix6d::Zero();
  info.diagonal().head<3>().setConstant(1.0 / (o.sigma_translation * o.sigma_translation));
  info.diagonal().tail<3>().setConstant(4.0 / (o.sigma_rotation * o.sigma_rotation));
  auto measure = [&](int i, int j) {
    geometry::Vector6d noise;
    for (int k = 0; k < 3; ++k) noise[k] = o.sigma_translation * n01(rng);
    for (int k = 3; k < 6; ++k) noise[k] = o.sigma_rotation * n01(rng);
    const auto& t = out.true_poses;
    const SE3 rel = t[static_cast<std::size_t>(i)].inverse() * t[static_cast<std::size_t>(j)];
    return SE3(rel.so3() * SO3::exp(noise.tail<3>()), rel.translation() + noise.head<3>());
  };
  auto addEdge = [&](int i, int j, const SE3& z) {
    auto e = std::make_unique<types_slam3d::EdgeSE3>();
    e->setVertexIds({i, j});
    e->setMeasurement(z);
    e->setInformation(info);
    out.graph.addEdge(std::move(e));
  };
  SE3 estimate = out.true_poses[0];
  std::vector<SE3> odometry;
  for (int k = 0; k + 1 < o.num_poses; ++k) odometry.push_back(measure(k, k + 1));
  for (int k = 0; k < o.num_poses; ++k) {
    auto v = std::make_unique<types_slam3d::VertexSE3>();
    v->setId(k);
    v->setEstimate(estimate);
    out.graph.addVertex(std::move(v));
    if (k + 1 < o.num_poses) estimate = estimate * odometry[static_cast<std::size_t>(k)];
  }
  for (int k = 0; k + 1 < o.num_poses; ++k)
    addEdge(k, k + 1, odometry[static_cast<std::size_t>(k)]);
  for (const auto& [i, j] : loops) {
    if (u01(rng) >= o.loop_probability) continue;
    addEdge(i, j, measure(i, j));
    ++out.num_loop_closures;
  }
  addPoints(o, rng, out);
  return out;
}

}  // namespace graphslam::simulation
