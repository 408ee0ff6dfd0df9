// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "graphslam/certify/problem.h"
#include "graphslam/core/graph.h"

namespace graphslam::certify {

/// Tuning of the Riemannian staircase and of the verification. Tolerances marked
/// "relative" are multiplied by Problem::scale() (an upper bound of Q's largest
/// eigenvalue), so they mean the same on graphs of any weights.
struct Options {
  enum class Start {
    kChordal,    ///< SE-Sync's chordal relaxation of the rotations (the default)
    kEstimates,  ///< the graph's own rotations (to certify, or escape from, a local solve)
  };
  Start start = Start::kChordal;
  /// First rank of the relaxation (SE-Sync's default 5; at least d).
  int initial_rank = 5;
  /// Highest rank the staircase climbs to before giving up ("not certified").
  int max_rank = 10;

  // Riemannian trust region (truncated conjugate gradients, preconditioned by the sparse
  // Cholesky factor of Q + mu I).
  /// Stop when |grad F| <= gradient_tolerance * scale (relative).
  double gradient_tolerance = 1e-7;
  /// Stop when an accepted step decreases F by less than this fraction of F.
  double relative_decrease_tolerance = 1e-14;
  int max_iterations = 500;
  int max_inner_iterations = 2000;
  /// mu of the preconditioner Q + mu I, relative (SE-Sync bounds its condition number by 1e6).
  double preconditioner_regularization = 1e-6;

  // Verification: S = Q - Lambda(X) must have lambda_min(S) >= -eigenvalue_tolerance * scale.
  /// The certificate's tolerance on lambda_min(S) (relative).
  double eigenvalue_tolerance = 1e-7;
  /// Lanczos iterations (restarts) and convergence tolerance of the eigensolver.
  int eigen_max_iterations = 300;
  double eigen_tolerance = 1e-10;
  /// The residual |S v - lambda v| allowed of the reported eigenpair (relative).
  double eigen_residual_tolerance = 1e-6;
  /// The largest relative suboptimality bound (F(x) - dual bound) / dual bound still
  /// called certified.
  double max_relative_suboptimality = 1e-6;
};

/// One rank of the staircase.
struct StaircaseStep {
  int rank = 0;
  int iterations = 0;        ///< trust-region iterations
  int inner_iterations = 0;  ///< conjugate-gradient iterations, summed
  double objective = 0.0;    ///< F at the rank's critical point
  double gradient_norm = 0.0;
  double lambda_min = 0.0;  ///< of its certificate S
  double solve_time = 0.0;
  double verify_time = 0.0;
};

/// The minimum eigenvalue of a certificate S = Q - Lambda(X).
struct EigenResult {
  bool converged = false;
  double lambda_min = 0.0;
  double residual = 0.0;   ///< |S v - lambda_min v| with |v| = 1
  Eigen::VectorXd vector;  ///< v (dn)
  int factorizations = 0;  ///< shifted Cholesky factorisations tried
  int operations = 0;      ///< products with the shift-inverted S
  std::string message;     ///< why it did not converge
};

/// Lambda(X) (d x dn: the symmetric d x d blocks side by side) of the certificate at X.
[[nodiscard]] Eigen::MatrixXd lagrangeMultipliers(const Problem& problem, const Eigen::MatrixXd& x);

/// lambda_min(Q - Lambda(X)) and its eigenvector, sparsely: Cholesky factorisations of the
/// certificate shifted by sigma (grown from tolerance * 4^k until one succeeds, which proves
/// lambda_min > -sigma), then Lanczos (Spectra) on the inverse of the shifted certificate
/// from a fixed start vector; the residual is computed with S itself.
[[nodiscard]] EigenResult minimumEigenvalue(const Problem& problem, const Eigen::MatrixXd& x,
                                            const Options& options);

/// What certify found.
struct CertificateReport {
  bool certified = false;
  /// "certified globally optimal" or why not ("not certified: eigensolver did not converge
  /// (residual ...)", "... lambda_min(S) = ... below -tolerance at the rank limit ...").
  std::string reason;
  int dimension = 0;
  int poses = 0;
  int measurements = 0;
  double objective = 0.0;      ///< SE-Sync's f at the rounded poses, F(x)
  double relaxation = 0.0;     ///< F(Y) at the relaxation's last critical point
  double dual_bound = 0.0;     ///< tr(Lambda) + dn min(lambda_min, 0) <= f*
  double suboptimality = 0.0;  ///< (objective - dual_bound) / dual_bound
  double lambda_min = 0.0;     ///< of the last certificate
  double residual = 0.0;       ///< of its eigenpair
  double tolerance = 0.0;      ///< lambda_min must be >= -tolerance
  bool eigensolver_converged = false;
  int rank = 0;  ///< the relaxation's rank at the end
  std::vector<StaircaseStep> steps;
  double setup_time = 0.0;  ///< building Q and the factors, the start
  double solve_time = 0.0;  ///< trust region at every rank
  double verify_time = 0.0;
  double total_time = 0.0;
  /// The rounded solution: rotations (R_i^T stacked, dn x d) and translations (n x d), in
  /// the problem's frame (first pose at the origin).
  Eigen::MatrixXd rotations;
  Eigen::MatrixXd translations;

  /// Lines for a program to print.
  [[nodiscard]] std::string report() const;
};

/// Runs the staircase on `problem` from `start` (dn x d rotations, X_i = R_i^T) and
/// certifies the result.
[[nodiscard]] CertificateReport certify(const Problem& problem, const Eigen::MatrixXd& start,
                                        const Options& options = {});

/// SE-Sync's chordal start: the rotations minimising the rotation terms with each block
/// free (a linear least-squares problem, the first pose held at the identity), each
/// projected onto SO(d).
[[nodiscard]] Eigen::MatrixXd chordalRotations(const Problem& problem);

/// Certifies the pose graph `graph` (problemFromGraph's requirements) and writes the
/// rounded solution into its vertices (in the frame of its fixed vertex, or of its
/// lowest-id pose's estimate). Throws InputError for unsupported graphs.
[[nodiscard]] CertificateReport certify(Graph& graph, const Options& options = {});

/// Checks the graph's current estimates: the certificate of its rotations as a rank-d
/// point (no solve). Certified only when they are SE-Sync's global optimum.
[[nodiscard]] CertificateReport verifyEstimates(const Graph& graph, const Options& options = {});

}  // namespace graphslam::certify
