// SPDX-License-Identifier: MIT
#include "graphslam/outliers/robust_init.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <unordered_map>

#include "graphslam/core/error.h"
#include "graphslam/init/initialization.h"

namespace graphslam::outliers {

namespace {

/// The candidates of a run: their thresholds, chi2 and weights, by edge.
struct InitCandidates {
  std::unordered_map<const Edge*, std::size_t> index;
  std::vector<const Edge*> edge;
  std::vector<double> c2, s, w;

  InitCandidates(const Graph& graph, const GncOptions& o) {
    for (const auto& e : graph.edges()) {
      const bool known = o.is_known_inlier ? o.is_known_inlier(*e) : isOdometryOrUnary(*e);
      if (known) continue;
      index.emplace(e.get(), edge.size());
      edge.push_back(e.get());
      c2.push_back(chi2Threshold(e->dimension(), o.inlier_probability));
    }
    s.assign(edge.size(), 0.0);
    w.assign(edge.size(), 1.0);
  }
  [[nodiscard]] double weight(const Edge& e) const {
    const auto it = index.find(&e);
    return it == index.end() ? 1.0 : w[it->second];
  }
  /// Sets the weights for control mu; returns how many are undecided.
  std::size_t setWeights(double mu, double tolerance) {
    std::size_t undecided = 0;
    for (std::size_t k = 0; k < edge.size(); ++k) {
      w[k] = tlsWeight(s[k], c2[k], mu);
      if (w[k] > 0.0 && w[k] < 1.0 - tolerance) ++undecided;
    }
    return undecided;
  }
};

}  // namespace

// Each step: place the vertices by the weighted initialisation, read every candidate's
// chi2 there, and update the weights (mu grows by mu_step per step); the last placement
// is made with the final weights.
RobustInitReport robustInitialization(Graph& graph, LinearSolver* solver,
                                      const GncOptions& options) {
  checkOptions(options);
  const auto t0 = std::chrono::steady_clock::now();
  RobustInitReport r;
  InitCandidates cand(graph, options);
  r.candidates = cand.edge.size();
  const init::EdgeWeight weight = [&cand](const Edge& e) { return cand.weight(e); };
  double mu = 0.0;
  for (int step = 1; step <= options.max_iterations + 1; ++step) {
    const init::InitializationReport placed = init::initializeGlobalWeighted(graph, solver, weight);
    r.steps = step;
    if (!placed.message.empty()) {
      r.ok = false;
      r.message = "weighted initialisation " + std::to_string(step) + ": " + placed.message;
      break;
    }
    if (r.converged || step > options.max_iterations) break;  // placed with the final weights
    (void)graph.chi2();
    for (std::size_t k = 0; k < cand.edge.size(); ++k) cand.s[k] = cand.edge[k]->chi2();
    if (step == 1) {
      r.initial_mu = mu = initialMu(cand.s, cand.c2, options.min_initial_mu);
      if (mu < 0.0) {  // every candidate within its threshold at the least-squares placement
        r.converged = true;
        break;
      }
    } else {
      mu *= options.mu_step;
    }
    r.final_mu = mu;
    r.converged = cand.setWeights(mu, options.weight_tolerance) == 0;
  }
  r.weights.reserve(graph.numEdges());
  for (const auto& e : graph.edges()) r.weights.push_back(cand.weight(*e));
  for (double w : cand.w) r.zero_weight += w == 0.0 ? 1 : 0;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

GncResult rejectionFromInitialization(Graph& graph, const RobustInitReport& report,
                                      const GncOptions& options) {
  if (report.weights.size() != graph.numEdges()) {
    throw Error("rejectionFromInitialization: the graph changed since the initialisation");
  }
  GncResult r;
  r.converged = report.converged;
  r.candidates = report.candidates;
  r.known_inliers = graph.numEdges() - report.candidates;
  r.iterations = report.steps;
  r.initial_mu = report.initial_mu;
  r.final_mu = report.final_mu;
  r.seconds = report.seconds;
  r.weights = report.weights;
  (void)graph.chi2();
  const auto& edges = graph.edges();
  for (std::size_t k = 0; k < edges.size(); ++k) {
    if (!(report.weights[k] < options.rejection_weight)) continue;
    RejectedEdge x;
    x.index = k;
    x.vertex_ids.assign(edges[k]->vertexIds().begin(), edges[k]->vertexIds().end());
    x.chi2 = edges[k]->chi2();
    x.weight = report.weights[k];
    r.rejected.push_back(std::move(x));
  }
  return r;
}

}  // namespace graphslam::outliers

namespace graphslam::outliers {

namespace {

/// Flat copy of every vertex's estimate (graph order).
std::vector<double> saveEstimates(const Graph& graph) {
  std::vector<double> state;
  std::vector<double> buf;
  for (const auto& [id, v] : graph.vertices()) {
    buf.resize(static_cast<std::size_t>(v->estimateDataDimension()));
    v->getEstimateData(buf.data());
    state.insert(state.end(), buf.begin(), buf.end());
  }
  return state;
}

void restoreEstimates(Graph& graph, const std::vector<double>& state) {
  std::size_t k = 0;
  for (const auto& [id, v] : graph.vertices()) {
    v->setEstimateData(state.data() + k);
    k += static_cast<std::size_t>(v->estimateDataDimension());
  }
}

/// Optimises the graph without the rejected edges (left out for the run, then put back),
/// returns the TLS cost there and refreshes the rejected edges' chi2.
double optimiseInliers(Graph& graph, const SolverRegistry& solvers, const GncOptions& options,
                       GncResult& result) {
  std::vector<Edge*> off;
  for (const RejectedEdge& x : result.rejected) off.push_back(graph.edges()[x.index].get());
  for (Edge* e : off) graph.setEdgeActive(*e, false);
  Optimizer optimizer(graph, solvers, options.optimizer);
  const Summary s = optimizer.optimize();
  for (Edge* e : off) graph.setEdgeActive(*e, true);
  if (!s.succeeded() && s.status != TerminationStatus::kNoProgress) {
    result.ok = false;
    result.message = "least squares over the inliers failed: " + s.message;
  }
  const double cost = tlsCost(graph, options);
  for (RejectedEdge& x : result.rejected) x.chi2 = graph.edges()[x.index]->chi2();
  return cost;
}

}  // namespace

double tlsCost(Graph& graph, const GncOptions& options) {
  (void)graph.chi2();
  std::map<int, double> c2;  // by edge dimension
  double cost = 0.0;
  for (const auto& e : graph.edges()) {
    const bool known =
        options.is_known_inlier ? options.is_known_inlier(*e) : isOdometryOrUnary(*e);
    const double s = e->chi2();
    if (known) {
      cost += s;
      continue;
    }
    auto it = c2.find(e->dimension());
    if (it == c2.end()) {
      it = c2.emplace(e->dimension(), chi2Threshold(e->dimension(), options.inlier_probability))
               .first;
    }
    cost += std::min(s, it->second);
  }
  return cost;
}

GncResult rejectFromGlobalStart(Graph& graph, const SolverRegistry& solvers,
                                LinearSolver* init_solver, const GncOptions& options,
                                GlobalStartReport* report) {
  GlobalStartReport local;
  GlobalStartReport& rep = report ? *report : local;
  rep.init = robustInitialization(graph, init_solver, options);
  if (!rep.init.ok) {
    GncResult failed;
    failed.ok = false;
    failed.message = rep.init.message;
    return failed;
  }
  if (!rep.init.converged) return runGnc(graph, solvers, options);
  GncResult by_init = rejectionFromInitialization(graph, rep.init, options);
  rep.cost_by_initialization = optimiseInliers(graph, solvers, options, by_init);
  if (!by_init.ok || !options.verify) return by_init;
  const std::vector<double> state = saveEstimates(graph);
  GncOptions from_here = options;
  from_here.initial_mu = 0.0;
  from_here.optimizer_iterations_per_step = options.verify_iterations_per_step;
  GncResult by_gnc = runGnc(graph, solvers, from_here);
  if (by_gnc.ok) rep.cost_by_gnc = optimiseInliers(graph, solvers, options, by_gnc);
  rep.chose_gnc = by_gnc.ok && rep.cost_by_gnc < rep.cost_by_initialization;
  if (rep.chose_gnc) {
    by_gnc.seconds += by_init.seconds;
    return by_gnc;
  }
  restoreEstimates(graph, state);
  (void)graph.chi2();
  return by_init;
}

}  // namespace graphslam::outliers
