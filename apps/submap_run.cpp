// SPDX-License-Identifier: MIT
#include "submap_run.h"

#include <cstdio>
#include <iostream>
#include <sstream>

#include "builtins.h"
#include "graphslam/solvers/process.h"
#include "graphslam/submap/submap_solver.h"

namespace graphslam::apps {
namespace {

std::string csvLine(const submap::IterationStats& s) {
  std::ostringstream o;
  o.precision(17);
  o << s.iteration << ',' << s.chi2 << ',' << s.step_norm << ',' << s.trials << ',' << s.trials
    << ',' << (s.accepted ? 1 : 0) << ',' << s.time_eliminate << ',' << 0.0 << ','
    << s.time_separator << ',' << s.time_back << ',' << s.elapsed << ",submaps,"
    << "gradient_norm=" << s.gradient_norm << ";lambda=" << s.lambda
    << ";separator_vertices=" << s.separator_vertices
    << ";separator_dimension=" << s.separator_dimension
    << ";separator_nonzeros=" << s.separator_nonzeros
    << ";separator_cg_iterations=" << s.separator_iterations;
  return o.str();
}

/// The submap summary in the optimizer's form (what the outputs and checks read).
Summary toOptimizerSummary(const submap::Summary& s) {
  Summary out;
  out.status = s.status;
  out.message = s.message;
  out.algorithm = Algorithm::kLevenbergMarquardt;
  out.linear_solver = "submaps";
  out.initial_chi2 = s.initial_chi2;
  out.final_chi2 = s.final_chi2;
  out.initial_cost = s.initial_cost;
  out.final_cost = s.final_cost;
  out.iterations = s.iterations;
  out.total_time = s.total_time;
  out.gauge_fixed = s.gauge_fixed;
  for (const auto& it : s.per_iteration) {
    IterationStats o;
    o.iteration = it.iteration;
    o.chi2 = it.chi2;
    o.step_norm = it.step_norm;
    o.trials = it.trials;
    o.accepted = it.accepted;
    // An undamped step's elimination factorised every interior and the separator system
    // of the undamped H: H was positive definite there.
    o.undamped = it.accepted && it.lambda == 0.0;
    o.elapsed = it.elapsed;
    out.per_iteration.push_back(o);
  }
  return out;
}

}  // namespace

Summary runSubmapSolver(Graph& graph, const SolverRegistry& solvers, int submaps,
                        const Optimizer::Options& options, bool quiet,
                        std::vector<std::string>& csv) {
  submap::Options so;
  // --solver names the separator system's solver: pcg its conjugate gradients in place
  // (no factor, no copy); auto: cholmod where the build has it, else Eigen's simplicial
  // LL^T (no registry).
  if (options.linear_solver == "pcg") {
    so.separator_method = submap::Options::SeparatorMethod::conjugate_gradients;
  } else if (options.linear_solver != "auto") {
    so.separator_solver = options.linear_solver;
    so.solvers = &solvers;
  } else if (solvers.contains(so.separator_solver)) {
    so.solvers = &solvers;
  }
  so.partition.num_submaps = submaps;
  so.max_iterations = options.max_iterations;
  so.function_tolerance = options.function_tolerance;
  so.step_tolerance = options.step_tolerance;
  so.threads = options.threads;
  // Each thread eliminates whole submaps: BLAS on one thread per call keeps the cores for
  // them instead of oversubscribing them (OPENBLAS_NUM_THREADS still decides when set).
  if (so.threads > 1) oneBlasThreadUnlessSet();
  solvers::retainFreedMemory();  // every submap's factor is made and freed once or twice a step
  so.fix_gauge = options.fix_gauge;
  so.callback = [&csv, quiet](const submap::IterationStats& s) {
    if (!quiet) {
      const std::string cg = s.separator_iterations > 0
                                 ? ", " + std::to_string(s.separator_iterations) + " CG iterations"
                                 : std::string();
      std::printf(
          "iter %3d  chi2 %.10g  gradient %.3e  step %.3e  lambda %.3e  separator %zu vertices "
          "(dimension %d%s)  time %.4f s%s\n",
          s.iteration, s.chi2, s.gradient_norm, s.step_norm, s.lambda, s.separator_vertices,
          s.separator_dimension, cg.c_str(), s.time, s.accepted ? "" : "  (rejected)");
      std::fflush(stdout);
    }
    csv.push_back(csvLine(s));
  };
  const submap::Summary summary = submap::SubmapSolver(graph, so).optimize();
  std::cout << summary.report() << "\n";
  return toOptimizerSummary(summary);
}

}  // namespace graphslam::apps
