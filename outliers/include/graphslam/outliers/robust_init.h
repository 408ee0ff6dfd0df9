// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/outliers/gnc.h"

namespace graphslam::outliers {

/// What robustInitialization() did.
struct RobustInitReport {
  bool ok = true;  ///< false: an initialisation failed (message says why)
  std::string message;
  bool converged = false;  ///< every weight decided (0 or 1)
  int steps = 0;           ///< weighted initialisations made
  double initial_mu = 0.0;
  double final_mu = 0.0;
  std::size_t candidates = 0;
  std::size_t zero_weight = 0;  ///< candidates of final weight 0
  double seconds = 0.0;
  /// Final weight of every edge of the graph (1 for known inliers).
  std::vector<double> weights;
};

/// Graduated non-convexity over the global SE(2) initialisation: each step places every
/// pose and landmark by the weighted linear least-squares problems of
/// init::initializeGlobalWeighted (chordal rotations, then positions) and sets the
/// candidates' truncated-least-squares weights from their chi2 at that estimate, as
/// runGnc does (same thresholds, mu_0 and weight rule; the first step weighs every edge
/// 1). Each step solves its convex problem exactly, where runGnc's steps are a few
/// nonlinear iterations from a start that wrong loop closures may have put far off; the
/// estimate it leaves is a start for runGnc (with its weights: GncOptions::initial_weights).
/// Uses options' known inliers, inlier_probability, mu_step, min_initial_mu,
/// max_iterations and weight_tolerance.
[[nodiscard]] RobustInitReport robustInitialization(Graph& graph, LinearSolver* solver,
                                                    const GncOptions& options);

/// The rejection robustInitialization's weights decide (candidates of weight below
/// options.rejection_weight; their chi2 at the graph's current estimates), as runGnc would
/// report it, for removeRejected: when the weighted initialisation converged, its
/// classification can stand without the nonlinear GNC.
[[nodiscard]] GncResult rejectionFromInitialization(Graph& graph, const RobustInitReport& report,
                                                    const GncOptions& options);

/// The truncated-least-squares objective at the current estimates: chi2 of the known
/// inliers plus min(chi2, c^2) of every candidate (recomputes all errors).
[[nodiscard]] double tlsCost(Graph& graph, const GncOptions& options);

/// What rejectFromGlobalStart() did besides its GncResult.
struct GlobalStartReport {
  RobustInitReport init;
  double cost_by_initialization = 0.0;  ///< TLS cost of the initialisation's rejection
  double cost_by_gnc = -1.0;            ///< TLS cost of the nonlinear GNC's (< 0: not run)
  bool chose_gnc = false;
};

/// Outlier rejection for graphs whose estimates cannot be trusted (edges-only files, or
/// files whose estimates the tool replaces by the global initialisation):
///  1. robustInitialization places the graph and classifies the candidates;
///  2. the candidates it rejects are left out (Graph::setEdgeActive) and the rest is
///     optimised by least squares: the first answer;
///  3. unless options.verify is false, the nonlinear GNC (runGnc, mu from the residuals)
///     runs from that optimum, and its inliers are optimised likewise: the second answer;
///  4. the answer of lower TLS cost (tlsCost) stands: its estimate is left in the graph,
///     its rejection returned (chi2 of the rejected edges at that estimate), nothing removed.
/// The two fail on different graphs: the weighted initialisation misplaces groups of right
/// closures where the chordal relaxation is rough (ringcity), the nonlinear GNC's
/// warm-started steps drift where its first, nearly convex steps let the odometry pull
/// the graph away (m3500); the TLS cost tells them apart. When the initialisation does
/// not converge, runGnc from its estimate alone.
[[nodiscard]] GncResult rejectFromGlobalStart(Graph& graph, const SolverRegistry& solvers,
                                              LinearSolver* init_solver, const GncOptions& options,
                                              GlobalStartReport* report = nullptr);

}  // namespace graphslam::outliers
