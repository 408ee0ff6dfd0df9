// SPDX-License-Identifier: MIT
#include "engine.h"

#include <chrono>
#include <cmath>

#include "graphslam/diagnostics/graph_checks.h"
#include "graphslam/optimizer/linear_system.h"
#include "graphslam/support/error.h"

namespace graphslam::submap::detail {

LocalSubmaps::LocalSubmaps(const Partition& partition, const std::vector<int>& indices, int threads,
                           bool keep_factorizations, bool supernodal)
    : partition_(&partition), pool_(std::max(1, threads)) {
  systems_.reserve(indices.size());
  const bool augmented = supernodal && AugmentedFactor::available();
  for (int k : indices) systems_.emplace_back(partition, k, keep_factorizations, augmented);
}

template <class Fn>
void LocalSubmaps::forEach(const Fn& fn) {
  if (serial_) {
    for (std::size_t k = 0; k < systems_.size(); ++k) fn(k);
    return;
  }
  pool_.parallelFor(systems_.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) fn(k);
  });
}

std::vector<Cost> LocalSubmaps::costs() {
  std::vector<Cost> out(systems_.size());
  forEach([&](std::size_t k) {
    out[k].first = systems_[k].cost();
    out[k].second = systems_[k].rawChi2();
  });
  return out;
}

void LocalSubmaps::linearize() {
  std::vector<char> in_place(systems_.size(), 0);
  forEach([&](std::size_t k) { in_place[k] = systems_[k].linearize() ? 1 : 0; });
  // Edges whose numeric Jacobian perturbs shared vertices in place keep the work serial.
  serial_ = false;
  for (char c : in_place) serial_ = serial_ || c != 0;
}

void LocalSubmaps::eliminate(double lambda,
                             const std::function<void(std::size_t, Contribution&)>& sink) {
  const std::size_t wave = serial_ ? 1 : static_cast<std::size_t>(pool_.threads());
  for (std::size_t first = 0; first < systems_.size(); first += wave) {
    std::vector<Contribution> out(std::min(wave, systems_.size() - first));
    pool_.parallelFor(out.size(), 1, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) out[k] = systems_[first + k].eliminate(lambda);
    });
    for (std::size_t k = 0; k < out.size(); ++k) {
      sink(first + k, out[k]);
      out[k] = Contribution{};
    }
  }
}

std::vector<Contribution> LocalSubmaps::gradients() {
  std::vector<Contribution> out(systems_.size());
  forEach([&](std::size_t k) { out[k] = systems_[k].gradient(); });
  return out;
}

bool LocalSubmaps::backSubstituteAndApply(const Eigen::VectorXd& separator_step, double lambda,
                                          double& squared_norm, std::string& message) {
  std::vector<Eigen::VectorXd> steps(systems_.size());
  std::vector<std::string> messages(systems_.size());
  std::vector<char> ok(systems_.size(), 0);
  forEach([&](std::size_t k) {
    const Submap& s = systems_[k].submap();
    Eigen::VectorXd local(s.separator_dimension);
    int at = 0;
    for (int sep : s.separators) {
      const int first = partition_->separator_offsets[static_cast<std::size_t>(sep)];
      const int dim = partition_->separator_offsets[static_cast<std::size_t>(sep) + 1] - first;
      local.segment(at, dim) = separator_step.segment(first, dim);
      at += dim;
    }
    ok[k] = systems_[k].backSubstitute(local, lambda, steps[k], messages[k]) ? 1 : 0;
  });
  for (std::size_t k = 0; k < systems_.size(); ++k) {
    if (!ok[k]) {
      message = messages[k];
      return false;
    }
  }
  forEach([&](std::size_t k) { systems_[k].applyInterior(steps[k]); });
  for (const auto& s : steps) squared_norm += s.squaredNorm();
  return true;
}

void LocalSubmaps::restore() {
  forEach([&](std::size_t k) { systems_[k].restoreInterior(); });
}

void SeparatorEstimates::apply(const Eigen::VectorXd& step) {
  saved_.clear();
  for (std::size_t k = 0; k < partition_->separators.size(); ++k) {
    Vertex* v = partition_->separators[k];
    const std::size_t at = saved_.size();
    saved_.resize(at + static_cast<std::size_t>(v->estimateDataDimension()));
    v->getEstimateData(saved_.data() + at);
    v->oplus(step.data() + partition_->separator_offsets[k]);
  }
}

void SeparatorEstimates::restore() {
  std::size_t at = 0;
  if (saved_.empty()) return;
  for (Vertex* v : partition_->separators) {
    v->setEstimateData(saved_.data() + at);
    at += static_cast<std::size_t>(v->estimateDataDimension());
  }
}

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// One iteration's trials: undamped first (or with the current damping), more damping after
/// each step that fails or raises the objective. Returns whether a step was kept.
bool tryStep(Engine& engine, const Options& options, Cost& cost, double& lambda, double& scale,
             IterationStats& st, Summary& summary, bool& at_rounding) {
  at_rounding = false;
  for (int trial = 0; trial <= options.max_rejections; ++trial) {
    const StepOutcome out = engine.step(lambda);
    ++st.trials;
    st.time_eliminate += out.time_eliminate;
    st.time_separator += out.time_separator;
    st.time_back += out.time_back;
    if (trial == 0) st.gradient_norm = out.gradient_norm;
    scale = std::max(scale, out.max_diagonal);
    if (out.ok) {
      const auto t = Clock::now();
      const Cost trial_cost = engine.cost();
      st.time_back += secondsSince(t);
      if (std::isfinite(trial_cost.first) && trial_cost.first < cost.first) {
        cost = trial_cost;
        st.step_norm = out.step_norm;
        st.lambda = lambda;
        st.separator_nonzeros = out.separator_nonzeros;
        st.separator_iterations = out.separator_iterations;
        return true;
      }
      at_rounding = trial == 0 && trial_cost.first - cost.first <= 1e-12 * cost.first;
      engine.undo();
      engine.cost();  // the errors of the linearisation point again
      if (at_rounding) return false;
    } else {
      summary.message = out.message;
    }
    lambda = lambda == 0.0 ? options.initial_lambda_factor * std::max(scale, 1e-300) : lambda * 10;
  }
  return false;
}

}  // namespace

Summary runIterations(Engine& engine, const Partition& partition, const Options& options) {
  const auto start = Clock::now();
  Summary summary;
  summary.partition = partition.describe();
  Cost cost = engine.cost();
  summary.initial_cost = summary.final_cost = cost.first;
  summary.initial_chi2 = summary.final_chi2 = cost.second;
  if (!std::isfinite(cost.first)) {
    summary.status = TerminationStatus::kNumericalFailure;
    summary.message = "the initial objective is not finite";
    return summary;
  }
  summary.status = TerminationStatus::kMaxIterations;
  double lambda = 0.0, scale = 0.0;
  for (int it = 1; it <= options.max_iterations; ++it) {
    const auto t0 = Clock::now();
    IterationStats st;
    st.iteration = it;
    st.separator_vertices = partition.separators.size();
    st.separator_dimension = partition.separator_offsets.back();
    engine.linearize();
    st.time_eliminate = secondsSince(t0);
    const double before = cost.first;
    bool at_rounding = false;
    st.accepted = tryStep(engine, options, cost, lambda, scale, st, summary, at_rounding);
    st.chi2 = cost.first;
    st.bytes_communicated = engine.takeBytes();
    st.time = secondsSince(t0);
    st.elapsed = secondsSince(start);
    summary.bytes_communicated += st.bytes_communicated;
    summary.per_iteration.push_back(st);
    summary.iterations = it;
    if (options.callback) options.callback(st);
    if (!st.accepted) {
      summary.status = at_rounding               ? TerminationStatus::kConverged
                       : summary.message.empty() ? TerminationStatus::kNoProgress
                                                 : TerminationStatus::kNumericalFailure;
      if (at_rounding) summary.message = "no step lowers the objective beyond rounding";
      if (summary.message.empty()) summary.message = "no damped step lowered the objective";
      break;
    }
    summary.message.clear();
    if (before - cost.first < options.function_tolerance * before ||
        st.step_norm < options.step_tolerance || st.gradient_norm < options.gradient_tolerance) {
      summary.status = TerminationStatus::kConverged;
      break;
    }
    lambda /= 10;
    if (lambda < 1e-12 * scale) lambda = 0.0;
  }
  summary.final_cost = cost.first;
  summary.final_chi2 = cost.second;
  engine.linearize();
  summary.final_gradient_norm = engine.gradientNorm();
  summary.total_time = secondsSince(start);
  return summary;
}

GaugeFix::GaugeFix(Graph& graph, bool enabled) {
  if (!enabled) {
    const auto groups = checkConstraints(graph).unanchored;
    if (groups.empty()) return;
    throw Error("submaps: nothing anchors vertices " + formatIdRanges(groups.front(), 20) +
                " (no fixed vertex and no unary edge in their component): their gauge is "
                "free and the separator system singular; fix a vertex of each such component "
                "or let the solver fix the gauge (Options::fix_gauge)");
  }
  if (Vertex* v = fixGaugeIfFree(graph)) fixed_.push_back(v);
  for (const auto& group : checkConstraints(graph).unanchored) {
    Vertex* anchor = nullptr;
    for (VertexId id : group) {
      Vertex* v = graph.vertex(id);
      if (v && betterGaugeAnchor(*v, anchor)) anchor = v;
    }
    if (anchor && !anchor->fixed()) {
      anchor->setFixed(true);
      fixed_.push_back(anchor);
    }
  }
}

GaugeFix::~GaugeFix() {
  for (Vertex* v : fixed_) v->setFixed(false);
}

std::vector<VertexId> GaugeFix::ids() const {
  std::vector<VertexId> ids;
  for (const Vertex* v : fixed_) ids.push_back(v->id());
  return ids;
}

}  // namespace graphslam::submap::detail
