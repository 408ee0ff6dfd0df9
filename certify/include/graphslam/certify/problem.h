// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "graphslam/core/graph.h"

namespace graphslam::certify {

/// One relative-pose measurement of SE-Sync's problem (Rosen et al., IJRR 2019, Problem 1):
/// the term kappa |R_j - R_i R~|_F^2 + tau |t_j - t_i - R_i t~|^2 between poses i and j
/// (indices into Problem::ids()).
struct Measurement {
  int i = 0;
  int j = 0;
  Eigen::MatrixXd rotation;     ///< R~ (d x d)
  Eigen::VectorXd translation;  ///< t~ (d)
  double kappa = 0.0;           ///< rotation weight
  double tau = 0.0;             ///< translation weight
};

/// SE-Sync's problem of a pose graph with the translations eliminated.
///
/// Variables are stored by rows: the rotations as X (dn x r), block i (rows d i .. d i + d-1)
/// holding X_i = R_i^T for r = d (a point of St(d, r)^n with orthonormal block rows for
/// r > d), the translations as T (n x r), row i holding t_i^T. The full objective is
/// tr([T; X]^T M [T; X]) with M the (1 + d) n square connection Laplacian of the data
/// (translation rows first), and eliminating T gives F(X) = tr(X^T Q X) with
///   Q = M_XX - M_XT L_tau^+ M_TX
/// (L_tau = M_TT, the translation-weighted graph Laplacian). Q is never formed: products
/// with it solve with the Cholesky factor of L_tau with the first pose's translation held
/// at zero (F is invariant under shifting every translation).
class Problem {
 public:
  /// The measurements' problem on `num_poses` poses of dimension `d` (2 or 3). Throws
  /// InputError when a measurement is malformed or the poses are not connected.
  Problem(int d, int num_poses, std::vector<Measurement> measurements);
  Problem(Problem&&) noexcept;
  Problem& operator=(Problem&&) noexcept;
  ~Problem();

  [[nodiscard]] int dimension() const { return d_; }
  [[nodiscard]] int numPoses() const { return n_; }
  [[nodiscard]] const std::vector<Measurement>& measurements() const { return measurements_; }

  /// Q X.
  [[nodiscard]] Eigen::MatrixXd applyQ(const Eigen::MatrixXd& x) const;
  /// F(X) = tr(X^T Q X), summed over the measurements' residuals at the optimal
  /// translations (accurate to rounding relative to F, where the trace is not).
  [[nodiscard]] double objective(const Eigen::MatrixXd& x) const;
  /// Q X and F(X) (into *f when not null), from the residuals as objective().
  [[nodiscard]] Eigen::MatrixXd objectiveAndProduct(const Eigen::MatrixXd& x, double* f) const;
  /// The translations (n x r) minimising the full objective for the rotations X, the first
  /// pose's at zero.
  [[nodiscard]] Eigen::MatrixXd translations(const Eigen::MatrixXd& x) const;
  /// SE-Sync's objective f of poses given by rotations R_i (stacked as X, X_i = R_i^T) and
  /// translations (n x d): the sum of the measurements' terms.
  [[nodiscard]] double poseObjective(const Eigen::MatrixXd& x, const Eigen::MatrixXd& t) const;
  /// Q as a dense matrix (dn x dn; for tests on small problems).
  [[nodiscard]] Eigen::MatrixXd denseQ() const;
  /// An upper bound of the largest eigenvalue of Q (a Gershgorin bound of M_XX): the
  /// problem's scale, to which the tolerances are relative.
  [[nodiscard]] double scale() const { return scale_; }

  /// The sparse matrices and factors (certify's own, src/problem_impl.h).
  struct Impl;
  [[nodiscard]] const Impl& impl() const { return *impl_; }

 private:
  int d_ = 0;
  int n_ = 0;
  double scale_ = 0.0;
  std::vector<Measurement> measurements_;
  std::unique_ptr<Impl> impl_;
};

/// A pose graph in SE-Sync's form: the problem and the vertex of each pose.
struct PoseGraphProblem {
  Problem problem;
  std::vector<VertexId> ids;  ///< vertex id of pose index i (ascending)
};

/// SE-Sync's problem of `graph`: every active EDGE_SE2 (or EDGE_SE3:QUAT) with SE-Sync's
/// weights (2D: tau = 2 / tr(Omega_t^-1), kappa = Omega_theta; 3D: tau = 3 / tr(Omega_t^-1),
/// kappa = 3 / (2 tr(Omega_R^-1))). Throws InputError naming what is not supported: a
/// vertex that is not a VERTEX_SE2 / VERTEX_SE3:QUAT pose (landmarks), 2D and 3D poses
/// together, an active edge of another type (priors, landmark observations), an edge
/// whose rotation or translation information gives no positive weight, a graph whose
/// poses are not connected by the edges, more than one fixed vertex.
[[nodiscard]] PoseGraphProblem problemFromGraph(const Graph& graph);

}  // namespace graphslam::certify
