// SPDX-License-Identifier: MIT
// The factorisation limit of a dataset: how long one bare CHOLMOD numeric factorisation of
// the final H takes, compared with the optimizer's factorisation per attempt and its time
// per iteration. A benchmark program, not library code: it includes cholmod.h directly
// (the library keeps SuiteSparse inside solvers/src).
#include <cholmod.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

#include "bench_common.h"
#include "graphslam/optimizer/linear_system.h"
#include "graphslam/optimizer/optimizer.h"
#include "graphslam/solvers/ordering.h"

using namespace graphslam;

namespace {

constexpr const char* kUsage =
    "usage: graphslam_factor_limit FILE.g2o [--repeats N] [--solvers A,B,...]\n"
    "                              [--kinds supernodal,simplicial]\n"
    "Loads FILE, applies the tool's global initialisation, optimises with the default options\n"
    "once per solver in --solvers (default: the optimizer's default solver and cholmod), each\n"
    "from the same initial estimates, then builds H at the optimum (LinearSystem) and times\n"
    "cholmod_factorize alone (supernodal and simplicial LL^T, each after cholmod_analyze_p with\n"
    "the ordering of the default solver: block AMD, or block METIS where it predicts fewer\n"
    "flops), median of --repeats (default 9); the limit\n"
    "(factorize_s) is the faster of the two. --kinds times only those named (the simplicial\n"
    "factorisation of a million-pose graph takes minutes; a kind not timed prints -1).\n"
    "Prints key=value lines.\n"
    "Exit 77 when FILE does not exist.";

struct BareFactorisation {
  double analyze_s = 0.0;
  double factorize_s = 0.0;  ///< median
  double factorize_min_s = 0.0;
  double factor_nnz = 0.0;
  double flops = 0.0;
};

/// cholmod_analyze_p with `perm`, then `repeats` timed cholmod_factorize calls, with the
/// Common settings of the library's "cholmod" / "cholmod-simplicial" solvers
/// (solvers/src/cholmod_solver.cpp).
BareFactorisation timeCholmod(const SparseStructure& s, const support::LargeVector<double>& values,
                              const std::vector<int>& perm, bool supernodal, int repeats) {
  cholmod_common c;
  cholmod_start(&c);
  c.supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  c.final_ll = 1;
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_GIVEN;
  c.postorder = 1;
  c.print = 0;
  c.zrelax[0] = 0.2;  // the library's amalgamation of block systems (cholmod_solver.cpp)
  c.zrelax[1] = 0.05;
  c.zrelax[2] = 0.02;
  cholmod_sparse a{};
  a.nrow = a.ncol = static_cast<size_t>(s.n);
  a.nzmax = s.nnz();
  a.p = const_cast<int*>(s.col_ptr);
  a.i = const_cast<int*>(s.row_idx);
  a.x = const_cast<double*>(values.data());
  a.stype = 1;
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_REAL;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  BareFactorisation r;
  auto start = bench::Clock::now();
  std::vector<int> p = perm;
  cholmod_factor* f = cholmod_analyze_p(&a, p.data(), nullptr, 0, &c);
  r.analyze_s = bench::secondsSince(start);
  if (!f || c.status < CHOLMOD_OK) throw std::runtime_error("cholmod_analyze_p failed");
  std::vector<double> times;
  for (int k = 0; k < repeats; ++k) {
    start = bench::Clock::now();
    const int ok = cholmod_factorize(&a, f, &c);
    times.push_back(bench::secondsSince(start));
    if (!ok || c.status != CHOLMOD_OK) throw std::runtime_error("cholmod_factorize failed");
  }
  r.factorize_s = bench::median(times);
  r.factorize_min_s = *std::min_element(times.begin(), times.end());
  r.factor_nnz = c.lnz;
  r.flops = c.fl;
  cholmod_free_factor(&f, &c);
  cholmod_finish(&c);
  return r;
}

std::vector<std::string> splitComma(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  bench::Args args(argc, argv, kUsage);
  const int repeats = args.integer("repeats", 9, 1);
  const auto solver_names =
      splitComma(args.text("solvers", Optimizer::Options{}.linear_solver + ",cholmod"));
  bool time_supernodal = false;
  bool time_simplicial = false;
  for (const auto& kind : splitComma(args.text("kinds", "supernodal,simplicial"))) {
    if (kind == "supernodal") {
      time_supernodal = true;
    } else if (kind == "simplicial") {
      time_simplicial = true;
    } else {
      args.fail("--kinds: unknown kind '" + kind + "' (supernodal, simplicial)");
    }
  }
  args.finish();
  args.skipIfAbsent();
  std::printf("openmp=%s\n", bench::serialiseOpenMp());
  const bench::Registries registries;
  const TypeRegistry& types = registries.types;
  const SolverRegistry& solvers = registries.solvers;
  return bench::guardedMain([&]() -> int {
    for (const auto& name : solver_names) {
      if (!solvers.contains(name)) throw bench::BadInput("unknown solver '" + name + "'");
    }
    io::LoadResult loaded = bench::loadInitialised(args.file(), types);
    Graph& graph = loaded.graph;
    const auto initial = bench::saveEstimates(graph);
    std::printf("file=%s\n", args.file().c_str());

    // The optimizer with default options, once per solver, from the same start; the last
    // run leaves the graph at its optimum.
    for (const auto& name : solver_names) {
      bench::restoreEstimates(graph, initial);
      Optimizer::Options options;
      options.linear_solver = name;
      Optimizer optimizer(graph, solvers, options);
      const Summary s = optimizer.optimize();
      int attempts = 0;
      for (const auto& it : s.per_iteration) attempts += it.factorizations;
      const double per_iteration = s.iterations ? s.time.total() / s.iterations : 0.0;
      const double per_factorisation = attempts ? s.time.factorize / attempts : 0.0;
      std::printf(
          "optimizer.%s status=%s iterations=%d attempts=%d chi2=%.17g total_s=%.6g "
          "iteration_s=%.6g factorize_per_attempt_s=%.6g dimension=%d nnz_h=%zu nnz_l=%zu\n",
          name.c_str(), toString(s.status), s.iterations, attempts, s.final_chi2, s.total_time,
          per_iteration, per_factorisation, s.system_dimension, s.hessian_nonzeros,
          s.factor_nonzeros);
      if (!s.succeeded() && s.status != TerminationStatus::kNoProgress) {
        std::fprintf(stderr, "optimisation with %s failed: %s\n", name.c_str(), s.message.c_str());
        return 1;
      }
    }

    // H at the optimum, with the optimizer's gauge rule.
    Vertex* gauge = fixGaugeIfFree(graph);
    LinearSystem system;
    (void)system.update(graph);
    (void)graph.chi2();  // current errors, as LinearSystem::linearize() expects
    system.linearize();
    system.assembleHessian();
    const SparseStructure h = system.hessianStructure();
    const auto order_start = bench::Clock::now();
    // The ordering the default solver uses (block AMD, or block METIS where it predicts
    // fewer flops).
    const solvers::ChosenOrdering chosen = solvers::chooseOrdering(h);
    const std::vector<int>& perm = chosen.perm;
    const double ordering_s = bench::secondsSince(order_start);
    const BareFactorisation none{-1.0, -1.0, -1.0, -1.0, -1.0};
    const BareFactorisation super =
        time_supernodal ? timeCholmod(h, system.hessianValues(), perm, true, repeats) : none;
    const BareFactorisation simple =
        time_simplicial ? timeCholmod(h, system.hessianValues(), perm, false, repeats) : none;
    if (gauge) gauge->setFixed(false);
    // The limit is the faster of CHOLMOD's numeric factorisations timed.
    const double limit = !time_simplicial   ? super.factorize_s
                         : !time_supernodal ? simple.factorize_s
                                            : std::min(super.factorize_s, simple.factorize_s);
    const BareFactorisation& counted = time_supernodal ? super : simple;
    std::printf(
        "limit n=%d nnz_h=%zu nnz_l=%.0f flops=%.6g ordering=%s ordering_s=%.6g repeats=%d "
        "factorize_s=%.6g "
        "supernodal_analyze_s=%.6g supernodal_s=%.6g supernodal_min_s=%.6g "
        "simplicial_analyze_s=%.6g simplicial_s=%.6g simplicial_min_s=%.6g\n",
        h.n, h.nnz(), counted.factor_nnz, counted.flops, toString(chosen.ordering), ordering_s,
        repeats, limit, super.analyze_s, super.factorize_s, super.factorize_min_s, simple.analyze_s,
        simple.factorize_s, simple.factorize_min_s);
    return 0;
  });
}
