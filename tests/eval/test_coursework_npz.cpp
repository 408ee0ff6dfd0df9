// SPDX-License-Identifier: MIT
// The CMU 16-833 HW3 graph builder on tiny homework-format files (tests/data/npz/hw_*.npz,
// noise free: 3 poses, 2 landmarks, 5 observations).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "graphslam/eval/point_errors.h"
#include "graphslam/io/coursework_npz.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/edge_pointxy.h"
#include "graphslam/types_slam2d/edge_prior_xy.h"
#include "graphslam/types_slam2d/edge_xy_bearing_range.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using namespace graphslam::types_slam2d;
using namespace graphslam::io;
using namespace graphslam::eval;

namespace {

std::string fixture(const std::string& name) {
  return std::string(GRAPHSLAM_TEST_DATA_DIR) + "/npz/" + name;
}

Eigen::Vector2d estimate(const Graph& g, VertexId id) {
  return static_cast<const VertexXY*>(g.vertex(id))->estimate();
}

/// Moves every vertex to its ground truth.
void setToTruth(CourseworkProblem& p) {
  const auto& gt = p.ground_truth;
  for (std::size_t k = 0; k < gt.pose_ids.size(); ++k)
    static_cast<VertexXY*>(p.graph.vertex(gt.pose_ids[k]))->setEstimate(gt.poses[k]);
  for (std::size_t k = 0; k < gt.landmark_ids.size(); ++k)
    static_cast<VertexXY*>(p.graph.vertex(gt.landmark_ids[k]))->setEstimate(gt.landmarks[k]);
}

TEST(Eval_CourseworkNpz, LinearFileBuildsTheHomeworkGraph) {
  CourseworkProblem p = loadCourseworkNpz(fixture("hw_linear.npz"));
  EXPECT_EQ(p.model, PointObservationModel::kLinear);
  EXPECT_NE(p.model_reason.find("fit the linear model at the ground truth"), std::string::npos)
      << p.model_reason;
  EXPECT_EQ(p.num_poses, 3);
  EXPECT_EQ(p.num_landmarks, 2);
  EXPECT_EQ(p.num_odometry, 2u);
  EXPECT_EQ(p.num_observations, 5u);
  EXPECT_EQ(p.graph.numVertices(), 5u);
  ASSERT_EQ(p.graph.numEdges(), 1u + 2u + 5u);
  EXPECT_EQ(p.landmarkId(1), 4);
  // Row order of the homework's A: prior, odometry, observations.
  const auto& edges = p.graph.edges();
  const auto* prior = dynamic_cast<const EdgePriorXY*>(edges[0].get());
  ASSERT_NE(prior, nullptr);
  EXPECT_EQ(prior->vertexId(0), 0);
  EXPECT_TRUE(prior->information().isIdentity());
  const auto* odo = dynamic_cast<const EdgePointXY*>(edges[2].get());
  ASSERT_NE(odo, nullptr);
  EXPECT_EQ(odo->vertexId(0), 1);
  EXPECT_EQ(odo->vertexId(1), 2);
  EXPECT_TRUE(odo->measurement().isApprox(Eigen::Vector2d(1.0, 0.5)));
  EXPECT_TRUE(odo->information().isApprox(Eigen::Matrix2d::Identity() * 100));
  const auto* obs = dynamic_cast<const EdgePointXY*>(edges[5].get());  // pose 1 -> landmark 1
  ASSERT_NE(obs, nullptr);
  EXPECT_EQ(obs->vertexId(0), 1);
  EXPECT_EQ(obs->vertexId(1), 4);
  EXPECT_TRUE(obs->measurement().isApprox(Eigen::Vector2d(2.0, -1.0)));
  EXPECT_TRUE(obs->information().isApprox(Eigen::Matrix2d::Identity() * 25));
  // Initial guess: zeros. Ground truth kept; noise-free data fit it exactly.
  for (VertexId id = 0; id < 5; ++id) EXPECT_EQ(estimate(p.graph, id), Eigen::Vector2d::Zero());
  ASSERT_EQ(p.ground_truth.poses.size(), 3u);
  ASSERT_EQ(p.ground_truth.landmark_ids, (std::vector<VertexId>{3, 4}));
  EXPECT_GT(positionErrors(p.graph, p.ground_truth).landmarks.rmse, 1.0);
  setToTruth(p);
  EXPECT_LT(p.graph.chi2(), 1e-20);
  const auto errors = positionErrors(p.graph, p.ground_truth);
  EXPECT_EQ(errors.poses.count, 3u);
  EXPECT_EQ(errors.landmarks.count, 2u);
  EXPECT_EQ(errors.landmarks.max, 0.0);
}

TEST(Eval_CourseworkNpz, BearingRangeFileUsesTheHomeworksInitialGuess) {
  CourseworkProblem p = loadCourseworkNpz(fixture("hw_bearing_range.npz"));
  EXPECT_EQ(p.model, PointObservationModel::kBearingRange);
  ASSERT_NE(dynamic_cast<const EdgeXYBearingRange*>(p.graph.edges()[3].get()), nullptr);
  // init_states: poses by summed odometry, landmarks from the first observation; the data
  // are noise free, so both are exact.
  EXPECT_TRUE(estimate(p.graph, 2).isApprox(Eigen::Vector2d(2.0, 0.5), 1e-12));
  EXPECT_TRUE(estimate(p.graph, 3).isApprox(Eigen::Vector2d(1.0, 2.0), 1e-12));
  EXPECT_TRUE(estimate(p.graph, 4).isApprox(Eigen::Vector2d(3.0, -1.0), 1e-12));
  EXPECT_LT(p.graph.chi2(), 1e-20);
}

TEST(Eval_CourseworkNpz, ModelFromTheFileNameWithoutTruth) {
  const CourseworkProblem p = loadCourseworkNpz(fixture("hw_no_truth_nonlinear.npz"));
  EXPECT_EQ(p.model, PointObservationModel::kBearingRange);
  EXPECT_NE(p.model_reason.find("file name contains \"nonlinear\""), std::string::npos);
  EXPECT_TRUE(p.ground_truth.empty());
  EXPECT_EQ(p.num_landmarks, 2);  // largest index + 1
  CourseworkNpzOptions o;
  o.model = PointObservationModel::kLinear;
  EXPECT_EQ(loadCourseworkNpz(fixture("hw_bearing_range.npz"), o).model,
            PointObservationModel::kLinear);
}

TEST(Eval_CourseworkNpz, BadFilesAreNamedByArrayAndRow) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"hw_fractional_index.npz",
       ": array 'observations': row 3: pose index 1.5 is not an integer"},
      {"hw_index_out_of_range.npz",
       ": array 'observations': row 4: landmark index 2 is out of range [0, 2)"},
      {"hw_nan.npz", ": array 'observations': row 2 column 3 is NaN"},
      {"hw_sigma_not_pd.npz", ": array 'sigma_odom': covariance is not positive definite"},
      {"hw_missing_odom.npz", ": array 'odom' is missing"},
      {"hw_bad_shape.npz", ": array 'observations': shape (5, 3), expected (N, 4)"},
  };
  for (const auto& [file, message] : cases) {
    try {
      (void)loadCourseworkNpz(fixture(file));
      ADD_FAILURE() << file << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fixture(file) + message), std::string::npos) << e.what();
    }
  }
}

}  // namespace
