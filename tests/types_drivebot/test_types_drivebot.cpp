// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <sstream>

#include "../common/edge_type_checks.h"
#include "graphslam/io/g2o.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_drivebot/edge_compass.h"
#include "graphslam/types_drivebot/edge_gps.h"
#include "graphslam/types_drivebot/edge_landmark_range_bearing.h"
#include "graphslam/types_drivebot/edge_vehicle_kinematics.h"
#include "graphslam/types_drivebot/edge_vehicle_prior.h"
#include "graphslam/types_drivebot/register.h"
#include "graphslam/types_drivebot/vertex_landmark.h"
#include "graphslam/types_drivebot/vertex_vehicle.h"

using namespace graphslam;
using namespace graphslam::types_drivebot;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Heading: uniform in half of the draws, within 1e-3 of +-pi in the other half (where
/// the wrap of the vertex update and of the errors matters).
double randomHeading(std::mt19937& rng) {
  std::uniform_real_distribution<double> a(-kPi, kPi), near(-1e-3, 1e-3);
  std::bernoulli_distribution edge(0.5), sign(0.5);
  if (!edge(rng)) return a(rng);
  return wrapAngle((sign(rng) ? kPi : -kPi) + near(rng));
}
Eigen::Vector3d randomState(std::mt19937& rng) {
  std::uniform_real_distribution<double> t(-50, 50);
  return {t(rng), t(rng), randomHeading(rng)};
}
Eigen::Vector2d randomPoint(std::mt19937& rng, double extent = 50) {
  std::uniform_real_distribution<double> t(-extent, extent);
  return {t(rng), t(rng)};
}
template <int D>
Eigen::Matrix<double, D, D> randomInformation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix<double, D, D> a;
  for (int i = 0; i < D * D; ++i) a.data()[i] = u(rng);
  const Eigen::Matrix<double, D, D> m = a * a.transpose() + Eigen::Matrix<double, D, D>::Identity();
  return 0.5 * (m + m.transpose());
}

VertexVehicle& addVehicle(Graph& g, VertexId id, const Eigen::Vector3d& x, double time = 0) {
  auto v = std::make_unique<VertexVehicle>();
  v->setId(id);
  v->setEstimate(x);
  v->setTime(time);
  return static_cast<VertexVehicle&>(g.addVertex(std::move(v)));
}
VertexLandmark& addLandmark(Graph& g, VertexId id, const Eigen::Vector2d& l) {
  auto v = std::make_unique<VertexLandmark>();
  v->setId(id);
  v->setEstimate(l);
  return static_cast<VertexLandmark&>(g.addVertex(std::move(v)));
}
template <typename E>
E& addEdge(Graph& g, std::unique_ptr<E> e) {
  return static_cast<E&>(g.addEdge(std::move(e)));
}

/// Builds a random graph holding one edge of type E and its vertices.
template <typename E>
struct EdgeFactory;

template <>
struct EdgeFactory<EdgeVehicleKinematics> {
  static EdgeVehicleKinematics* make(Graph& g, std::mt19937& rng) {
    std::uniform_real_distribution<double> dt(0.05, 2.0), speed(-10, 10), rate(-1, 1),
        small(-0.5, 0.5);
    std::bernoulli_distribution consistent(0.5);
    auto e = std::make_unique<EdgeVehicleKinematics>();
    e->setDeltaT(dt(rng));
    e->setMeasurement({speed(rng), small(rng), rate(rng)});
    const Eigen::Vector3d a = randomState(rng);
    Eigen::Vector3d b = randomState(rng);
    if (consistent(rng)) {  // near the model: small errors, heading change across +-pi
      b = EdgeVehicleKinematics::predict(a, e->measurement(), e->deltaT());
      b += Eigen::Vector3d(small(rng), small(rng), 0.1 * small(rng));
      b[2] = wrapAngle(b[2]);
    }
    addVehicle(g, 0, a);
    addVehicle(g, 1, b);
    e->setVertexIds({0, 1});
    e->setInformation(randomInformation<3>(rng));
    return &addEdge(g, std::move(e));
  }
};

template <>
struct EdgeFactory<EdgeGps> {
  static EdgeGps* make(Graph& g, std::mt19937& rng) {
    addVehicle(g, 0, randomState(rng));
    auto e = std::make_unique<EdgeGps>();
    e->setVertexIds({0});
    e->setOffset(randomPoint(rng, 20));
    e->setMeasurement(randomPoint(rng));
    e->setInformation(randomInformation<2>(rng));
    return &addEdge(g, std::move(e));
  }
};

template <>
struct EdgeFactory<EdgeCompass> {
  static EdgeCompass* make(Graph& g, std::mt19937& rng) {
    std::uniform_real_distribution<double> a(-kPi, kPi);
    addVehicle(g, 0, randomState(rng));
    auto e = std::make_unique<EdgeCompass>();
    e->setVertexIds({0});
    e->setOffset(a(rng));
    e->setMeasurement(a(rng));
    e->setInformation(randomInformation<1>(rng));
    return &addEdge(g, std::move(e));
  }
};

template <>
struct EdgeFactory<EdgeLandmarkRangeBearing> {
  static EdgeLandmarkRangeBearing* make(Graph& g, std::mt19937& rng) {
    std::uniform_real_distribution<double> r(0.5, 30), b(-kPi, kPi);
    const Eigen::Vector3d x = randomState(rng);
    addVehicle(g, 0, x);
    // Landmarks at 0.5..30 m in every direction, also straight behind (bearing +-pi).
    const Eigen::Vector2d z_true(r(rng), randomHeading(rng));
    addLandmark(g, 1, EdgeLandmarkRangeBearing::landmarkFrom(x, z_true));
    auto e = std::make_unique<EdgeLandmarkRangeBearing>();
    e->setVertexIds({0, 1});
    e->setMeasurement({r(rng), b(rng)});
    e->setInformation(randomInformation<2>(rng));
    return &addEdge(g, std::move(e));
  }
};

template <>
struct EdgeFactory<EdgeVehiclePrior> {
  static EdgeVehiclePrior* make(Graph& g, std::mt19937& rng) {
    addVehicle(g, 0, randomState(rng));
    auto e = std::make_unique<EdgeVehiclePrior>();
    e->setVertexIds({0});
    e->setMeasurement(randomState(rng));
    e->setInformation(randomInformation<3>(rng));
    return &addEdge(g, std::move(e));
  }
};

template <typename E>
class TypesDrivebot_Edge : public ::testing::Test {};
using EdgeTypes = ::testing::Types<EdgeVehicleKinematics, EdgeGps, EdgeCompass,
                                   EdgeLandmarkRangeBearing, EdgeVehiclePrior>;
TYPED_TEST_SUITE(TypesDrivebot_Edge, EdgeTypes, ::testing::internal::DefaultNameGenerator);

TYPED_TEST(TypesDrivebot_Edge, AnalyticJacobianMatchesNumeric) {
  graphslam::test::expectAnalyticJacobians<TypeParam>(EdgeFactory<TypeParam>::make, 2024, 1000);
}

TYPED_TEST(TypesDrivebot_Edge, WriteReadRoundTripIsExact) {
  TypeRegistry types;
  registerTypes(types);
  std::mt19937 rng(7);
  Graph g;
  EdgeFactory<TypeParam>::make(g, rng);
  static_cast<VertexVehicle*>(g.vertex(0))->setTime(12.3456789);
  graphslam::test::expectExactRoundTrip(g, types);
}

TEST(TypesDrivebot_Io, LinesHaveTheDocumentedLayout) {
  TypeRegistry types;
  registerTypes(types);
  const std::string text =
      "VERTEX_VEHICLE 0 1 2 0.5 10.25\n"
      "VERTEX_VEHICLE 1 2 2 0.5 10.35\n"
      "VERTEX_LANDMARK 7 3 4\n"
      "EDGE_VEHICLE_KINEMATICS 0 1 5 0 0.1 0.2 25 0 0 100 0 3282.8\n"
      "EDGE_GPS 1 12 -18 10 -20 1 0 1\n"
      "EDGE_COMPASS 1 2.8 2.35619 0 131.3\n"
      "EDGE_LANDMARK_RANGE_BEARING 1 7 2.5 0.3 100 0 3282.8\n"
      "EDGE_VEHICLE_PRIOR 0 1 2 0.5 1 0 0 1 0 1\n";
  std::istringstream in(text);
  auto loaded = io::readG2o(in, "layout", types);
  ASSERT_TRUE(loaded.ok()) << loaded.diagnostics.at(0).str();
  const auto& g = loaded.graph;
  EXPECT_EQ(static_cast<const VertexVehicle*>(g.vertex(0))->time(), 10.25);
  EXPECT_EQ(static_cast<const VertexVehicle*>(g.vertex(1))->time(), 10.35);
  const auto& kin = static_cast<const EdgeVehicleKinematics&>(*g.edges()[0]);
  EXPECT_EQ(kin.deltaT(), 0.2);
  EXPECT_EQ(kin.measurement(), Eigen::Vector3d(5, 0, 0.1));
  EXPECT_EQ(kin.information()(2, 2), 3282.8);
  const auto& gps = static_cast<const EdgeGps&>(*g.edges()[1]);
  EXPECT_EQ(gps.offset(), Eigen::Vector2d(10, -20));
  const auto& compass = static_cast<const EdgeCompass&>(*g.edges()[2]);
  EXPECT_EQ(compass.offset(), 2.35619);
  EXPECT_FALSE(compass.wrapError());
  EXPECT_EQ(compass.information()(0, 0), 131.3);
  std::ostringstream out;
  io::writeG2o(out, g, types);
  EXPECT_NE(out.str().find("VERTEX_VEHICLE 0 1 2 0.5 10.25\n"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("EDGE_GPS 1 12 -18 10 -20 1 0 1\n"), std::string::npos) << out.str();
}

TEST(TypesDrivebot_Io, BadParametersAreReportedWithTheLine) {
  TypeRegistry types;
  registerTypes(types);
  struct Case {
    std::string text;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"VERTEX_VEHICLE 0 0 0 0 0\nVERTEX_VEHICLE 1 0 0 0 0.1\n"
       "EDGE_VEHICLE_KINEMATICS 0 1 5 0 0 0 1 0 0 1 0 1\n",
       "bad:3: EDGE_VEHICLE_KINEMATICS: vehicle kinematics: time step dT must be positive"},
      {"VERTEX_VEHICLE 0 0 0 0 0\nEDGE_COMPASS 0 1 0 2 1\n",
       "bad:2: EDGE_COMPASS: compass: the wrap flag must be 0 or 1"},
      {"VERTEX_VEHICLE 0 0 0 0\n",
       "bad:1: VERTEX_VEHICLE expects 5 numbers after the tag, found 4"},
      {"VERTEX_VEHICLE 0 0 0 0 0\nEDGE_GPS 0 1 2 1 0 1\n",
       "bad:2: EDGE_GPS expects 8 numbers after the tag, found 6"},
  };
  for (const auto& c : cases) {
    std::istringstream in(c.text);
    auto loaded = io::readG2o(in, "bad", types);
    ASSERT_FALSE(loaded.ok()) << c.text;
    EXPECT_EQ(loaded.diagnostics.at(0).str().rfind(c.expected, 0), 0u)
        << loaded.diagnostics.at(0).str();
  }
}

TEST(TypesDrivebot_Wrap, VehicleUpdateWrapsTheHeading) {
  VertexVehicle v;
  const Eigen::Vector3d x(1, 2, 3.1);
  const Eigen::Vector3d y = v.plus(x, Eigen::Vector3d(0.5, -1, 0.1));
  EXPECT_DOUBLE_EQ(y[0], 1.5);
  EXPECT_DOUBLE_EQ(y[1], 1.0);
  EXPECT_NEAR(y[2], 3.2 - 2 * kPi, 1e-12);
  // A full wrap: several turns come back into [-pi, pi).
  EXPECT_NEAR(v.plus(x, Eigen::Vector3d(0, 0, 7 * kPi))[2], 3.1 - kPi, 1e-12);
  EXPECT_NEAR(v.plus(x, Eigen::Vector3d(0, 0, -9 * kPi))[2], 3.1 - kPi, 1e-12);
  EXPECT_NEAR(v.plus(x, Eigen::Vector3d(0, 0, 0.0415926535897932))[2], -kPi, 1e-12);
}

TEST(TypesDrivebot_Wrap, ErrorsAreSmallAcrossPlusMinusPi) {
  Graph g;
  addVehicle(g, 0, {0, 0, kPi - 0.01});
  addVehicle(g, 1, {1, -0.01, -kPi + 0.01});
  addLandmark(g, 2, {-5, 0.0});
  auto kin = std::make_unique<EdgeVehicleKinematics>();
  kin->setVertexIds({0, 1});
  kin->setDeltaT(0.1);
  kin->setMeasurement({-10, 0, 0.2});  // heading change +0.02 rad in 0.1 s, backwards at 10 m/s
  auto& k = addEdge(g, std::move(kin));
  k.computeError();
  EXPECT_NEAR(k.error()[2], 0.0, 1e-12);  // the heading crossed pi as predicted
  EXPECT_LT(k.error().norm(), 1e-2) << k.error().transpose();

  auto prior = std::make_unique<EdgeVehiclePrior>();
  prior->setVertexIds({1});
  prior->setMeasurement({1, 0, kPi - 0.01});
  auto& p = addEdge(g, std::move(prior));
  p.computeError();
  EXPECT_NEAR(p.error()[2], 0.02, 1e-12);

  // Landmark almost straight behind vehicle 0 (bearing pi - 0.005), measured on the other
  // side of the cut (-pi + 0.005): the bearing error is -0.01, not 2 pi - 0.01.
  static_cast<VertexLandmark*>(g.vertex(2))
      ->setEstimate(EdgeLandmarkRangeBearing::landmarkFrom(Eigen::Vector3d(0, 0, kPi - 0.01),
                                                           {5, kPi - 0.005}));
  auto rb = std::make_unique<EdgeLandmarkRangeBearing>();
  rb->setVertexIds({0, 2});
  rb->setMeasurement({5, -kPi + 0.005});
  auto& r = addEdge(g, std::move(rb));
  r.computeError();
  EXPECT_NEAR(r.error()[0], 0.0, 1e-12);
  EXPECT_NEAR(r.error()[1], -0.01, 1e-12);
}

TEST(TypesDrivebot_Wrap, CompassBugIsReproducibleAndFixed) {
  // Offset 0.75 pi (the coursework's q1_c): psi = 1 gives a reading of
  // wrap(1 + 0.75 pi) = 1 + 0.75 pi - 2 pi.
  Graph g;
  addVehicle(g, 0, {0, 0, 1.0});
  auto c = std::make_unique<EdgeCompass>();
  c->setVertexIds({0});
  c->setOffset(0.75 * kPi);
  c->setMeasurement(wrapAngle(1.0 + 0.75 * kPi));
  auto& compass = addEdge(g, std::move(c));
  compass.computeError();
  EXPECT_NEAR(compass.error()[0], 0.0, 1e-12);
  compass.setWrapError(false);
  compass.computeError();
  EXPECT_NEAR(compass.error()[0], 2 * kPi, 1e-12);
}

TEST(TypesDrivebot_Init, PredictionAndLandmarkInitialisationGiveZeroError) {
  Graph g;
  addVehicle(g, 0, {3, -2, 3.0});
  addVehicle(g, 1, {0, 0, 0});
  addLandmark(g, 2, {0, 0});
  auto kin = std::make_unique<EdgeVehicleKinematics>();
  kin->setVertexIds({0, 1});
  kin->setDeltaT(0.5);
  kin->setMeasurement({4, 0.3, 0.6});
  auto& k = addEdge(g, std::move(kin));
  k.initializeSecond();
  const Eigen::Vector3d x1 = static_cast<VertexVehicle*>(g.vertex(1))->estimate();
  EXPECT_NEAR(x1[0], 3 + 0.5 * (std::cos(3.0) * 4 - std::sin(3.0) * 0.3), 1e-12);
  EXPECT_NEAR(x1[1], -2 + 0.5 * (std::sin(3.0) * 4 + std::cos(3.0) * 0.3), 1e-12);
  EXPECT_NEAR(x1[2], 3.3 - 2 * kPi, 1e-12);
  k.computeError();
  EXPECT_LT(k.error().norm(), 1e-12);

  auto rb = std::make_unique<EdgeLandmarkRangeBearing>();
  rb->setVertexIds({1, 2});
  rb->setMeasurement({7.5, -2.5});
  auto& r = addEdge(g, std::move(rb));
  r.initializeLandmark();
  r.computeError();
  EXPECT_LT(r.error().norm(), 1e-12);

  EdgeVehicleKinematics loose;
  EXPECT_THROW(loose.initializeSecond(), Error);
  EdgeLandmarkRangeBearing loose_rb;
  EXPECT_THROW(loose_rb.initializeLandmark(), Error);
  EXPECT_THROW(loose.setDeltaT(0.0), Error);
  EXPECT_THROW(loose.setDeltaT(std::nan("")), Error);
}

TEST(TypesDrivebot_Register, AllTagsRegistered) {
  TypeRegistry types;
  registerTypes(types);
  for (const char* tag :
       {"VERTEX_VEHICLE", "VERTEX_LANDMARK", "EDGE_VEHICLE_KINEMATICS", "EDGE_GPS", "EDGE_COMPASS",
        "EDGE_LANDMARK_RANGE_BEARING", "EDGE_VEHICLE_PRIOR"}) {
    EXPECT_TRUE(types.contains(tag)) << tag;
  }
  EXPECT_THROW(registerTypes(types), RegistryError);
}

/// Noise-free DriveBot run: a vehicle drives a curve through +-pi with odometry every
/// step, GPS every 10 steps and a compass (offset 0.75 pi) every 5 steps.
struct Scenario {
  Graph graph;
  std::vector<Eigen::Vector3d> truth;
};

Scenario makeScenario(bool wrap_compass) {
  Scenario s;
  const double dt = 0.1;
  const int n = 200;
  const Eigen::Vector2d gps_offset(10, -20);
  const double compass_offset = 0.75 * kPi;
  Eigen::Vector3d x(0, 0, 2.5);
  std::vector<Eigen::Vector3d> controls;
  for (int k = 0; k < n; ++k) {
    s.truth.push_back(x);
    const Eigen::Vector3d u(5 + 2 * std::sin(0.05 * k), 0, 0.4 * std::cos(0.03 * k));
    controls.push_back(u);
    x = EdgeVehicleKinematics::predict(x, u, dt);
  }
  std::mt19937 rng(3);
  std::normal_distribution<double> pos(0, 3), ang(0, 0.5);
  for (int k = 0; k < n; ++k) {
    // Start far from the truth: positions off by metres, headings by ~0.5 rad.
    const Eigen::Vector3d start(s.truth[k][0] + pos(rng), s.truth[k][1] + pos(rng),
                                wrapAngle(s.truth[k][2] + ang(rng)));
    addVehicle(s.graph, k, start, k * dt);
    if (k > 0) {
      auto e = std::make_unique<EdgeVehicleKinematics>();
      e->setVertexIds({k - 1, k});
      e->setDeltaT(dt);
      e->setMeasurement(controls[k - 1]);
      e->setInformation(Eigen::Vector3d(25, 100, 3282.8).asDiagonal());
      s.graph.addEdge(std::move(e));
    }
    if (k % 10 == 0) {
      auto e = std::make_unique<EdgeGps>();
      e->setVertexIds({k});
      e->setOffset(gps_offset);
      e->setMeasurement(s.truth[k].head<2>() + types_slam2d::rotation2(s.truth[k][2]) * gps_offset);
      s.graph.addEdge(std::move(e));
    }
    if (k % 5 == 0) {
      auto e = std::make_unique<EdgeCompass>();
      e->setVertexIds({k});
      e->setOffset(compass_offset);
      e->setWrapError(wrap_compass);
      e->setMeasurement(wrapAngle(s.truth[k][2] + compass_offset));
      e->setInformation(Eigen::Matrix<double, 1, 1>(131.3));
      s.graph.addEdge(std::move(e));
    }
  }
  return s;
}

TEST(TypesDrivebot_Optimize, VehicleChainWithGpsAndCompassReachesTheTruth) {
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Scenario s = makeScenario(true);
  // The trajectory crosses the +-pi heading boundary.
  bool crosses = false;
  for (std::size_t k = 1; k < s.truth.size(); ++k)
    crosses |= std::abs(s.truth[k][2] - s.truth[k - 1][2]) > kPi;
  ASSERT_TRUE(crosses);
  Optimizer::Options options;
  options.max_iterations = 50;
  Optimizer optimizer(s.graph, solvers, options);
  const Summary summary = optimizer.optimize();
  ASSERT_TRUE(summary.succeeded()) << summary.report();
  EXPECT_TRUE(summary.gauge_fixed.empty());
  EXPECT_LT(summary.final_chi2, 1e-12) << summary.report();
  for (std::size_t k = 0; k < s.truth.size(); ++k) {
    const Eigen::Vector3d x =
        static_cast<VertexVehicle*>(s.graph.vertex(static_cast<int>(k)))->estimate();
    EXPECT_NEAR(x[0], s.truth[k][0], 1e-6) << k;
    EXPECT_NEAR(x[1], s.truth[k][1], 1e-6) << k;
    EXPECT_NEAR(wrapAngle(x[2] - s.truth[k][2]), 0.0, 1e-8) << k;
  }
}

TEST(TypesDrivebot_Optimize, UnwrappedCompassErrorBreaksTheSameProblem) {
  // The coursework's q1_c bug: with the unwrapped compass error the truth is not a
  // minimum (its chi2 is huge), so the optimizer cannot end there.
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Scenario s = makeScenario(false);
  for (std::size_t k = 0; k < s.truth.size(); ++k)
    static_cast<VertexVehicle*>(s.graph.vertex(static_cast<int>(k)))->setEstimate(s.truth[k]);
  EXPECT_GT(s.graph.chi2(), 1000.0);
  Optimizer optimizer(s.graph, solvers);
  const Summary summary = optimizer.optimize();
  EXPECT_GT(summary.final_chi2, 1.0) << summary.report();
}

}  // namespace
