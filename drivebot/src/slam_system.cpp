// SPDX-License-Identifier: MIT
#include "graphslam/drivebot/slam_system.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <set>

#include "graphslam/support/error.h"
#include "graphslam/types_drivebot/edge_compass.h"
#include "graphslam/types_drivebot/edge_gps.h"
#include "graphslam/types_drivebot/edge_landmark_range_bearing.h"
#include "graphslam/types_drivebot/edge_vehicle_kinematics.h"
#include "graphslam/types_drivebot/edge_vehicle_prior.h"
#include "graphslam/types_drivebot/vertex_landmark.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

namespace graphslam::drivebot {

using namespace graphslam::types_drivebot;

const char* toString(PredictionEdgeRemoval removal) {
  switch (removal) {
    case PredictionEdgeRemoval::kNone:
      return "none";
    case PredictionEdgeRemoval::kAll:
      return "all";
    case PredictionEdgeRemoval::kKeepFirst:
      return "keep-first";
  }
  return "?";
}

const char* toString(PruneRule rule) {
  switch (rule) {
    case PruneRule::kNone:
      return "none";
    case PruneRule::kEverySecond:
      return "every-second";
    case PruneRule::kCoursework:
      return "coursework";
    case PruneRule::kStaggered:
      return "staggered";
    case PruneRule::kKeyframe:
      return "keyframe";
  }
  return "?";
}

namespace {

/// Inverse of an event's covariance, checked to be symmetric positive definite.
template <int N>
Eigen::Matrix<double, N, N> informationOf(const Event& event) {
  if (event.covariance.rows() != N || event.covariance.cols() != N) {
    throw Error(std::string("DriveBot SLAM: ") + toString(event.type) +
                " event at t = " + std::to_string(event.time) + " needs a " + std::to_string(N) +
                "x" + std::to_string(N) + " covariance");
  }
  const Eigen::Matrix<double, N, N> cov = event.covariance;
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(cov);
  if (llt.info() != Eigen::Success || !cov.isApprox(cov.transpose())) {
    throw Error(std::string("DriveBot SLAM: ") + toString(event.type) + " event at t = " +
                std::to_string(event.time) + ": covariance is not symmetric positive definite");
  }
  return llt.solve(Eigen::Matrix<double, N, N>::Identity());
}

void expectValueSize(const Event& event, int n) {
  if (event.value.size() != n) {
    throw Error(std::string("DriveBot SLAM: ") + toString(event.type) +
                " event at t = " + std::to_string(event.time) + " needs " + std::to_string(n) +
                " values, has " + std::to_string(event.value.size()));
  }
}

}  // namespace

DriveBotSlamSystem::DriveBotSlamSystem(const SolverRegistry& solvers, SlamSystemOptions options)
    : options_(std::move(options)),
      optimizer_(std::make_unique<Optimizer>(graph_, solvers, options_.optimizer)),
      marginals_(MarginalCovariance::Options{true, &solvers, Ordering::kAmd}) {
  if (options_.optimize_every < 0) throw Error("DriveBot SLAM: optimize_every must be >= 0");
  if (options_.max_iterations < 1) throw Error("DriveBot SLAM: max_iterations must be >= 1");
  if (options_.prune_every < 1) throw Error("DriveBot SLAM: prune_every must be >= 1");
  if (windowed()) {
    if (!usesIncremental()) {
      throw Error(
          "DriveBot SLAM: the fixed-lag window needs the incremental optimizer (not with "
          "prediction-edge removal, the coursework's pruning or the unwrapped compass error)");
    }
    on_marginalised_ = std::move(options_.incremental_options.window.on_marginalised);
    options_.incremental_options.window.on_marginalised =
        [this](const Vertex& v, const incremental::WindowState* s) { recordMarginalized(v, s); };
  }
  if (usesIncremental()) {
    incremental_ =
        std::make_unique<incremental::IncrementalOptimizer>(graph_, options_.incremental_options);
  }
}

bool DriveBotSlamSystem::usesIncremental() const {
  // The coursework's unwrapped compass error jumps by 2 pi where the heading wraps:
  // undamped Gauss-Newton passes diverge on it, the batch optimizer's damping does not.
  return options_.incremental && options_.remove_prediction_edges == PredictionEdgeRemoval::kNone &&
         options_.prune != PruneRule::kCoursework && options_.compass_wrap_error;
}

Vertex& DriveBotSlamSystem::addVertex(std::unique_ptr<Vertex> vertex) {
  return incremental_ ? incremental_->addVertex(std::move(vertex))
                      : graph_.addVertex(std::move(vertex));
}

Edge& DriveBotSlamSystem::addEdge(std::unique_ptr<Edge> edge) {
  return incremental_ ? incremental_->addEdge(std::move(edge)) : graph_.addEdge(std::move(edge));
}

DriveBotSlamSystem::~DriveBotSlamSystem() = default;

void DriveBotSlamSystem::processEvents(const std::vector<Event>& events) {
  ++step_number_;
  for (const Event& e : events) processEvent(e);
}

void DriveBotSlamSystem::processEvent(const Event& event) {
  if (initialized()) {
    const double dt = event.time - current_time_;
    if (std::abs(dt) >= 1e-3) {
      predictToTime(event.time, dt);
      current_time_ = event.time;
    }
  }
  switch (event.type) {
    case EventType::kInitialCondition:
      if (initialized()) throw Error("DriveBot SLAM: a second initial condition event");
      handleInitialCondition(event);
      break;
    case EventType::kOdometry:
      expectValueSize(event, 3);
      u_information_ = informationOf<3>(event);
      u_ = event.value;
      have_odometry_ = true;
      break;
    case EventType::kGps:
      if (initialized()) handleGps(event);
      break;
    case EventType::kCompass:
      if (initialized()) handleCompass(event);
      break;
    case EventType::kLandmarks:
      if (initialized()) handleLandmarks(event);
      break;
    case EventType::kHeartbeat:
      break;
  }
}

void DriveBotSlamSystem::handleInitialCondition(const Event& event) {
  expectValueSize(event, 3);
  auto v = std::make_unique<VertexVehicle>();
  v->setId(next_id_++);
  v->setTime(event.time);
  v->setEstimate(event.value);
  current_time_ = event.time;
  const bool known = event.covariance.rows() == 3 && event.covariance.cols() == 3 &&
                     event.covariance.determinant() < options_.fixed_initial_det;
  v->setFixed(known);
  current_vehicle_ = static_cast<VertexVehicle*>(&addVertex(std::move(v)));
  vehicle_ids_.push_back(current_vehicle_->id());
  if (windowed()) incremental_->addState(current_vehicle_->id(), event.time);
  if (!known) {
    auto prior = std::make_unique<EdgeVehiclePrior>();
    prior->setVertexId(0, current_vehicle_->id());
    prior->setMeasurement(event.value);
    prior->setInformation(informationOf<3>(event));
    addEdge(std::move(prior));
  }
}

void DriveBotSlamSystem::predictToTime(double time, double dt) {
  if (!have_odometry_) {
    throw Error("DriveBot SLAM: an event at t = " + std::to_string(time) +
                " needs a prediction, but no odometry has been received yet");
  }
  auto v = std::make_unique<VertexVehicle>();
  v->setId(next_id_++);
  v->setTime(time);
  auto* next = static_cast<VertexVehicle*>(&addVertex(std::move(v)));
  auto edge = std::make_unique<EdgeVehicleKinematics>();
  edge->setVertexId(0, current_vehicle_->id());
  edge->setVertexId(1, next->id());
  edge->setDeltaT(dt);
  edge->setMeasurement(u_);
  edge->setInformation(u_information_);
  auto& added = static_cast<EdgeVehicleKinematics&>(addEdge(std::move(edge)));
  added.initializeSecond();
  if (current_vehicle_->id() == vehicle_ids_.front()) first_prediction_edge_ = &added;
  current_vehicle_ = next;
  vehicle_ids_.push_back(next->id());
  if (windowed()) incremental_->addState(next->id(), time);
}

void DriveBotSlamSystem::handleGps(const Event& event) {
  expectValueSize(event, 2);
  auto edge = std::make_unique<EdgeGps>();
  edge->setVertexId(0, current_vehicle_->id());
  edge->setOffset(options_.gps_offset);
  edge->setMeasurement(event.value);
  edge->setInformation(informationOf<2>(event));
  addEdge(std::move(edge));
}

void DriveBotSlamSystem::handleCompass(const Event& event) {
  expectValueSize(event, 1);
  auto edge = std::make_unique<EdgeCompass>();
  edge->setVertexId(0, current_vehicle_->id());
  edge->setOffset(options_.compass_offset);
  edge->setWrapError(options_.compass_wrap_error);
  edge->setMeasurement(event.value[0]);
  edge->setInformation(informationOf<1>(event));
  addEdge(std::move(edge));
}

std::vector<bool> DriveBotSlamSystem::selectObservations(const Event& event) {
  const auto& obs = event.observations;
  std::vector<bool> keep(obs.size(), true);
  auto is_new = [&](const RangeBearing& o) { return landmark_ids_.count(o.landmark_id) == 0; };
  auto seen = [&](const std::map<int, int>& counts, int id) {
    const auto it = counts.find(id);
    return it == counts.end() ? 0 : it->second;
  };
  const int n = options_.prune_every;
  switch (options_.prune) {
    case PruneRule::kNone:
    case PruneRule::kCoursework:  // prunes the graph at optimize(), not on arrival
      break;
    case PruneRule::kEverySecond:
      for (std::size_t k = 0; k < obs.size(); ++k) {
        keep[k] = seen(sightings_, obs[k].landmark_id) % n == 0;
      }
      break;
    case PruneRule::kStaggered:
      // Landmark j's phase is offset by j: scans are thinned partly, not dropped whole.
      for (std::size_t k = 0; k < obs.size(); ++k) {
        const int id = obs[k].landmark_id;
        keep[k] = is_new(obs[k]) || (seen(sightings_, id) + id) % n == 0;
      }
      break;
    case PruneRule::kKeyframe: {
      const Eigen::Vector3d x = current_vehicle_->estimate();
      const bool sees_new = std::any_of(obs.begin(), obs.end(), is_new);
      const bool keyframe =
          keyframe_vertex_ == current_vehicle_->id() || !have_keyframe_ || sees_new ||
          (x.head<2>() - last_keyframe_.head<2>()).norm() >= options_.keyframe_distance ||
          std::abs(wrapAngle(x[2] - last_keyframe_[2])) >= options_.keyframe_angle;
      if (keyframe) {
        have_keyframe_ = true;
        last_keyframe_ = x;
        keyframe_vertex_ = current_vehicle_->id();
      }
      for (std::size_t k = 0; k < obs.size(); ++k) keep[k] = keyframe || is_new(obs[k]);
      break;
    }
  }
  return keep;
}

void DriveBotSlamSystem::handleLandmarks(const Event& event) {
  const Eigen::Matrix2d information = informationOf<2>(event);
  const std::vector<bool> keep = selectObservations(event);
  for (std::size_t k = 0; k < event.observations.size(); ++k) {
    const RangeBearing& o = event.observations[k];
    ++observations_received_;
    ++sightings_[o.landmark_id];
    last_seen_step_[o.landmark_id] = step_number_;
    if (!keep[k]) continue;
    auto found = landmark_ids_.find(o.landmark_id);
    const bool is_new = found == landmark_ids_.end();
    bool restarted = false;
    if (!is_new && windowed() && !windowTakesObservation(found->second, restarted)) continue;
    if (is_new) {
      auto l = std::make_unique<VertexLandmark>();
      l->setId(next_id_++);
      const VertexId id = addVertex(std::move(l)).id();
      found = landmark_ids_.emplace(o.landmark_id, id).first;
      landmark_of_vertex_.emplace(id, o.landmark_id);
    }
    auto edge = std::make_unique<EdgeLandmarkRangeBearing>();
    edge->setVertexId(0, current_vehicle_->id());
    edge->setVertexId(1, found->second);
    edge->setMeasurement(Eigen::Vector2d(o.range, o.bearing));
    edge->setInformation(information);
    auto& added = static_cast<EdgeLandmarkRangeBearing&>(addEdge(std::move(edge)));
    if (is_new || restarted) added.initializeLandmark();
  }
}

bool DriveBotSlamSystem::recommendOptimization() const {
  return options_.optimize_every > 0 && step_number_ % options_.optimize_every == 0;
}

void DriveBotSlamSystem::removePredictionEdges() {
  if (options_.remove_prediction_edges == PredictionEdgeRemoval::kNone) return;
  const bool keep_first = options_.remove_prediction_edges == PredictionEdgeRemoval::kKeepFirst;
  graph_.removeEdges([&](const Edge& e) {
    return dynamic_cast<const EdgeVehicleKinematics*>(&e) != nullptr &&
           !(keep_first && &e == first_prediction_edge_);
  });
  if (!keep_first) first_prediction_edge_ = nullptr;
}

void DriveBotSlamSystem::pruneObservationEdges() {
  if (options_.prune != PruneRule::kCoursework) return;
  // Edges are kept in insertion order, so each landmark's edges come in time order.
  std::map<VertexId, int> seen;  // landmark vertex -> its observation edges so far
  std::set<const Edge*> drop;
  for (const auto& e : graph_.edges()) {
    if (dynamic_cast<const EdgeLandmarkRangeBearing*>(e.get()) == nullptr) continue;
    if (seen[e->vertexId(1)]++ % options_.prune_every != 0) drop.insert(e.get());
  }
  if (!drop.empty()) graph_.removeEdges([&](const Edge& e) { return drop.count(&e) != 0; });
}

Summary DriveBotSlamSystem::optimize(int max_iterations) {
  if (!incremental_ || !initialized()) return optimizeBatch(max_iterations);
  Summary summary;
  summary.num_edges = graph_.numEdges();
  summary.initial_chi2 = summary.final_chi2 = std::nan("");
  // Gauss-Newton passes without damping can fail where the batch optimizer's damping goes
  // on (the coursework's unwrapped compass error jumps by 2 pi): a failed update falls
  // back to one batch optimisation, which also restarts the incremental factor.
  if (!incremental_->update()) return optimizeBatch(max_iterations);
  summary.status = TerminationStatus::kConverged;
  summary.iterations = incremental_->lastStats().passes;
  return summary;
}

Summary DriveBotSlamSystem::optimizeBatch(int max_iterations) {
  Summary summary;
  if (!initialized()) {
    summary.status = TerminationStatus::kUnderDetermined;
    summary.message = "the SLAM system has no initial condition yet";
    return summary;
  }
  removePredictionEdges();
  pruneObservationEdges();
  // With every prediction edge in place each vehicle state hangs off the first one (fixed
  // or under a prior) by a 3-dimensional edge and each landmark has an observation, so the
  // check can only find something once prediction edges are removed (it costs about a
  // tenth of an optimisation of an otherwise converged graph).
  constraints_ = options_.remove_prediction_edges == PredictionEdgeRemoval::kNone
                     ? ConstraintReport{}
                     : checkConstraints(graph_);
  // Vertices without edges are left out of the optimisation and keep their estimates;
  // groups with no anchor or under-measured vertices would make the system singular.
  if (!constraints_.unanchored.empty() || !constraints_.too_few_measurements.empty()) {
    summary.status = TerminationStatus::kUnderDetermined;
    summary.message = diagnose(constraints_);
    summary.initial_chi2 = summary.final_chi2 = graph_.chi2();
    summary.num_edges = graph_.numEdges();
    summary.unanchored = constraints_.unanchored;
    return summary;
  }
  optimizer_->mutableOptions().max_iterations =
      max_iterations > 0 ? max_iterations : options_.max_iterations;
  summary = optimizer_->optimize();
  // The batch run moved the estimates: the incremental factor starts again from them (a
  // window keeps its states and what left).
  if (incremental_) incremental_->restart();
  return summary;
}

std::string DriveBotSlamSystem::describeVertices(const std::vector<VertexId>& ids) const {
  std::vector<VertexId> vehicles, landmark_vertices;
  std::vector<VertexId> landmark_numbers;  // landmark ids, for the message
  double t0 = 0.0, t1 = 0.0;
  for (VertexId id : ids) {
    const auto l = landmark_of_vertex_.find(id);
    if (l != landmark_of_vertex_.end()) {
      landmark_vertices.push_back(id);
      landmark_numbers.push_back(l->second);
      continue;
    }
    const auto* v = dynamic_cast<const VertexVehicle*>(graph_.vertex(id));
    if (v == nullptr) continue;
    if (vehicles.empty()) t0 = v->time();
    t1 = v->time();
    vehicles.push_back(id);
  }
  std::string out;
  if (!vehicles.empty()) {
    char times[80];
    std::snprintf(times, sizeof times, "t = %.1f-%.1f s", t0, t1);
    out += std::to_string(vehicles.size()) + " vehicle vertices " + formatIdRanges(vehicles, 12) +
           " (" + times + ")";
  }
  if (!landmark_vertices.empty()) {
    if (!out.empty()) out += " and ";
    std::sort(landmark_numbers.begin(), landmark_numbers.end());
    out += std::to_string(landmark_vertices.size()) + " landmark vertices " +
           formatIdRanges(landmark_vertices, 12) + " (landmarks " +
           formatIdRanges(landmark_numbers, 12) + ")";
  }
  return out;
}

std::string DriveBotSlamSystem::diagnose(const ConstraintReport& report) const {
  std::string out = "the graph does not determine every vertex, not optimising:";
  for (const auto& group : report.unanchored) {
    out += "\n  no fixed vertex or prior connects to " + describeVertices(group) +
           ": they can translate and rotate freely together";
  }
  if (!report.without_edges.empty()) {
    out += "\n  no edge at all on " + describeVertices(report.without_edges);
  }
  if (!report.too_few_measurements.empty()) {
    out += "\n  fewer measured dimensions than unknowns on " +
           describeVertices(report.too_few_measurements) +
           " (a vehicle state needs 3, e.g. two landmark observations or a prediction edge)";
  }
  const VertexId first = vehicle_ids_.front();
  if (options_.remove_prediction_edges == PredictionEdgeRemoval::kAll &&
      graph_.vertex(first)->fixed() && graph_.vertex(first)->edges().empty()) {
    out += "\n  cause: all prediction edges were removed, so the fixed first vehicle vertex " +
           std::to_string(first) +
           " has no edge left and nothing ties the map and the trajectory to it; keep the "
           "first prediction edge (remove all but the first) to anchor them";
  } else if (options_.remove_prediction_edges != PredictionEdgeRemoval::kNone) {
    out += "\n  cause: prediction edges were removed (" +
           std::string(toString(options_.remove_prediction_edges)) +
           "), so vehicle states rest on landmark observations alone";
  }
  return out;
}

Eigen::Vector3d DriveBotSlamSystem::currentVehicleEstimate() const {
  return current_vehicle_ ? current_vehicle_->estimate() : Eigen::Vector3d::Zero();
}

VertexId DriveBotSlamSystem::currentVehicleVertex() const {
  return current_vehicle_ ? current_vehicle_->id() : -1;
}

MarginalSummary DriveBotSlamSystem::currentVehicleCovariance(Eigen::Matrix3d& covariance) {
  covariance.setZero();
  if (!current_vehicle_) {
    MarginalSummary s;
    s.status = MarginalStatus::kUnconstrained;
    s.message = "the SLAM system has no vehicle state yet";
    return s;
  }
  MarginalSummary s = marginals_.compute(graph_, {current_vehicle_->id()});
  if (s.ok()) covariance = marginals_.block(current_vehicle_->id());
  return s;
}

std::vector<int> DriveBotSlamSystem::loopClosureLandmarks(const std::vector<Event>& events) const {
  std::vector<int> out;
  for (const Event& e : events) {
    if (e.type != EventType::kLandmarks) continue;
    for (const auto& o : e.observations) {
      const auto it = last_seen_step_.find(o.landmark_id);
      // This batch would be step step_number_ + 1.
      if (it != last_seen_step_.end() &&
          step_number_ + 1 - it->second >= options_.loop_closure_gap) {
        out.push_back(o.landmark_id);
      }
    }
  }
  return out;
}

GraphStatistics DriveBotSlamSystem::statistics() const {
  GraphStatistics s;
  s.vehicle_vertices = vehicle_ids_.size();
  s.landmark_vertices = landmark_ids_.size();
  s.edges = graph_.numEdges();
  s.observations_received = observations_received_;
  for (const auto& e : graph_.edges()) {
    if (dynamic_cast<const EdgeVehicleKinematics*>(e.get())) {
      ++s.prediction_edges;
    } else if (dynamic_cast<const EdgeLandmarkRangeBearing*>(e.get())) {
      ++s.observation_edges;
      ++s.observations_of_landmark[landmark_of_vertex_.at(e->vertexId(1))];
    } else if (dynamic_cast<const EdgeGps*>(e.get())) {
      ++s.gps_edges;
    } else if (dynamic_cast<const EdgeCompass*>(e.get())) {
      ++s.compass_edges;
    } else if (dynamic_cast<const EdgeVehiclePrior*>(e.get())) {
      ++s.prior_edges;
    }
  }
  if (s.vehicle_vertices > 0) {
    s.observations_per_vehicle_vertex =
        static_cast<double>(s.observation_edges) / static_cast<double>(s.vehicle_vertices);
  }
  if (s.landmark_vertices > 0) {
    s.observations_per_landmark =
        static_cast<double>(s.observation_edges) / static_cast<double>(s.landmark_vertices);
  }
  return s;
}

}  // namespace graphslam::drivebot
