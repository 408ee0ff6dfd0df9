// SPDX-License-Identifier: MIT
// Checkpoints of DriveBotSlamSystem: the incremental optimizer's checkpoint (graph, window,
// estimates) with the system's own state in its note (ids, the current vehicle state and
// odometry, landmark bookkeeping, the estimates of the vertices that left the window).
#include <Eigen/Core>

#include "graphslam/drivebot/slam_system.h"
#include "graphslam/incremental/checkpoint_bytes.h"
#include "graphslam/support/error.h"
#include "graphslam/types_drivebot/edge_vehicle_kinematics.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

namespace graphslam::drivebot {

namespace {

using incremental::ByteReader;
using incremental::ByteWriter;

constexpr char kStateMark[] = "DRIVEBOT-SLAM-1";

template <typename Derived>
void putMatrix(ByteWriter& w, const Eigen::MatrixBase<Derived>& m) {
  const Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime> c = m;
  w.putDoubles(c.data(), static_cast<std::size_t>(c.size()));
}

template <typename M>
void getMatrix(ByteReader& r, M& m) {
  const std::vector<double> v = r.getDoubles(static_cast<std::size_t>(m.size()));
  m = Eigen::Map<const M>(v.data());
}

template <typename K, typename V>
void putMap(ByteWriter& w, const std::map<K, V>& m) {
  w.put<std::uint64_t>(m.size());
  for (const auto& [k, v] : m) {
    w.put<std::int64_t>(k);
    w.put<std::int64_t>(v);
  }
}

template <typename K, typename V>
void getMap(ByteReader& r, std::map<K, V>& m) {
  m.clear();
  const auto n = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < n; ++k) {
    const auto key = static_cast<K>(r.get<std::int64_t>());
    m[key] = static_cast<V>(r.get<std::int64_t>());
  }
}

}  // namespace

void DriveBotSlamSystem::saveCheckpoint(const std::string& path, const TypeRegistry& types,
                                        const std::string& note) {
  if (!incremental_) {
    throw Error("DriveBot SLAM: checkpoints need the incremental optimizer (usesIncremental())");
  }
  ByteWriter w;
  w.putString(kStateMark);
  w.put<std::int64_t>(next_id_);
  w.put<std::int64_t>(step_number_);
  w.put(current_time_);
  w.put<std::int64_t>(currentVehicleVertex());
  w.put<std::uint64_t>(vehicle_ids_.size());
  for (VertexId id : vehicle_ids_) w.put<std::int64_t>(id);
  putMap(w, landmark_ids_);
  putMap(w, last_seen_step_);
  putMap(w, sightings_);
  w.put<std::uint8_t>(have_odometry_ ? 1 : 0);
  putMatrix(w, u_);
  putMatrix(w, u_information_);
  w.put<std::uint64_t>(observations_received_);
  w.put<std::uint8_t>(have_keyframe_ ? 1 : 0);
  putMatrix(w, last_keyframe_);
  w.put<std::int64_t>(keyframe_vertex_);
  w.put<std::uint64_t>(frozen_vehicles_.size());
  for (const auto& [id, f] : frozen_vehicles_) {
    w.put<std::int64_t>(id);
    w.put(f.time);
    putMatrix(w, f.x);
  }
  w.put<std::uint64_t>(frozen_landmarks_.size());
  for (const auto& [id, x] : frozen_landmarks_) {
    w.put<std::int64_t>(id);
    putMatrix(w, x);
  }
  w.put<std::uint64_t>(refused_observations_);
  w.putString(note);
  incremental_->saveCheckpoint(path, types, w.bytes());
}

std::string DriveBotSlamSystem::loadCheckpoint(const std::string& path, const TypeRegistry& types) {
  if (!incremental_) {
    throw Error("DriveBot SLAM: checkpoints need the incremental optimizer (usesIncremental())");
  }
  if (initialized() || graph_.numVertices() > 0) {
    throw Error("DriveBot SLAM: a checkpoint is loaded into a system that has seen no event");
  }
  const std::string state = incremental_->loadCheckpoint(path, types);
  ByteReader r(state, path);
  if (r.getString() != kStateMark) r.fail("not a DriveBot SLAM system's checkpoint");
  next_id_ = static_cast<VertexId>(r.get<std::int64_t>());
  step_number_ = static_cast<long>(r.get<std::int64_t>());
  current_time_ = r.get<double>();
  const auto current = static_cast<VertexId>(r.get<std::int64_t>());
  vehicle_ids_.resize(r.get<std::uint64_t>());
  for (VertexId& id : vehicle_ids_) id = static_cast<VertexId>(r.get<std::int64_t>());
  getMap(r, landmark_ids_);
  getMap(r, last_seen_step_);
  getMap(r, sightings_);
  have_odometry_ = r.get<std::uint8_t>() != 0;
  getMatrix(r, u_);
  getMatrix(r, u_information_);
  observations_received_ = r.get<std::uint64_t>();
  have_keyframe_ = r.get<std::uint8_t>() != 0;
  getMatrix(r, last_keyframe_);
  keyframe_vertex_ = static_cast<VertexId>(r.get<std::int64_t>());
  const auto vehicles = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < vehicles; ++k) {
    const auto id = static_cast<VertexId>(r.get<std::int64_t>());
    FrozenVehicle& f = frozen_vehicles_[id];
    f.time = r.get<double>();
    getMatrix(r, f.x);
  }
  const auto landmarks = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < landmarks; ++k) {
    const auto id = static_cast<VertexId>(r.get<std::int64_t>());
    getMatrix(r, frozen_landmarks_[id]);
  }
  refused_observations_ = r.get<std::uint64_t>();
  std::string note = r.getString();
  if (!r.done()) r.fail("bytes after the DriveBot SLAM system's state (inconsistent file)");
  current_vehicle_ = dynamic_cast<types_drivebot::VertexVehicle*>(graph_.vertex(current));
  if (!current_vehicle_)
    r.fail("its current vehicle state " + std::to_string(current) + " is not in its graph");
  for (const auto& [landmark, vertex] : landmark_ids_) landmark_of_vertex_[vertex] = landmark;
  for (const auto& e : graph_.edges()) {
    const auto* k = dynamic_cast<const types_drivebot::EdgeVehicleKinematics*>(e.get());
    if (k && k->vertexId(0) == vehicle_ids_.front()) first_prediction_edge_ = k;
  }
  return note;
}

}  // namespace graphslam::drivebot
