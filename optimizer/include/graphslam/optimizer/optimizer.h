// SPDX-License-Identifier: MIT
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"

namespace graphslam {

namespace detail {
class GaugeFix;
struct StepContext;
struct StepResult;
}  // namespace detail

enum class Algorithm {
  kGaussNewton,         ///< undamped steps, always accepted
  kLevenbergMarquardt,  ///< damped steps, Nielsen's lambda update (as g2o)
  /// The default. Gauss-Newton steps, accepted even when chi2 rises for a while (up to
  /// Options::fallback_patience steps in a row without a new best); then back to the best
  /// estimate, and Levenberg-Marquardt from there. Chord steps (Options::chord_steps): after
  /// a step that lowered chi2 by very little, or that agreed closely with its quadratic
  /// model when the factor is dense enough, the next step first solves the new system by conjugate
  /// gradients preconditioned with the last factorisation; it is kept when it lowers chi2,
  /// and chord steps follow one another while their iterations reach their tolerance.
  kGaussNewtonFallback,
  /// Powell's dogleg in a trust region (Options::Dogleg): one factorisation per iteration,
  /// rejected steps retried on the same factorisation with a smaller radius.
  kDogleg,
};

[[nodiscard]] const char* toString(Algorithm algorithm);

/// How an optimisation ended.
enum class TerminationStatus {
  kConverged,         ///< relative chi2 decrease or step below tolerance
  kMaxIterations,     ///< iteration budget used up
  kNoProgress,        ///< LM could not find a decreasing step
  kNumericalFailure,  ///< factorisation failed (singular / not positive definite) or NaN
  kUnderDetermined,   ///< nothing to optimise or the system cannot be built
};

[[nodiscard]] const char* toString(TerminationStatus status);

/// Wall time spent in each phase, in seconds.
struct TimeSplit {
  double linearize = 0.0;  ///< computeError + linearizeOplus over all edges
  double build = 0.0;      ///< assembly of H and b (plus structure analysis when it changed)
  double factorize = 0.0;  ///< numeric factorisation (every LM attempt)
  double solve = 0.0;      ///< triangular solves, update and chi2 of the new estimate
  [[nodiscard]] double total() const { return linearize + build + factorize + solve; }
  TimeSplit& operator+=(const TimeSplit& o);
};

/// What the step strategy reports of one iteration: the kind of step it took and its own
/// figures (damping, trust radius, conjugate-gradient iterations, ...), by name. Each
/// strategy documents its names; the optimizer does not read them.
struct StrategyReport {
  /// The step taken: "gauss-newton", "chord", "first-step dogleg", "dogleg",
  /// "levenberg-marquardt"; empty when none was.
  std::string step;
  /// One line on the step for progress output ("chord step: previous factorisation, 6 CG
  /// iterations"); empty for a plain step.
  std::string note;
  std::vector<std::pair<std::string, double>> values;  ///< e.g. {"lambda", 1e-5}

  /// The value of `name`, or `otherwise` when the strategy did not report it.
  [[nodiscard]] double value(const std::string& name, double otherwise = 0.0) const;
  /// "name=value;name=value" (the shortest decimal form of each value).
  [[nodiscard]] std::string valuesText() const;
};

/// One outer iteration (one linearisation).
struct IterationStats {
  int iteration = 0;       ///< 1-based
  double chi2 = 0.0;       ///< after the iteration's (accepted) step
  double step_norm = 0.0;  ///< Euclidean norm of the accepted update
  /// Numeric factorisations this iteration: every factorisation a strategy asked for (LM's
  /// retries with more damping among them); 0 for a step that reused an earlier one.
  int factorizations = 0;
  /// Steps the evaluator tried (applied and scored) this iteration.
  int trials = 0;
  bool accepted = true;  ///< false when no step was kept
  /// The iteration factorised the undamped H successfully (Gauss-Newton, a chord step on
  /// such a factorisation, dogleg's unregularised Gauss-Newton point): H was positive
  /// definite there. Never for Levenberg-Marquardt, whose H is damped.
  bool undamped = false;
  StrategyReport strategy;  ///< the step strategy's own figures
  TimeSplit time;
  double elapsed = 0.0;  ///< since optimize() started
};

/// Result of Optimizer::optimize().
struct Summary {
  TerminationStatus status = TerminationStatus::kUnderDetermined;
  std::string message;
  Algorithm algorithm = Algorithm::kGaussNewtonFallback;
  std::string linear_solver;
  /// sum of e^T Omega e before and after (robust kernels ignored).
  double initial_chi2 = 0.0;
  double final_chi2 = 0.0;
  /// The objective minimised: sum of rho(e^T Omega e), equal to chi2 when no edge has a
  /// robust kernel.
  double initial_cost = 0.0;
  double final_cost = 0.0;
  /// Edges with a robust kernel.
  std::size_t robust_edges = 0;
  int iterations = 0;
  std::vector<IterationStats> per_iteration;
  TimeSplit time;
  double total_time = 0.0;       ///< wall time of optimize(), including set-up
  std::size_t num_vertices = 0;  ///< optimised (non-fixed) vertices
  std::size_t num_edges = 0;     ///< active edges (Edge::active)
  int system_dimension = 0;
  std::size_t hessian_nonzeros = 0;  ///< stored non-zeros (upper triangle, full diagonal blocks)
  std::size_t factor_nonzeros = 0;
  /// Vertices the optimizer fixed to remove the gauge freedom (see Options::fix_gauge): the
  /// lowest id when nothing anchors the graph, and the lowest id of every further component
  /// in `unanchored`.
  std::vector<VertexId> gauge_fixed;
  /// Connected groups of non-fixed vertices with no fixed vertex and no unary edge besides
  /// the one the lowest id anchors: their position is undetermined (with fix_gauge, each
  /// is anchored at its first id for the run). Each holds up to 20 ids (smallest first).
  std::vector<std::vector<VertexId>> unanchored;
  /// On a numerical failure of the factorisation: the vertex whose column failed (-1 when
  /// the solver did not say) and its active edges, as indices into graph.edges(); the
  /// message names both (the vertex's edges by the vertices they join it to).
  VertexId failed_vertex = -1;
  std::vector<std::size_t> failed_vertex_edges;
  /// When the initial chi2 is not finite: the first active edge whose term is not, as an
  /// index into graph.edges() (-1 otherwise); the message names its vertices and says
  /// whether its error is not finite or e^T Omega e overflows.
  std::ptrdiff_t failed_edge = -1;

  [[nodiscard]] bool succeeded() const {
    return status == TerminationStatus::kConverged || status == TerminationStatus::kMaxIterations;
  }
  /// Multi-line human-readable report.
  [[nodiscard]] std::string report() const;
};

/// The first active edge whose term e^T Omega e (through its kernel) is not finite at the
/// current estimates.
struct NonFiniteEdge {
  std::ptrdiff_t index = -1;  ///< into graph.edges(); -1 when every term is finite
  /// Its vertices and whether its error is not finite or a finite error overflows
  /// e^T Omega e, then how many more edges are not finite.
  std::string description;
};
/// Computes every active edge's error (the graph's edges keep them).
[[nodiscard]] NonFiniteEdge findNonFiniteEdge(Graph& graph);

/// Sparse nonlinear least squares over a Graph: minimises sum_e e^T Omega e.
class Optimizer {
 public:
  struct Options {
    Algorithm algorithm = Algorithm::kGaussNewtonFallback;
    int max_iterations = 100;
    /// Any registered name (optionally "name:ordering"). "auto" (solvers::registerSolvers)
    /// orders by AMD or METIS and factorises with eigen-ldlt, or supernodal cholmod when the
    /// predicted work is large.
    std::string linear_solver = "auto";
    /// Converged when an accepted step lowers chi2 by less than this fraction (1e-8: one
    /// Gauss-Newton step fewer than 1e-10 on the standard files, same chi2 to 9 digits).
    double function_tolerance = 1e-8;
    /// Converged when the Euclidean norm of the update is below this.
    double step_tolerance = 1e-12;
    /// LM damping term: lambda * I (g2o) or lambda * diag(H) (Marquardt, scale-invariant).
    enum class Damping { kIdentity, kDiagonal };
    Damping damping = Damping::kIdentity;
    /// LM: initial lambda = initial_lambda_factor * max diagonal entry of H (identity
    /// damping) or initial_lambda_factor itself (diagonal damping).
    double initial_lambda_factor = 1e-5;
    /// LM: smallest factor lambda may shrink by after a good step (Nielsen uses 1/3).
    double min_lambda_decrease = 1.0 / 3.0;
    /// kGaussNewtonFallback: undamped steps in a row that may fail to beat the best chi2
    /// before switching to LM from the best estimate. Gauss-Newton often climbs for a few
    /// steps before it drops into a much better basin (docs/BENCHMARKS.md has the counts
    /// measured on the benchmark files; the longest climb seen there is below this).
    int fallback_patience = 10;
    /// kGaussNewtonFallback: when the first (undamped) step raises chi2, the first
    /// iteration takes a dogleg step instead, from the same factorisation: along the
    /// steepest descent scaled by diag(H) to its Cauchy point, then towards the
    /// Gauss-Newton step, at a trust radius halved from the Gauss-Newton step's length
    /// until the quadratic model predicts the decrease of chi2 within
    /// first_step_agreement (one evaluation of chi2 per trial; the first trial is at a
    /// quarter when chi2 along the Gauss-Newton step, interpolated by a parabola, is
    /// lowest at a quarter of it or less). From the initial estimate the quadratic model
    /// can be far off, and the undamped step lands far above where the dogleg path does.
    /// Files whose first step lowers chi2, and Jacobian-form solvers, are not affected.
    /// false: keep the undamped step.
    bool first_step_dogleg = true;
    /// The first-step dogleg takes the first trial whose actual decrease of chi2 is within
    /// this fraction of the model's...
    double first_step_agreement = 0.25;
    /// ...or the lowest chi2 seen after this many halvings of the trust region.
    int first_step_max_halvings = 20;
    /// Smallest LM damping, relative to the scale of the initial one (the largest diagonal
    /// entry of H for identity damping, 1 for diagonal damping): below it the damping is
    /// lost in rounding.
    double min_relative_lambda = 1e-16;
    /// Chord steps: near convergence (or where the problem is close to linear) H hardly
    /// changes between steps, and conjugate gradients preconditioned with the last
    /// factorisation give a step almost as good as a new factorisation for a few solves.
    struct ChordSteps {
      /// A step that lowered chi2 by less than this fraction is followed by a chord step.
      double trigger = 1e-4;
      /// So is a step whose actual decrease of chi2 was within this fraction of its
      /// quadratic model's, when the chord step may take at least agreement_iterations
      /// iterations (far from convergence one iteration gains much less than a
      /// Gauss-Newton step, a few preconditioned ones as much).
      double agreement = 0.05;
      int agreement_iterations = 4;
      /// The iterations stop when one lowers the model by less than this fraction of what
      /// the first one did...
      double relative_tolerance = 1e-4;
      /// ...or by less than this fraction of function_tolerance times chi2...
      double absolute_tolerance = 0.1;
      /// ...or after this many (fewer when the factor is sparse: half the solves a
      /// factorisation costs, nnz(L) / n / 4, at least one).
      int max_iterations = 10;
    };
    ChordSteps chord_steps;
    /// kDogleg's trust region, in the D-norm (D = diag(H)).
    struct Dogleg {
      /// First radius; 0: the D-norm of the first Gauss-Newton step.
      double initial_radius = 0.0;
      /// An accepted step whose actual decrease is above this fraction of the model's lets
      /// the radius grow to expand_factor times the step's length...
      double expand_agreement = 0.75;
      double expand_factor = 3.0;
      /// ...one below this fraction, or a rejected step, shrinks it to shrink_factor
      /// times the step's length.
      double shrink_agreement = 0.25;
      double shrink_factor = 0.25;
      /// When H does not factorise (not positive definite: an unanchored part, a landmark
      /// seen once), the Gauss-Newton step is taken of H + lambda I with lambda this
      /// fraction of H's largest diagonal entry, grown tenfold per failure.
      double initial_regularization = 1e-8;
    };
    Dogleg dogleg;
    /// LM: retries (factorisations with larger damping) before giving up; dogleg: radii
    /// tried per iteration, and regularisations of an H that does not factorise.
    int max_rejections = 10;
    /// If no vertex is fixed and there is no unary edge, fix the lowest id; and fix the
    /// lowest id of every further component that nothing anchors (all restored after
    /// optimize()). Off: such components are only reported (Summary::unanchored) and
    /// their system is singular.
    bool fix_gauge = true;
    /// Threads for evaluating errors and Jacobians (the caller's included). The result
    /// is bit-identical for every count; the linear solver's own threads are separate
    /// (OpenBLAS / OpenMP environment variables).
    int threads = 1;
    /// Called after every iteration (progress output is the caller's business).
    std::function<void(const IterationStats&)> callback;
  };

  /// The graph and registry must outlive the optimizer. Throws RegistryError when the
  /// linear solver name is unknown.
  Optimizer(Graph& graph, const SolverRegistry& solvers, Options options);
  Optimizer(Graph& graph, const SolverRegistry& solvers);
  ~Optimizer();
  Optimizer(const Optimizer&) = delete;
  Optimizer& operator=(const Optimizer&) = delete;

  [[nodiscard]] const Options& options() const { return options_; }
  Options& mutableOptions() { return options_; }

  /// Runs up to options().max_iterations iterations from the current estimates.
  Summary optimize();

  /// Current chi2 (recomputes all errors).
  [[nodiscard]] double chi2();

 private:
  bool setUp(Summary& summary, detail::GaugeFix& gauge);
  void linearizeAndAssemble(IterationStats& st);
  void recordIteration(Summary& summary, IterationStats& st, const detail::StepResult& r,
                       std::chrono::steady_clock::time_point t_start);
  bool stopped(Summary& summary, const detail::StepResult& r) const;

 public:
  struct Impl;  ///< the optimizer's state (private to the library's sources)

 private:
  Graph& graph_;
  const SolverRegistry& solvers_;
  Options options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace graphslam
