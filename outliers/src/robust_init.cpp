// SPDX-License-Identifier: MIT
#include "graphslam/outliers/robust_init.h"

#include <algorithm>
#include <chrono>
#include <unordered_map>

#include "graphslam/init/global_se2.h"
#include "graphslam/support/error.h"

namespace graphslam::outliers {

namespace {

/// The candidates of a run: their thresholds, chi2 and weights, by edge.
struct InitCandidates {
  std::unordered_map<const Edge*, std::size_t> index;
  std::vector<const Edge*> edge;
  std::vector<double> c2, s, w;

  InitCandidates(const Graph& graph, const GncOptions& o) {
    Chi2Thresholds threshold(o.inlier_probability);
    for (const auto& e : graph.edges()) {
      const bool known = isKnownInlier(o, *e);
      if (known) continue;
      index.emplace(e.get(), edge.size());
      edge.push_back(e.get());
      c2.push_back(threshold(e->dimension()));
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

/// mu_0 by Remark 5 over the candidates whose chi2 is below initial_max_ratio times their
/// threshold (the others start at weight 0); every candidate's when that is infinite.
double initialMuBelow(const std::vector<double>& s, const std::vector<double>& c2,
                      const GncOptions& options) {
  std::vector<double> s_in, c2_in;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (s[k] < options.initial_max_ratio * c2[k]) {
      s_in.push_back(s[k]);
      c2_in.push_back(c2[k]);
    }
  }
  const double mu = initialMu(s_in, c2_in, options.min_initial_mu);
  if (mu > 0.0 || s_in.size() == s.size()) return mu;
  // Every candidate below the bound is an inlier: start where the bound's are weight 0.
  return initialMu({options.initial_max_ratio}, {1.0}, options.min_initial_mu);
}

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
      r.initial_mu = mu = initialMuBelow(cand.s, cand.c2, options);
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

/// mu_0 of the verifying GNC (GncOptions::verify_max_ratio) from the errors stored at the
/// initialisation's optimum; negative when no candidate lies between its threshold and
/// the bound.
double verifyInitialMu(const Graph& graph, const GncOptions& options) {
  std::vector<double> s, c2;
  Chi2Thresholds threshold(options.inlier_probability);
  for (const auto& e : graph.edges()) {
    const bool known = isKnownInlier(options, *e);
    if (known) continue;
    const double t = threshold(e->dimension());
    if (e->chi2() < options.verify_max_ratio * t) {
      s.push_back(e->chi2());
      c2.push_back(t);
    }
  }
  return initialMu(s, c2, options.min_initial_mu);
}

}  // namespace

double tlsCost(Graph& graph, const GncOptions& options) {
  (void)graph.chi2();
  Chi2Thresholds threshold(options.inlier_probability);
  double cost = 0.0;
  for (const auto& e : graph.edges()) {
    const bool known = isKnownInlier(options, *e);
    cost += known ? e->chi2() : std::min(e->chi2(), threshold(e->dimension()));
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
  const double mu0 = verifyInitialMu(graph, options);
  if (mu0 < 0.0) return by_init;  // nothing the nonlinear GNC could decide differently
  const std::vector<double> state = saveEstimates(graph);
  GncOptions from_here = options;
  from_here.initial_mu = mu0;
  from_here.optimizer_iterations_per_step = options.verify_iterations_per_step;
  GncResult by_gnc = runGnc(graph, solvers, from_here);
  if (by_gnc.ok) rep.cost_by_gnc = optimiseInliers(graph, solvers, options, by_gnc);
  double largest_c2 = 0.0;
  Chi2Thresholds threshold(options.inlier_probability);
  for (const auto& e : graph.edges()) largest_c2 = std::max(largest_c2, threshold(e->dimension()));
  rep.chose_gnc = by_gnc.ok &&
                  rep.cost_by_gnc < rep.cost_by_initialization - options.verify_margin * largest_c2;
  if (rep.chose_gnc) {
    by_gnc.seconds += by_init.seconds;
    return by_gnc;
  }
  restoreEstimates(graph, state);
  (void)graph.chi2();
  return by_init;
}

}  // namespace graphslam::outliers
