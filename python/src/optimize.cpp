// SPDX-License-Identifier: MIT
// graphslam.optimize: the work of `graphslam optimize FILE` on a graph Python holds, with
// the tool's defaults: the finite-terms check, the initial guess (init="auto": global for
// pose-graph files), the observability check, optional GNC outlier rejection and robust
// kernel, the optimizer, and the check of H at a damped result. The library runs without
// the GIL; the per-iteration callback takes it back.
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <unordered_set>

#include "common.h"
#include "graphslam/diagnostics/observability.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/init/initial_guess.h"
#include "graphslam/optimizer/marginals.h"
#include "graphslam/outliers/gnc.h"
#include "graphslam/outliers/robust_init.h"
#include "graphslam/robust/apply.h"
#include "optimize.h"

namespace graphslam::python {

namespace {

struct OptimizeArgs {
  std::string algorithm = "auto";
  std::string solver = "auto";
  int max_iterations = 100;
  std::string init = "auto";
  std::string robust_kernel;
  std::string robust_edges = "all";
  bool reject_outliers = false;
  double inlier_probability = 0.99;
  std::string gnc_init = "robust";
  bool drop_unobservable = false;
  int threads = 1;
  double function_tolerance = 1e-8;
  double step_tolerance = 1e-12;
  double lambda_init = 1e-5;
  double lambda_decrease = 1.0 / 3.0;
  std::string damping = "identity";
  std::string first_step = "dogleg";
};

Algorithm parseAlgorithm(const std::string& a) {
  if (a == "auto") return Algorithm::kGaussNewtonFallback;
  if (a == "gn") return Algorithm::kGaussNewton;
  if (a == "lm") return Algorithm::kLevenbergMarquardt;
  if (a == "dogleg") return Algorithm::kDogleg;
  throw py::value_error("algorithm must be auto, gn, lm or dogleg, not '" + a + "'");
}

/// The optimizer's options from the arguments, each checked as the tool checks its flags.
Optimizer::Options optimizerOptions(const OptimizeArgs& a) {
  Optimizer::Options o;
  if (a.max_iterations < 1) throw py::value_error("max_iterations must be at least 1");
  if (a.threads < 1 || a.threads > 256) throw py::value_error("threads must be between 1 and 256");
  if (!(a.lambda_init > 0 && std::isfinite(a.lambda_init))) {
    throw py::value_error("lambda_init must be a positive finite number");
  }
  if (!(a.lambda_decrease > 0 && a.lambda_decrease <= 1)) {
    throw py::value_error("lambda_decrease must be in (0, 1]");
  }
  if (!(a.function_tolerance >= 0 && std::isfinite(a.function_tolerance))) {
    throw py::value_error("function_tolerance must be a finite number >= 0");
  }
  if (!(a.step_tolerance >= 0 && std::isfinite(a.step_tolerance))) {
    throw py::value_error("step_tolerance must be a finite number >= 0");
  }
  if (a.damping != "identity" && a.damping != "diagonal") {
    throw py::value_error("damping must be identity or diagonal, not '" + a.damping + "'");
  }
  if (a.first_step != "dogleg" && a.first_step != "gn") {
    throw py::value_error("first_step must be dogleg or gn, not '" + a.first_step + "'");
  }
  if (a.init != "auto" && a.init != "global" && a.init != "none") {
    throw py::value_error("init must be auto, global or none, not '" + a.init + "'");
  }
  if (a.gnc_init != "robust" && a.gnc_init != "known-inliers") {
    throw py::value_error("gnc_init must be robust or known-inliers, not '" + a.gnc_init + "'");
  }
  if (!(a.inlier_probability > 0 && a.inlier_probability < 1)) {
    throw py::value_error("inlier_probability must be in (0, 1)");
  }
  if (!registries().solvers.contains(a.solver)) {
    throw py::value_error("unknown solver '" + a.solver + "' (graphslam.solvers() lists them)");
  }
  o.algorithm = parseAlgorithm(a.algorithm);
  o.linear_solver = a.solver;
  o.max_iterations = a.max_iterations;
  o.threads = a.threads;
  o.function_tolerance = a.function_tolerance;
  o.step_tolerance = a.step_tolerance;
  o.initial_lambda_factor = a.lambda_init;
  o.min_lambda_decrease = a.lambda_decrease;
  o.damping = a.damping == "diagonal" ? Optimizer::Options::Damping::kDiagonal
                                      : Optimizer::Options::Damping::kIdentity;
  o.first_step_dogleg = a.first_step == "dogleg";
  return o;
}

std::string edgeLinesText(const PyGraph& g, const std::vector<std::size_t>& edges) {
  constexpr std::size_t kShown = 5;
  if (edges.empty() || g.edge_lines.size() != g.graph.numEdges()) return {};
  std::string out = edges.size() == 1 ? "line " : "lines ";
  for (std::size_t k = 0; k < edges.size() && k < kShown; ++k) {
    if (edges[k] >= g.edge_lines.size() || g.edge_lines[edges[k]] == 0) return {};
    out += (k == 0 ? "" : ", ") + std::to_string(g.edge_lines[edges[k]]);
  }
  if (edges.size() > kShown) out += ", ... (" + std::to_string(edges.size()) + " edges)";
  return out;
}

std::string failedEdgeNote(const PyGraph& g, std::ptrdiff_t edge) {
  if (edge < 0) return {};
  const std::string lines = edgeLinesText(g, {static_cast<std::size_t>(edge)});
  return lines.empty() ? lines : "; that edge is on " + lines + " of " + g.path;
}

/// The initial guess as the tool makes it (apps/input.cpp, outlier_options.cpp). Returns
/// whether the GNC must start from the robust global initialisation.
bool initialGuess(PyGraph& g, const OptimizeArgs& a, OptimizeResult& r) {
  std::string init = a.init;
  if (init == "auto") init = g.keep_initial_guess ? "none" : "global";
  if (init != "global") {
    r.initialization.push_back(g.keep_initial_guess && a.init == "auto"
                                   ? "none (keeping the graph's estimates)"
                                   : "none");
    return false;
  }
  if (a.reject_outliers) {
    if (a.gnc_init == "robust") {
      r.initialization.push_back("global with graduated non-convexity (outlier rejection)");
      return true;
    }
    const auto solver = registries().solvers.create("auto");
    const auto report = init::initializeGlobal(g.graph, solver.get(), outliers::isOdometryOrUnary);
    r.initialization.push_back(report.message.empty()
                                   ? "global from the known inliers only (odometry and priors)"
                                   : report.message);
    return false;
  }
  for (const std::string& line : init::initializeGraph(g.graph, registries().solvers).lines) {
    r.initialization.push_back(line);
  }
  return false;
}

/// The observability check before solving: InputError listing the undetermined vertices
/// (with their edges' file lines), or with drop_unobservable their removal.
void checkBeforeSolving(PyGraph& g, const OptimizeArgs& a, OptimizeResult& r) {
  ObservabilityOptions options;
  options.types = &registries().types;
  options.threads = a.threads;
  for (int round = 0; round < 100; ++round) {
    const ObservabilityReport report = checkObservability(g.graph, options);
    if (report.ok()) return;
    if (!a.drop_unobservable) {
      throw InputError(
          g.name() + ": " +
          report.describeUndetermined(20, [&](const UndeterminedVertex& u) {
            const std::string lines = edgeLinesText(g, u.edges);
            return lines.empty() ? lines : " [edges on " + lines + "]";
          }) +
          "\nnot optimising: optimize(drop_unobservable=True) removes these vertices and their edges");
    }
    std::unordered_set<const Edge*> gone;
    const std::vector<VertexId> ids = report.undeterminedIds();
    for (VertexId id : ids) {
      for (const Edge* e : g.graph.vertex(id)->edges()) gone.insert(e);
    }
    if (g.edge_lines.size() == g.graph.numEdges()) {
      std::vector<std::size_t> kept;
      for (std::size_t k = 0; k < g.graph.numEdges(); ++k) {
        if (!gone.count(g.graph.edges()[k].get())) kept.push_back(g.edge_lines[k]);
      }
      g.edge_lines.swap(kept);
    }
    g.graph.removeEdges([&](const Edge& e) { return gone.count(&e) != 0; });
    for (VertexId id : ids) g.graph.removeVertex(id);
    r.dropped.insert(r.dropped.end(), ids.begin(), ids.end());
  }
}

/// GNC outlier rejection as the tool runs it; false (with the message) when it failed.
bool rejectOutliers(PyGraph& g, const OptimizeArgs& a, const Optimizer::Options& optimizer,
                    bool global_start, OptimizeResult& r) {
  outliers::GncOptions gnc;
  gnc.inlier_probability = a.inlier_probability;
  gnc.optimizer = optimizer;
  gnc.optimizer.callback = nullptr;
  outliers::GncResult result;
  if (global_start) {
    const auto init_solver = registries().solvers.create("auto");
    result = outliers::rejectFromGlobalStart(g.graph, registries().solvers, init_solver.get(), gnc);
  } else {
    result = outliers::runGnc(g.graph, registries().solvers, gnc);
  }
  if (!result.ok) {
    r.status = "numerical_failure";
    r.message = "outlier rejection failed: " + result.message;
    return false;
  }
  const bool lines = g.edge_lines.size() == g.graph.numEdges();
  std::vector<bool> removed(g.graph.numEdges(), false);
  for (const auto& x : result.rejected) {
    RejectedEdgeInfo info;
    info.index = x.index;
    info.vertex_ids = x.vertex_ids;
    info.chi2 = x.chi2;
    info.line = lines && x.index < g.edge_lines.size() ? g.edge_lines[x.index] : 0;
    if (x.index < removed.size()) removed[x.index] = true;
    r.rejected.push_back(std::move(info));
  }
  if (lines) {
    std::vector<std::size_t> kept;
    for (std::size_t k = 0; k < removed.size(); ++k) {
      if (!removed[k]) kept.push_back(g.edge_lines[k]);
    }
    g.edge_lines.swap(kept);
  }
  (void)outliers::removeRejected(g.graph, result);
  return true;
}

py::dict iterationDict(const IterationStats& s) {
  py::dict d;
  d["iteration"] = s.iteration;
  d["chi2"] = s.chi2;
  d["step_norm"] = s.step_norm;
  d["accepted"] = s.accepted;
  d["factorizations"] = s.factorizations;
  d["elapsed"] = s.elapsed;
  d["time"] = s.time.total();
  d["step"] = s.strategy.step;
  for (const auto& [name, value] : s.strategy.values) d[py::str(name)] = value;
  return d;
}

std::string statusName(TerminationStatus s) {
  switch (s) {
    case TerminationStatus::kConverged: return "converged";
    case TerminationStatus::kMaxIterations: return "max_iterations";
    case TerminationStatus::kNoProgress: return "no_progress";
    case TerminationStatus::kNumericalFailure: return "numerical_failure";
    case TerminationStatus::kUnderDetermined: return "under_determined";
  }
  return "?";
}

/// Runs the optimizer without the GIL; the callback (and Ctrl-C) can stop it after any
/// iteration by lowering its iteration budget to the current one. A Python exception of
/// the callback is left set for the caller.
Summary runOptimizer(PyGraph& g, const Optimizer::Options& options, const py::object& callback,
                     bool& stopped) {
  Optimizer optimizer(g.graph, registries().solvers, options);
  bool python_error = false;
  optimizer.mutableOptions().callback = [&](const IterationStats& s) {
    if (python_error) return;
    py::gil_scoped_acquire gil;
    bool stop = PyErr_CheckSignals() != 0;
    if (!stop && !callback.is_none()) {
      try {
        g.paused.store(true);
        struct Resume {
          PyGraph& g;
          ~Resume() { g.paused.store(false); }
        } resume{g};
        py::object verdict = callback(iterationDict(s));
        stop = !verdict.is_none() && !verdict.cast<bool>();
      } catch (py::error_already_set& e) {
        e.restore();
        stop = true;
      } catch (const py::cast_error&) {
        PyErr_SetString(PyExc_TypeError, "the callback must return None, True or False");
        stop = true;
      }
    }
    python_error = PyErr_Occurred() != nullptr;
    if (stop) {
      stopped = true;
      optimizer.mutableOptions().max_iterations = s.iteration;
    }
  };
  py::gil_scoped_release release;
  return optimizer.optimize();
}

/// After a run in which no iteration factorised the undamped H: H at the result must be
/// positive definite, or the damping hid an undetermined vertex (the tool's check).
void checkUndamped(PyGraph& g, OptimizeResult& r) {
  if (!r.summary.succeeded()) return;
  for (const IterationStats& it : r.summary.per_iteration) {
    if (it.undamped) return;
  }
  MarginalCovariance::Options options;
  options.solvers = &registries().solvers;
  MarginalCovariance marginals(options);
  const MarginalSummary check = marginals.compute(g.graph, {});
  if (check.ok()) return;
  r.ok = false;
  r.status = "singular";
  r.message = std::string(toString(r.summary.status)) + " by " + toString(r.summary.algorithm) +
              ", but H is singular at the result (the damping hid it): " + check.message;
}

OptimizeResult optimize(PyGraph& g, const OptimizeArgs& a, const py::object& callback) {
  const auto t0 = std::chrono::steady_clock::now();
  const Optimizer::Options options = optimizerOptions(a);
  if (!callback.is_none() && !PyCallable_Check(callback.ptr())) {
    throw py::type_error("callback must be callable");
  }
  robust::KernelSpec spec;
  robust::EdgeSelector selector;
  if (!a.robust_kernel.empty()) {
    spec = robust::parseKernelSpec(a.robust_kernel, registries().kernels);
    selector = robust::parseEdgeSelection(a.robust_edges, registries().types);
  }
  BusyGraph busy(g);
  OptimizeResult r;
  {
    py::gil_scoped_release release;
    const NonFiniteEdge bad = findNonFiniteEdge(g.graph);
    if (bad.index >= 0) {
      r.status = "numerical_failure";
      r.message = "initial chi2 is not finite: " + bad.description + failedEdgeNote(g, bad.index);
      return r;
    }
    const bool global_start = initialGuess(g, a, r);
    checkBeforeSolving(g, a, r);
    if (a.reject_outliers && !rejectOutliers(g, a, options, global_start, r)) return r;
    if (!a.robust_kernel.empty()) {
      r.robust_edges = robust::applyRobustKernel(g.graph, robust::createKernel(spec, registries().kernels),
                                                 selector, registries().types);
    }
  }
  r.summary = runOptimizer(g, options, callback, r.stopped);
  if (PyErr_Occurred()) throw py::error_already_set();
  r.ok = r.summary.succeeded();
  r.status = r.stopped ? "stopped" : statusName(r.summary.status);
  r.message = r.stopped ? "stopped by the callback after iteration " + std::to_string(r.summary.iterations)
                        : r.summary.message;
  if (!r.ok && r.summary.failed_edge >= 0) r.message += failedEdgeNote(g, r.summary.failed_edge);
  {
    py::gil_scoped_release release;
    checkUndamped(g, r);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace

void bindOptimize(py::module_& m) {
  bindOptimizeResult(m);
  m.def(
      "optimize",
      [](PyGraph& g, const std::string& algorithm, const std::string& solver, int max_iterations,
         const std::string& init, const py::object& robust_kernel, const std::string& robust_edges,
         bool reject_outliers, double inlier_probability, const std::string& gnc_init,
         const py::object& callback, bool drop_unobservable, int threads, double function_tolerance,
         double step_tolerance, double lambda_init, double lambda_decrease,
         const std::string& damping, const std::string& first_step) {
        OptimizeArgs a;
        a.algorithm = algorithm;
        a.solver = solver;
        a.max_iterations = max_iterations;
        a.init = init;
        a.robust_kernel = robust_kernel.is_none() ? std::string() : robust_kernel.cast<std::string>();
        a.robust_edges = robust_edges;
        a.reject_outliers = reject_outliers;
        a.inlier_probability = inlier_probability;
        a.gnc_init = gnc_init;
        a.drop_unobservable = drop_unobservable;
        a.threads = threads;
        a.function_tolerance = function_tolerance;
        a.step_tolerance = step_tolerance;
        a.lambda_init = lambda_init;
        a.lambda_decrease = lambda_decrease;
        a.damping = damping;
        a.first_step = first_step;
        return optimize(g, a, callback);
      },
      py::arg("graph"), py::arg("algorithm") = "auto", py::arg("solver") = "auto",
      py::arg("max_iterations") = 100, py::arg("init") = "auto", py::arg("robust_kernel") = py::none(),
      py::arg("robust_edges") = "all", py::arg("reject_outliers") = false,
      py::arg("inlier_probability") = 0.99, py::arg("gnc_init") = "robust",
      py::arg("callback") = py::none(), py::arg("drop_unobservable") = false, py::arg("threads") = 1,
      py::arg("function_tolerance") = 1e-8, py::arg("step_tolerance") = 1e-12,
      py::arg("lambda_init") = 1e-5, py::arg("lambda_decrease") = 1.0 / 3.0,
      py::arg("damping") = "identity", py::arg("first_step") = "dogleg",
      R"doc(Optimises the graph in place, as `graphslam optimize FILE` does, with its defaults.

algorithm: auto (Gauss-Newton, Levenberg-Marquardt when steps fail), gn, lm or dogleg.
solver: a linear solver of graphslam.solvers() ("NAME[:ORDERING]"; auto chooses).
max_iterations: iteration budget. init: auto (global for pose-graph files, the graph's own
estimates for graphs built in code and .npz files: Graph.keep_initial_guess), global (SE(2)
and SE(3) global initialisation) or none.
robust_kernel: "NAME[:WIDTH]" (graphslam.kernels()) on the edges robust_edges selects (all,
loop-closures or a tag). reject_outliers: graduated non-convexity with truncated least
squares first (odometry and priors are known inliers), the rejected edges removed from the
graph (result.rejected_edges); inlier_probability and gnc_init (robust, known-inliers) tune it.
callback(stats: dict) after every iteration (iteration, chi2, step_norm, accepted, elapsed,
...); returning False stops the run there (status "stopped"); it may read the graph
(estimates, edges) but not change it. The library works without the
GIL; Ctrl-C stops it after the current iteration (KeyboardInterrupt).
Vertices the edges do not determine raise graphslam.InputError naming them (and their
edges' lines) unless drop_unobservable removes them. Returns an OptimizeResult; numerical
failures are its status, not exceptions.)doc");
}

}  // namespace graphslam::python
