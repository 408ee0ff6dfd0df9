// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/robust_kernel.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/optimizer/optimizer.h"

namespace graphslam::outliers {

/// A fixed weight on an edge's information: rho(s) = w s, rho'(s) = w, rho''(s) = 0. The
/// GNC gives every candidate edge one of its own and changes its weight between optimizer
/// runs (the one mutation RobustKernel allows a derived class: never during optimize()).
class WeightKernel final : public RobustKernel {
 public:
  explicit WeightKernel(double weight = 1.0) : weight_(weight) {}
  void robustify(double squared_error, double rho[3]) const override {
    rho[0] = weight_ * squared_error;
    rho[1] = weight_;
    rho[2] = 0.0;
  }
  void setWeight(double weight) { weight_ = weight; }
  [[nodiscard]] double weight() const { return weight_; }

 private:
  double weight_;
};

/// One GNC step, for progress output.
struct GncIterationStats {
  int iteration = 0;          ///< 1-based
  double mu = 0.0;            ///< the control parameter the step's weights were made with
  double cost = 0.0;          ///< sum of w_k chi2_k (known inliers: w = 1) after the step
  std::size_t inliers = 0;    ///< candidates of weight >= rejection_weight
  std::size_t undecided = 0;  ///< candidates whose weight is neither 0 nor 1 (weight_tolerance)
  int optimizer_iterations = 0;
  double elapsed = 0.0;  ///< seconds since the GNC started
};

/// Graduated non-convexity with the truncated-least-squares (TLS) surrogate (Yang,
/// Antonante, Tzoumas, Carlone, "Graduated Non-Convexity for Robust Spatial Perception",
/// RA-L 2020; GTSAM's GncOptimizer). Edge k of a candidate set has the cost
/// min(s_k, c_k^2), s_k = e_k^T Omega_k e_k; GNC minimises the surrogate with control mu,
/// convex for mu -> 0 and TLS for mu -> infinity, alternating a weighted least-squares
/// step with the closed-form weights
///   w_k = 1                                   if s_k <= mu / (mu + 1) c_k^2
///   w_k = 0                                   if s_k >= (mu + 1) / mu c_k^2
///   w_k = c_k sqrt(mu (mu + 1) / s_k) - mu    otherwise,
/// and mu_0 = c^2 / (2 s_max - c^2) (Remark 5 of the paper, over the candidates), then
/// mu <- mu * mu_step, until every weight is 0 or 1.
struct GncOptions {
  /// Probability that an inlier's s_k lies below its threshold: c_k^2 is the quantile of
  /// the chi-square distribution with the edge's dimension as degrees of freedom at this
  /// probability (GTSAM's setInlierCostThresholdsAtProbability; 0.99: 11.34 for SE(2)).
  double inlier_probability = 0.99;
  /// Factor mu grows by per step (the paper's and GTSAM's 1.4 for TLS; 2 with three
  /// iterations per step was as accurate on the benchmarks in half the steps).
  double mu_step = 2.0;
  /// mu of the first step; 0: from the residuals at the start (Remark 5). A start that
  /// already separates the outliers (robustInitialization) passes its final mu.
  double initial_mu = 0.0;
  /// Smallest mu_0 (GTSAM's floor: a huge residual would otherwise start at mu ~ 0).
  double min_initial_mu = 1e-6;
  /// At most this many GNC steps (GTSAM: 100).
  int max_iterations = 100;
  /// Optimizer iterations per GNC step, warm-started from the last step's estimate: the
  /// weights change little from one step to the next, so a few Gauss-Newton iterations
  /// follow the solution, where a full solve per step (GTSAM) costs tens of times more
  /// (m3500 with 10 %: one iteration lost a right closure, three kept all).
  int optimizer_iterations_per_step = 3;
  /// Optimizer iterations of plain least squares over every edge (all weights 1) before
  /// mu_0 is computed, as GTSAM's GncOptimizer starts; 0 (default): mu_0 from the estimate
  /// as given (the known inliers' initial guess). Measured (docs/BENCHMARKS.md): the pass
  /// lets ring's 26 right closures, all far off at the odometry start, close the loop
  /// (without it all are rejected), but spoils ringcity (nearly all right closures then
  /// rejected) where the odometry start alone is exact.
  int initial_least_squares_iterations = 0;
  /// A weight within this of 1 counts as decided (GTSAM's weightsTol); one near 0 only
  /// when it is 0 (the TLS weight is exactly 0 beyond (mu + 1) / mu c^2): at a small mu
  /// every far-off edge has a tiny weight, right ones included, and stopping there would
  /// reject every loop closure the start has not closed yet.
  double weight_tolerance = 1e-4;
  /// rejectFromGlobalStart: also run the nonlinear GNC from the initialisation's answer
  /// and keep the answer of lower TLS cost (false: the initialisation's answer, faster).
  bool verify = true;
  /// Optimizer iterations per step of that nonlinear GNC: it starts at an optimum, and one
  /// iteration per step follows it (m3500, intel, ring, ringcity and city10000 with 10 %
  /// and 20 % wrong closures: the same rejection as three, in a third of the time).
  int verify_iterations_per_step = 1;
  /// That GNC's mu_0 comes (Remark 5) from the candidates whose chi2 at the
  /// initialisation's optimum is below this many times their threshold only; those far
  /// beyond it (above about twice the bound) then start at weight 0 and stay out of H
  /// from the first step (random wrong closures fill it in), while a misplaced group of
  /// right closures (ringcity's: 104-130 times) is tried again. When no candidate lies
  /// between its threshold and this bound, the GNC would only repeat the
  /// initialisation's answer and is skipped.
  double verify_max_ratio = 1000.0;
  /// robustInitialization's mu_0 likewise, from the chi2 at the least-squares placement of
  /// every edge (infinity: Remark 5 over every candidate, as runGnc).
  double initial_max_ratio = 1000.0;
  /// The nonlinear GNC's answer replaces the initialisation's only when its TLS cost is
  /// lower by more than this many candidate thresholds (the largest c^2): two answers
  /// within one edge's worth are equally plausible, and the initialisation's keeps fewer
  /// doubtful edges (m3500 with 20 % wrong closures: the nonlinear GNC absorbs one wrong
  /// closure at a cost below c^2 and ends 0.097 m off; the initialisation's answer is
  /// exact).
  double verify_margin = 1.0;
  /// After the GNC, candidates whose weight is below this are rejected.
  double rejection_weight = 0.5;
  /// Edges that are never rejected (weight 1 throughout). Empty: isOdometryOrUnary.
  std::function<bool(const Edge&)> is_known_inlier;
  /// Options of the optimizer run at each step (max_iterations is replaced by
  /// optimizer_iterations_per_step; the callback is kept).
  Optimizer::Options optimizer;
  /// Called after each GNC step.
  std::function<void(const GncIterationStats&)> callback;
};

/// The default known inliers: unary edges (priors) and edges between two vertices whose
/// ids are consecutive (odometry, in the numbering of the public datasets and of g2o's
/// simulators). Every other edge, loop closures and landmark observations included, is a
/// candidate.
[[nodiscard]] bool isOdometryOrUnary(const Edge& edge);

/// Whether `edge` is a known inlier under `options` (GncOptions::is_known_inlier, or
/// isOdometryOrUnary when that is empty).
[[nodiscard]] inline bool isKnownInlier(const GncOptions& options, const Edge& edge) {
  return options.is_known_inlier ? options.is_known_inlier(edge) : isOdometryOrUnary(edge);
}

/// c^2 for an edge of `dimension` (chi-square quantile at `probability`, in (0, 1)).
[[nodiscard]] double chi2Threshold(int dimension, double probability);

/// chi2Threshold at one probability, computed once per dimension (a quantile costs a few
/// microseconds: tens of milliseconds over the edges of a large graph).
class Chi2Thresholds {
 public:
  explicit Chi2Thresholds(double probability) : probability_(probability) {}
  [[nodiscard]] double operator()(int dimension) {
    auto it = cache_.find(dimension);
    if (it == cache_.end()) {
      it = cache_.emplace(dimension, chi2Threshold(dimension, probability_)).first;
    }
    return it->second;
  }

 private:
  double probability_;
  std::map<int, double> cache_;
};

/// The TLS weight of an edge with squared error s and threshold c2 at control mu > 0.
[[nodiscard]] double tlsWeight(double s, double c2, double mu);

/// mu_0 = min_k c_k^2 / (2 s_k - c_k^2) over the k with 2 s_k > c_k^2, at least
/// `min_mu`; returns a negative value when no s_k exceeds c_k^2 (every candidate already
/// an inlier: nothing to do).
[[nodiscard]] double initialMu(const std::vector<double>& s, const std::vector<double>& c2,
                               double min_mu);

/// An edge the GNC rejected.
struct RejectedEdge {
  std::size_t index = 0;  ///< in graph.edges() when rejectOutliers was called
  std::vector<VertexId> vertex_ids;
  double chi2 = 0.0;    ///< at the end of the GNC (where its weight went to 0)
  double weight = 0.0;  ///< its final GNC weight
};

struct GncResult {
  bool ok = true;  ///< false when an optimizer step failed (message says why)
  std::string message;
  bool converged = false;  ///< every weight decided (0 or 1) within max_iterations
  std::size_t known_inliers = 0;
  std::size_t candidates = 0;
  std::vector<RejectedEdge> rejected;  ///< by increasing index
  int iterations = 0;                  ///< GNC steps
  int optimizer_iterations = 0;        ///< over all steps
  double initial_mu = 0.0;             ///< negative: every candidate was an inlier at the start
  double final_mu = 0.0;
  double seconds = 0.0;
  /// Final weight of every edge of the graph as it was passed in (1 for known inliers).
  std::vector<double> weights;
};

/// Runs the GNC on `graph` from its current estimates (which should come from the known
/// inliers only: see the tool's --reject-outliers), leaving the estimate of its last step
/// and the rejected edges (weight < rejection_weight) in the result, without removing
/// anything. Candidate edges' own robust kernels are replaced during the run and put back
/// afterwards. Throws graphslam::Error for invalid options.
[[nodiscard]] GncResult runGnc(Graph& graph, const SolverRegistry& solvers,
                               const GncOptions& options);

/// Removes the edges `result` rejected from `graph` (which must be unchanged since the
/// run); returns how many.
std::size_t removeRejected(Graph& graph, const GncResult& result);

/// runGnc, removeRejected, then a plain least-squares optimisation of the inliers with
/// options.optimizer (its summary in `reoptimization`).
[[nodiscard]] GncResult rejectOutliers(Graph& graph, const SolverRegistry& solvers,
                                       const GncOptions& options, Summary* reoptimization);

/// Checks the options; throws graphslam::Error naming the first bad field.
void checkOptions(const GncOptions& options);

}  // namespace graphslam::outliers
