// SPDX-License-Identifier: MIT
#include "graphslam/outliers/gnc.h"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <unordered_set>
#include <utility>

#include "graphslam/support/error.h"

namespace graphslam::outliers {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// The candidate edges of a run with their thresholds and kernels; restores the edges'
/// own kernels when destroyed.
class Candidates {
 public:
  Candidates(Graph& graph, const GncOptions& o) : graph_(graph) {
    const auto& edges = graph.edges();
    Chi2Thresholds threshold(o.inlier_probability);
    for (std::size_t k = 0; k < edges.size(); ++k) {
      Edge& e = *edges[k];
      const bool known = isKnownInlier(o, e);
      if (known) continue;
      index_.push_back(k);
      edge_.push_back(&e);
      c2_.push_back(threshold(e.dimension()));
      saved_.push_back(e.sharedRobustKernel());
      auto kernel = std::make_shared<WeightKernel>(1.0);
      kernel_.push_back(kernel);
      e.setRobustKernel(std::move(kernel));
    }
    s_.assign(edge_.size(), 0.0);
    w_.assign(edge_.size(), 1.0);
  }
  ~Candidates() {
    for (std::size_t k = 0; k < edge_.size(); ++k) {
      edge_[k]->setRobustKernel(saved_[k]);
      graph_.setEdgeActive(*edge_[k], true);
    }
  }
  Candidates(const Candidates&) = delete;
  Candidates& operator=(const Candidates&) = delete;

  [[nodiscard]] std::size_t size() const { return edge_.size(); }
  /// Reads every candidate's chi2 (errors must be up to date: Graph::chi2()).
  void readErrors() {
    for (std::size_t k = 0; k < edge_.size(); ++k) s_[k] = edge_[k]->chi2();
  }
  /// Sets every weight for control mu; returns how many are undecided. An edge of weight
  /// 0 is left out of the optimisation (Graph::setEdgeActive) until its weight rises
  /// again: it adds nothing to H but its fill-in, which random wrong loop closures make
  /// large.
  std::size_t setWeights(double mu, double tolerance) {
    std::size_t undecided = 0;
    for (std::size_t k = 0; k < edge_.size(); ++k) {
      w_[k] = tlsWeight(s_[k], c2_[k], mu);
      kernel_[k]->setWeight(w_[k]);
      graph_.setEdgeActive(*edge_[k], w_[k] > 0.0);
      if (w_[k] > 0.0 && w_[k] < 1.0 - tolerance) ++undecided;
    }
    return undecided;
  }
  [[nodiscard]] std::size_t countAtLeast(double weight) const {
    return static_cast<std::size_t>(
        std::count_if(w_.begin(), w_.end(), [weight](double w) { return w >= weight; }));
  }
  /// sum w_k s_k over the candidates (known inliers are added by the caller).
  [[nodiscard]] double weightedCost() const {
    double c = 0.0;
    for (std::size_t k = 0; k < edge_.size(); ++k) c += w_[k] * s_[k];
    return c;
  }
  /// sum s_k over the active candidates (what Graph::chi2() adds of them).
  [[nodiscard]] double candidateChi2() const {
    double c = 0.0;
    for (std::size_t k = 0; k < edge_.size(); ++k) c += edge_[k]->active() ? s_[k] : 0.0;
    return c;
  }
  const std::vector<double>& s() const { return s_; }
  const std::vector<double>& c2() const { return c2_; }

  /// Fills the result's weights and rejected edges.
  void report(std::size_t num_edges, double rejection_weight, GncResult& r) const {
    r.weights.assign(num_edges, 1.0);
    for (std::size_t k = 0; k < edge_.size(); ++k) {
      r.weights[index_[k]] = w_[k];
      if (w_[k] >= rejection_weight) continue;
      RejectedEdge x;
      x.index = index_[k];
      x.vertex_ids.assign(edge_[k]->vertexIds().begin(), edge_[k]->vertexIds().end());
      x.chi2 = s_[k];
      x.weight = w_[k];
      r.rejected.push_back(std::move(x));
    }
  }

 private:
  Graph& graph_;
  std::vector<std::size_t> index_;
  std::vector<Edge*> edge_;
  std::vector<double> c2_, s_, w_;
  std::vector<std::shared_ptr<const RobustKernel>> saved_;
  std::vector<std::shared_ptr<WeightKernel>> kernel_;
};

/// Holds the gauge for the whole run: with nothing fixed and no unary edge, fixes the
/// lowest id with an edge (as the optimizer would at every call), so that the optimizer
/// sees one structure throughout and analyses it once; restored when destroyed.
class GaugeHold {
 public:
  GaugeHold(Graph& graph, bool fix_gauge) {
    if (!fix_gauge) return;
    for (const auto& [id, v] : graph.vertices()) {
      if (v->fixed()) return;
    }
    for (const auto& e : graph.edges()) {
      if (e->vertexIds().size() == 1) return;
    }
    for (const auto& [id, v] : graph.vertices()) {
      if (v->edges().empty()) continue;
      fixed_ = v.get();
      fixed_->setFixed(true);
      return;
    }
  }
  ~GaugeHold() {
    if (fixed_) fixed_->setFixed(false);
  }
  GaugeHold(const GaugeHold&) = delete;
  GaugeHold& operator=(const GaugeHold&) = delete;

 private:
  Vertex* fixed_ = nullptr;
};

}  // namespace

bool isOdometryOrUnary(const Edge& edge) {
  const auto ids = edge.vertexIds();
  if (ids.size() <= 1) return true;
  if (ids.size() != 2) return false;
  const VertexId a = edge.vertexId(0), b = edge.vertexId(1);
  return (a > b ? a - b : b - a) == 1;
}

double chi2Threshold(int dimension, double probability) {
  if (dimension < 1) throw Error("chi2Threshold: dimension must be at least 1");
  if (!(probability > 0.0 && probability < 1.0)) {
    throw Error("chi2Threshold: probability must be in (0, 1)");
  }
  const boost::math::chi_squared_distribution<double> chi2(dimension);
  return boost::math::quantile(chi2, probability);
}

double tlsWeight(double s, double c2, double mu) {
  if (s <= mu / (mu + 1.0) * c2) return 1.0;
  if (s >= (mu + 1.0) / mu * c2) return 0.0;
  const double w = std::sqrt(c2 * mu * (mu + 1.0) / s) - mu;
  return std::clamp(w, 0.0, 1.0);
}

double initialMu(const std::vector<double>& s, const std::vector<double>& c2, double min_mu) {
  double mu = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (s[k] > c2[k]) mu = std::min(mu, c2[k] / (2.0 * s[k] - c2[k]));
  }
  if (std::isinf(mu)) return -1.0;
  return std::max(mu, min_mu);
}

void checkOptions(const GncOptions& o) {
  if (!(o.inlier_probability > 0.0 && o.inlier_probability < 1.0))
    throw Error("GncOptions::inlier_probability must be in (0, 1)");
  if (!(o.mu_step > 1.0 && std::isfinite(o.mu_step)))
    throw Error("GncOptions::mu_step must be a finite number > 1");
  if (!(o.initial_mu >= 0.0 && std::isfinite(o.initial_mu)))
    throw Error("GncOptions::initial_mu must be a finite number >= 0");
  if (!(o.min_initial_mu > 0.0 && std::isfinite(o.min_initial_mu)))
    throw Error("GncOptions::min_initial_mu must be a positive finite number");
  if (o.max_iterations < 1) throw Error("GncOptions::max_iterations must be at least 1");
  if (o.initial_least_squares_iterations < 0)
    throw Error("GncOptions::initial_least_squares_iterations must be at least 0");
  if (!(o.verify_margin >= 0.0 && std::isfinite(o.verify_margin)))
    throw Error("GncOptions::verify_margin must be a finite number >= 0");
  if (!(o.verify_max_ratio > 1.0))
    throw Error("GncOptions::verify_max_ratio must be greater than 1");
  if (o.verify_iterations_per_step < 1)
    throw Error("GncOptions::verify_iterations_per_step must be at least 1");
  if (o.optimizer_iterations_per_step < 1)
    throw Error("GncOptions::optimizer_iterations_per_step must be at least 1");
  if (!(o.weight_tolerance >= 0.0 && o.weight_tolerance < 0.5))
    throw Error("GncOptions::weight_tolerance must be in [0, 0.5)");
  if (!(o.rejection_weight > 0.0 && o.rejection_weight <= 1.0))
    throw Error("GncOptions::rejection_weight must be in (0, 1]");
}

GncResult runGnc(Graph& graph, const SolverRegistry& solvers, const GncOptions& options) {
  checkOptions(options);
  const auto t0 = Clock::now();
  GncResult r;
  Candidates cand(graph, options);
  r.candidates = cand.size();
  r.known_inliers = graph.numEdges() - cand.size();
  const GaugeHold gauge(graph, options.optimizer.fix_gauge);
  Optimizer::Options step_options = options.optimizer;
  step_options.max_iterations = std::max(1, options.initial_least_squares_iterations);
  Optimizer optimizer(graph, solvers, step_options);
  if (options.initial_least_squares_iterations > 0) {  // every weight is 1 here
    const Summary first = optimizer.optimize();
    r.optimizer_iterations += first.iterations;
    if (!first.succeeded() && first.status != TerminationStatus::kNoProgress) {
      r.ok = false;
      r.message = "initial least-squares step failed: " + first.message;
      cand.report(graph.numEdges(), options.rejection_weight, r);
      return r;
    }
  }
  (void)graph.chi2();
  cand.readErrors();
  r.initial_mu = options.initial_mu > 0.0 ? options.initial_mu
                                          : initialMu(cand.s(), cand.c2(), options.min_initial_mu);
  double mu = r.initial_mu;
  if (mu < 0.0) {  // every candidate is within its threshold: all inliers
    r.converged = true;
    cand.report(graph.numEdges(), options.rejection_weight, r);
    r.seconds = secondsSince(t0);
    return r;
  }
  optimizer.mutableOptions().max_iterations = options.optimizer_iterations_per_step;
  for (int it = 1; it <= options.max_iterations; ++it) {
    const std::size_t undecided = cand.setWeights(mu, options.weight_tolerance);
    const Summary step = optimizer.optimize();
    r.iterations = it;
    r.optimizer_iterations += step.iterations;
    r.final_mu = mu;
    if (!step.succeeded() && step.status != TerminationStatus::kNoProgress) {
      r.ok = false;
      r.message = "optimizer step " + std::to_string(it) + " failed: " + step.message;
      break;
    }
    const double chi2 = graph.chi2();
    cand.readErrors();
    const double known = chi2 - cand.candidateChi2();
    if (options.callback) {
      GncIterationStats s;
      s.iteration = it;
      s.mu = mu;
      s.cost = known + cand.weightedCost();
      s.inliers = cand.countAtLeast(options.rejection_weight);
      s.undecided = undecided;
      s.optimizer_iterations = step.iterations;
      s.elapsed = secondsSince(t0);
      options.callback(s);
    }
    if (undecided == 0) {  // the step was made with binary weights: GNC has converged
      r.converged = true;
      break;
    }
    mu *= options.mu_step;
  }
  cand.report(graph.numEdges(), options.rejection_weight, r);
  r.seconds = secondsSince(t0);
  return r;
}

std::size_t removeRejected(Graph& graph, const GncResult& result) {
  std::unordered_set<const Edge*> doomed;
  const auto& edges = graph.edges();
  for (const RejectedEdge& x : result.rejected) {
    if (x.index >= edges.size()) throw Error("removeRejected: the graph changed since the GNC");
    doomed.insert(edges[x.index].get());
  }
  return graph.removeEdges([&doomed](const Edge& e) { return doomed.count(&e) != 0; });
}

GncResult rejectOutliers(Graph& graph, const SolverRegistry& solvers, const GncOptions& options,
                         Summary* reoptimization) {
  GncResult r = runGnc(graph, solvers, options);
  if (!r.ok) return r;
  removeRejected(graph, r);
  Optimizer optimizer(graph, solvers, options.optimizer);
  const Summary s = optimizer.optimize();
  if (reoptimization) *reoptimization = s;
  return r;
}

}  // namespace graphslam::outliers
