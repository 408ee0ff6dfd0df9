// SPDX-License-Identifier: MIT
// certify on a Graph: the start from its estimates, the solution written back, the report.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "graphslam/certify/certify.h"
#include "graphslam/geometry/so3.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam3d/vertex_se3.h"

namespace graphslam::certify {

namespace {

/// The rotation and translation of a pose vertex (2D or 3D).
void poseOf(const Vertex& v, Eigen::MatrixXd& r, Eigen::VectorXd& t) {
  if (const auto* se2 = dynamic_cast<const types_slam2d::VertexSE2*>(&v)) {
    r = se2->estimate().rotation();
    t = se2->estimate().translation();
  } else {
    const auto& se3 = static_cast<const types_slam3d::VertexSE3&>(v).estimate();
    r = se3.rotation();
    t = se3.translation();
  }
}

void setPose(Vertex& v, const Eigen::MatrixXd& r, const Eigen::VectorXd& t) {
  if (auto* se2 = dynamic_cast<types_slam2d::VertexSE2*>(&v)) {
    se2->setEstimate(geometry::SE2(Eigen::Vector2d(t), std::atan2(r(1, 0), r(0, 0))));
  } else {
    const Eigen::Matrix3d r3 = r;
    static_cast<types_slam3d::VertexSE3&>(v).setEstimate(
        geometry::SE3(geometry::SO3::fromMatrix(r3), Eigen::Vector3d(t)));
  }
}

/// The graph's rotations, X_i = R_i^T stacked.
Eigen::MatrixXd estimatedRotations(const Graph& graph, const PoseGraphProblem& pg) {
  const int d = pg.problem.dimension();
  Eigen::MatrixXd x(d * pg.problem.numPoses(), d);
  Eigen::MatrixXd r;
  Eigen::VectorXd t;
  for (std::size_t i = 0; i < pg.ids.size(); ++i) {
    poseOf(*graph.vertex(pg.ids[i]), r, t);
    x.middleRows(d * static_cast<Eigen::Index>(i), d) = r.transpose();
  }
  return x;
}

/// Writes the report's poses into the graph, moved rigidly so that the anchor (the fixed
/// vertex, else the lowest id) keeps its estimate.
void writePoses(Graph& graph, const PoseGraphProblem& pg, const CertificateReport& report) {
  const int d = pg.problem.dimension();
  std::size_t anchor = 0;
  for (std::size_t i = 0; i < pg.ids.size(); ++i) {
    if (graph.vertex(pg.ids[i])->fixed()) anchor = i;
  }
  Eigen::MatrixXd ra;
  Eigen::VectorXd ta;
  poseOf(*graph.vertex(pg.ids[anchor]), ra, ta);
  const auto a = static_cast<Eigen::Index>(anchor);
  const Eigen::MatrixXd g = ra * report.rotations.middleRows(d * a, d);  // R_A R^_a^T
  const Eigen::VectorXd ta_hat = report.translations.row(a).transpose();
  for (std::size_t i = 0; i < pg.ids.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const Eigen::MatrixXd r = g * report.rotations.middleRows(d * k, d).transpose();
    const Eigen::VectorXd t = g * (report.translations.row(k).transpose() - ta_hat) + ta;
    setPose(*graph.vertex(pg.ids[i]), r, t);
  }
}

}  // namespace

CertificateReport certify(Graph& graph, const Options& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const PoseGraphProblem pg = problemFromGraph(graph);
  const Eigen::MatrixXd start = options.start == Options::Start::kChordal
                                    ? chordalRotations(pg.problem)
                                    : estimatedRotations(graph, pg);
  const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CertificateReport report = certify(pg.problem, start, options);
  report.setup_time += setup;
  report.total_time += setup;
  writePoses(graph, pg, report);
  return report;
}

CertificateReport verifyEstimates(const Graph& graph, const Options& options) {
  const PoseGraphProblem pg = problemFromGraph(graph);
  Options verify = options;
  verify.initial_rank = verify.max_rank = pg.problem.dimension();
  verify.max_iterations = 0;  // the trust region only evaluates the start
  return certify(pg.problem, estimatedRotations(graph, pg), verify);
}

std::string CertificateReport::report() const {
  std::ostringstream o;
  char line[512];
  o << reason << "\n";
  std::snprintf(line, sizeof line,
                "  F(x) %.10g (SE-Sync's objective, %dD, %d poses, %d measurements)\n"
                "  dual bound %.10g, relative suboptimality bound %.3g\n"
                "  lambda_min(S) %.3g (tolerance -%.3g), residual %.3g%s\n"
                "  rank %d; time %.3f s (setup %.3f, solve %.3f, verify %.3f)\n",
                objective, dimension, poses, measurements, dual_bound, suboptimality, lambda_min,
                tolerance, residual, eigensolver_converged ? "" : " (eigensolver not converged)",
                rank, total_time, setup_time, solve_time, verify_time);
  o << line;
  for (const StaircaseStep& s : steps) {
    std::snprintf(line, sizeof line,
                  "  rank %d: F %.10g, |grad| %.2g, %d iterations (%d inner), lambda_min %.3g, "
                  "%.3f + %.3f s\n",
                  s.rank, s.objective, s.gradient_norm, s.iterations, s.inner_iterations,
                  s.lambda_min, s.solve_time, s.verify_time);
    o << line;
  }
  return o.str();
}

}  // namespace graphslam::certify
