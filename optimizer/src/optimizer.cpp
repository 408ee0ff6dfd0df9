// SPDX-License-Identifier: MIT
#include "graphslam/optimizer/optimizer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "graphslam/diagnostics/observability.h"
#include "graphslam/optimizer/linear_system.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "graphslam/support/logging.h"
#include "hessian_structure.h"
#include "minimizer/step_strategy.h"
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
    case Algorithm::kDogleg:
      return "dogleg";
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
  s << "\niterations:    " << iterations;
  s.precision(4);
  s << "\ntime:          " << total_time << " s (linearize " << time.linearize << ", build "
    << time.build << ", factorize " << time.factorize << ", solve " << time.solve << ")";
  if (!gauge_fixed.empty()) {
    s << "\ngauge:         fixed vertex";
    for (VertexId id : gauge_fixed) s << ' ' << id;
  }
  for (const auto& group : unanchored) {
    s << "\nno anchor:     vertices";
    for (VertexId id : group) s << ' ' << id;
    if (std::find(gauge_fixed.begin(), gauge_fixed.end(), group.front()) != gauge_fixed.end()) {
      s << " (a component without a fixed vertex or prior: fixed its vertex " << group.front()
        << ")";
    }
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

namespace {

/// Why a vertex that made the factorisation fail may not be determined by its edges.
std::string likelyCause(const Vertex* v, const std::vector<std::vector<VertexId>>& unanchored) {
  if (!v) return {};
  for (const auto& group : unanchored) {
    if (std::find(group.begin(), group.end(), v->id()) != group.end()) {
      return "it is in a component without an anchor (no fixed vertex, no prior)";
    }
  }
  const std::size_t edges = v->edges().size();
  if (edges == 0) return "it has no edges";
  const std::string its =
      edges == 1 ? "its single edge" : "its " + std::to_string(edges) + " edges";
  const int rank = ownBlockRank(*v);  // from the Jacobians of the failed iteration
  if (rank >= 0 && rank < v->dimension()) {
    return its + (edges == 1 ? " determines" : " determine") + " only " + std::to_string(rank) +
           " of its " + std::to_string(v->dimension()) +
           " directions (a landmark seen by one range, or by bearings along one line?)";
  }
  return its + (edges == 1 ? " determines" : " determine") +
         " it when the other vertices are held fixed: it is undetermined together with its "
         "neighbours (too few edges among them)";
}

/// The active edges of `v` as indices into graph.edges(), and the vertices they join it to
/// ("vertices 3, 5, 9"; at most `max_ids`; "no other vertex" for unary edges only).
std::vector<std::size_t> edgesOf(const Graph& graph, const Vertex& v, std::string& joins) {
  constexpr std::size_t max_ids = 10;
  std::vector<std::size_t> out;
  std::vector<VertexId> others;
  const auto& edges = graph.edges();
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const Edge& e = *edges[k];
    if (!e.active() || std::find(v.edges().begin(), v.edges().end(), &e) == v.edges().end())
      continue;
    out.push_back(k);
    for (std::size_t s = 0; s < e.numVertices(); ++s) {
      if (e.vertex(s) != &v) others.push_back(e.vertexId(s));
    }
  }
  std::sort(others.begin(), others.end());
  others.erase(std::unique(others.begin(), others.end()), others.end());
  for (std::size_t k = 0; k < others.size() && k < max_ids; ++k) {
    joins += (k == 0 ? "" : ", ") + std::to_string(others[k]);
  }
  if (others.size() > max_ids) joins += ", ... (" + std::to_string(others.size()) + " in all)";
  joins = others.empty()       ? "no other vertex"
          : others.size() == 1 ? "vertex " + joins
                               : "vertices " + joins;
  return out;
}

/// The numerical failure of the linear solver, with the vertex, its edges and its likely
/// cause (the vertex and its edges also into the summary).
std::string failureMessage(const Optimizer::Impl& im, const Graph& graph,
                           const LinearSolverResult& r, Summary& summary) {
  std::string msg = std::string("linear solver: ") + toString(r.status);
  if (!r.message.empty()) msg += ": " + r.message;
  const VertexId id = im.structure.vertexOfColumn(r.column);
  const Vertex* v = id >= 0 ? graph.vertex(id) : nullptr;
  if (v) {
    msg += " (at vertex " + std::to_string(id) + ")";
    std::string joins;
    summary.failed_vertex = id;
    summary.failed_vertex_edges = edgesOf(graph, *v, joins);
    const std::size_t n = summary.failed_vertex_edges.size();
    msg += "; its " + (n == 1 ? std::string("edge joins") : std::to_string(n) + " edges join") +
           " it to " + joins;
    const std::string cause = likelyCause(v, summary.unanchored);
    if (!cause.empty()) msg += "; " + cause;
  }
  return msg;
}

}  // namespace

double StrategyReport::value(const std::string& name, double otherwise) const {
  for (const auto& [key, v] : values) {
    if (key == name) return v;
  }
  return otherwise;
}

std::string StrategyReport::valuesText() const {
  std::string out;
  for (const auto& [key, v] : values) {
    out += (out.empty() ? "" : ";") + key + "=" + support::formatDouble(v);
  }
  return out;
}

NonFiniteEdge findNonFiniteEdge(Graph& graph) {
  const auto& edges = graph.edges();
  std::size_t count = 0;
  NonFiniteEdge found;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    Edge& e = *edges[k];
    if (!e.active()) continue;
    e.computeError();
    if (std::isfinite(e.robustChi2())) continue;
    if (++count > 1) continue;
    found.index = static_cast<std::ptrdiff_t>(k);
    std::string ids;
    for (std::size_t s = 0; s < e.numVertices(); ++s) {
      ids += (s == 0 ? "" : ", ") + std::to_string(e.vertexId(s));
    }
    std::string& first = found.description;
    first = (e.numVertices() == 1 ? "the edge of vertex " : "the edge joining vertices ") + ids;
    const int d = e.dimension();
    const Eigen::Map<const Eigen::VectorXd> err(e.errorData(), d);
    const Eigen::Map<const Eigen::MatrixXd> info(e.informationData(), d, d);
    if (!err.allFinite()) {
      first +=
          ": its error is not finite at the initial estimate (a measurement or an estimate "
          "too large for double arithmetic?)";
    } else if (std::isfinite(e.chi2())) {
      first += ": its robust kernel's value is not finite";
    } else {
      first += ": its error is finite (largest entry " +
               support::formatDouble(err.cwiseAbs().maxCoeff()) +
               ") but e^T Omega e overflows the range of a double (information entries up to " +
               support::formatDouble(info.cwiseAbs().maxCoeff()) + ")";
    }
  }
  if (count > 1) found.description += " (and " + std::to_string(count - 1) + " more edges)";
  return found;
}

// The structure, the gauge of every unanchored component, the initial objective and the
// solver's symbolic analysis. Returns false when there is nothing to iterate (the
// summary says why).
bool Optimizer::setUp(Summary& summary, detail::GaugeFix& gauge) {
  Impl& im = *impl_;
  const auto t0 = Clock::now();
  im.structure.setThreads(options_.threads);
  if (im.structure.update(graph_)) im.analyzed = false;
  summary.unanchored = im.structure.unanchoredGroups();
  if (options_.fix_gauge && !summary.unanchored.empty()) {
    gauge.anchorGroups(graph_, summary.unanchored);
    if (im.structure.update(graph_)) im.analyzed = false;
  }
  if (!options_.fix_gauge) {
    for (const auto& group : summary.unanchored) {
      std::string ids;
      for (VertexId id : group) ids += " " + std::to_string(id);
      support::log(support::LogLevel::kWarning,
                   "vertices with no anchor (no fixed vertex, no prior) — their position is "
                   "undetermined:" +
                       ids);
    }
  }
  summary.gauge_fixed = gauge.fixedIds();
  for (VertexId id : summary.gauge_fixed) {
    support::log(support::LogLevel::kInfo,
                 "fixing vertex " + std::to_string(id) +
                     " (of a component without a fixed vertex or prior: its lowest id among the "
                     "vertices of the largest dimension) "
                     "to remove its gauge freedom");
  }
  im.jacobian_form = im.solver->form() == SystemForm::kJacobian;
  if (im.jacobian_form && options_.algorithm == Algorithm::kDogleg) {
    throw Error("the dogleg algorithm needs a solver of the normal equations; " +
                options_.linear_solver + " solves the Jacobian form");
  }
  summary.num_vertices = im.structure.activeVertices().size();
  summary.num_edges = static_cast<std::size_t>(std::count_if(
      graph_.edges().begin(), graph_.edges().end(), [](const auto& e) { return e->active(); }));
  summary.system_dimension = im.structure.dimension();
  summary.hessian_nonzeros = im.structure.hessianStructure().nnz();
  summary.initial_cost = im.evalChi2(graph_);
  summary.final_cost = summary.initial_cost;
  for (const auto& e : graph_.edges()) summary.robust_edges += e->robustKernel() ? 1 : 0;
  summary.initial_chi2 =
      summary.robust_edges > 0 ? im.structure.rawChi2(graph_) : summary.initial_cost;
  summary.final_chi2 = summary.initial_chi2;
  if (im.structure.dimension() == 0) {
    summary.status = TerminationStatus::kConverged;
    summary.message = "no free vertex with an edge: nothing to optimise";
    return false;
  }
  if (!std::isfinite(summary.initial_cost)) {
    summary.status = TerminationStatus::kNumericalFailure;
    const NonFiniteEdge bad = findNonFiniteEdge(graph_);
    summary.failed_edge = bad.index;
    summary.message = "initial chi2 is not finite: " + bad.description;
    return false;
  }
  if (!im.analyzed) {
    const LinearSolverResult r = im.analyze();
    if (!r.ok()) {
      summary.status = TerminationStatus::kNumericalFailure;
      summary.message = "symbolic analysis failed: " + r.message;
      return false;
    }
    im.analyzed = true;
  }
  im.dx.resize(static_cast<std::size_t>(im.structure.dimension()));
  summary.time.build += seconds(t0, Clock::now());
  return true;
}

// The minimizer: linearise at the current estimate, let the strategy compute, try and
// accept or reject steps, record the iteration, and stop on the strategy's verdict or when
// the objective or the step becomes small.
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
  detail::GaugeFix gauge(graph_, options_.fix_gauge);
  if (!setUp(summary, gauge)) {
    summary.total_time = seconds(t_start, Clock::now());
    return summary;
  }
  const auto strategy = detail::makeStepStrategy(options_.algorithm);
  double cost = summary.initial_cost;
  summary.status = TerminationStatus::kMaxIterations;
  for (int it = 1; it <= options_.max_iterations; ++it) {
    IterationStats st;
    st.iteration = it;
    linearizeAndAssemble(st);
    detail::StepContext ctx{im, graph_, options_, st, it, cost};
    const detail::StepResult r = detail::runIteration(*strategy, ctx);
    st.strategy = strategy->report();
    const double old_cost = cost;
    cost = r.cost;
    recordIteration(summary, st, r, t_start);
    if (stopped(summary, r)) break;
    const bool small_change = options_.function_tolerance > 0 &&
                              std::abs(old_cost - cost) <= options_.function_tolerance * old_cost;
    if ((small_change || r.step_norm < options_.step_tolerance) && r.may_stop) {
      summary.status = TerminationStatus::kConverged;
      break;
    }
  }
  IterationStats last;
  detail::StepContext end{im, graph_, options_, last, summary.iterations, cost};
  cost = strategy->finish(end);
  summary.final_cost = cost;
  summary.final_chi2 = summary.robust_edges > 0 ? graph_.chi2() : cost;
  summary.factor_nonzeros = im.solver->factorNonZeros();
  // A solver that chooses its backend at analysis ("auto") names its choice (asked at the
  // end: it may take its figures from its backend's first factorisation).
  const std::string chosen = im.solver->name();
  if (chosen.rfind(options_.linear_solver, 0) == 0) summary.linear_solver = chosen;
  summary.total_time = seconds(t_start, Clock::now());
  return summary;
}

void Optimizer::linearizeAndAssemble(IterationStats& st) {
  const auto t0 = Clock::now();
  impl_->structure.linearize();
  const auto t1 = Clock::now();
  impl_->assemble();
  st.time.linearize = seconds(t0, t1);
  st.time.build = seconds(t1, Clock::now());
}

void Optimizer::recordIteration(Summary& summary, IterationStats& st, const detail::StepResult& r,
                                Clock::time_point t_start) {
  using Kind = detail::StepResult::Kind;
  st.chi2 = r.cost;
  st.step_norm = r.kind == Kind::kAccepted || r.kind == Kind::kRestarted ? r.step_norm : 0.0;
  st.accepted = r.kind == Kind::kAccepted || r.kind == Kind::kRestarted;
  st.undamped = r.undamped;
  st.elapsed = seconds(t_start, Clock::now());
  summary.time += st.time;
  summary.per_iteration.push_back(st);
  summary.iterations = st.iteration;
  if (options_.callback) options_.callback(st);
}

bool Optimizer::stopped(Summary& summary, const detail::StepResult& r) const {
  using Kind = detail::StepResult::Kind;
  switch (r.kind) {
    case Kind::kAccepted:
    case Kind::kRestarted:
      return false;
    case Kind::kConverged:
      summary.status = TerminationStatus::kConverged;
      break;
    case Kind::kNoProgress:
      summary.status = TerminationStatus::kNoProgress;
      break;
    case Kind::kFailed:
      summary.status = TerminationStatus::kNumericalFailure;
      break;
  }
  summary.message = r.message;
  if (r.kind == Kind::kFailed && r.message.empty()) {
    summary.message = failureMessage(*impl_, graph_, r.solver, summary);
  }
  return true;
}

}  // namespace graphslam
