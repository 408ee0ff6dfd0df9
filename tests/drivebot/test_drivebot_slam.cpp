// SPDX-License-Identifier: MIT
// The DriveBot SLAM system: event handling, landmarks, optimisation, prediction-edge
// removal, pruning, covariances, loop closure; and the simulation run around it.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "drivebot_test_util.h"
#include "graphslam/drivebot/run.h"
#include "graphslam/support/error.h"
#include "graphslam/types_drivebot/edge_landmark_range_bearing.h"
#include "graphslam/types_drivebot/edge_vehicle_kinematics.h"
#include "graphslam/types_drivebot/vertex_landmark.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

using namespace graphslam;
using namespace graphslam::drivebot;
using namespace graphslam::types_drivebot;

namespace {

constexpr double kPi = 3.14159265358979323846;

using drivebot_test::allSolvers;

Event event(EventType type, double time, Eigen::VectorXd value, Eigen::MatrixXd cov) {
  Event e;
  e.type = type;
  e.time = time;
  e.value = std::move(value);
  e.covariance = std::move(cov);
  return e;
}

Event odometry(double time, double speed, double yaw_rate) {
  return event(EventType::kOdometry, time, Eigen::Vector3d(speed, 0.0, yaw_rate),
               SimulatorConfig::odometryCovarianceDefault());
}

Event initial(double time = 0.0, Eigen::Matrix3d cov = Eigen::Matrix3d::Zero()) {
  return event(EventType::kInitialCondition, time, Eigen::Vector3d::Zero(), cov);
}

Event landmarks(double time, std::vector<RangeBearing> obs) {
  Event e = event(EventType::kLandmarks, time, {}, SimulatorConfig::laserCovarianceDefault());
  e.observations = std::move(obs);
  return e;
}

double wrap(double a) { return std::remainder(a, 2.0 * kPi); }

/// Runs a scenario with the given sensors through the SLAM system.
RunResult simulate(const std::string& scenario, SimulatorConfig sim, SlamSystemOptions slam,
                   RunOptions run = {}, DriveBotSlamSystem** system_out = nullptr) {
  static std::unique_ptr<DriveBotSlamSystem> keep;
  Simulator simulator(builtinScenario(scenario), sim);
  slam.gps_offset = sim.gps_offset;
  slam.compass_offset = sim.compass_offset;
  keep = std::make_unique<DriveBotSlamSystem>(allSolvers(), slam);
  RunResult r = runDriveBot(simulator, *keep, run);
  if (system_out) *system_out = keep.get();
  return r;
}

/// Vehicle states without a landmark observation edge.
std::size_t statesWithoutObservations(const DriveBotSlamSystem& system) {
  std::size_t n = 0;
  for (VertexId id : system.vehicleVertices()) {
    const auto& edges = system.graph().vertex(id)->edges();
    n += std::none_of(edges.begin(), edges.end(), [](const Edge* e) {
      return dynamic_cast<const EdgeLandmarkRangeBearing*>(e) != nullptr;
    });
  }
  return n;
}

/// The q3_a laser (range 30 m) for `steps` steps.
SimulatorConfig q3aLaser(long steps) {
  SimulatorConfig sim;
  sim.enable_laser = true;
  sim.laser_range = 30.0;
  sim.max_steps = steps;
  return sim;
}

Eigen::Vector3d rmsError(const RunResult& r) {
  Eigen::Vector3d sq = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    Eigen::Vector3d e = r.history.x[k] - r.steps[k].truth;
    e[2] = wrap(e[2]);
    sq += e.cwiseProduct(e);
  }
  return (sq / static_cast<double>(r.steps.size())).cwiseSqrt();
}

}  // namespace

TEST(DriveBot_Slam, EventsBuildTheGraphAsTheCourseworkSays) {
  DriveBotSlamSystem slam(allSolvers(), {});
  // The start: odometry first (stored), then the initial condition (covariance 0: fixed).
  slam.processEvents({odometry(0.0, 2.0, 0.1), initial()});
  ASSERT_TRUE(slam.initialized());
  ASSERT_EQ(slam.vehicleVertices().size(), 1u);
  EXPECT_TRUE(slam.graph().vertex(slam.vehicleVertices()[0])->fixed());
  EXPECT_EQ(slam.graph().numEdges(), 0u);

  // Next step: odometry at t = 0.1 predicts with the odometry stored at t = 0, then
  // stores its own; a GPS event 0.5 ms later needs no new vertex (|dT| < 1 ms).
  slam.processEvents(
      {odometry(0.1, 3.0, 0.0),
       event(EventType::kGps, 0.1005, Eigen::Vector2d(10.0, -20.0), Eigen::Matrix2d::Identity())});
  ASSERT_EQ(slam.vehicleVertices().size(), 2u);
  const auto* v1 =
      static_cast<const VertexVehicle*>(slam.graph().vertex(slam.vehicleVertices()[1]));
  EXPECT_DOUBLE_EQ(v1->time(), 0.1);
  EXPECT_NEAR(v1->estimate()[0], 0.2, 1e-12);  // 2 m/s for 0.1 s
  EXPECT_NEAR(v1->estimate()[2], 0.01, 1e-12);
  EXPECT_EQ(slam.graph().numEdges(), 2u);  // kinematics + GPS

  // A landmark event 0.2 s later: prediction with u = (3, 0, 0), then the landmark
  // created and initialised from the first observation.
  slam.processEvents({landmarks(0.3, {{4, 5.0, kPi / 2}})});
  ASSERT_EQ(slam.vehicleVertices().size(), 3u);
  const auto* v2 =
      static_cast<const VertexVehicle*>(slam.graph().vertex(slam.vehicleVertices()[2]));
  const auto& kin = *dynamic_cast<const EdgeVehicleKinematics*>(v2->edges().front());
  EXPECT_NEAR(kin.deltaT(), 0.2, 1e-12);
  ASSERT_EQ(slam.landmarkVertices().count(4), 1u);
  const auto* l =
      static_cast<const VertexLandmark*>(slam.graph().vertex(slam.landmarkVertices().at(4)));
  const Eigen::Vector3d x = v2->estimate();
  EXPECT_NEAR(l->estimate()[0], x[0] + 5.0 * std::cos(kPi / 2 + x[2]), 1e-12);
  EXPECT_NEAR(l->estimate()[1], x[1] + 5.0 * std::sin(kPi / 2 + x[2]), 1e-12);
  // Seen again: same vertex, one more edge, estimate unchanged.
  const Eigen::Vector2d before = l->estimate();
  slam.processEvents({landmarks(0.3, {{4, 5.2, kPi / 2}})});
  EXPECT_EQ(slam.landmarkVertices().size(), 1u);
  EXPECT_EQ(l->estimate(), before);
  EXPECT_EQ(l->edges().size(), 2u);
  EXPECT_EQ(slam.statistics().observation_edges, 2u);
  EXPECT_EQ(slam.stepNumber(), 4);

  EXPECT_THROW(slam.processEvent(initial(0.3)), Error);
}

TEST(DriveBot_Slam, UncertainInitialConditionBecomesAPriorAndBadEventsAreRefused) {
  DriveBotSlamSystem slam(allSolvers(), {});
  slam.processEvent(initial(0.0, Eigen::Matrix3d::Identity()));
  EXPECT_FALSE(slam.graph().vertex(slam.currentVehicleVertex())->fixed());
  EXPECT_EQ(slam.statistics().prior_edges, 1u);
  // A prediction is needed but no odometry came yet.
  EXPECT_THROW(slam.processEvent(landmarks(1.0, {{1, 2.0, 0.0}})), Error);
  DriveBotSlamSystem other(allSolvers(), {});
  EXPECT_THROW(other.processEvent(event(EventType::kOdometry, 0.0, Eigen::Vector2d(1, 2),
                                        Eigen::Matrix2d::Identity())),
               Error);
  EXPECT_THROW(other.processEvent(event(EventType::kOdometry, 0.0, Eigen::Vector3d(1, 2, 3),
                                        -Eigen::Matrix3d::Identity())),
               Error);
  // Observations before the initial condition are ignored, as in the coursework.
  other.processEvent(landmarks(0.0, {{1, 2.0, 0.0}}));
  EXPECT_EQ(other.graph().numVertices(), 0u);
  EXPECT_EQ(other.optimize().status, TerminationStatus::kUnderDetermined);
}

TEST(DriveBot_Slam, OptimisationRecommendedEveryNSteps) {
  SlamSystemOptions o;
  o.optimize_every = 3;
  DriveBotSlamSystem slam(allSolvers(), o);
  std::vector<bool> rec;
  for (int k = 0; k < 7; ++k) {
    slam.processEvents({});
    rec.push_back(slam.recommendOptimization());
  }
  EXPECT_EQ(rec, (std::vector<bool>{false, false, true, false, false, true, false}));
  DriveBotSlamSystem never(allSolvers(), {});
  never.processEvents({});
  EXPECT_FALSE(never.recommendOptimization());
}

TEST(DriveBot_Slam, GpsBoundsTheErrorOdometryAloneLetsCovarianceGrow) {
  SimulatorConfig sim;
  sim.max_steps = 1500;  // about two sides of the square
  sim.seed = 4;
  SlamSystemOptions slam;
  slam.optimize_every = 100;

  const RunResult odo = simulate("q1_d", sim, slam);
  ASSERT_FALSE(odo.failed) << odo.failure.message;
  ASSERT_TRUE(odo.history_marginals.ok()) << odo.history_marginals.message;
  ASSERT_EQ(odo.history.time.size(), odo.steps.size());
  EXPECT_EQ(odo.history.variance.front(), Eigen::Vector3d::Zero());  // the fixed vertex
  // Heading variance grows without bound (about linearly) with odometry only.
  const double var_mid = odo.history.variance[700][2];
  const double var_end = odo.history.variance.back()[2];
  EXPECT_GT(var_end, 1.8 * var_mid);
  EXPECT_GT(odo.history.variance.back()[0] + odo.history.variance.back()[1], 1.0);

  sim.enable_gps = true;
  const RunResult gps = simulate("q1_d", sim, slam);
  ASSERT_FALSE(gps.failed) << gps.failure.message;
  const Eigen::Vector3d rms = rmsError(gps);
  EXPECT_LT(rms[0], 0.5);
  EXPECT_LT(rms[1], 0.5);
  EXPECT_LT(rms[2], 2.0 * kPi / 180);
  double max_var = 0.0;
  for (std::size_t k = 100; k < gps.history.variance.size(); ++k) {
    max_var = std::max(max_var, gps.history.variance[k][0] + gps.history.variance[k][1]);
  }
  EXPECT_LT(max_var, 0.3);  // bounded: GPS noise 1 m^2, fixes every second
  for (std::size_t k = 0; k < gps.steps.size(); ++k) {  // errors within the 4-sigma band
    const Eigen::Vector2d e = gps.history.x[k].head<2>() - gps.steps[k].truth.head<2>();
    EXPECT_LT(std::abs(e[0]), 4.0 * std::sqrt(gps.history.variance[k][0]) + 1e-9) << k;
  }
  EXPECT_EQ(gps.optimizations, 16);  // every 100 of 1500 steps, and the final one
}

TEST(DriveBot_Slam, CompassBugReproducedAndFixed) {
  SimulatorConfig sim;
  sim.enable_compass = true;
  sim.compass_offset = 0.75 * kPi;
  SlamSystemOptions slam;
  slam.optimize_every = 20;
  slam.compass_wrap_error = false;
  const RunResult bug = simulate("q1_c", sim, slam);
  slam.compass_wrap_error = true;
  const RunResult fix = simulate("q1_c", sim, slam);
  ASSERT_FALSE(bug.failed) << bug.failure.message;
  ASSERT_FALSE(fix.failed);
  EXPECT_LT(rmsError(fix)[2], 1.0 * kPi / 180);
  EXPECT_GT(rmsError(bug)[2], 20.0 * kPi / 180);
  EXPECT_GT(bug.final_summary.final_chi2, 100.0 * fix.final_summary.final_chi2);
}

TEST(DriveBot_Slam, LaserSlamLandmarksAndStatistics) {
  SimulatorConfig sim;
  sim.enable_laser = true;
  sim.seed = 2;
  SlamSystemOptions slam;
  slam.optimize_every = 5;
  DriveBotSlamSystem* system = nullptr;
  const RunResult r = simulate("q2_b", sim, slam, {}, &system);
  ASSERT_FALSE(r.failed) << r.failure.message;
  const Scenario s = builtinScenario("q2_b");
  ASSERT_EQ(r.landmarks.size(), 7u);  // the square passes within 10 m of all seven
  ASSERT_TRUE(r.landmark_marginals.ok()) << r.landmark_marginals.message;
  for (const auto& l : r.landmarks) {
    const Eigen::Vector2d err = l.x - s.landmarks[static_cast<std::size_t>(l.landmark_id - 1)];
    const double sigma = std::sqrt(l.covariance.trace());  // >= the largest axis
    EXPECT_LT(err.norm(), 4.0 * sigma + 0.05) << "landmark " << l.landmark_id;
    EXPECT_GT(l.covariance.determinant(), 0.0);
  }
  const GraphStatistics g = r.statistics;
  EXPECT_EQ(g.vehicle_vertices, r.steps.size());
  EXPECT_EQ(g.landmark_vertices, 7u);
  EXPECT_EQ(g.prediction_edges, g.vehicle_vertices - 1);
  EXPECT_EQ(g.observation_edges, g.observations_received);
  EXPECT_EQ(g.edges, g.prediction_edges + g.observation_edges);
  int sum = 0;
  for (const auto& [id, n] : g.observations_of_landmark) sum += n;
  EXPECT_EQ(static_cast<std::size_t>(sum), g.observation_edges);
  EXPECT_NEAR(g.observations_per_landmark, g.observation_edges / 7.0, 1e-12);
  // One optimiser reused: every 5th step optimised, each time a valid chi2.
  int optimised = 0;
  for (const auto& st : r.steps) {
    if (!st.optimized) continue;
    ++optimised;
    EXPECT_TRUE(std::isfinite(st.chi2));
  }
  EXPECT_EQ(optimised, static_cast<int>(r.steps.size()) / 5);
  Eigen::Matrix3d cov;
  ASSERT_TRUE(system->currentVehicleCovariance(cov).ok());
  EXPECT_GT(cov(0, 0), 0.0);
}

TEST(DriveBot_Slam, RemovingAllPredictionEdgesIsDiagnosedKeepingTheFirstWorks) {
  const SimulatorConfig sim = q3aLaser(300);
  SlamSystemOptions slam;
  slam.optimize_every = 100;
  slam.remove_prediction_edges = PredictionEdgeRemoval::kAll;
  const RunResult all = simulate("q3_a", sim, slam);
  ASSERT_TRUE(all.failed);
  EXPECT_EQ(all.failed_step, 99);
  EXPECT_EQ(all.failure.status, TerminationStatus::kUnderDetermined);
  const std::string& m = all.failure.message;
  EXPECT_NE(m.find("no fixed vertex or prior connects to"), std::string::npos) << m;
  EXPECT_NE(m.find("vehicle vertices 1"), std::string::npos) << m;
  EXPECT_NE(m.find("(landmarks "), std::string::npos) << m;
  EXPECT_NE(m.find("all prediction edges were removed"), std::string::npos) << m;
  EXPECT_NE(m.find("first vehicle vertex 0"), std::string::npos) << m;
  EXPECT_FALSE(all.constraints.unanchored.empty() && all.failure.unanchored.empty());

  slam.remove_prediction_edges = PredictionEdgeRemoval::kKeepFirst;
  DriveBotSlamSystem* system = nullptr;
  const RunResult keep = simulate("q3_a", sim, slam, {}, &system);
  ASSERT_FALSE(keep.failed) << keep.failure.message;
  EXPECT_EQ(keep.statistics.prediction_edges, 1u);
  // Steps without a laser scan (dither) leave vertices without edges: not estimated.
  for (VertexId id : keep.constraints.without_edges) {
    EXPECT_TRUE(system->graph().vertex(id)->edges().empty());
  }
  std::size_t nan_rows = 0;
  for (const auto& v : keep.history.variance) nan_rows += std::isnan(v[0]);
  EXPECT_EQ(nan_rows, keep.constraints.without_edges.size());
}

TEST(DriveBot_Slam, PruningRules) {
  const SimulatorConfig sim = q3aLaser(800);
  SlamSystemOptions slam;
  slam.optimize_every = 400;
  const RunResult none = simulate("q3_a", sim, slam);
  slam.prune = PruneRule::kEverySecond;
  DriveBotSlamSystem* last_system = nullptr;
  const RunResult half = simulate("q3_a", sim, slam, {}, &last_system);
  const std::size_t blind_half = statesWithoutObservations(*last_system);
  slam.prune = PruneRule::kStaggered;
  const RunResult staggered = simulate("q3_a", sim, slam, {}, &last_system);
  // The staggered rule keeps as many edges (up to first sightings) but thins scans partly
  // where the coursework's rule drops whole scans: fewer states keep no observation.
  EXPECT_NEAR(static_cast<double>(staggered.statistics.observation_edges),
              static_cast<double>(half.statistics.observation_edges), 13.0);
  const std::size_t blind_staggered = statesWithoutObservations(*last_system);
  EXPECT_GT(blind_half, 200u);
  EXPECT_LT(blind_staggered, blind_half * 4 / 5);
  slam.prune = PruneRule::kKeyframe;
  const RunResult kf = simulate("q3_a", sim, slam);
  for (const RunResult* r : {&none, &half, &staggered, &kf}) {
    ASSERT_FALSE(r->failed) << r->failure.message;
    EXPECT_EQ(r->statistics.observations_received, none.statistics.observations_received);
    EXPECT_EQ(r->statistics.landmark_vertices, none.statistics.landmark_vertices);
  }
  // Every second observation of each landmark: ceil(n / 2) of its n sightings.
  for (const auto& [id, n] : none.statistics.observations_of_landmark) {
    EXPECT_EQ(half.statistics.observations_of_landmark.at(id), (n + 1) / 2) << id;
  }
  // Keyframes every 2 m at up to 7 m/s (0.7 m a step): about a third or less.
  EXPECT_LT(kf.statistics.observation_edges, none.statistics.observation_edges / 2);
  EXPECT_GT(kf.statistics.observation_edges, none.statistics.observation_edges / 12);
  // Pruned graphs still estimate every vehicle state (odometry edges are kept).
  const Eigen::Vector3d e_none = rmsError(none), e_kf = rmsError(kf), e_half = rmsError(half);
  EXPECT_LT(e_kf.head<2>().norm(), 1.0);
  EXPECT_LT(e_half.head<2>().norm(), 1.0);
  EXPECT_LT(e_none.head<2>().norm(), 1.0);
}

TEST(DriveBot_Slam, CourseworkPruningHalvesTheGraphAtEveryOptimisation) {
  SlamSystemOptions options;
  options.prune = PruneRule::kCoursework;
  DriveBotSlamSystem slam(allSolvers(), options);
  slam.processEvents({odometry(0.0, 1.0, 0.0), initial()});
  // Landmark 1 ahead, landmark 2 to the left, both seen from every state.
  auto scan = [&](int k) {
    const double t = 0.1 * k, x = 0.1 * k;
    slam.processEvents({odometry(t, 1.0, 0.0),
                        landmarks(t, {{1, 10.0 - x, 0.0},
                                      {2, std::hypot(5.0 - x, 5.0), std::atan2(5.0, 5.0 - x)}})});
  };
  auto optimised = [&] {
    const TerminationStatus s = slam.optimize().status;
    return s == TerminationStatus::kConverged || s == TerminationStatus::kMaxIterations;
  };
  auto edges_of = [&](int id) {
    return slam.graph().vertex(slam.landmarkVertices().at(id))->edges().size();
  };
  for (int k = 1; k <= 8; ++k) scan(k);
  EXPECT_EQ(edges_of(1), 8u);  // nothing pruned on arrival
  ASSERT_TRUE(optimised());
  EXPECT_EQ(edges_of(1), 4u);  // 1st, 3rd, 5th, 7th
  EXPECT_EQ(edges_of(2), 4u);
  for (int k = 9; k <= 16; ++k) scan(k);
  EXPECT_EQ(edges_of(1), 12u);
  ASSERT_TRUE(optimised());
  // Every second of the 12 in time order: the 4 older ones are halved again (0.1, 0.5),
  // the 8 new ones once (0.9 ... 1.5).
  EXPECT_EQ(edges_of(1), 6u);
  std::vector<double> times;
  for (const Edge* e : slam.graph().vertex(slam.landmarkVertices().at(1))->edges()) {
    times.push_back(static_cast<const VertexVehicle*>(e->vertex(0))->time());
  }
  std::sort(times.begin(), times.end());
  const std::vector<double> expected = {0.1, 0.5, 0.9, 1.1, 1.3, 1.5};
  ASSERT_EQ(times.size(), expected.size());
  for (std::size_t k = 0; k < times.size(); ++k) EXPECT_NEAR(times[k], expected[k], 1e-9) << k;
  EXPECT_EQ(slam.statistics().observations_received, 32u);
}

TEST(DriveBot_Slam, LoopClosureShrinksTheMostRecentlySeenLandmarkMost) {
  SimulatorConfig sim;
  sim.enable_laser = true;
  sim.perturb_with_noise = false;
  sim.max_steps = 2000;
  RunOptions run;
  run.snapshot_loop_closure = true;
  const RunResult r = simulate("q2_d", sim, {}, run);
  ASSERT_FALSE(r.failed) << r.failure.message;
  ASSERT_TRUE(r.loop_closure.has_value());
  const LoopClosure& lc = *r.loop_closure;
  EXPECT_GT(lc.step, 1000);  // after driving round the square
  ASSERT_EQ(lc.before.landmarks.size(), lc.after.landmarks.size());
  double smallest_ratio = 1e300;
  int most_reduced = -1;
  long latest = -1;
  int most_recent = -1;
  for (std::size_t k = 0; k < lc.before.landmarks.size(); ++k) {
    const auto& b = lc.before.landmarks[k];
    const auto& a = lc.after.landmarks[k];
    ASSERT_EQ(a.landmark_id, b.landmark_id);
    const double ratio = a.covariance.determinant() / b.covariance.determinant();
    EXPECT_LE(ratio, 1.0 + 1e-6) << "landmark " << b.landmark_id;  // information only grows
    if (ratio < smallest_ratio) {
      smallest_ratio = ratio;
      most_reduced = b.landmark_id;
    }
    if (b.last_seen_step > latest) {
      latest = b.last_seen_step;
      most_recent = b.landmark_id;
    }
  }
  EXPECT_EQ(most_reduced, most_recent);
  EXPECT_LT(smallest_ratio, 0.01);
  // Noise-free: the estimate is the truth.
  EXPECT_LT(rmsError(r).norm(), 1e-6);
}
