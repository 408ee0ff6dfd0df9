// SPDX-License-Identifier: MIT
// DriveBot simulator and scenarios: determinism, controller, sensors, event order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "../common/test_util.h"
#include "graphslam/drivebot/scenario.h"
#include "graphslam/drivebot/simulator.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/se2.h"

using namespace graphslam;
using namespace graphslam::drivebot;

namespace {

constexpr double kPi = 3.14159265358979323846;

SimulatorConfig allSensors(std::uint64_t seed = 1) {
  SimulatorConfig c;
  c.enable_gps = true;
  c.enable_compass = true;
  c.enable_laser = true;
  c.seed = seed;
  return c;
}

/// Every event of the first `steps` steps, flattened to numbers.
std::vector<double> trace(Simulator& sim, int steps) {
  std::vector<double> out;
  for (int k = 0; k < steps && sim.keepRunning(); ++k) {
    if (k > 0) sim.step();
    for (const Event& e : sim.events()) {
      out.push_back(static_cast<double>(e.type));
      out.push_back(e.time);
      for (int i = 0; i < e.value.size(); ++i) out.push_back(e.value[i]);
      for (const auto& o : e.observations) {
        out.insert(out.end(), {double(o.landmark_id), o.range, o.bearing});
      }
    }
    out.insert(out.end(), sim.truth().x.data(), sim.truth().x.data() + 3);
  }
  return out;
}

std::string tempDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("graphslam_drivebot_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

void writeFile(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

TEST(DriveBot_Simulator, SameSeedSameRunDifferentSeedDifferentNoise) {
  Simulator a(builtinScenario("q2_b"), allSensors(7));
  Simulator b(builtinScenario("q2_b"), allSensors(7));
  Simulator c(builtinScenario("q2_b"), allSensors(8));
  const auto ta = trace(a, 300);
  EXPECT_EQ(ta, trace(b, 300));
  EXPECT_NE(ta, trace(c, 300));
  a.start();  // a restart replays the run
  EXPECT_EQ(ta, trace(a, 300));
}

TEST(DriveBot_Simulator, OtherSensorsDoNotChangeOdometryNoise) {
  SimulatorConfig only_odometry;
  only_odometry.seed = 3;
  Simulator a(builtinScenario("q1_b"), only_odometry);
  Simulator b(builtinScenario("q1_b"), allSensors(3));
  for (int k = 0; k < 200; ++k) {
    auto odometry = [](const Simulator& s) {
      for (const Event& e : s.events()) {
        if (e.type == EventType::kOdometry) return Eigen::VectorXd(e.value);
      }
      return Eigen::VectorXd();
    };
    ASSERT_EQ(odometry(a), odometry(b)) << "step " << k;
    a.step();
    b.step();
  }
}

TEST(DriveBot_Simulator, ControllerVisitsEveryWaypointInOrderAndStops) {
  for (bool quirk : {true, false}) {
    SimulatorConfig c;
    c.waypoint_sign_quirk = quirk;
    const Scenario s = builtinScenario("q2_b");  // the 70 x 70 square once
    Simulator sim(s, c);
    std::size_t next = 0;
    while (sim.keepRunning() && sim.stepCount() < 20000) {
      sim.step();
      if (next < s.waypoints.size() &&
          (sim.truth().x.head<2>() - s.waypoints[next]).norm() < 1.0 + 1.0 /*one step*/) {
        ++next;
      }
      EXPECT_GE(sim.truth().u[0], c.min_speed - 1e-12);
      EXPECT_LE(std::abs(sim.truth().u[1]), c.max_steer + 1e-12);
    }
    EXPECT_FALSE(sim.keepRunning()) << "quirk " << quirk;
    EXPECT_EQ(next, s.waypoints.size()) << "quirk " << quirk;
    EXPECT_LT((sim.truth().x.head<2>() - s.waypoints.back()).norm(), 1.0) << "quirk " << quirk;
    // About 280 m at <= 7 m/s: at least 400 steps; the controller must not wander.
    EXPECT_GT(sim.stepCount(), 400);
    EXPECT_LT(sim.stepCount(), 1500);
  }
}

TEST(DriveBot_Simulator, WaypointSignQuirkSteersAwayOnTheSwitchStep) {
  // On the step after reaching (70, 0), the quirk steers towards position - (70, 70),
  // i.e. away from the next waypoint; without it the steer turns towards it (left, +).
  auto steerAfterSwitch = [](bool quirk) {
    SimulatorConfig c;
    c.waypoint_sign_quirk = quirk;
    Simulator sim(builtinScenario("q1_b"), c);
    while (sim.truth().waypoint_index == 0) sim.step();
    return sim.truth().u[1];
  };
  const double with = steerAfterSwitch(true);
  const double without = steerAfterSwitch(false);
  EXPECT_GT(without, with);
  EXPECT_LT(with, 0.0);
}

TEST(DriveBot_Simulator, EventOrderWithinAStep) {
  SimulatorConfig c = allSensors(2);
  c.gps_period = c.laser_period = c.compass_period = c.dt;  // every sensor every step
  c.sensor_dither_time = 0.0;
  Simulator sim(builtinScenario("q2_b"), c);
  ASSERT_EQ(sim.events().size(), 2u);
  EXPECT_EQ(sim.events()[0].type, EventType::kOdometry);
  EXPECT_EQ(sim.events()[1].type, EventType::kInitialCondition);
  EXPECT_TRUE(sim.events()[1].covariance.isZero(0.0));
  EXPECT_EQ(sim.events()[1].value, Eigen::VectorXd(Eigen::Vector3d::Zero()));
  int full_steps = 0;
  for (int k = 0; k < 50; ++k) {
    sim.step();
    std::vector<EventType> types;
    for (const Event& e : sim.events()) {
      types.push_back(e.type);
      EXPECT_DOUBLE_EQ(e.time, sim.time());
    }
    if (types.size() == 4) {
      ++full_steps;
      EXPECT_EQ(types, (std::vector<EventType>{EventType::kOdometry, EventType::kCompass,
                                               EventType::kLandmarks, EventType::kGps}));
    }
  }
  EXPECT_GT(full_steps, 40);  // landmarks (2,2), (5,3) are in range at the start
}

TEST(DriveBot_Simulator, SensorPeriodsAndDither) {
  SimulatorConfig c = allSensors(5);
  Simulator sim(builtinScenario("q1_d"), c);
  std::vector<double> gps_times;
  int compass = 0;
  while (sim.stepCount() < 2000) {
    sim.step();
    for (const Event& e : sim.events()) {
      if (e.type == EventType::kGps) gps_times.push_back(e.time);
      if (e.type == EventType::kCompass) ++compass;
    }
  }
  // GPS every 1 s + U(0, 0.01): the step grid (0.1 s) gives 10 or 11 steps between fixes.
  ASSERT_GT(gps_times.size(), 150u);
  for (std::size_t k = 1; k < gps_times.size(); ++k) {
    const double gap = gps_times[k] - gps_times[k - 1];
    EXPECT_GT(gap, 0.95);
    EXPECT_LT(gap, 1.15);
  }
  // Compass every 0.1 s + dither: in 2000 steps it must skip a step now and then.
  EXPECT_GT(compass, 1800);
  EXPECT_LT(compass, 2000);
}

TEST(DriveBot_Simulator, MeasurementModelsWithoutNoise) {
  SimulatorConfig c = allSensors(9);
  c.perturb_with_noise = false;
  c.compass_offset = 0.75 * kPi;
  c.laser_range = 30.0;
  const Scenario s = builtinScenario("q3_a");
  Simulator sim(s, c);
  int checked = 0;
  for (int k = 0; k < 300; ++k) {
    const VehicleTruth before = sim.truth();
    sim.step();
    const VehicleTruth& t = sim.truth();
    // Vehicle model with the previous controls.
    const double v_dt = before.u[0] * c.dt;
    EXPECT_NEAR(t.x[0], before.x[0] + v_dt * std::cos(before.x[2]), 1e-12);
    EXPECT_NEAR(t.x[1], before.x[1] + v_dt * std::sin(before.x[2]), 1e-12);
    EXPECT_NEAR(types_slam2d::normalizeAngle(t.x[2] - before.x[2] -
                                             v_dt * std::sin(before.u[1]) / c.wheelbase),
                0.0, 1e-12);
    for (const Event& e : sim.events()) {
      switch (e.type) {
        case EventType::kOdometry:
          EXPECT_NEAR(e.value[0], t.u[0], 1e-12);
          EXPECT_EQ(e.value[1], 0.0);
          EXPECT_NEAR(e.value[2], t.u[0] * std::sin(t.u[1]) / c.wheelbase, 1e-12);
          break;
        case EventType::kGps: {
          const Eigen::Vector2d expected =
              t.x.head<2>() + types_slam2d::rotation2(t.x[2]) * c.gps_offset;
          EXPECT_NEAR((Eigen::Vector2d(e.value) - expected).norm(), 0.0, 1e-12);
          break;
        }
        case EventType::kCompass:
          EXPECT_NEAR(types_slam2d::normalizeAngle(e.value[0] - t.x[2] - c.compass_offset), 0.0,
                      1e-12);
          EXPECT_LE(std::abs(e.value[0]), kPi);
          break;
        case EventType::kLandmarks: {
          std::size_t in_range = 0;
          for (const auto& l : s.landmarks) in_range += (l - t.x.head<2>()).norm() <= 30.0;
          EXPECT_EQ(e.observations.size(), in_range);
          for (const auto& o : e.observations) {
            const Eigen::Vector2d l = s.landmarks[o.landmark_id - 1];
            const Eigen::Vector2d d = l - t.x.head<2>();
            EXPECT_NEAR(o.range, d.norm(), 1e-12);
            EXPECT_NEAR(types_slam2d::normalizeAngle(o.bearing - std::atan2(d[1], d[0]) + t.x[2]),
                        0.0, 1e-12);
            ++checked;
          }
          break;
        }
        default:
          ADD_FAILURE() << "unexpected event " << toString(e.type);
      }
    }
  }
  EXPECT_GT(checked, 300);
}

TEST(DriveBot_Simulator, OdometryNoiseHasTheConfiguredCovariance) {
  SimulatorConfig c;
  c.seed = 11;
  Simulator sim(builtinScenario("q2_c"), c);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  int n = 0;
  while (sim.keepRunning() && n < 3000) {
    sim.step();
    for (const Event& e : sim.events()) {
      if (e.type != EventType::kOdometry) continue;
      const Eigen::Vector3d exact(sim.truth().u[0], 0.0,
                                  sim.truth().u[0] * std::sin(sim.truth().u[1]) / c.wheelbase);
      const Eigen::Vector3d noise = Eigen::Vector3d(e.value) - exact;
      mean += noise;
      sum += noise * noise.transpose();
      ++n;
    }
  }
  ASSERT_GT(n, 2000);
  mean /= n;
  const Eigen::Matrix3d cov = sum / n;
  for (int i = 0; i < 3; ++i) {
    const double sigma = std::sqrt(c.odometry_covariance(i, i));
    EXPECT_LT(std::abs(mean[i]), 4.0 * sigma / std::sqrt(n)) << i;
    EXPECT_NEAR(cov(i, i) / c.odometry_covariance(i, i), 1.0, 0.1) << i;
  }
  EXPECT_LT(std::abs(cov(0, 1)) / std::sqrt(cov(0, 0) * cov(1, 1)), 0.1);
}

TEST(DriveBot_Simulator, MaxStepsAndScenarioStart) {
  SimulatorConfig c;
  c.max_steps = 25;
  Scenario s = builtinScenario("q1_b");
  s.x0 = Eigen::Vector3d(3.0, 4.0, 0.5);
  Simulator sim(s, c);
  EXPECT_EQ(sim.truth().x, Eigen::Vector3d::Zero());  // the coursework ignores x0
  while (sim.keepRunning()) sim.step();
  EXPECT_EQ(sim.stepCount(), 25);
  c.start_at_scenario_x0 = true;
  Simulator from_x0(s, c);
  EXPECT_EQ(from_x0.truth().x, s.x0);
  EXPECT_EQ(from_x0.events()[1].value, Eigen::VectorXd(s.x0));
}

// Without --max-steps a run is bounded by its scenario's path: every built-in scenario ends
// well inside the bound, a waypoint too far away is refused before the run, and a run that
// does not reach its last waypoint within the bound is an error, not a result.
TEST(DriveBot_Simulator, RunsAreBoundedByTheScenariosPath) {
  for (const auto& name : builtinScenarioNames()) {
    Simulator sim(builtinScenario(name), SimulatorConfig{});
    while (sim.keepRunning()) sim.step();
    EXPECT_LT(sim.stepCount(), sim.stepLimit() / 2) << name;
  }
  Scenario far = builtinScenario("q1_b");
  far.waypoints.emplace_back(1e12, 0.0);
  try {
    Simulator sim(far, SimulatorConfig{});
    FAIL() << "a waypoint at 1e12 m was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a run may take without --max-steps"), std::string::npos)
        << e.what();
  }
  SimulatorConfig tight;
  tight.path_step_factor = 0.2;
  tight.path_step_slack = 0;
  Simulator sim(builtinScenario("q1_b"), tight);
  try {
    while (sim.keepRunning()) sim.step();
    FAIL() << "the run ended at step " << sim.stepCount() << " without an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has not reached waypoint"), std::string::npos)
        << e.what();
  }
}

TEST(DriveBot_Scenario, BuiltInScenariosMatchTheCourseworkFiles) {
  const std::string dir = test::dataDir() + "/seeds/comp0130_23-24_cw2_simulations";
  if (!test::fileExists(dir + "/q1_b/wp.txt")) {
    GTEST_SKIP() << "coursework scenario files not found under " << dir
                 << " (set GRAPHSLAM_DATA to the datasets folder)";
  }
  for (const auto& name : builtinScenarioNames()) {
    const Scenario built_in = builtinScenario(name);
    const Scenario file = loadScenario(dir + "/" + name);
    EXPECT_EQ(file.name, name);
    EXPECT_EQ(file.x0, built_in.x0) << name;
    EXPECT_EQ(file.waypoints, built_in.waypoints) << name;
    EXPECT_EQ(file.landmarks, built_in.landmarks) << name;
  }
  const Scenario large = findScenario("q3-large-test", dir);
  EXPECT_EQ(large.landmarks.size(), 200u);
  EXPECT_EQ(large.waypoints.size(), 20u);
}

TEST(DriveBot_Scenario, BuiltInShapes) {
  EXPECT_EQ(builtinScenario("q1_e").waypoints.size(), 1u);
  EXPECT_EQ(builtinScenario("q1_b").waypoints.size(), 2u);
  EXPECT_EQ(builtinScenario("q2_d").waypoints.size(), 4u);
  EXPECT_EQ(builtinScenario("q2_c").waypoints.size(), 16u);
  EXPECT_EQ(builtinScenario("q3_a").landmarks.size(), 13u);  // lm.txt has 13 rows
  EXPECT_EQ(builtinScenario("q2_b").landmarks.size(), 7u);
  EXPECT_EQ(findScenario("q2_d", "/nonexistent").source, "built-in");
  EXPECT_THROW((void)builtinScenario("q9_z"), InputError);
  try {
    (void)findScenario("nothing-here", "/nonexistent");
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/nothing-here"), std::string::npos);
  }
}

TEST(DriveBot_Scenario, MalformedFilesNameFileAndLine) {
  const std::string dir = tempDir("bad_scenario");
  writeFile(dir + "/x0.txt", "0 0 0\n");
  writeFile(dir + "/wp.txt", "70 0\n\n70 abc\n");
  writeFile(dir + "/lm.txt", "1 2 3\n");
  try {
    (void)loadScenario(dir);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("wp.txt:3: 'abc' is not a number"), std::string::npos)
        << e.what();
  }
  writeFile(dir + "/wp.txt", "70 0\n");
  writeFile(dir + "/lm.txt", "1 2 3\n4\n");
  try {
    (void)loadScenario(dir);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lm.txt:2: expected 2 or 3 numbers, found 1"),
              std::string::npos)
        << e.what();
  }
  writeFile(dir + "/lm.txt", "1 2 nan\n");
  EXPECT_THROW((void)loadScenario(dir), InputError);
  std::filesystem::remove(dir + "/x0.txt");
  EXPECT_THROW((void)loadScenario(dir), InputError);
  std::filesystem::remove_all(dir);
}

TEST(Drivebot_Scenario, FilesReadTheLastRowAndReportATruncatedOne) {
  const auto dir = std::filesystem::temp_directory_path() / "graphslam_last_line_scenario";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "x0.txt") << "0 0 0";
  std::ofstream(dir / "wp.txt") << "70 0\n70 70";
  std::ofstream(dir / "lm.txt") << "1 2\n3 4\n5 6 0";
  const auto s = drivebot::loadScenario(dir.string());
  EXPECT_EQ(s.waypoints.size(), 2u);
  ASSERT_EQ(s.landmarks.size(), 3u);
  EXPECT_EQ(s.landmarks[2].x(), 5.0);
  std::ofstream(dir / "lm.txt", std::ios::trunc) << "1 2\n3 4\n5";
  EXPECT_THROW_MSG(static_cast<void>(drivebot::loadScenario(dir.string())), InputError,
                   "lm.txt:3: expected 2 or 3 numbers, found 1");
  std::filesystem::remove_all(dir);
}
