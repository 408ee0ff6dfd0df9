// SPDX-License-Identifier: MIT
#include "graphslam/submap/submap_solver.h"

#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

#include "engine.h"
#include "separator_system.h"

namespace graphslam::submap {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Every submap in this process.
class LocalEngine final : public detail::Engine {
 public:
  LocalEngine(const Partition& partition, const Options& options)
      : partition_(partition),
        submaps_(partition, allIndices(partition), options.threads, options.keep_factorizations,
                 options.supernodal_interiors),
        separator_(partition, options),
        estimates_(partition) {}

  detail::Cost cost() override {
    detail::Cost sum{0.0, 0.0};
    for (const auto& c : submaps_.costs()) {
      sum.first += c.first;
      sum.second += c.second;
    }
    return sum;
  }
  void linearize() override { submaps_.linearize(); }

  detail::StepOutcome step(double lambda) override {
    detail::StepOutcome out;
    auto t = Clock::now();
    separator_.clear();
    double interior_squared = 0.0;
    submaps_.eliminate(lambda, [&](std::size_t k, detail::Contribution& c) {
      out.max_diagonal = std::max(out.max_diagonal, c.max_diagonal);
      interior_squared += c.interior_gradient_squared;
      if (!c.ok) {
        if (out.ok) out.message = c.message;
        out.ok = false;
        return;
      }
      separator_.add(static_cast<int>(k), c);
    });
    out.gradient_norm = std::sqrt(interior_squared + separator_.gradientSquared());
    out.time_eliminate = secondsSince(t);
    if (!out.ok) return out;
    t = Clock::now();
    Eigen::VectorXd dx_s;
    out.ok = separator_.solve(lambda, dx_s, out.message);
    out.separator_nonzeros = separator_.nonzeros();
    out.separator_iterations = separator_.iterations();
    out.time_separator = secondsSince(t);
    if (!out.ok) return out;
    t = Clock::now();
    double squared = dx_s.squaredNorm();
    if (!submaps_.backSubstituteAndApply(dx_s, lambda, squared, out.message)) {
      out.ok = false;
      return out;
    }
    estimates_.apply(dx_s);
    out.step_norm = std::sqrt(squared);
    out.time_back = secondsSince(t);
    return out;
  }

  void undo() override {
    submaps_.restore();
    estimates_.restore();
  }

  double gradientNorm() override {
    separator_.clear();
    double interior_squared = 0.0;
    const auto contributions = submaps_.gradients();
    for (std::size_t k = 0; k < contributions.size(); ++k) {
      interior_squared += contributions[k].interior_gradient_squared;
      detail::Contribution c = contributions[k];
      const auto n = c.gradient.size();
      c.schur.setZero(n, n);
      c.reduced.setZero(n);
      separator_.add(static_cast<int>(k), c);
    }
    return std::sqrt(interior_squared + separator_.gradientSquared());
  }

 private:
  static std::vector<int> allIndices(const Partition& p) {
    std::vector<int> all(p.submaps.size());
    std::iota(all.begin(), all.end(), 0);
    return all;
  }

  const Partition& partition_;
  detail::LocalSubmaps submaps_;
  detail::SeparatorSystem separator_;
  detail::SeparatorEstimates estimates_;
};

}  // namespace

std::string Summary::report() const {
  std::ostringstream out;
  out.precision(10);
  out << "termination: " << toString(status);
  if (!message.empty()) out << " (" << message << ")";
  out << "\npartition: " << partition << "\niterations: " << iterations
      << "\nchi2: " << initial_chi2 << " -> " << final_chi2;
  if (final_cost != final_chi2) out << "\nobjective: " << initial_cost << " -> " << final_cost;
  out << "\nfinal gradient norm: " << final_gradient_norm << "\ntime: " << total_time << " s";
  if (bytes_communicated > 0) out << "\ncommunicated: " << bytes_communicated << " bytes";
  return out.str();
}

SubmapSolver::SubmapSolver(Graph& graph, Options options)
    : graph_(graph), options_(std::move(options)) {}

Summary SubmapSolver::optimize() {
  const auto start = Clock::now();
  detail::GaugeFix gauge(graph_, options_.fix_gauge);
  const Partition partition = partitionGraph(graph_, options_.partition);
  LocalEngine engine(partition, options_);
  Summary summary = detail::runIterations(engine, partition, options_);
  summary.gauge_fixed = gauge.ids();
  summary.total_time = secondsSince(start);
  return summary;
}

}  // namespace graphslam::submap
