// SPDX-License-Identifier: MIT
// certify: SE-Sync's reduced problem, the sparse minimum eigenvalue of the certificate
// against a dense solver, the staircase on small graphs, refusals of unsupported graphs.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "certify_fixtures.h"
#include "graphslam/certify/certify.h"
#include "graphslam/init/chordal_objective.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/error.h"
#include "graphslam/support/logging.h"
#include "graphslam/types_slam2d/edge_prior_se2.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"

using namespace graphslam;
using Shape = simulation::PoseGraph3dOptions::Shape;

namespace {

/// The dense certificate S = Q - Lambda(X).
Eigen::MatrixXd denseCertificate(const certify::Problem& p, const Eigen::MatrixXd& x) {
  const int d = p.dimension();
  const Eigen::MatrixXd lambda = certify::lagrangeMultipliers(p, x);
  Eigen::MatrixXd s = p.denseQ();
  for (int i = 0; i < p.numPoses(); ++i) s.block(d * i, d * i, d, d) -= lambda.middleCols(d * i, d);
  return s;
}

/// Rotations drawn at random (a point far from any critical point).
Eigen::MatrixXd randomRotations(int d, int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Eigen::MatrixXd x(d * n, d);
  for (int i = 0; i < n; ++i) {
    Eigen::MatrixXd a(d, d);
    for (int k = 0; k < d * d; ++k) a.data()[k] = g(rng);
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
    Eigen::MatrixXd q = qr.householderQ();
    if (q.determinant() < 0) q.col(0) *= -1.0;
    x.middleRows(d * i, d) = q;
  }
  return x;
}

/// SE-Sync's f minimised by the project's local solver on the chordal edges, from the
/// graph's estimates.
double localChordalOptimum(Graph& graph) {
  SolverRegistry solvers;
  solvers::registerSolvers(solvers);
  support::setLogLevel(support::LogLevel::kError);
  init::ChordalObjective objective(graph);
  Optimizer::Options o;
  o.max_iterations = 200;
  Optimizer optimizer(graph, solvers, o);
  (void)optimizer.optimize();
  const double f = objective.value();
  objective.restore();
  return f;
}

TEST(CertifyProblem, ReducedObjectiveMatchesThePoseTermsAndTheDenseQ) {
  for (const bool three_d : {false, true}) {
    Graph g = three_d ? test::poseGraph3d(Shape::kGrid, 27, 3) : test::manhattan2d(40, 3);
    const auto pg = certify::problemFromGraph(g);
    const auto& p = pg.problem;
    const Eigen::MatrixXd x = randomRotations(p.dimension(), p.numPoses(), 7);
    const Eigen::MatrixXd t = p.translations(x);
    // F(X) is the pose objective at the optimal translations, and no other translations
    // do better.
    EXPECT_NEAR(p.objective(x), p.poseObjective(x, t), 1e-9 * p.objective(x));
    Eigen::MatrixXd t2 = t;
    t2.row(3) += Eigen::RowVectorXd::Constant(p.dimension(), 0.1);
    EXPECT_GT(p.poseObjective(x, t2), p.objective(x));
    const Eigen::MatrixXd q = p.denseQ();
    EXPECT_LT((q * x - p.applyQ(x)).norm(), 1e-9 * (q * x).norm());
    EXPECT_LT((q - q.transpose()).norm(), 1e-9 * q.norm());
  }
}

TEST(CertifyEigen, SparseMinimumEigenvalueMatchesTheDenseSolver) {
  for (const bool three_d : {false, true}) {
    Graph g = three_d ? test::poseGraph3d(Shape::kSphere, 60, 5) : test::manhattan2d(60, 5);
    const auto pg = certify::problemFromGraph(g);
    const auto& p = pg.problem;
    certify::Options options;
    const auto report = certify::certify(p, certify::chordalRotations(p), options);
    ASSERT_TRUE(report.certified) << report.report();
    // At the optimum (lambda_min ~ 0: the certificate's kernel) and at random rotations
    // (far from critical: lambda_min clearly negative).
    for (const Eigen::MatrixXd& x :
         {Eigen::MatrixXd(report.rotations), randomRotations(p.dimension(), p.numPoses(), 9)}) {
      const Eigen::VectorXd dense =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(denseCertificate(p, x)).eigenvalues();
      const certify::EigenResult sparse = certify::minimumEigenvalue(p, x, options);
      ASSERT_TRUE(sparse.converged) << sparse.message;
      EXPECT_NEAR(sparse.lambda_min, dense[0], 1e-8 * p.scale())
          << (three_d ? "3D" : "2D") << " dense " << dense[0];
      EXPECT_LT(sparse.residual, 1e-8 * p.scale());
      EXPECT_NEAR(sparse.vector.norm(), 1.0, 1e-12);
    }
  }
}

TEST(CertifyEigen, ANonConvergedEigensolverIsNeverCertified) {
  Graph g = test::manhattan2d(60, 5);
  certify::Options options;
  options.eigen_max_iterations = 0;
  const auto report = certify::certify(g, options);
  EXPECT_FALSE(report.certified);
  EXPECT_FALSE(report.eigensolver_converged);
  EXPECT_EQ(report.reason.rfind("not certified: eigensolver did not converge (residual ", 0), 0u)
      << report.reason;
}

TEST(CertifyStaircase, CertifiesSmallGraphsAtTheLocalSolversOptimum) {
  for (const bool three_d : {false, true}) {
    Graph g = three_d ? test::poseGraph3d(Shape::kSphere, 200, 11) : test::manhattan2d(300, 11);
    Graph reference =
        three_d ? test::poseGraph3d(Shape::kSphere, 200, 11) : test::manhattan2d(300, 11);
    const auto report = certify::certify(g);
    ASSERT_TRUE(report.certified) << report.report();
    EXPECT_GE(report.lambda_min, -report.tolerance);
    EXPECT_LE(report.suboptimality, 1e-6);
    EXPECT_LE(report.dual_bound, report.objective * (1 + 1e-12));
    // The poses written back give F(x) (SE-Sync's f with the chordal edges), and the local
    // solver from them finds nothing lower.
    const auto pg = certify::problemFromGraph(g);
    const auto back = certify::verifyEstimates(g);
    EXPECT_NEAR(back.relaxation, report.objective, 1e-8 * report.objective);
    EXPECT_TRUE(back.certified) << back.report();
    const double local = localChordalOptimum(reference);
    EXPECT_LE(report.objective, local * (1 + 1e-7)) << "local " << local;
  }
}

TEST(CertifyStaircase, WritesTheSolutionInTheFrameOfTheFixedVertex) {
  Graph g = test::manhattan2d(50, 13);
  g.vertex(10)->setFixed(true);
  const auto before = static_cast<types_slam2d::VertexSE2*>(g.vertex(10))->estimate();
  const auto report = certify::certify(g);
  ASSERT_TRUE(report.certified) << report.report();
  const auto after = static_cast<types_slam2d::VertexSE2*>(g.vertex(10))->estimate();
  EXPECT_LT((after.translation() - before.translation()).norm(), 1e-9);
  EXPECT_NEAR(after.angle(), before.angle(), 1e-9);
}

/// The message of the InputError problemFromGraph throws for `g`.
std::string refusal(const Graph& g) {
  try {
    (void)certify::problemFromGraph(g);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(CertifyRefusals, NamesWhatIsNotSupported) {
  {
    Graph g = test::manhattan2d(20, 1);
    auto l = std::make_unique<types_slam2d::VertexXY>();
    l->setId(1000);
    g.addVertex(std::move(l));
    EXPECT_NE(refusal(g).find("vertex 1000"), std::string::npos) << refusal(g);
    EXPECT_NE(refusal(g).find("pose graphs only"), std::string::npos);
  }
  {
    Graph g = test::manhattan2d(20, 1);
    auto p = std::make_unique<types_slam2d::EdgePriorSE2>();
    p->setVertexIds({4});
    p->setInformation(Eigen::Matrix3d::Identity());
    g.addEdge(std::move(p));
    EXPECT_NE(refusal(g).find("the edge on vertex 4 is"), std::string::npos) << refusal(g);
  }
  {
    Graph g = test::manhattan2d(20, 1);
    auto v = std::make_unique<types_slam2d::VertexSE2>();
    v->setId(500);
    g.addVertex(std::move(v));
    EXPECT_NE(refusal(g).find("disconnected"), std::string::npos) << refusal(g);
    EXPECT_NE(refusal(g).find("vertex 500"), std::string::npos) << refusal(g);
  }
  {
    Graph g = test::manhattan2d(20, 1);
    auto* e = static_cast<types_slam2d::EdgeSE2*>(g.edges()[5].get());
    Eigen::Matrix3d info = e->information();
    info(2, 2) = 0.0;
    e->setInformation(info);
    EXPECT_NE(refusal(g).find("no usable rotation information"), std::string::npos) << refusal(g);
  }
  {
    Graph g = test::manhattan2d(20, 1);
    g.vertex(0)->setFixed(true);
    g.vertex(3)->setFixed(true);
    EXPECT_NE(refusal(g).find("vertices 0 and 3 are both fixed"), std::string::npos) << refusal(g);
  }
}

}  // namespace
