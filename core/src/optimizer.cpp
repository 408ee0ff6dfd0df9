// SPDX-License-Identifier: MIT
#include "graphslam/core/optimizer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "graphslam/core/error.h"
#include "graphslam/core/linear_system.h"
#include "graphslam/core/logging.h"
#include "hessian_structure.h"
#include "optimizer_impl.h"
#include "timing.h"

namespace graphslam {

const char* toString(Algorithm algorithm) {
  switch (algorithm) {
    case Algorithm::kGaussNewton:
      return "gauss-newton";
    case Algorithm::kLevenbergMarquardt:
      return "levenberg-marquardt";
    case Algorithm::kGaussNewtonFallback:
      return "gauss-newton with lm fallback";
  }
  return "?";
}

const char* toString(TerminationStatus status) {
  switch (status) {
    case TerminationStatus::kConverged:
      return "converged";
    case TerminationStatus::kMaxIterations:
      return "maximum iterations reached";
    case TerminationStatus::kNoProgress:
      return "no progress";
    case TerminationStatus::kNumericalFailure:
      return "numerical failure";
    case TerminationStatus::kUnderDetermined:
      return "under-determined";
  }
  return "?";
}

TimeSplit& TimeSplit::operator+=(const TimeSplit& o) {
  linearize += o.linearize;
  build += o.build;
  factorize += o.factorize;
  solve += o.solve;
  return *this;
}

std::string Summary::report() const {
  std::ostringstream s;
  s.precision(10);
  s << "status:        " << toString(status);
  if (!message.empty()) s << " (" << message << ")";
  s << "\nalgorithm:     " << toString(algorithm) << ", linear solver " << linear_solver
    << "\nproblem:       " << num_vertices << " free vertices, " << num_edges << " edges, "
    << system_dimension << " unknowns, nnz(H) " << hessian_nonzeros << ", nnz(L) "
    << factor_nonzeros << "\nchi2:          " << initial_chi2 << " -> " << final_chi2;
  if (robust_edges > 0) {
    s << "\nrobust cost:   " << initial_cost << " -> " << final_cost << " (" << robust_edges
      << " edges with a robust kernel)";
  }
  s
    << "\niterations:    " << iterations;
  s.precision(4);
  s << "\ntime:          " << total_time << " s (linearize " << time.linearize << ", build "
    << time.build << ", factorize " << time.factorize << ", solve " << time.solve << ")";
  if (!gauge_fixed.empty()) {
    s << "\ngauge:         fixed vertex";
    for (VertexId id : gauge_fixed) s << ' ' << id;
  }
  for (const auto& group : unanchored) {
    s << "\nunanchored:    vertices";
    for (VertexId id : group) s << ' ' << id;
  }
  return s.str();
}

using detail::Clock;
using detail::seconds;

Optimizer::Optimizer(Graph& graph, const SolverRegistry& solvers, Options options)
    : graph_(graph),
      solvers_(solvers),
      options_(std::move(options)),
      impl_(std::make_unique<Impl>()) {
  impl_->solver = solvers_.create(options_.linear_solver);
  impl_->solver_name = options_.linear_solver;
}

Optimizer::Optimizer(Graph& graph, const SolverRegistry& solvers)
    : Optimizer(graph, solvers, Options{}) {}

Optimizer::~Optimizer() = default;

double Optimizer::chi2() { return impl_->evalChi2(graph_); }

Summary Optimizer::optimize() {
  const auto t_start = Clock::now();
  Impl& im = *impl_;
  Summary summary;
  summary.algorithm = options_.algorithm;
  summary.linear_solver = options_.linear_solver;
  if (im.solver_name != options_.linear_solver) {
    im.solver = solvers_.create(options_.linear_solver);
    im.solver_name = options_.linear_solver;
    im.analyzed = false;
  }

  // Gauge: with nothing fixed and no unary edge, the whole graph can move freely.
  const detail::GaugeFix gauge(graph_, options_.fix_gauge);
  summary.gauge_fixed = gauge.fixedIds();
  for (VertexId id : summary.gauge_fixed) {
    log(LogLevel::kInfo, "no vertex is fixed and no prior exists: fixing vertex " +
                             std::to_string(id) + " (the lowest id) to remove the gauge freedom");
  }

  TimeSplit setup;
  auto t0 = Clock::now();
  im.structure.setThreads(options_.threads);
  if (im.structure.update(graph_)) im.analyzed = false;
  im.jacobian_form = im.solver->form() == SystemForm::kJacobian;
  summary.num_vertices = im.structure.activeVertices().size();
  summary.num_edges = graph_.numEdges();
  summary.system_dimension = im.structure.dimension();
  summary.hessian_nonzeros = im.structure.hessianStructure().nnz();

  summary.unanchored = im.structure.unanchoredGroups();
  for (const auto& group : summary.unanchored) {
    std::string ids;
    for (VertexId id : group) ids += " " + std::to_string(id);
    log(LogLevel::kWarning,
        "vertices with no anchor (no fixed vertex, no prior) — their position is undetermined:" +
            ids);
  }

  summary.initial_cost = im.evalChi2(graph_);
  summary.final_cost = summary.initial_cost;
  for (const auto& e : graph_.edges()) summary.robust_edges += e->robustKernel() ? 1 : 0;
  summary.initial_chi2 =
      summary.robust_edges > 0 ? im.structure.rawChi2(graph_) : summary.initial_cost;
  summary.final_chi2 = summary.initial_chi2;
  if (im.structure.dimension() == 0) {
    summary.status = TerminationStatus::kConverged;
    summary.message = "no free vertex with an edge: nothing to optimise";
    summary.total_time = seconds(t_start, Clock::now());
    return summary;
  }
  if (!std::isfinite(summary.initial_cost)) {
    summary.status = TerminationStatus::kNumericalFailure;
    summary.message = "initial chi2 is not finite";
    summary.total_time = seconds(t_start, Clock::now());
    return summary;
  }
  if (!im.analyzed) {
    const LinearSolverResult r = im.analyze();
    if (!r.ok()) {
      summary.status = TerminationStatus::kNumericalFailure;
      summary.message = "symbolic analysis failed: " + r.message;
      summary.total_time = seconds(t_start, Clock::now());
      return summary;
    }
    im.analyzed = true;
  }
  setup.build += seconds(t0, Clock::now());
  summary.time += setup;

  const int n = im.structure.dimension();
  im.dx.resize(static_cast<std::size_t>(n));
  double chi2 = summary.initial_cost;
  double lambda = -1.0;  // < 0: initialise from H at the next damped iteration
  double lambda_floor = 0.0;
  double nu = 2.0;
  // kGaussNewtonFallback takes undamped steps, accepting a temporary increase of chi2
  // (non-monotone), until `fallback_patience` steps in a row fail to beat the best chi2
  // seen; then it returns to the best estimate and continues as Levenberg-Marquardt.
  const bool fallback = options_.algorithm == Algorithm::kGaussNewtonFallback;
  bool damped = options_.algorithm == Algorithm::kLevenbergMarquardt;
  double best_chi2 = chi2;
  int non_improving = 0;
  // Chord steps (the default algorithm's undamped phase only; kGaussNewton stays plain
  // Gauss-Newton): the solver holds the factorisation of the last undamped step, which
  // lowered chi2 by last_decrease.
  bool chord_ready = false;
  double last_decrease = 0.0;
  double last_rho = 0.0;  // actual / model decrease of the last undamped step
  std::vector<double> best_state;
  summary.status = TerminationStatus::kMaxIterations;

  auto failure_message = [&](const LinearSolverResult& r) {
    std::string msg = std::string("linear solver: ") + toString(r.status);
    if (!r.message.empty()) msg += ": " + r.message;
    const VertexId v = im.structure.vertexOfColumn(r.column);
    if (v >= 0) msg += " (at vertex " + std::to_string(v) + ")";
    if (!summary.unanchored.empty()) {
      msg += "; vertices without anchor start with " + std::to_string(summary.unanchored[0][0]);
    }
    return msg;
  };

  for (int it = 1; it <= options_.max_iterations; ++it) {
    IterationStats st;
    st.iteration = it;
    auto ta = Clock::now();
    im.structure.linearize();
    auto tb = Clock::now();
    st.time.linearize = seconds(ta, tb);
    im.assemble();
    auto tc = Clock::now();
    st.time.build = seconds(tb, tc);

    if (damped) {
      im.saveDiagonal();
      double max_diag = 0.0;
      for (int i = 0; i < n; ++i) max_diag = std::max(max_diag, std::abs(im.saved_diag[i]));
      if (lambda < 0) {
        const double scale =
            options_.damping == Options::Damping::kIdentity ? std::max(max_diag, 1e-12) : 1.0;
        lambda = options_.initial_lambda_factor * scale;
        // Below this the damping is lost in rounding: a lambda shrunk further by a long
        // run of good steps would need more rejections to matter again than an iteration
        // allows, and the optimizer would stop at a point that is not a minimum.
        lambda_floor = options_.min_relative_lambda * scale;
        nu = 2.0;
      }
      if (options_.damping == Options::Damping::kDiagonal) {
        im.damping_diag.resize(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) im.damping_diag[i] = std::clamp(im.saved_diag[i], 1e-6, 1e32);
      } else {
        im.damping_diag.assign(static_cast<std::size_t>(n), 1.0);
      }
    } else if (fallback && chi2 <= best_chi2) {
      best_chi2 = chi2;
      im.saveState(best_state);
    }

    // Near convergence (or where the problem is close to linear) H hardly changes between
    // steps: conjugate gradients preconditioned with the last factorisation give a step (a
    // chord step) almost as good, for the price of a few solves. It is the iteration's step
    // when it lowers chi2 (the next iteration factorises again unless its iterations
    // reached their tolerance); otherwise it is undone and the iteration goes on as usual.
    bool chord = false;
    bool chord_converged = false;
    double chord_chi2 = chi2;
    const Options::ChordSteps& cs = options_.chord_steps;
    const int chord_budget = chord_ready ? im.chordIterations(cs.max_iterations) : 0;
    if (chord_ready &&
        (last_decrease < cs.trigger * chi2 ||
         (std::abs(1.0 - last_rho) < cs.agreement && chord_budget >= cs.agreement_iterations))) {
      const auto ts = Clock::now();
      const auto [cg_iterations, cg_converged] =
          im.chordSolve(cs.relative_tolerance,
                        cs.absolute_tolerance * options_.function_tolerance * chi2, chord_budget);
      st.cg_iterations = cg_iterations;
      chord_converged = cg_converged;
      if (cg_iterations > 0) {
        im.applyUpdate();
        chord_chi2 = im.evalChi2(graph_);
        chord = chord_chi2 < chi2 || (chord_chi2 == chi2 && chi2 == 0.0);
        if (!chord) im.undoUpdate();
      }
      st.time.solve += seconds(ts, Clock::now());
    }

    bool accepted = chord;
    bool stop = false;
    double new_chi2 = chord ? chord_chi2 : chi2;
    int attempts = 0;
    double used_lambda = 0.0;
    while (!chord) {
      ++attempts;
      used_lambda = damped ? lambda : 0.0;
      auto tf0 = Clock::now();
      LinearSolverResult r = im.factorize(used_lambda);
      auto tf1 = Clock::now();
      st.time.factorize += seconds(tf0, tf1);
      if (r.ok()) {
        r = im.solve();
      }
      if (!r.ok()) {
        st.time.solve += seconds(tf1, Clock::now());
        if (damped && attempts <= options_.max_rejections) {
          lambda *= nu;
          nu *= 2.0;
          continue;
        }
        summary.status = TerminationStatus::kNumericalFailure;
        summary.message = failure_message(r);
        stop = true;
        break;
      }
      im.applyUpdate();
      new_chi2 = im.evalChi2(graph_);
      st.time.solve += seconds(tf1, Clock::now());
      if (!damped && fallback && it == 1 && options_.first_step_dogleg && !im.jacobian_form &&
          !(new_chi2 <= chi2)) {
        // The first undamped step raised chi2: from the initial estimate the quadratic
        // model can be far off. A dogleg step in a trust region shrunk until the model
        // agrees, from the same factorisation (Options::first_step_dogleg).
        const auto td = Clock::now();
        im.undoUpdate();
        const Impl::DoglegResult dogleg = im.firstStepDogleg(graph_, chi2, new_chi2, options_.first_step_agreement,
                                options_.first_step_max_halvings);
        new_chi2 = dogleg.chi2;
        st.dogleg_halvings = dogleg.halvings;
        st.dogleg_trials = dogleg.trials;
        st.time.solve += seconds(td, Clock::now());
      }
      if (!damped) {
        if (!std::isfinite(new_chi2) && !fallback) {
          im.undoUpdate();
          new_chi2 = im.evalChi2(graph_);
          summary.status = TerminationStatus::kNumericalFailure;
          summary.message = "chi2 is not finite after the update";
          stop = true;
          break;
        }
        accepted = true;
        break;
      }
      double dx2 = 0.0;
      double bdx = 0.0;
      for (int i = 0; i < n; ++i) {
        dx2 += im.dx[i] * im.dx[i] * im.damping_diag[i];
        bdx += im.structure.gradient()[i] * im.dx[i];
      }
      const double predicted = lambda * dx2 - bdx;  // model decrease of chi2
      const double rho = (chi2 - new_chi2) / predicted;
      if (std::isfinite(new_chi2) && predicted > 0 && rho > 0) {
        const double a = 2.0 * rho - 1.0;
        lambda = std::max(lambda_floor,
                          lambda * std::max(options_.min_lambda_decrease, 1.0 - a * a * a));
        nu = 2.0;
        accepted = true;
        break;
      }
      im.undoUpdate();
      if (!(predicted > options_.function_tolerance * chi2)) {
        // The model promises no meaningful decrease: we are at a minimum.
        summary.status = TerminationStatus::kConverged;
        summary.message = "no further decrease possible";
        stop = true;
        break;
      }
      if (attempts > options_.max_rejections) {
        summary.status = TerminationStatus::kNoProgress;
        summary.message = "no decreasing step after " + std::to_string(attempts) + " attempts";
        stop = true;
        break;
      }
      lambda *= nu;
      nu *= 2.0;
    }
    if (!accepted) new_chi2 = im.evalChi2(graph_);  // errors at the restored estimate

    double step = 0.0;
    double model_decrease = 0.0;  // -g.dx: the quadratic model's decrease (undamped step)
    if (accepted) {
      for (int i = 0; i < n; ++i) {
        step += im.dx[i] * im.dx[i];
        model_decrease -= im.structure.gradient()[i] * im.dx[i];
      }
      step = std::sqrt(step);
    }
    if (fallback && !damped && !stop) {
      non_improving = (std::isfinite(new_chi2) && new_chi2 < best_chi2) ? 0 : non_improving + 1;
      if (non_improving >= options_.fallback_patience || !std::isfinite(new_chi2)) {
        im.restoreState(best_state);
        new_chi2 = im.evalChi2(graph_);
        damped = true;
        lambda = -1.0;
        step = 1.0;  // not converged: the damped phase starts now
      }
    }
    st.chi2 = new_chi2;
    st.lambda = used_lambda;
    st.step_norm = step;
    st.attempts = attempts;
    st.accepted = accepted;
    st.elapsed = seconds(t_start, Clock::now());
    summary.time += st.time;
    summary.per_iteration.push_back(st);
    summary.iterations = it;
    const double old_chi2 = chi2;
    chi2 = new_chi2;
    // A chord step that did not reach its tolerance is followed by a factorisation.
    chord_ready = fallback && !damped && !im.jacobian_form && accepted &&
                  (attempts == 1 || (chord && chord_converged)) &&
                  options_.function_tolerance > 0 && new_chi2 <= old_chi2;
    last_decrease = old_chi2 - new_chi2;
    last_rho = model_decrease > 0 ? last_decrease / model_decrease : 0.0;
    // After a chord step only its agreement with the model may call for another.
    if (chord) last_decrease = std::numeric_limits<double>::infinity();
    if (options_.callback) options_.callback(st);
    if (stop) break;
    const bool small_change =
        options_.function_tolerance > 0 &&
        std::abs(old_chi2 - new_chi2) <= options_.function_tolerance * old_chi2;
    // A Gauss-Newton phase at the optimum sees chi2 jitter by rounding; above the best
    // chi2 by no more than the function tolerance counts as being there.
    const bool above_best = chi2 > best_chi2 + options_.function_tolerance * std::abs(best_chi2);
    if ((small_change || step < options_.step_tolerance) && !(fallback && !damped && above_best)) {
      summary.status = TerminationStatus::kConverged;
      break;
    }
  }
  if (fallback && !damped && !best_state.empty() && chi2 > best_chi2) {
    // The undamped phase ended above its best point: return there.
    im.restoreState(best_state);
    chi2 = im.evalChi2(graph_);
  }
  summary.final_cost = chi2;
  summary.final_chi2 = summary.robust_edges > 0 ? graph_.chi2() : chi2;
  summary.factor_nonzeros = im.solver->factorNonZeros();
  // A solver that chooses its backend at analysis ("auto") names its choice (asked at the
  // end: it may take its figures from its backend's first factorisation).
  const std::string chosen = im.solver->name();
  if (chosen.rfind(options_.linear_solver, 0) == 0) summary.linear_solver = chosen;
  summary.total_time = seconds(t_start, Clock::now());
  return summary;
}

}  // namespace graphslam
