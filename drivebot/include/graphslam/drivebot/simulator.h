// SPDX-License-Identifier: MIT
// The DriveBot simulator of UCL COMP0130 coursework 2: a car-like vehicle drives through
// waypoints; odometry, GPS, compass and a range-bearing laser produce time-stamped events.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <random>

#include "graphslam/drivebot/events.h"
#include "graphslam/drivebot/scenario.h"

namespace graphslam::drivebot {

/// Simulator parameters. The defaults are the coursework's SimulatorConfiguration.m;
/// angles in radians, times in seconds, distances in metres.
struct SimulatorConfig {
  double dt = 0.1;  ///< simulation step
  /// Stop after this many steps (the coursework's maximumStepNumber). 0: a bound from the
  /// scenario, path_step_factor times the steps its path (start, then every waypoint in
  /// turn) takes at min_speed, plus path_step_slack; a run that has not reached its last
  /// waypoint by then is an error (an unreachable waypoint), not a result.
  long max_steps = 0;
  double path_step_factor = 3.0;  ///< of the automatic bound (max_steps 0)
  long path_step_slack = 1000;    ///< steps of the automatic bound for turning and slowing
  /// The automatic bound may not exceed this (a waypoint far away would otherwise grow the
  /// graph until memory runs out): such a scenario is refused unless max_steps is given.
  long max_automatic_steps = 2000000;
  double wheelbase = 2.5;
  /// false: every measurement is exact (sensor start times and dither stay random).
  bool perturb_with_noise = true;
  double sensor_dither_time = 1e-2;        ///< each sensor's next time += period + U(0, dither)
  double max_steer_rate = 20.0 * kDegree;  ///< per second (x dt per step)
  double max_steer = 40.0 * kDegree;
  double max_speed = 10.0;
  double min_speed = 1.0;
  double max_acceleration = 0.5;

  bool enable_odometry = true;
  /// Odometry noise on u = (speed, lateral speed, yaw rate).
  Eigen::Matrix3d odometry_covariance = odometryCovarianceDefault();

  bool enable_compass = false;
  double compass_period = 0.1;
  double compass_variance = (5.0 * kDegree) * (5.0 * kDegree);
  double compass_offset = 0.0;  ///< z = psi + offset + noise (the coursework's q1_c: 0.75 pi)

  bool enable_gps = false;
  double gps_period = 1.0;
  Eigen::Matrix2d gps_covariance = Eigen::Matrix2d::Identity();
  /// Antenna position in the vehicle frame: z = (x, y) + R(psi) offset + noise.
  Eigen::Vector2d gps_offset = Eigen::Vector2d(10.0, -20.0);

  bool enable_laser = false;
  double laser_period = 0.1;
  double laser_range = 10.0;  ///< landmarks at range <= this are observed
  /// Range-bearing noise (range m, bearing rad).
  Eigen::Matrix2d laser_covariance = laserCovarianceDefault();

  /// The coursework's controller, on the one step right after it switches to the next
  /// waypoint, steers towards (position - waypoint) instead of (waypoint - position).
  /// true (the default) reproduces that; false steers the right way on that step too.
  bool waypoint_sign_quirk = true;
  /// The coursework resets the start state to (0, 0, 0) whatever x0.txt says (all its
  /// scenarios have x0 = 0 anyway). true starts from the scenario's x0 instead.
  bool start_at_scenario_x0 = false;

  /// Seed of the random numbers (noise, sensor start times, dither).
  std::uint64_t seed = 0;

  static constexpr double kDegree = 3.14159265358979323846 / 180.0;
  static Eigen::Matrix3d odometryCovarianceDefault() {
    return Eigen::Vector3d(0.2 * 0.2, 0.1 * 0.1, kDegree * kDegree).asDiagonal();
  }
  static Eigen::Matrix2d laserCovarianceDefault() {
    return Eigen::Vector2d(0.1 * 0.1, kDegree * kDegree).asDiagonal();
  }
};

/// True state of the simulated vehicle.
struct VehicleTruth {
  double time = 0.0;
  long step = 0;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  ///< (x, y, psi)
  Eigen::Vector2d u = Eigen::Vector2d::Zero();  ///< (speed, steer angle)
  int waypoint_index = 0;                       ///< 0-based index of the current target
};

/// The coursework's DriveBotSimulator.
///
/// start() (called by the constructor) puts the vehicle at (0, 0, 0) with u = 0, draws
/// each sensor's first time uniformly in [0, period) and queues an initial-condition
/// event (covariance zero: the first state is known exactly) and the first odometry.
/// step() then: moves the vehicle with the controls held over dt
///   x += s dt cos(psi), y += s dt sin(psi), psi = wrap(psi + s dt sin(delta) / B),
/// advances time, emits GPS, laser and compass events whose time has come (next time +=
/// period + U(0, dither)), computes the controls for the next step, and emits the
/// odometry u = (s, 0, s sin(delta) / B) + noise that the next step will use. All events of
/// a step share its time; in the queue they read odometry, compass, laser, GPS.
///
/// Random numbers: one std::mt19937_64 per source (odometry, GPS, compass, laser, sensor
/// start times), seeded from `seed` through SplitMix64 (a sensor's dither comes from its
/// own stream); uniforms take the top 53 bits,
/// normals come from Marsaglia's polar method. A seed therefore gives the same run with any
/// standard library (bit-identical where libm's sqrt/log/sin/cos agree), and switching a
/// sensor on or off does not change the noise any other sensor sees.
class Simulator {
 public:
  Simulator(Scenario scenario, SimulatorConfig config);

  /// Restarts the run (same seed: same run).
  void start();
  /// False once the last waypoint is reached or max_steps steps were taken.
  [[nodiscard]] bool keepRunning() const;
  /// Advances one step and replaces events() with the new step's events. Throws
  /// graphslam::InputError when the automatic step bound (max_steps 0) is reached before
  /// the last waypoint.
  void step();
  /// The step bound of this run (max_steps, or the automatic one).
  [[nodiscard]] long stepLimit() const { return step_limit_; }

  /// Events of the current step (after start(): odometry, then the initial condition).
  [[nodiscard]] const std::vector<Event>& events() const { return queue_.events(); }
  [[nodiscard]] const VehicleTruth& truth() const { return truth_; }
  [[nodiscard]] double time() const { return truth_.time; }
  [[nodiscard]] long stepCount() const { return truth_.step; }
  [[nodiscard]] const Scenario& scenario() const { return scenario_; }
  [[nodiscard]] const SimulatorConfig& config() const { return config_; }

 private:
  /// Seeded generator with the draws the simulator needs.
  class Random {
   public:
    void seed(std::uint64_t seed) {
      engine_.seed(seed);
      has_spare_ = false;
    }
    double uniform();
    double normal();

   private:
    std::mt19937_64 engine_;
    bool has_spare_ = false;
    double spare_ = 0.0;
  };

  void computeControlInputs();
  /// The automatic step bound (max_steps 0); throws InputError above max_automatic_steps.
  [[nodiscard]] long automaticStepLimit() const;
  [[nodiscard]] Event odometryEvent();
  void emitGps();
  void emitCompass();
  void emitLaser();
  /// True when an enabled sensor's time has come; then schedules its next time.
  [[nodiscard]] bool sensorDue(bool enabled, double& next_time, double period, Random& rng);
  [[nodiscard]] Event makeEvent(EventType type, Eigen::VectorXd value,
                                Eigen::MatrixXd covariance) const;
  [[nodiscard]] double noiseScale() const { return config_.perturb_with_noise ? 1.0 : 0.0; }

  Scenario scenario_;
  SimulatorConfig config_;
  long step_limit_ = 0;  // max_steps, or the automatic bound
  Eigen::Matrix3d odometry_sqrt_;
  Eigen::Matrix2d gps_sqrt_;
  VehicleTruth truth_;
  bool running_ = true;
  double next_gps_ = 0.0;
  double next_laser_ = 0.0;
  double next_compass_ = 0.0;
  Random rng_odometry_, rng_gps_, rng_compass_, rng_laser_, rng_timing_;
  OrderedEventQueue queue_;
};

}  // namespace graphslam::drivebot
