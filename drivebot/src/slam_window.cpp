// SPDX-License-Identifier: MIT
// DriveBotSlamSystem's estimates for the run's results (landmarks, vehicle history) and its
// fixed-lag window: the estimates of the vertices that left it, and observations of
// landmarks that left.
#include <cmath>

#include "graphslam/drivebot/slam_system.h"
#include "graphslam/types_drivebot/vertex_landmark.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

namespace graphslam::drivebot {

using types_drivebot::VertexLandmark;
using types_drivebot::VertexVehicle;

std::size_t DriveBotSlamSystem::marginalizedCount() const {
  return incremental_ ? incremental_->marginalizedCount() : 0;
}

void DriveBotSlamSystem::recordMarginalized(const Vertex& vertex,
                                            const incremental::WindowState* state) {
  if (const auto* v = dynamic_cast<const VertexVehicle*>(&vertex)) {
    frozen_vehicles_[v->id()] = FrozenVehicle{v->time(), v->estimate()};
    // The first prediction edge leaves with the first vehicle vertex.
    if (v->id() == vehicle_ids_.front()) first_prediction_edge_ = nullptr;
  } else if (const auto* l = dynamic_cast<const VertexLandmark*>(&vertex)) {
    frozen_landmarks_[l->id()] = l->estimate();
  }
  if (on_marginalised_) on_marginalised_(vertex, state);
}

bool DriveBotSlamSystem::windowTakesObservation(VertexId vertex, bool& restarted) {
  if (!incremental_->isMarginalized(vertex)) return true;
  if (!options_.incremental_options.window.reinitialize_landmarks) {
    ++refused_observations_;
    return false;
  }
  frozen_landmarks_.erase(vertex);
  auto l = std::make_unique<VertexLandmark>();
  l->setId(vertex);
  addVertex(std::move(l));
  restarted = true;
  return true;
}

MarginalSummary DriveBotSlamSystem::landmarkEstimates(std::vector<LandmarkEstimate>& out) {
  out.clear();
  std::vector<VertexId> ids;  // those in the graph
  for (const auto& [landmark, vertex] : landmark_ids_) {
    if (graph_.hasVertex(vertex)) ids.push_back(vertex);
  }
  if (landmark_ids_.empty()) return {};
  MarginalSummary s = ids.empty() ? MarginalSummary{} : marginals_.compute(graph_, ids);
  for (const auto& [landmark, vertex] : landmark_ids_) {
    LandmarkEstimate e;
    e.landmark_id = landmark;
    e.vertex = vertex;
    e.last_seen_step = last_seen_step_.at(landmark);
    if (const auto* v = static_cast<const VertexLandmark*>(graph_.vertex(vertex))) {
      e.x = v->estimate();
      if (s.ok()) e.covariance = marginals_.block(vertex);
      e.observations = static_cast<int>(v->edges().size());
    } else {
      e.x = frozen_landmarks_.at(vertex);
      e.covariance.setConstant(std::nan(""));
    }
    out.push_back(e);
  }
  return s;
}

MarginalSummary DriveBotSlamSystem::vehicleHistory(VehicleHistory& out) {
  out = VehicleHistory{};
  std::vector<VertexId> determined;  // vertices without edges have no covariance
  for (VertexId id : vehicle_ids_) {
    const Vertex* v = graph_.vertex(id);
    if (v && (v->fixed() || !v->edges().empty())) determined.push_back(id);
  }
  MarginalSummary s = marginals_.compute(graph_, determined);
  for (VertexId id : vehicle_ids_) {
    const auto* v = static_cast<const VertexVehicle*>(graph_.vertex(id));
    if (!v) {  // marginalised: its estimate as it left the window
      const FrozenVehicle& f = frozen_vehicles_.at(id);
      out.time.push_back(f.time);
      out.x.push_back(f.x);
      out.variance.push_back(Eigen::Vector3d::Constant(std::nan("")));
      continue;
    }
    out.time.push_back(v->time());
    out.x.push_back(v->estimate());
    out.variance.push_back(s.ok() && marginals_.hasBlock(id)
                               ? Eigen::Vector3d(marginals_.block(id).diagonal())
                               : Eigen::Vector3d::Constant(std::nan("")));
  }
  return s;
}

}  // namespace graphslam::drivebot
