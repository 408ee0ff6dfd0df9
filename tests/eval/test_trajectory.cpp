// SPDX-License-Identifier: MIT
// Tests of graphslam::Trajectory (I/O, planar helpers) and the evo-compatible metrics.
// Reference numbers for the ShanghaiTech SLAM 2024 homework 1 are those of
// shared/SEEDS.md section 3 (evo APE, 12 poses, 13th dropped).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "graphslam/eval/trajectory_metrics.h"
#include "graphslam/io/trajectory.h"
#include "graphslam/support/error.h"

namespace graphslam::eval {
using namespace graphslam::io;
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSixDigits = 5e-7;  // "to 6 digits" after the decimal point
constexpr const char* kHomeworkDir = "seeds/shanghaitech_slam2024_hw1";

bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

/// Data root: $GRAPHSLAM_DATA, then GRAPHSLAM_DEFAULT_DATA_DIR, then ../shared/datasets —
/// the first that holds the homework file; empty if none does.
std::string dataRoot() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("GRAPHSLAM_DATA"); env != nullptr && *env != '\0') {
    candidates.emplace_back(env);
  }
#ifdef GRAPHSLAM_DEFAULT_DATA_DIR
  candidates.emplace_back(GRAPHSLAM_DEFAULT_DATA_DIR);
#endif
  candidates.emplace_back("../shared/datasets");
  for (const auto& root : candidates) {
    if (fileExists(root + "/" + kHomeworkDir + "/hw1_data.txt")) return root;
  }
  return {};
}

std::string homeworkFile(const std::string& name) {
  const std::string root = dataRoot();
  return root.empty() ? std::string() : root + "/" + kHomeworkDir + "/" + name;
}

#define GRAPHSLAM_REQUIRE_HOMEWORK_DATA(path_var, name)                                    \
  const std::string path_var = homeworkFile(name);                                         \
  if (path_var.empty() || !fileExists(path_var)) {                                         \
    GTEST_SKIP() << "homework data " << (name) << " not found; set GRAPHSLAM_DATA to the " \
                 << "datasets folder (containing " << kHomeworkDir << ")";                 \
  }

/// Ground truth of the homework: pose i = (cos(30 deg i) - 1, sin(30 deg i), 30 deg i).
Trajectory circleGroundTruth() {
  Eigen::Matrix3Xd gt(3, 12);
  for (int i = 0; i < 12; ++i) {
    const double a = kPi / 6.0 * i;
    gt.col(i) << std::cos(a) - 1.0, std::sin(a), a;
  }
  return trajectoryFromSE2(gt);
}

/// The Gauss-Newton optimised poses of SEEDS.md section 3 (6 decimals).
Trajectory optimisedPoses() {
  Eigen::Matrix3Xd p(3, 12);
  p << 0.0, -0.142843, -0.484483, -0.958422, -1.507941, -1.929261, -2.072789, -1.901761, -1.498456,
      -0.965912, -0.491896, -0.127890,  //
      0.0, 0.510642, 0.852230, 0.931622, 0.815206, 0.454785, -0.031202, -0.498165, -0.896772,
      -1.007422, -0.823690, -0.473351,  //
      0.0, 0.486148, 1.062447, 1.537147, 2.041180, 2.629051, -3.078287, -2.572021, -2.000082,
      -1.493382, -1.014469, -0.530638;
  return trajectoryFromSE2(p);
}

Trajectory deadReckonedHomework(const std::string& path) {
  return trajectoryFromSE2(deadReckonSE2(readMatrix3xN(path)));
}

void expectStatistics(const ErrorStatistics& s, double max, double mean, double median, double min,
                      double rmse, double sse, double std_dev, double tol) {
  EXPECT_NEAR(s.max, max, tol);
  EXPECT_NEAR(s.mean, mean, tol);
  EXPECT_NEAR(s.median, median, tol);
  EXPECT_NEAR(s.min, min, tol);
  EXPECT_NEAR(s.rmse, rmse, tol);
  EXPECT_NEAR(s.sse, sse, tol);
  EXPECT_NEAR(s.std_dev, std_dev, tol);
}

/// A non-planar test trajectory (helix with varying attitude), timestamps 0.1 s apart.
Trajectory helix(int n) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    pose.translation() << 2.0 * std::cos(0.3 * i), 2.0 * std::sin(0.3 * i), 0.1 * i;
    t.append(1000.0 + 0.1 * i, pose);
  }
  return t;
}

std::string tempPath(const std::string& name) {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir != nullptr && *dir != '\0' ? dir : "/tmp") + "/graphslam_test_" + name;
}

template <typename Fn>
std::string inputErrorMessage(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "<no InputError thrown>";
}

// ---------------------------------------------------------------------------------------
// I/O

TEST(Core_Trajectory, TumRoundTrip) {
  const Trajectory original = helix(25);
  const std::string path = tempPath("roundtrip.tum");
  writeTum(path, original);
  const Trajectory read = readTum(path);
  std::remove(path.c_str());
  ASSERT_EQ(read.size(), original.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read.timestamp(i), original.timestamp(i));
    EXPECT_EQ(read.position(i), original.position(i));  // shortest exact decimal form
    EXPECT_LT((read.pose(i).linear() - original.pose(i).linear()).cwiseAbs().maxCoeff(), 1e-15);
  }
}

TEST(Core_Trajectory, TumParsesCommentsAndNormalisesQuaternion) {
  std::istringstream in(
      "# timestamp tx ty tz qx qy qz qw\n"
      "\n"
      "1.5 1 2 3 0 0 0 1   # trailing comment\r\n"
      "2.5\t4 5 6 0 0 0.7071 0.7071\n");
  const Trajectory t = readTum(in, "mem.tum");
  ASSERT_EQ(t.size(), 2U);
  EXPECT_EQ(t.timestamp(0), 1.5);
  EXPECT_EQ(t.position(1), Eigen::Vector3d(4, 5, 6));
  EXPECT_NEAR(rotationAngle(t.pose(1).linear()), kPi / 2.0, 1e-12);
  EXPECT_NEAR(Eigen::Quaterniond(t.pose(1).linear()).norm(), 1.0, 1e-15);
}

TEST(Core_Trajectory, KittiRoundTrip) {
  const Trajectory original = helix(10);
  const std::string path = tempPath("roundtrip.kitti");
  writeKitti(path, original);
  const Trajectory read = readKitti(path);
  std::remove(path.c_str());
  ASSERT_EQ(read.size(), original.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read.timestamp(i), static_cast<double>(i));
    EXPECT_EQ(read.pose(i).matrix(), original.pose(i).matrix());
  }
}

TEST(Core_Trajectory, BadInputThrowsWithFileAndLine) {
  const auto tum = [](const std::string& text) {
    return inputErrorMessage([&] {
      std::istringstream in(text);
      (void)readTum(in, "t.tum");
    });
  };
  EXPECT_EQ(tum("# c\n0 0 0 0 0 0 1\n").rfind("t.tum:2: expected 8 values", 0), 0U);
  EXPECT_EQ(
      tum("0 0 0 0 0 0 0 1\n1 0 x 0 0 0 0 1\n").rfind("t.tum:2: token 3 'x' is not a number", 0),
      0U);
  EXPECT_EQ(tum("0 nan 0 0 0 0 0 1\n").rfind("t.tum:1: token 2 'nan' is not finite", 0), 0U);
  EXPECT_EQ(tum("0 0 0 inf 0 0 0 1\n").rfind("t.tum:1: token 4 'inf' is not finite", 0), 0U);
  EXPECT_EQ(tum("0 0 0 0 0 0 0 1.1\n").rfind("t.tum:1: quaternion norm", 0), 0U);
  EXPECT_EQ(tum("0 0 0 0 0 0 0 0\n").rfind("t.tum:1: quaternion norm", 0), 0U);
  EXPECT_EQ(tum("0 1.5e 0 0 0 0 0 1\n").rfind("t.tum:1: token 2 '1.5e' is not a number", 0), 0U);
  // Time goes forward: a repeated or earlier timestamp names its line and both times.
  EXPECT_EQ(tum("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n")
                .rfind("t.tum:3: timestamp 2 is not after the previous pose's (2)", 0),
            0U);
  EXPECT_EQ(tum("5 0 0 0 0 0 0 1\n# c\n4.5 0 0 0 0 0 0 1\n")
                .rfind("t.tum:3: timestamp 4.5 is not after the previous pose's (5)", 0),
            0U);

  const auto kitti = [](const std::string& text) {
    return inputErrorMessage([&] {
      std::istringstream in(text);
      (void)readKitti(in, "k.txt");
    });
  };
  EXPECT_EQ(kitti("1 0 0 0 0 1 0 0 0 0 1\n").rfind("k.txt:1: expected 12 values", 0), 0U);
  EXPECT_EQ(kitti("1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 1 0 0 0 0 1 0\n")
                .rfind("k.txt:2: rotation block is not a rotation matrix", 0),
            0U);
  EXPECT_EQ(kitti("-1 0 0 0 0 1 0 0 0 0 1 0\n").rfind("k.txt:1: rotation block", 0), 0U);

  const auto matrix = [](const std::string& text) {
    return inputErrorMessage([&] {
      std::istringstream in(text);
      (void)readMatrix3xN(in, "m.txt");
    });
  };
  EXPECT_EQ(matrix("1 2\n3 4 5\n6 7\n").rfind("m.txt:2: expected 2 columns", 0), 0U);
  EXPECT_EQ(matrix("1 2\n3 4\n").rfind("m.txt:2: expected 3 rows, got 2", 0), 0U);
  EXPECT_EQ(matrix("1\n2\n3\n4\n").rfind("m.txt:4: more than 3 rows", 0), 0U);

  EXPECT_THROW((void)readTum("/nonexistent/graphslam/file.tum"), InputError);
}

// ---------------------------------------------------------------------------------------
// ShanghaiTech homework 1

TEST(Core_Trajectory, HomeworkDeadReckoningThirteenthPose) {
  GRAPHSLAM_REQUIRE_HOMEWORK_DATA(path, "hw1_data.txt");
  const Eigen::Matrix3Xd relative = readMatrix3xN(path);
  ASSERT_EQ(relative.cols(), 12);
  EXPECT_DOUBLE_EQ(relative(0, 0), -0.146303);
  EXPECT_DOUBLE_EQ(relative(2, 11), 0.507884);
  const Eigen::Matrix3Xd poses = deadReckonSE2(relative);
  ASSERT_EQ(poses.cols(), 13);
  EXPECT_EQ(poses.col(0), Eigen::Vector3d::Zero());
  EXPECT_NEAR(poses(0, 12), -0.056860, kSixDigits);
  EXPECT_NEAR(poses(1, 12), 0.057527, kSixDigits);
  EXPECT_NEAR(poses(2, 12), -0.141896, kSixDigits);
  EXPECT_NEAR(poses.col(12).head<2>().norm(), 0.0809, 5e-5);
}

TEST(Core_Trajectory, HomeworkApeTranslationDeadReckoning) {
  GRAPHSLAM_REQUIRE_HOMEWORK_DATA(path, "hw1_data.txt");
  const Trajectory dr = deadReckonedHomework(path);
  ASSERT_EQ(dr.size(), 13U);
  // Association (max_diff 0.01) drops the 13th pose, as in the homework.
  const ApeResult ape = computeApe(circleGroundTruth(), dr);
  ASSERT_EQ(ape.errors.size(), 12U);
  expectStatistics(ape.statistics, 0.221483, 0.114939, 0.138624, 0.000000, 0.138007, 0.228553,
                   0.076387, kSixDigits);
  // Same without association on the first 12 poses.
  ApeOptions plain;
  plain.associate = false;
  const ApeResult ape12 =
      computeApe(circleGroundTruth(), dr.subset({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}), plain);
  EXPECT_EQ(ape12.errors, ape.errors);
  ApeOptions mismatched;
  mismatched.associate = false;
  EXPECT_THROW((void)computeApe(circleGroundTruth(), dr, mismatched), Error);
}

TEST(Core_Trajectory, HomeworkApeTranslationOptimised) {
  const ApeResult ape = computeApe(circleGroundTruth(), optimisedPoses());
  ASSERT_EQ(ape.errors.size(), 12U);
  // Inputs carry 6 decimals, so allow one unit in the 6th digit.
  expectStatistics(ape.statistics, 0.080027, 0.041242, 0.035335, 0.000000, 0.048338, 0.028038,
                   0.025211, 1e-6);
}

TEST(Core_Trajectory, HomeworkApeFullTransformation) {
  GRAPHSLAM_REQUIRE_HOMEWORK_DATA(path, "hw1_data.txt");
  ApeOptions full;
  full.pose_relation = PoseRelation::kFullTransformation;
  const ApeResult dr = computeApe(circleGroundTruth(), deadReckonedHomework(path), full);
  EXPECT_NEAR(dr.statistics.rmse, 0.166972, kSixDigits);
  const ApeResult opt = computeApe(circleGroundTruth(), optimisedPoses(), full);
  EXPECT_NEAR(opt.statistics.rmse, 0.083525, 1e-6);
}

TEST(Core_Trajectory, HomeworkStudentGroundTruthFile) {
  GRAPHSLAM_REQUIRE_HOMEWORK_DATA(gt_path, "gt_tum_student_generated.txt");
  GRAPHSLAM_REQUIRE_HOMEWORK_DATA(data_path, "hw1_data.txt");
  const Trajectory gt = readTum(gt_path);
  ASSERT_EQ(gt.size(), 12U);
  const Trajectory exact = circleGroundTruth();
  for (std::size_t i = 0; i < gt.size(); ++i) {
    EXPECT_LT((gt.pose(i).matrix() - exact.pose(i).matrix()).cwiseAbs().maxCoeff(), 2e-6) << i;
  }
  const ApeResult ape = computeApe(gt, deadReckonedHomework(data_path));
  EXPECT_NEAR(ape.statistics.rmse, 0.138007, 2e-6);
}

// ---------------------------------------------------------------------------------------
// Metrics on constructed cases

TEST(Core_Trajectory, StatisticsMatchNumpy) {
  const ErrorStatistics even = computeStatistics({4.0, 1.0, 3.0, 2.0});
  expectStatistics(even, 4.0, 2.5, 2.5, 1.0, std::sqrt(7.5), 30.0, std::sqrt(1.25), 1e-15);
  const ErrorStatistics odd = computeStatistics({5.0, 1.0, 3.0});
  EXPECT_DOUBLE_EQ(odd.median, 3.0);
  EXPECT_DOUBLE_EQ(odd.std_dev, std::sqrt(8.0 / 3.0));  // population std (ddof = 0)
  EXPECT_THROW((void)computeStatistics({}), Error);
}

TEST(Core_Trajectory, KnownRigidOffset) {
  const Trajectory ref = helix(30);
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  offset.linear() =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  offset.translation() << 0.5, -1.0, 2.0;

  // Pure translation: every unaligned translation error equals the offset length.
  Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
  shift.translation() = offset.translation();
  Trajectory shifted = ref;
  shifted.transform(shift);
  const ApeResult unaligned = computeApe(ref, shifted);
  EXPECT_NEAR(unaligned.statistics.min, std::sqrt(5.25), 1e-12);
  EXPECT_NEAR(unaligned.statistics.max, std::sqrt(5.25), 1e-12);
  EXPECT_NEAR(unaligned.statistics.std_dev, 0.0, 1e-12);
  // Rotation angle error of a left-multiplied rotation is its angle at every pose.
  Trajectory moved = ref;
  moved.transform(offset);
  ApeOptions angle;
  angle.pose_relation = PoseRelation::kRotationAngleDeg;
  EXPECT_NEAR(computeApe(ref, moved, angle).statistics.mean, 0.4 * 180.0 / kPi, 1e-10);

  // SE(3) alignment removes the rigid offset.
  ApeOptions se3;
  se3.alignment.mode = AlignmentMode::kSE3;
  const ApeResult aligned = computeApe(ref, moved, se3);
  EXPECT_LT(aligned.statistics.max, 1e-9);
  EXPECT_NEAR(aligned.umeyama.scale, 1.0, 0.0);
  EXPECT_LT((aligned.umeyama.rotation - offset.linear().transpose()).norm(), 1e-9);
  se3.pose_relation = PoseRelation::kFullTransformation;
  EXPECT_LT(computeApe(ref, moved, se3).statistics.max, 1e-9);

  // Sim(3): estimate = 2.5 * (R ref + t) is mapped back with scale 1/2.5.
  Trajectory scaled = moved;
  scaled.scale(2.5);
  ApeOptions sim3;
  sim3.alignment.mode = AlignmentMode::kSim3;
  const ApeResult sim = computeApe(ref, scaled, sim3);
  EXPECT_NEAR(sim.umeyama.scale, 1.0 / 2.5, 1e-12);
  EXPECT_LT(sim.statistics.max, 1e-9);
  ApeOptions se3_only;
  se3_only.alignment.mode = AlignmentMode::kSE3;
  EXPECT_GT(computeApe(ref, scaled, se3_only).statistics.rmse, 0.1);  // scale not corrected

  // align_origin: first poses coincide afterwards.
  ApeOptions origin;
  origin.alignment.align_origin = true;
  const ApeResult o = computeApe(ref, moved, origin);
  EXPECT_NEAR(o.errors.front(), 0.0, 1e-12);
  EXPECT_LT(o.statistics.max, 1e-9);  // a rigid offset is fully removed by the origin too
}

TEST(Core_Trajectory, AssociationFollowsEvo) {
  Trajectory a;
  Trajectory b;
  for (int i = 0; i < 10; ++i) a.append(i * 1.0, se2ToIsometry3(i, 0, 0));
  for (int i = 0; i < 5; ++i) b.append(2.0 * i + 0.005, se2ToIsometry3(2.0 * i, 0, 0));
  const auto [ra, rb] = associateTrajectories(a, b);
  ASSERT_EQ(ra.size(), 5U);
  ASSERT_EQ(rb.size(), 5U);
  EXPECT_EQ(ra.timestamp(4), 8.0);
  EXPECT_EQ(rb.timestamp(4), 8.005);
  AssociationOptions tight;
  tight.max_diff = 0.001;
  EXPECT_THROW((void)associateTrajectories(a, b, tight), Error);
  AssociationOptions shifted;
  shifted.max_diff = 0.001;
  shifted.offset_2 = -0.005;
  EXPECT_EQ(associateTrajectories(a, b, shifted).first.size(), 5U);
  const MatchingIndices m = matchingTimeIndices({0.0, 0.5, 1.0}, {0.0, 1.0}, 0.5);
  EXPECT_EQ(m.first, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(m.second, (std::vector<std::size_t>{0, 0, 1}));  // first minimum on ties
}

TEST(Core_Trajectory, SortedMatchingEqualsTheFullScan) {
  // Sorted stamps take a binary search; it must pick what numpy's argmin picks (the first
  // minimum), ties and repeated stamps included.
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> tick(0, 40);
  for (int round = 0; round < 20; ++round) {
    std::vector<double> s1, s2;
    for (int i = 0; i < 60; ++i) s1.push_back(tick(rng) * 0.25);
    for (int i = 0; i < 30; ++i) s2.push_back(tick(rng) * 0.5);
    std::sort(s2.begin(), s2.end());
    const double offset = round % 2 ? 0.25 : 0.0;
    const MatchingIndices fast = matchingTimeIndices(s1, s2, 0.3, offset);
    MatchingIndices expected;
    for (std::size_t i = 0; i < s1.size(); ++i) {
      std::size_t best = 0;
      for (std::size_t j = 1; j < s2.size(); ++j) {
        if (std::abs(s2[j] + offset - s1[i]) < std::abs(s2[best] + offset - s1[i])) best = j;
      }
      if (std::abs(s2[best] + offset - s1[i]) <= 0.3) {
        expected.first.push_back(i);
        expected.second.push_back(best);
      }
    }
    EXPECT_EQ(fast.first, expected.first) << "round " << round;
    EXPECT_EQ(fast.second, expected.second) << "round " << round;
  }
  // Unsorted stamps: the full scan.
  const MatchingIndices m = matchingTimeIndices({1.0, 3.0}, {3.1, 0.9, 1.1}, 0.5);
  EXPECT_EQ(m.second, (std::vector<std::size_t>{1, 0}));
}

TEST(Core_Trajectory, RpeKnownCase) {
  // Reference: 11 poses 1 m apart along x. Estimate: steps of 1.1 m and a 0.01 rad yaw
  // increment per step.
  Trajectory ref;
  Trajectory est;
  Eigen::Isometry3d e = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d step = se2ToIsometry3(1.1, 0.0, 0.01);
  for (int i = 0; i <= 10; ++i) {
    ref.append(i, se2ToIsometry3(i, 0.0, 0.0));
    est.append(i, e);
    e = e * step;
  }
  const RpeResult trans = computeRpe(ref, est);
  ASSERT_EQ(trans.errors.size(), 10U);
  EXPECT_NEAR(trans.statistics.min, 0.1, 1e-12);
  EXPECT_NEAR(trans.statistics.max, 0.1, 1e-12);

  RpeOptions angle;
  angle.pose_relation = PoseRelation::kRotationAngleRad;
  angle.delta = 2;
  angle.all_pairs = true;
  const RpeResult rot = computeRpe(ref, est, angle);
  ASSERT_EQ(rot.errors.size(), 9U);  // (0,2) ... (8,10)
  EXPECT_NEAR(rot.statistics.mean, 0.02, 1e-12);
  EXPECT_EQ(rot.id_pairs.front(), IdPair(0, 2));

  // Two-frame consecutive pairs: (0,2), (2,4), ..., (8,10); error = |E_t| where
  // E = (ref_i^-1 ref_j)^-1 (est_i^-1 est_j) = T(-2,0) * step * step.
  RpeOptions two;
  two.delta = 2;
  const RpeResult r2 = computeRpe(ref, est, two);
  ASSERT_EQ(r2.errors.size(), 5U);
  const Eigen::Isometry3d expected = se2ToIsometry3(-2.0, 0.0, 0.0) * step * step;
  EXPECT_NEAR(r2.errors[0], expected.translation().norm(), 1e-12);

  // Metres, consecutive (evo semantics: the first endpoint is the first pose at >= delta
  // travelled path, not pose 0): est steps are 1.1 m, delta 2 m -> ids 2, 4, 6, 8, 10.
  RpeOptions metres;
  metres.delta = 2.0;
  metres.delta_unit = DeltaUnit::kMeters;
  const RpeResult rm = computeRpe(ref, est, metres);
  ASSERT_EQ(rm.id_pairs.size(), 4U);
  EXPECT_EQ(rm.id_pairs.front(), IdPair(2, 4));
  EXPECT_EQ(rm.id_pairs.back(), IdPair(8, 10));

  // Point distance error ratio: |2.2-ish - 2| / 2 in percent, for ref-based pairs (0,2)...
  RpeOptions ratio;
  ratio.pose_relation = PoseRelation::kPointDistanceErrorRatio;
  ratio.delta = 2;
  const RpeResult rr = computeRpe(ref, est, ratio);
  const double d02 = (est.position(2) - est.position(0)).norm();
  EXPECT_NEAR(rr.errors[0], std::abs(2.0 - d02) / 2.0 * 100.0, 1e-10);

  EXPECT_THROW((void)idPairsFromDelta(ref.poses(), 1.5, DeltaUnit::kFrames), Error);
  EXPECT_THROW((void)idPairsFromDelta(ref.poses(), 20, DeltaUnit::kFrames), Error);
}

}  // namespace
}  // namespace graphslam::eval
