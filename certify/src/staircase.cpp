// SPDX-License-Identifier: MIT
// The Riemannian staircase (SE-Sync, Rosen et al. 2019, Algorithm 1): solve the rank-r
// relaxation, verify, climb along the certificate's negative eigenvector, round.
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <chrono>
#include <cmath>
#include <sstream>

#include "graphslam/certify/certify.h"
#include "graphslam/support/error.h"
#include "problem_impl.h"
#include "riemannian.h"

namespace graphslam::certify {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The nearest rotation to `a` (SVD, the determinant forced to +1).
Eigen::MatrixXd nearestRotation(const Eigen::MatrixXd& a) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::VectorXd s = Eigen::VectorXd::Ones(a.rows());
  s[a.rows() - 1] = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
}

/// Rotations (R_i^T stacked) from a point of the relaxation: its d principal directions
/// (X W, W the top eigenvectors of X^T X), reflected when most blocks have a negative
/// determinant, each block projected onto SO(d).
Eigen::MatrixXd round(const Eigen::MatrixXd& x, int d) {
  const Eigen::Index n = x.rows() / d;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(x.transpose() * x);
  const Eigen::MatrixXd w = eig.eigenvectors().rightCols(d);  // ascending order
  Eigen::MatrixXd z = x * w;
  Eigen::Index positive = 0;
  for (Eigen::Index i = 0; i < n; ++i) positive += z.middleRows(d * i, d).determinant() > 0;
  if (2 * positive < n) z.col(d - 1) *= -1.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    z.middleRows(d * i, d) = nearestRotation(z.middleRows(d * i, d).transpose()).transpose();
  }
  return z;
}

/// The point one rank up, in descent direction [0 v] from the critical point [X 0]: the
/// largest step 2^-k alpha0 that decreases F.
Eigen::MatrixXd escape(const Problem& problem, const Eigen::MatrixXd& x, double f,
                       const Eigen::VectorXd& v) {
  const int d = problem.dimension();
  Eigen::MatrixXd up = Eigen::MatrixXd::Zero(x.rows(), x.cols() + 1);
  up.leftCols(x.cols()) = x;
  Eigen::MatrixXd dir = Eigen::MatrixXd::Zero(x.rows(), x.cols() + 1);
  dir.col(x.cols()) = v;
  double alpha = std::sqrt(static_cast<double>(problem.numPoses()));
  for (int k = 0; k < 80; ++k, alpha *= 0.5) {
    Eigen::MatrixXd y = retract(up, alpha * dir, d);
    if (problem.objective(y) < f) return y;
  }
  return up;  // no decrease found: the trust region starts from the saddle itself
}

Eigen::MatrixXd lift(const Eigen::MatrixXd& x, int rank) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(x.rows(), rank);
  out.leftCols(std::min<Eigen::Index>(rank, x.cols())) =
      x.leftCols(std::min<Eigen::Index>(rank, x.cols()));
  return out;
}

/// F(x), the dual bound and the verdict, from the last rank's certificate.
void conclude(const Problem& problem, const Eigen::MatrixXd& y, const EigenResult& eig,
              const Options& options, CertificateReport& report) {
  const int d = problem.dimension();
  report.rotations = round(y, d);
  report.translations = problem.translations(report.rotations);
  report.objective = problem.objective(report.rotations);
  report.relaxation = problem.objective(y);
  report.lambda_min = eig.lambda_min;
  report.residual = eig.residual;
  report.eigensolver_converged = eig.converged;
  const double dn = static_cast<double>(y.rows());
  report.dual_bound = report.relaxation + dn * std::min(eig.lambda_min, 0.0);
  report.suboptimality =
      (report.objective - report.dual_bound) / std::max(std::abs(report.dual_bound), 1e-300);
  std::ostringstream why;
  why.precision(3);
  if (!eig.converged) {
    why << "not certified: eigensolver did not converge (residual " << eig.residual << "; "
        << eig.message << ")";
  } else if (eig.lambda_min < -report.tolerance) {
    why << "not certified: lambda_min(S) = " << eig.lambda_min << " is below -" << report.tolerance
        << " at rank " << report.rank << " (the rank limit, --max-rank)";
  } else if (report.suboptimality > options.max_relative_suboptimality) {
    why << "not certified: the relaxation is not exact (relative suboptimality bound "
        << report.suboptimality << " above " << options.max_relative_suboptimality << ")";
  } else {
    report.certified = true;
    why << "certified globally optimal";
  }
  report.reason = why.str();
}

}  // namespace

Eigen::MatrixXd chordalRotations(const Problem& problem) {
  const int d = problem.dimension();
  const int n = problem.numPoses();
  std::vector<Eigen::Triplet<double>> t;
  for (const Measurement& m : problem.measurements()) {
    // kappa |X_j - R~^T X_i|^2 with the blocks free; pose 0's block is the identity.
    for (int a = 0; a < d; ++a) {
      t.emplace_back(d * m.i + a, d * m.i + a, m.kappa);
      t.emplace_back(d * m.j + a, d * m.j + a, m.kappa);
      for (int b = 0; b < d; ++b) {
        t.emplace_back(d * m.i + a, d * m.j + b, -m.kappa * m.rotation(a, b));
        t.emplace_back(d * m.j + b, d * m.i + a, -m.kappa * m.rotation(a, b));
      }
    }
  }
  SparseMatrix l(d * n, d * n);
  l.setFromTriplets(t.begin(), t.end());
  const int free = d * (n - 1);
  const SparseMatrix lff = l.bottomRightCorner(free, free);
  const Eigen::MatrixXd rhs = -(l.block(d, 0, free, d) * Eigen::MatrixXd::Identity(d, d));
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt(lff);
  if (ldlt.info() != Eigen::Success) throw Error("certify: the chordal start's system failed");
  Eigen::MatrixXd x(d * n, d);
  x.topRows(d).setIdentity();
  x.bottomRows(free) = ldlt.solve(rhs);
  for (int i = 1; i < n; ++i) {
    x.middleRows(d * i, d) = nearestRotation(x.middleRows(d * i, d).transpose()).transpose();
  }
  return x;
}

CertificateReport certify(const Problem& problem, const Eigen::MatrixXd& start,
                          const Options& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const int d = problem.dimension();
  CertificateReport report;
  report.dimension = d;
  report.poses = problem.numPoses();
  report.measurements = static_cast<int>(problem.measurements().size());
  report.tolerance = options.eigenvalue_tolerance * problem.scale();
  ShiftedFactor preconditioner(problem);
  if (!preconditioner.factorize({}, options.preconditioner_regularization * problem.scale())) {
    throw Error("certify: the preconditioner's Cholesky factorisation failed");
  }
  Eigen::MatrixXd x = lift(start, std::max(options.initial_rank, d));
  report.setup_time = secondsSince(t0);
  EigenResult eig;
  for (;;) {
    StaircaseStep step;
    step.rank = static_cast<int>(x.cols());
    auto t1 = std::chrono::steady_clock::now();
    const TrustRegionResult tr = trustRegion(problem, x, preconditioner, options);
    step.solve_time = secondsSince(t1);
    t1 = std::chrono::steady_clock::now();
    eig = minimumEigenvalue(problem, tr.x, options);
    step.verify_time = secondsSince(t1);
    step.iterations = tr.iterations;
    step.inner_iterations = tr.inner_iterations;
    step.objective = tr.objective;
    step.gradient_norm = tr.gradient_norm;
    step.lambda_min = eig.lambda_min;
    report.steps.push_back(step);
    report.solve_time += step.solve_time;
    report.verify_time += step.verify_time;
    report.rank = step.rank;
    x = tr.x;
    if (!eig.converged || eig.lambda_min >= -report.tolerance || step.rank >= options.max_rank) {
      break;
    }
    x = escape(problem, tr.x, tr.objective, eig.vector);
  }
  conclude(problem, x, eig, options, report);
  report.total_time = secondsSince(t0);
  return report;
}

}  // namespace graphslam::certify
