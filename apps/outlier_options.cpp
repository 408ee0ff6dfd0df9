// SPDX-License-Identifier: MIT
#include "outlier_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "graphslam/init/global_se2.h"
#include "graphslam/outliers/robust_init.h"
#include "graphslam/support/file_util.h"
#include "graphslam/support/logging.h"
#include "graphslam/types_slam2d/edge_se2.h"

namespace graphslam::apps {

void declareOutlierOptions(po::options_description& desc, OutlierCliOptions& o) {
  outliers::GncOptions& g = o.gnc;
  desc.add_options()(
      "reject-outliers",
      "reject wrong measurements by graduated non-convexity (truncated least squares; odometry "
      "and priors are known inliers, every other edge a candidate), then optimise the inliers; "
      "a global initialisation is then made robust too (--gnc-init)")(
      "outliers", po::value(&o.outliers_file),
      "with --reject-outliers: write one line per rejected edge here (its line in IN, its "
      "vertex ids, its chi2 at the end of the GNC)")(
      "inlier-probability", doubleValue(&g.inlier_probability, g.inlier_probability),
      "GNC: an edge's threshold is the chi-square quantile of its dimension at this probability")(
      "gnc-mu-step", doubleValue(&g.mu_step, g.mu_step),
      "GNC: factor the control parameter mu grows by per step")(
      "gnc-step-iterations",
      po::value(&g.optimizer_iterations_per_step)->default_value(g.optimizer_iterations_per_step),
      "GNC: optimizer iterations per step (warm-started)")(
      "gnc-initial-iterations",
      po::value(&g.initial_least_squares_iterations)
          ->default_value(g.initial_least_squares_iterations),
      "GNC: least-squares iterations over every edge before the first step (0: none)")(
      "gnc-max-steps", po::value(&g.max_iterations)->default_value(g.max_iterations),
      "GNC: at most this many steps")(
      "gnc-init", po::value(&o.init_choice)->default_value(o.init_choice),
      "GNC's start when the initialisation is global: robust (the global initialisation by "
      "graduated non-convexity over every edge, checked against the nonlinear GNC by the "
      "truncated-least-squares cost) or known-inliers (from the odometry and priors only)")(
      "gnc-no-verify", po::bool_switch(),
      "with --gnc-init robust: take the initialisation's rejection without the nonlinear "
      "GNC's (faster)");
}

void checkOutlierOptions(const po::variables_map& vm, OutlierCliOptions& o) {
  o.reject = vm.count("reject-outliers") != 0;
  if (o.init_choice != "robust" && o.init_choice != "known-inliers")
    throw UsageError("--gnc-init must be robust or known-inliers, not '" + o.init_choice + "'");
  o.robust_init = o.init_choice == "robust";
  o.gnc.verify = !vm["gnc-no-verify"].as<bool>();
  if (!o.outliers_file.empty() && !o.reject) throw UsageError("--outliers needs --reject-outliers");
  const outliers::GncOptions& g = o.gnc;
  if (!(g.inlier_probability > 0 && g.inlier_probability < 1))
    throw UsageError("--inlier-probability must be in (0, 1)");
  if (!(g.mu_step > 1 && std::isfinite(g.mu_step)))
    throw UsageError("--gnc-mu-step must be a finite number > 1");
  if (g.optimizer_iterations_per_step < 1)
    throw UsageError("--gnc-step-iterations must be at least 1");
  if (g.initial_least_squares_iterations < 0)
    throw UsageError("--gnc-initial-iterations must be at least 0");
  if (g.max_iterations < 1) throw UsageError("--gnc-max-steps must be at least 1");
}

void initializeFromKnownInliers(const LoadedInput& in, Graph& graph, std::string init,
                                const SolverRegistry& solvers, OutlierCliOptions& o) {
  if (init == "auto") init = in.keep_initial_guess ? "none" : "global";
  if (init != "global") {
    applyInitialGuess(in, graph, init, solvers);
    return;
  }
  if (o.robust_init) {  // rejectOutliersForOptimize places the graph
    o.global_start = true;
    return;
  }
  const auto known = o.gnc.is_known_inlier ? o.gnc.is_known_inlier : outliers::isOdometryOrUnary;
  const auto init_solver = solvers.create("auto");
  const auto r = init::initializeGlobal(graph, init_solver.get(), known);
  if (!r.message.empty()) {
    std::cout << "initialisation (known inliers only): " << r.message << "\n";
  } else {
    std::printf(
        "initialisation: global from the known inliers only (odometry and priors; the "
        "loop closures may be wrong), %zu poses and %zu landmarks placed in %.4f s\n",
        r.poses, r.landmarks, r.seconds);
    std::fflush(stdout);
  }
}

namespace {
void printGlobalStart(const outliers::GlobalStartReport& s) {
  std::printf(
      "initialisation: global with graduated non-convexity, %d weighted placements, %zu of "
      "%zu candidate edges at weight 0 (%.4f s)%s\n",
      s.init.steps, s.init.zero_weight, s.init.candidates, s.init.seconds,
      s.init.converged ? "" : "; weights not all decided: the nonlinear GNC goes on from there");
  if (s.cost_by_gnc >= 0.0) {
    std::printf(
        "truncated-least-squares cost: %.10g by the initialisation's rejection, %.10g by "
        "the nonlinear GNC's: the %s stands\n",
        s.cost_by_initialization, s.cost_by_gnc,
        s.chose_gnc ? "nonlinear GNC's" : "initialisation's");
  }
  std::fflush(stdout);
}
}  // namespace

bool rejectOutliersForOptimize(Graph& graph, const SolverRegistry& solvers,
                               const Optimizer::Options& optimizer, OutlierCliOptions& o,
                               bool quiet, outliers::GncResult& result) {
  o.gnc.optimizer = optimizer;
  o.gnc.optimizer.callback = nullptr;
  o.gnc.callback = [quiet](const outliers::GncIterationStats& s) {
    if (quiet) return;
    std::printf("gnc %3d  mu %.3e  cost %.10g  inliers %zu  undecided %zu  time %.4f s\n",
                s.iteration, s.mu, s.cost, s.inliers, s.undecided, s.elapsed);
    std::fflush(stdout);
  };
  // The optimizer's notes (the gauge it fixes) would repeat at every step.
  support::setLogLevel(support::LogLevel::kWarning);
  if (o.global_start) {
    const bool planar = std::any_of(graph.edges().begin(), graph.edges().end(), [](const auto& e) {
      return dynamic_cast<const types_slam2d::EdgeSE2*>(e.get()) != nullptr;
    });
    if (!planar) {
      throw UsageError(
          "--reject-outliers with --gnc-init robust (the default) places 2D pose graphs "
          "(EDGE_SE2) only, and this graph has none; --gnc-init known-inliers rejects on any "
          "graph, starting from the odometry");
    }
    const auto init_solver = solvers.create("auto");
    outliers::GlobalStartReport start;
    result = outliers::rejectFromGlobalStart(graph, solvers, init_solver.get(), o.gnc, &start);
    printGlobalStart(start);
  } else {
    result = outliers::runGnc(graph, solvers, o.gnc);
  }
  support::setLogLevel(support::LogLevel::kInfo);
  if (!result.ok) {
    std::cerr << "outlier rejection failed: " << result.message << "\n";
    return false;
  }
  const std::size_t removed = outliers::removeRejected(graph, result);
  std::printf(
      "outlier rejection (GNC, truncated least squares): %zu of %zu candidate edges rejected "
      "(%zu known inliers), %d steps%s, %d optimizer iterations, mu %.3g -> %.3g, %.4f s\n",
      removed, result.candidates, result.known_inliers, result.iterations,
      result.converged ? "" : " (weights not all decided: stopped at --gnc-max-steps)",
      result.optimizer_iterations, result.initial_mu, result.final_mu, result.seconds);
  std::printf("optimising the %zu remaining edges by least squares\n", graph.numEdges());
  std::fflush(stdout);
  return true;
}

void writeOutliersFile(const std::string& path, const outliers::GncResult& result,
                       const std::vector<std::size_t>& edge_lines, const std::string& shown) {
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "# line vertex_ids... chi2 (rejected edges; line in the input file, chi2 at the end "
           "of the GNC)\n";
    char chi2[32];
    for (const auto& x : result.rejected) {
      out << (x.index < edge_lines.size() ? edge_lines[x.index] : 0);
      for (VertexId id : x.vertex_ids) out << ' ' << id;
      std::snprintf(chi2, sizeof chi2, " %.6g\n", x.chi2);
      out << chi2;
    }
  });
  std::cout << "wrote " << (shown.empty() ? path : shown) << " (" << result.rejected.size()
            << " rejected edges)\n";
}

}  // namespace graphslam::apps
