// SPDX-License-Identifier: MIT
// The CMU 16-833 HW3 files (../shared/datasets/seeds/2d_*.npz, SEEDS.md section 1): graph
// sizes, the linear solution against an independent dense least-squares solution, and the
// homework's 10 Gauss-Newton iterations on the nonlinear file. Skipped without the files.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <cmath>

#include "../common/test_util.h"
#include "graphslam/eval/point_errors.h"
#include "graphslam/io/coursework_npz.h"
#include "graphslam/io/npz.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/logging.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using namespace graphslam::types_slam2d;
using namespace graphslam::io;
using namespace graphslam::eval;

namespace {

struct SeedCase {
  std::string file;
  PointObservationModel model;
  int poses, landmarks;
  std::size_t observations;
};

std::ostream& operator<<(std::ostream& os, const SeedCase& c) { return os << c.file; }

std::string seedPath(const std::string& file) { return test::dataDir() + "/seeds/" + file; }

#define SKIP_IF_ABSENT(path)                                        \
  if (!test::fileExists(path))                                      \
  GTEST_SKIP() << "dataset " << (path)                              \
               << " not found (set GRAPHSLAM_DATA to the datasets " \
                  "folder)"

class Datasets_Coursework : public ::testing::TestWithParam<SeedCase> {};

TEST_P(Datasets_Coursework, GraphHasTheSizesOfSeedsMd) {
  const SeedCase& c = GetParam();
  const std::string path = seedPath(c.file);
  SKIP_IF_ABSENT(path);
  const CourseworkProblem p = loadCourseworkNpz(path);
  EXPECT_EQ(p.model, c.model) << p.model_reason;
  EXPECT_EQ(p.num_poses, c.poses);
  EXPECT_EQ(p.num_landmarks, c.landmarks);
  EXPECT_EQ(p.num_observations, c.observations);
  EXPECT_EQ(p.graph.numVertices(), static_cast<std::size_t>(c.poses + c.landmarks));
  EXPECT_EQ(p.graph.numEdges(), 1 + static_cast<std::size_t>(c.poses - 1) + c.observations);
  EXPECT_TRUE(p.notes.empty());  // every landmark is observed
  EXPECT_EQ(p.ground_truth.poses.size(), static_cast<std::size_t>(c.poses));
  EXPECT_EQ(p.ground_truth.poses[0], Eigen::Vector2d::Zero());
}

INSTANTIATE_TEST_SUITE_P(
    Seeds, Datasets_Coursework,
    ::testing::Values(
        SeedCase{"2d_linear.npz", PointObservationModel::kLinear, 1000, 100, 52566},
        SeedCase{"2d_linear_loop.npz", PointObservationModel::kLinear, 200, 200, 4072},
        SeedCase{"2d_nonlinear.npz", PointObservationModel::kBearingRange, 100, 15, 766}));

/// The state of the graph in the homework's order [r_0 .. r_{P-1}, l_0 ..].
Eigen::VectorXd state(const CourseworkProblem& p) {
  Eigen::VectorXd x(2 * (p.num_poses + p.num_landmarks));
  for (int k = 0; k < p.num_poses + p.num_landmarks; ++k) {
    x.segment<2>(2 * k) = static_cast<const VertexXY*>(p.graph.vertex(k))->estimate();
  }
  return x;
}

Summary optimize(CourseworkProblem& p, Algorithm algorithm, int iterations) {
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  Optimizer::Options o;
  o.algorithm = algorithm;
  o.max_iterations = iterations;
  o.function_tolerance = 0;  // the homework runs a fixed number of iterations
  o.step_tolerance = 0;
  support::setLogLevel(support::LogLevel::kError);
  Optimizer optimizer(p.graph, solvers, o);
  return optimizer.optimize();
}

/// The homework's linear system (linear.py create_linear_system), built here from the
/// arrays alone: rows prior, odometry, observations, each whitened by Sigma^-1/2.
/// Returns A^T A and A^T b when `normal` is set, else A and b.
void homeworkSystem(const std::string& path, bool normal, Eigen::MatrixXd& m, Eigen::VectorXd& v) {
  const io::NpzArchive npz(path);
  const Eigen::MatrixXd odom = npz.read("odom").matrix();
  const Eigen::MatrixXd obs = npz.read("observations").matrix();
  const Eigen::MatrixXd s_odom = npz.read("sigma_odom").matrix();
  const Eigen::MatrixXd s_obs = npz.read("sigma_landmark").matrix();
  const long P = npz.read("gt_traj").matrix().rows();
  const long L = npz.read("gt_landmarks").matrix().rows();
  // Sigma^-1/2 of a diagonal covariance (the homework files' are diagonal).
  ASSERT_EQ(s_odom(0, 1), 0.0);
  ASSERT_EQ(s_obs(0, 1), 0.0);
  const Eigen::Matrix2d w_odom = s_odom.diagonal().cwiseSqrt().cwiseInverse().asDiagonal();
  const Eigen::Matrix2d w_obs = s_obs.diagonal().cwiseSqrt().cwiseInverse().asDiagonal();
  const long n = 2 * (P + L);
  const long rows = 2 * (1 + odom.rows() + obs.rows());
  if (normal) {
    m = Eigen::MatrixXd::Zero(n, n);
    v = Eigen::VectorXd::Zero(n);
  } else {
    m = Eigen::MatrixXd::Zero(rows, n);
    v = Eigen::VectorXd::Zero(rows);
  }
  long row = 0;
  // One 2-row block: w * (x_b - x_a) = w * z (a < 0: prior on b).
  auto block = [&](long a, long b, const Eigen::Matrix2d& w, const Eigen::Vector2d& z) {
    if (normal) {
      const Eigen::Matrix2d wtw = w.transpose() * w;
      m.block<2, 2>(2 * b, 2 * b) += wtw;
      v.segment<2>(2 * b) += wtw * z;
      if (a >= 0) {
        m.block<2, 2>(2 * a, 2 * a) += wtw;
        m.block<2, 2>(2 * a, 2 * b) -= wtw;
        m.block<2, 2>(2 * b, 2 * a) -= wtw;
        v.segment<2>(2 * a) -= wtw * z;
      }
    } else {
      m.block<2, 2>(row, 2 * b) = w;
      if (a >= 0) m.block<2, 2>(row, 2 * a) = -w;
      v.segment<2>(row) = w * z;
      row += 2;
    }
  };
  block(-1, 0, Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero());
  for (long i = 0; i < odom.rows(); ++i) block(i, i + 1, w_odom, odom.row(i).transpose());
  for (long k = 0; k < obs.rows(); ++k) {
    block(static_cast<long>(obs(k, 0)), P + static_cast<long>(obs(k, 1)), w_obs,
          obs.row(k).tail<2>().transpose());
  }
}

/// Loads a linear homework file and solves it with Gauss-Newton (one step solves it; the
/// second confirms convergence).
Summary solveLinear(const std::string& path, CourseworkProblem& p) {
  p = loadCourseworkNpz(path);
  return optimize(p, Algorithm::kGaussNewton, 2);
}

TEST(Datasets_Coursework, LinearLoopSolutionEqualsDenseQr) {
  const std::string path = seedPath("2d_linear_loop.npz");
  SKIP_IF_ABSENT(path);
  CourseworkProblem p;
  const Summary s = solveLinear(path, p);
  ASSERT_TRUE(s.succeeded()) << s.message;
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  homeworkSystem(path, false, a, b);
  ASSERT_EQ(a.rows(), 2 * (1 + 199 + 4072));
  ASSERT_EQ(a.cols(), 800);
  const Eigen::VectorXd x = a.householderQr().solve(b);
  const Eigen::VectorXd ours = state(p);
  EXPECT_LT((ours - x).cwiseAbs().maxCoeff(), 1e-9);
  // chi2 is the squared residual norm of the whitened system.
  EXPECT_NEAR(s.final_chi2, (a * x - b).squaredNorm(), 1e-9 * s.final_chi2);
  std::printf("2d_linear_loop: chi2 %.10g, max |x - x_qr| %.3g\n", s.final_chi2,
              (ours - x).cwiseAbs().maxCoeff());
}

TEST(Datasets_Coursework, LinearSolutionEqualsDenseNormalEquations) {
  const std::string path = seedPath("2d_linear.npz");
  SKIP_IF_ABSENT(path);
  CourseworkProblem p;
  const Summary s = solveLinear(path, p);
  ASSERT_TRUE(s.succeeded()) << s.message;
  Eigen::MatrixXd h;
  Eigen::VectorXd g;
  homeworkSystem(path, true, h, g);
  const Eigen::VectorXd x = h.llt().solve(g);
  EXPECT_LT((state(p) - x).cwiseAbs().maxCoeff(), 1e-8);
  const auto errors = positionErrors(p.graph, p.ground_truth);
  std::printf("2d_linear: chi2 %.10g, pose rmse %.6f m, landmark rmse %.6f m\n", s.final_chi2,
              errors.poses.rmse, errors.landmarks.rmse);
  EXPECT_LT(errors.landmarks.rmse, 0.1);
}

// chi2 = sum e^T Omega e at the homework's init_states and after its 10 Gauss-Newton
// iterations, computed independently with SciPy (bench/scipy_solver_study.py's system:
// chi2 = |b|^2 of the whitened system, plus the prior's |r_0|^2 ~ 1e-22).
constexpr double kNonlinearInitialChi2 = 8623.32247557;
constexpr double kNonlinearFinalChi2 = 1555.18964563;

TEST(Datasets_Coursework, NonlinearTenGaussNewtonIterations) {
  const std::string path = seedPath("2d_nonlinear.npz");
  SKIP_IF_ABSENT(path);
  CourseworkProblem p = loadCourseworkNpz(path);
  const auto before = positionErrors(p.graph, p.ground_truth);
  const Summary s = optimize(p, Algorithm::kGaussNewton, 10);
  const auto after = positionErrors(p.graph, p.ground_truth);
  std::printf(
      "2d_nonlinear: chi2 %.10g -> %.10g; landmark rmse %.6f -> %.6f m; pose rmse %.6f -> %.6f "
      "m\n",
      s.initial_chi2, s.final_chi2, before.landmarks.rmse, after.landmarks.rmse, before.poses.rmse,
      after.poses.rmse);
  EXPECT_EQ(s.iterations, 10);
  EXPECT_NEAR(s.initial_chi2, kNonlinearInitialChi2, 1e-6 * kNonlinearInitialChi2);
  EXPECT_NEAR(s.final_chi2, kNonlinearFinalChi2, 1e-6 * kNonlinearFinalChi2);
  EXPECT_LT(after.landmarks.rmse, before.landmarks.rmse);
}

}  // namespace
