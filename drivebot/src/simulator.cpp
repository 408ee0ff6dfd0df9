// SPDX-License-Identifier: MIT
#include "graphslam/drivebot/simulator.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/se2.h"

namespace graphslam::drivebot {

using types_slam2d::normalizeAngle;

const char* toString(EventType type) {
  switch (type) {
    case EventType::kInitialCondition:
      return "initial-condition";
    case EventType::kOdometry:
      return "odometry";
    case EventType::kGps:
      return "gps";
    case EventType::kCompass:
      return "compass";
    case EventType::kLandmarks:
      return "landmarks";
    case EventType::kHeartbeat:
      return "heartbeat";
  }
  return "?";
}

void OrderedEventQueue::insert(Event event) {
  const auto pos = std::find_if(events_.begin(), events_.end(),
                                [&](const Event& e) { return event.time <= e.time; });
  events_.insert(pos, std::move(event));
}

namespace {

/// SplitMix64: decorrelated seeds for the per-source engines.
std::uint64_t splitMix(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

template <int N>
Eigen::Matrix<double, N, N> choleskyFactor(const Eigen::Matrix<double, N, N>& cov,
                                           const char* what) {
  if (cov.isZero(0.0)) return Eigen::Matrix<double, N, N>::Zero();
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(cov);
  if (llt.info() != Eigen::Success) {
    throw Error(std::string("simulator: the ") + what +
                " covariance is not symmetric positive definite");
  }
  return llt.matrixL();
}

}  // namespace

double Simulator::Random::uniform() {
  return static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0);  // [0, 1)
}

double Simulator::Random::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u, v, s;
  do {
    u = 2.0 * uniform() - 1.0;
    v = 2.0 * uniform() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double f = std::sqrt(-2.0 * std::log(s) / s);
  spare_ = v * f;
  has_spare_ = true;
  return u * f;
}

Simulator::Simulator(Scenario scenario, SimulatorConfig config)
    : scenario_(std::move(scenario)), config_(std::move(config)) {
  if (scenario_.waypoints.empty()) {
    throw Error("simulator: scenario '" + scenario_.name + "' has no waypoints");
  }
  if (!(config_.dt > 0.0)) throw Error("simulator: dt must be positive");
  for (double period : {config_.gps_period, config_.compass_period, config_.laser_period}) {
    if (!(period > 0.0)) throw Error("simulator: sensor periods must be positive");
  }
  step_limit_ = config_.max_steps > 0 ? config_.max_steps : automaticStepLimit();
  odometry_sqrt_ = choleskyFactor<3>(config_.odometry_covariance, "odometry");
  gps_sqrt_ = choleskyFactor<2>(config_.gps_covariance, "GPS");
  start();
}

void Simulator::start() {
  std::uint64_t state = config_.seed;
  for (Random* r : {&rng_odometry_, &rng_gps_, &rng_compass_, &rng_laser_, &rng_timing_}) {
    r->seed(splitMix(state));
  }
  truth_ = VehicleTruth{};
  if (config_.start_at_scenario_x0) truth_.x = scenario_.x0;
  running_ = true;
  next_gps_ = rng_timing_.uniform() * config_.gps_period;
  next_laser_ = rng_timing_.uniform() * config_.laser_period;
  next_compass_ = rng_timing_.uniform() * config_.compass_period;

  queue_.clear();
  queue_.insert(makeEvent(EventType::kInitialCondition, truth_.x, Eigen::Matrix3d::Zero()));
  if (config_.enable_odometry) queue_.insert(odometryEvent());
}

bool Simulator::keepRunning() const { return running_ && truth_.step < step_limit_; }

long Simulator::automaticStepLimit() const {
  const Eigen::Vector2d start = config_.start_at_scenario_x0
                                    ? Eigen::Vector2d(scenario_.x0.head<2>())
                                    : Eigen::Vector2d::Zero();
  double length = 0.0;
  Eigen::Vector2d from = start;
  for (const Eigen::Vector2d& wp : scenario_.waypoints) {
    length += (wp - from).norm();
    from = wp;
  }
  const double steps =
      config_.path_step_factor * length / (std::max(config_.min_speed, 1e-3) * config_.dt) +
      static_cast<double>(config_.path_step_slack);
  if (!(steps <= static_cast<double>(config_.max_automatic_steps))) {
    std::ostringstream msg;
    msg << "scenario '" << scenario_.name << "' (" << scenario_.source << "): its path through "
        << scenario_.waypoints.size() << " waypoints is " << length << " m long, about " << steps
        << " steps, more than the " << config_.max_automatic_steps
        << " a run may take without --max-steps (a waypoint too far away?)";
    throw InputError(msg.str());
  }
  return static_cast<long>(steps);
}

void Simulator::step() {
  if (config_.max_steps <= 0 && truth_.step + 1 >= step_limit_ && running_) {
    const Eigen::Vector2d& wp = scenario_.waypoints[truth_.waypoint_index];
    std::ostringstream msg;
    msg << "scenario '" << scenario_.name << "': the vehicle has not reached waypoint "
        << truth_.waypoint_index + 1 << " of " << scenario_.waypoints.size() << " (" << wp[0]
        << ", " << wp[1] << ") after " << step_limit_ << " steps, " << config_.path_step_factor
        << " times what its path takes at the minimum speed; it looks unreachable (--max-steps "
           "sets the bound)";
    throw InputError(msg.str());
  }
  ++truth_.step;
  queue_.clear();

  const double v_dt = truth_.u[0] * config_.dt;
  const double psi = truth_.x[2];
  truth_.x[0] += v_dt * std::cos(psi);
  truth_.x[1] += v_dt * std::sin(psi);
  truth_.x[2] = normalizeAngle(psi + v_dt * std::sin(truth_.u[1]) / config_.wheelbase);
  truth_.time += config_.dt;

  emitGps();
  emitLaser();
  emitCompass();
  computeControlInputs();
  if (running_ && config_.enable_odometry) queue_.insert(odometryEvent());
}

void Simulator::computeControlInputs() {
  const auto& wps = scenario_.waypoints;
  const Eigen::Vector2d xy = truth_.x.head<2>();
  Eigen::Vector2d dx = wps[truth_.waypoint_index] - xy;
  double d = dx.norm();
  if (d < 1.0) {
    ++truth_.waypoint_index;
    if (truth_.waypoint_index >= static_cast<int>(wps.size())) {
      truth_.waypoint_index = static_cast<int>(wps.size()) - 1;
      running_ = false;
      return;
    }
    const Eigen::Vector2d& wp = wps[truth_.waypoint_index];
    dx = config_.waypoint_sign_quirk ? Eigen::Vector2d(xy - wp) : Eigen::Vector2d(wp - xy);
    d = dx.norm();
  }
  const double max_diff_speed = config_.max_acceleration * config_.dt;
  const double diff_speed = std::clamp(0.1 * d - truth_.u[0], -max_diff_speed, max_diff_speed);
  truth_.u[0] = std::clamp(truth_.u[0] + diff_speed, config_.min_speed, config_.max_speed);

  const double max_diff_steer = config_.max_steer_rate * config_.dt;
  const double diff_steer =
      std::clamp(normalizeAngle(std::atan2(dx[1], dx[0]) - truth_.x[2] - truth_.u[1]),
                 -max_diff_steer, max_diff_steer);
  truth_.u[1] = std::clamp(truth_.u[1] + diff_steer, -config_.max_steer, config_.max_steer);
  running_ = true;
}

Event Simulator::odometryEvent() {
  const double s = truth_.u[0];
  const Eigen::Vector3d u(s, 0.0, s * std::sin(truth_.u[1]) / config_.wheelbase);
  const Eigen::Vector3d n(rng_odometry_.normal(), rng_odometry_.normal(), rng_odometry_.normal());
  return makeEvent(EventType::kOdometry, u + noiseScale() * (odometry_sqrt_ * n),
                   config_.odometry_covariance);
}

bool Simulator::sensorDue(bool enabled, double& next_time, double period, Random& rng) {
  if (!enabled || truth_.time < next_time) return false;
  next_time += period + rng.uniform() * config_.sensor_dither_time;
  return true;
}

Event Simulator::makeEvent(EventType type, Eigen::VectorXd value,
                           Eigen::MatrixXd covariance) const {
  Event e;
  e.type = type;
  e.time = truth_.time;
  e.value = std::move(value);
  e.covariance = std::move(covariance);
  return e;
}

void Simulator::emitGps() {
  if (!sensorDue(config_.enable_gps, next_gps_, config_.gps_period, rng_gps_)) return;
  const Eigen::Vector2d antenna =
      truth_.x.head<2>() + types_slam2d::rotation2(truth_.x[2]) * config_.gps_offset;
  const Eigen::Vector2d n(rng_gps_.normal(), rng_gps_.normal());
  queue_.insert(
      makeEvent(EventType::kGps, antenna + noiseScale() * (gps_sqrt_ * n), config_.gps_covariance));
}

void Simulator::emitCompass() {
  if (!sensorDue(config_.enable_compass, next_compass_, config_.compass_period, rng_compass_)) {
    return;
  }
  const double noise = noiseScale() * std::sqrt(config_.compass_variance) * rng_compass_.normal();
  queue_.insert(makeEvent(
      EventType::kCompass,
      Eigen::VectorXd::Constant(1, normalizeAngle(truth_.x[2] + config_.compass_offset + noise)),
      Eigen::MatrixXd::Constant(1, 1, config_.compass_variance)));
}

void Simulator::emitLaser() {
  if (!sensorDue(config_.enable_laser, next_laser_, config_.laser_period, rng_laser_)) return;
  Event e = makeEvent(EventType::kLandmarks, {}, config_.laser_covariance);
  const double sigma_r = std::sqrt(config_.laser_covariance(0, 0));
  const double sigma_b = std::sqrt(config_.laser_covariance(1, 1));
  for (std::size_t k = 0; k < scenario_.landmarks.size(); ++k) {
    const Eigen::Vector2d d = scenario_.landmarks[k] - truth_.x.head<2>();
    const double r = d.norm();
    if (r > config_.laser_range) continue;
    RangeBearing o;
    o.landmark_id = static_cast<int>(k) + 1;
    o.range = r + noiseScale() * sigma_r * rng_laser_.normal();
    o.bearing = normalizeAngle(std::atan2(d[1], d[0]) - truth_.x[2] +
                               noiseScale() * sigma_b * rng_laser_.normal());
    e.observations.push_back(o);
  }
  if (!e.observations.empty()) queue_.insert(std::move(e));
}

}  // namespace graphslam::drivebot
