// SPDX-License-Identifier: MIT
// g2o's slam2d tags beyond the basic pose and point ones: hand-computed errors, the `.g2o`
// layouts (shared offset parameters, the "||" line of EDGE_SE2_LOTSOFXY) and an
// optimisation with offset and bearing-only observations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "edge_factories.h"
#include "graphslam/io/g2o.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/types_slam2d/register.h"

using namespace graphslam;
using namespace graphslam::types_slam2d;
using namespace slam2d_test;

namespace {

TypeRegistry slam2dTypes() {
  TypeRegistry types;
  registerTypes(types);
  return types;
}

io::LoadResult readText(const std::string& text, const TypeRegistry& types) {
  std::istringstream in(text);
  return io::readG2o(in, "f.g2o", types);
}

std::string writeText(const Graph& g, const TypeRegistry& types) {
  std::ostringstream out;
  io::writeG2o(out, g, types);
  return out.str();
}

template <typename E>
typename E::InformationMatrix identity() {
  return E::InformationMatrix::Identity();
}

TEST(TypesSlam2d_ParameterSE2Offset, KeepsItsInverseAndRotation) {
  ParameterSE2Offset p;
  p.setValue(SE2(1, 2, kPi / 2));
  EXPECT_TRUE(p.inverse().toVector().isApprox(Eigen::Vector3d(-2, 1, -kPi / 2), 1e-15));
  Eigen::Matrix2d r;
  r << 0, -1, 1, 0;
  EXPECT_TRUE(p.rotation().isApprox(r, 1e-15));
  double data[3] = {3, 4, 0};
  p.setData(data);
  EXPECT_TRUE(p.inverse().toVector().isApprox(Eigen::Vector3d(-3, -4, 0), 1e-15));
}

TEST(TypesSlam2d_EdgeSE2Offset, ErrorIsTheRelativePoseOfTheSensors) {
  // A = X_i O_i = (1, 0, pi/2), B = X_j O_j = (1, 3, 0): A^-1 B = (3, 0, -pi/2).
  Graph g;
  addPose(g, 0, SE2(0, 0, 0));
  addPose(g, 1, SE2(1, 2, 0));
  addOffset(g, 5, SE2(1, 0, kPi / 2));
  addOffset(g, 6, SE2(0, 1, 0));
  auto e = newEdge<EdgeSE2Offset>({0, 1});
  e->setParameterId(0, 5);
  e->setParameterId(1, 6);
  auto& edge = addEdge(g, std::move(e), SE2(3, 0, -kPi / 2), identity<EdgeSE2Offset>());
  EXPECT_NEAR(edge.error().norm(), 0.0, 1e-15);
  // e = [R_z^T ((3, 0) - (2.5, 0.5)); 0] = (0.5, 0.5, 0) with R_z = R(-pi/2).
  edge.setMeasurement(SE2(2.5, 0.5, -kPi / 2));
  edge.computeError();
  EXPECT_TRUE(edge.error().isApprox(Eigen::Vector3d(0.5, 0.5, 0), 1e-14)) << edge.error();
  // e = [0; -pi/2 - (-pi/2 - 0.2)].
  edge.setMeasurement(SE2(3, 0, -kPi / 2 - 0.2));
  edge.computeError();
  EXPECT_LT((edge.error() - Eigen::Vector3d(0, 0, 0.2)).norm(), 1e-14) << edge.error();
}

TEST(TypesSlam2d_EdgeSE2PointXYOffset, ErrorIsInTheRobotFrameAsG2os) {
  // X = (1, 1, pi/2), l = (1, 3): R^T (l - t) = (2, 0). g2o leaves the offset out.
  for (const SE2& offset : {SE2(0, 0, 0), SE2(5, -5, 1)}) {
    Graph g;
    addPose(g, 0, SE2(1, 1, kPi / 2));
    addPoint(g, 1, {1, 3});
    addOffset(g, 2, offset);
    auto e = newEdge<EdgeSE2PointXYOffset>({0, 1});
    e->setParameterId(0, 2);
    auto& edge = addEdge(g, std::move(e), {1.5, 0.5}, identity<EdgeSE2PointXYOffset>());
    EXPECT_TRUE(edge.error().isApprox(Eigen::Vector2d(0.5, -0.5), 1e-15)) << edge.error();
  }
}

TEST(TypesSlam2d_EdgeBearingSE2XY, ErrorIsMeasurementMinusBearingWrapped) {
  Graph g;
  addPose(g, 0, SE2(1, 1, kPi / 2));
  addPoint(g, 1, {1, 3});  // straight ahead: bearing 0
  auto& edge = addEdge(g, newEdge<EdgeBearingSE2XY>({0, 1}), 0.3, identity<EdgeBearingSE2XY>());
  EXPECT_NEAR(edge.error()[0], 0.3, 1e-15);
  // Behind the pose, just left of the -x axis: bearing pi - atan(0.01); a measurement
  // of -pi + 0.02 is 0.02 + atan(0.01) away across the wrap.
  Graph h;
  addPose(h, 0, SE2(0, 0, 0));
  addPoint(h, 1, {-1, 0.01});
  auto& wrapped =
      addEdge(h, newEdge<EdgeBearingSE2XY>({0, 1}), -kPi + 0.02, identity<EdgeBearingSE2XY>());
  EXPECT_NEAR(wrapped.error()[0], 0.02 + std::atan(0.01), 1e-14);
}

TEST(TypesSlam2d_EdgeSE2XYCalib, ErrorIsInTheCalibratedSensorFrame) {
  // X C = (1, 1, pi/2) (0, 1, -pi/2) = (0, 1, 0); l = (2, 3) is (2, 2) in that frame.
  Graph g;
  addPose(g, 0, SE2(1, 1, kPi / 2));
  addPoint(g, 1, {2, 3});
  addPose(g, 2, SE2(0, 1, -kPi / 2));
  auto& edge = addEdge(g, newEdge<EdgeSE2XYCalib>({0, 1, 2}), {2, 1.5}, identity<EdgeSE2XYCalib>());
  EXPECT_TRUE(edge.error().isApprox(Eigen::Vector2d(0, 0.5), 1e-14)) << edge.error();
}

TEST(TypesSlam2d_EdgePriorSE2XY, ErrorIsThePositionMinusTheMeasurement) {
  Graph g;
  addPose(g, 0, SE2(1, 2, 0.7));
  auto& edge = addEdge(g, newEdge<EdgePriorSE2XY>({0}), {0.5, 2.5}, identity<EdgePriorSE2XY>());
  EXPECT_TRUE(edge.error().isApprox(Eigen::Vector2d(0.5, -0.5), 1e-15)) << edge.error();
}

/// Pose 0 at (1, 1, pi/2) and points 1 = (1, 3), 2 = (0, 1), 3 = (1, 1): in the pose's frame
/// (2, 0), (0, 1) and (0, 0).
void addTwoOrThreePoints(Graph& g, bool third) {
  addPose(g, 0, SE2(1, 1, kPi / 2));
  addPoint(g, 1, {1, 3});
  addPoint(g, 2, {0, 1});
  if (third) addPoint(g, 3, {1, 1});
}

TEST(TypesSlam2d_EdgeSE2TwoPointsXY, ErrorStacksBothPointsInThePoseFrame) {
  Graph g;
  addTwoOrThreePoints(g, false);
  auto& edge = addEdge(g, newEdge<EdgeSE2TwoPointsXY>({0, 1, 2}), {2, 0.5, 0, 0},
                       identity<EdgeSE2TwoPointsXY>());
  EXPECT_TRUE(edge.error().isApprox(Eigen::Vector4d(0, -0.5, 0, 1), 1e-15)) << edge.error();
}

TEST(TypesSlam2d_EdgeSE2LotsOfXY, ErrorStacksEveryPointInThePoseFrame) {
  Graph g;
  addTwoOrThreePoints(g, true);
  auto e = newEdge<EdgeSE2LotsOfXY>({0, 1, 2, 3});
  EXPECT_EQ(e->dimension(), 6);
  EXPECT_EQ(e->measurement().size(), 6);
  Eigen::VectorXd z(6);
  z << 2, 0, 0, 1, 1, 0;
  auto& edge = addEdge(g, std::move(e), z, Eigen::MatrixXd::Identity(6, 6));
  Eigen::VectorXd expected(6);
  expected << 0, 0, 0, 0, -1, 0;
  EXPECT_TRUE(edge.error().isApprox(expected, 1e-15)) << edge.error();
  EXPECT_THROW(EdgeSE2LotsOfXY().setVertexIds({0}), Error);  // a pose without points
}

TEST(TypesSlam2d_EdgeSE2LotsOfXY, LineCarriesThePointCountAfterTheIds) {
  // g2o's line: the vertex ids, "||", the number of points, the 2n measurement values and
  // the upper triangle of the 2n x 2n information.
  const TypeRegistry types = slam2dTypes();
  const std::string edge_line = "EDGE_SE2_LOTSOFXY 0 1 2 || 2 2 0 0 1 1 0 0 0 1 0 0 1 0 1\n";
  const std::string text =
      "VERTEX_SE2 0 1 1 1.5707963267948966\nVERTEX_XY 1 1 3\nVERTEX_XY 2 0 1\n" + edge_line;
  auto res = readText(text, types);
  ASSERT_TRUE(res.ok()) << res.diagnostics[0].str();
  const Edge& e = *res.graph.edges()[0];
  EXPECT_EQ(e.numVertices(), 3u);
  EXPECT_EQ(e.dimension(), 4);
  EXPECT_NEAR(res.graph.chi2(), 0.0, 1e-28);
  EXPECT_EQ(writeText(res.graph, types), text);

  const std::pair<std::string, std::string> bad[] = {
      {"EDGE_SE2_LOTSOFXY 0 1 2 || 3 2 0 0 1 1 0 0 0 1 0 0 1 0 1\n",
       "f.g2o:4: EDGE_SE2_LOTSOFXY: the count '3' after '||' does not match its 3 vertex ids (2 "
       "expected)"},
      {"EDGE_SE2_LOTSOFXY 0 1 2 2 2 0 0 1 1 0 0 0 1 0 0 1 0 1\n",
       "f.g2o:4: EDGE_SE2_LOTSOFXY expects its vertex ids to be followed by '||' and a count"},
      {"EDGE_SE2_LOTSOFXY 0 1 2 || 2 2 0 0 1 1 0 0 0 1 0 0 1 0\n",
       "f.g2o:4: EDGE_SE2_LOTSOFXY expects 19 numbers after the tag, found 18"},
      {"EDGE_SE2_LOTSOFXY || 0\n",
       "f.g2o:4: EDGE_SE2_LOTSOFXY expects its vertex ids to be followed by '||' and a count"},
      {"EDGE_SE2_LOTSOFXY 0 || 0\n",
       "f.g2o:4: EDGE_SE2_LOTSOFXY: EdgeSE2LotsOfXY takes a pose and at least one point, 1 "
       "vertices given"},
      {"EDGE_SE2_LOTSOFXY 1 0 2 || 2 2 0 0 1 1 0 0 0 1 0 0 1 0 1\n",
       "f.g2o:4: EDGE_SE2_LOTSOFXY: vertex 1 has the wrong type for slot 0: it is a VERTEX_XY, "
       "the slot takes VERTEX_SE2"},
  };
  const std::string vertices = text.substr(0, text.size() - edge_line.size());
  for (const auto& [line, expected] : bad) {
    auto r = readText(vertices + line, types);
    ASSERT_FALSE(r.ok()) << line;
    EXPECT_NE(r.diagnostics[0].str().find(expected), std::string::npos) << r.diagnostics[0].str();
  }
}

TEST(TypesSlam2d_ParameterSE2Offset, FileWithOffsetsRoundTrips) {
  // Parameter ids follow the vertex ids (g2o's layout); the written file is the read one.
  const TypeRegistry types = slam2dTypes();
  const std::string text =
      "PARAMS_SE2OFFSET 0 0.25 -0.1 0.5\n"
      "PARAMS_SE2OFFSET 7 0 0 0\n"
      "VERTEX_SE2 0 0 0 0\n"
      "VERTEX_SE2 1 1.5 0.2 0.1\n"
      "VERTEX_XY 2 3 1\n"
      "FIX 0\n"
      "EDGE_SE2_OFFSET 0 1 0 7 1.4 0.3 -0.4 100 0 0 100 0 1000\n"
      "EDGE_SE2_POINTXY_OFFSET 1 2 0 1.3 0.9 50 1 50\n";
  auto res = readText(text, types);
  ASSERT_TRUE(res.ok()) << res.diagnostics[0].str();
  EXPECT_EQ(res.graph.parameters().size(), 2u);
  const Edge& offset_edge = *res.graph.edges()[0];
  EXPECT_EQ(offset_edge.parameterId(0), 0);
  EXPECT_EQ(offset_edge.parameterId(1), 7);
  EXPECT_EQ(res.graph.edges()[1]->parameterId(0), 0);
  EXPECT_EQ(writeText(res.graph, types), text);
  // A point edge naming an offset that is not defined is refused with its line.
  auto bad = readText(text + "EDGE_SE2_POINTXY_OFFSET 1 2 3 1.3 0.9 50 1 50\n", types);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.diagnostics[0].str().find("f.g2o:9: EDGE_SE2_POINTXY_OFFSET: refers to parameter "
                                          "3, which is not defined before this line"),
            std::string::npos)
      << bad.diagnostics[0].str();
}

/// A robot on a circle seeing landmarks around it through a sensor mounted at an offset:
/// odometry (EDGE_SE2), positions of the landmarks in the robot frame
/// (EDGE_SE2_POINTXY_OFFSET, as g2o's error has them) and bearings (EDGE_BEARING_SE2_XY),
/// all noise-free. Pose 0 is fixed; the other estimates are perturbed.
struct OffsetWorld {
  static constexpr int kPoses = 12;
  static constexpr int kLandmarks = 8;
  Graph g;
  std::vector<SE2> poses;
  std::vector<Eigen::Vector2d> landmarks;

  OffsetWorld() {
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 0.3);
    addOffset(g, 0, SE2(0.3, -0.1, 0.2));
    for (int i = 0; i < kPoses; ++i) {
      const double a = 2 * kPi * i / kPoses;
      poses.emplace_back(5 * std::cos(a), 5 * std::sin(a), a + kPi / 2);
      addPose(g, i,
              i == 0 ? poses[0]
                     : SE2(poses[i].translation().x() + noise(rng),
                           poses[i].translation().y() + noise(rng), poses[i].angle() + noise(rng)));
      if (i > 0) {
        addEdge(g, newEdge<EdgeSE2>({i - 1, i}), poses[i - 1].inverse() * poses[i],
                identity<EdgeSE2>());
      }
    }
    g.vertex(0)->setFixed(true);
    for (int k = 0; k < kLandmarks; ++k) {
      const double a = 2 * kPi * (k + 0.5) / kLandmarks;
      landmarks.emplace_back((k % 2 ? 2.0 : 8.0) * std::cos(a), (k % 2 ? 2.0 : 8.0) * std::sin(a));
      const VertexId id = 100 + k;
      addPoint(g, id, landmarks[k] + Eigen::Vector2d(noise(rng), noise(rng)));
      for (int i = 0; i < kPoses; ++i) {
        const Eigen::Vector2d local = poses[i].inverseTimes(landmarks[k]);
        if (i % 3 == k % 3) {
          auto e = newEdge<EdgeSE2PointXYOffset>({i, id});
          e->setParameterId(0, 0);
          addEdge(g, std::move(e), local, 10 * identity<EdgeSE2PointXYOffset>());
        }
        addEdge(g, newEdge<EdgeBearingSE2XY>({i, id}), std::atan2(local.y(), local.x()),
                100 * identity<EdgeBearingSE2XY>());
      }
    }
  }
};

TEST(TypesSlam2d_Optimization, OffsetAndBearingObservationsConvergeToTheTruth) {
  OffsetWorld w;
  const double before = w.g.chi2();
  ASSERT_GT(before, 100.0);
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Optimizer::Options options;
  options.algorithm = Algorithm::kLevenbergMarquardt;
  Optimizer optimizer(w.g, solvers, options);
  const Summary s = optimizer.optimize();
  ASSERT_TRUE(s.succeeded()) << s.message;
  std::printf("chi2 %.6g -> %.3g in %d iterations\n", before, s.final_chi2, s.iterations);
  EXPECT_LT(s.final_chi2, 1e-12) << "from " << before;
  for (int i = 0; i < OffsetWorld::kPoses; ++i) {
    const SE2& x = static_cast<const VertexSE2*>(w.g.vertex(i))->estimate();
    EXPECT_NEAR((x.translation() - w.poses[i].translation()).norm(), 0.0, 1e-6) << i;
    EXPECT_NEAR(normalizeAngle(x.angle() - w.poses[i].angle()), 0.0, 1e-6) << i;
  }
  for (int k = 0; k < OffsetWorld::kLandmarks; ++k) {
    const auto& l = static_cast<const VertexXY*>(w.g.vertex(100 + k))->estimate();
    EXPECT_NEAR((l - w.landmarks[k]).norm(), 0.0, 1e-6) << k;
  }
}

}  // namespace
