// SPDX-License-Identifier: MIT
// The hard case: a graph with large rotation noise where the local solver, started from
// odometry, converges to a worse local minimum of SE-Sync's objective. Its certificate has
// a negative eigenvalue, and the staircase climbs out of it to the certified optimum.
#include <gtest/gtest.h>

#include <cstdio>

#include "certify_fixtures.h"
#include "graphslam/certify/certify.h"
#include "graphslam/init/chordal_objective.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/logging.h"

using namespace graphslam;
using Shape = simulation::PoseGraph3dOptions::Shape;

namespace {

/// Minimises SE-Sync's f with the project's local solver from the graph's estimates;
/// returns f at the end.
double localSolve(Graph& graph) {
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  support::setLogLevel(support::LogLevel::kError);
  init::ChordalObjective objective(graph);
  Optimizer::Options o;
  o.max_iterations = 500;
  Optimizer optimizer(graph, solvers, o);
  const Summary s = optimizer.optimize();
  EXPECT_TRUE(s.succeeded()) << s.message;
  const double f = objective.value();
  objective.restore();
  return f;
}

TEST(CertifyHardCase, StaircaseEscapesTheLocalSolversMinimum) {
  // 100 poses on a sphere, rotation noise 0.24 rad per axis (seed 2): the local solver from
  // odometry stops at f = 5654, while the optimum is 1926.
  Graph g = test::poseGraph3d(Shape::kSphere, 100, 2, 0.24);
  const double f_local = localSolve(g);
  const auto at_local = certify::verifyEstimates(g);
  EXPECT_FALSE(at_local.certified) << at_local.report();
  EXPECT_TRUE(at_local.eigensolver_converged);
  EXPECT_LT(at_local.lambda_min, -at_local.tolerance);
  EXPECT_NEAR(at_local.relaxation, f_local, 1e-6 * f_local);
  // From the local solver's poses, the staircase climbs out along the negative eigenvector.
  certify::Options o;
  o.start = certify::Options::Start::kEstimates;
  o.initial_rank = 3;
  const auto report = certify::certify(g, o);
  EXPECT_TRUE(report.certified) << report.report();
  ASSERT_GE(report.steps.size(), 2u);
  EXPECT_LT(report.steps.front().lambda_min, -report.tolerance);
  EXPECT_LT(report.objective, 0.5 * f_local) << "local " << f_local;
  // The poses written back are the certified optimum: the local solver stays there.
  const double f_refined = localSolve(g);
  EXPECT_NEAR(f_refined, report.objective, 1e-6 * report.objective);
  std::printf("local solve f %.6g (lambda_min %.3g), certified f %.6g at rank %d\n", f_local,
              at_local.lambda_min, report.objective, report.rank);
}

}  // namespace
