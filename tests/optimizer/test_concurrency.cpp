// SPDX-License-Identifier: MIT
// Optimizers share no hidden state: two of them in two threads compute what each computes
// alone, and using the solvers leaves the process's settings as they were.
//
// Under ThreadSanitizer (the build's `tsan` label runs these tests): configure a separate
// build directory with -DGRAPHSLAM_SANITIZE=thread, build only this suite and run it,
//   cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGRAPHSLAM_SANITIZE=thread
//   cmake --build build-tsan --target graphslam_core_tests
//   export OMP_NUM_THREADS=1 OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1
//   build-tsan/tests/graphslam_core_tests --gtest_filter='Core_Concurrency.*'
// (or `ctest --test-dir build-tsan -L tsan`, which sets these variables). OpenBLAS and
// OpenMP are not instrumented: their own worker threads would be reported as races inside
// those libraries, so they run on the calling thread (OMP_THREAD_LIMIT: CHOLMOD asks for
// its OpenMP threads by number, which OMP_NUM_THREADS does not override).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "graphslam/optimizer/optimizer.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/solvers/options.h"
#include "graphslam/solvers/process.h"
#include "graphslam/solvers/register.h"

#ifdef GRAPHSLAM_TEST_HAVE_CHOLMOD
#include <cholmod.h>
#endif

namespace graphslam {
namespace {

/// What an optimisation produced: every vertex's estimate, in id order, and its chi2.
struct Outcome {
  std::vector<double> estimates;
  double initial_chi2 = 0.0;
  double final_chi2 = 0.0;
  int iterations = 0;
  std::string solver;
};

/// A simulated SE(2) pose graph (deterministic for its seed), optimised with `solver`.
Outcome optimizeSimulated(std::uint32_t seed, const std::string& solver,
                          const SolverRegistry& registry) {
  simulation::ManhattanOptions o;
  o.num_poses = 3000;
  o.seed = seed;
  simulation::SimulatedGraph sim = simulation::simulateManhattan(o);
  Optimizer::Options options;
  options.linear_solver = solver;
  Optimizer optimizer(sim.graph, registry, options);
  const Summary summary = optimizer.optimize();
  EXPECT_TRUE(summary.succeeded()) << summary.message;
  Outcome out;
  out.initial_chi2 = summary.initial_chi2;
  out.final_chi2 = summary.final_chi2;
  out.iterations = summary.iterations;
  out.solver = summary.linear_solver;
  for (const auto& [id, vertex] : sim.graph.vertices()) {
    std::vector<double> data(static_cast<std::size_t>(vertex->estimateDataDimension()));
    vertex->getEstimateData(data.data());
    out.estimates.insert(out.estimates.end(), data.begin(), data.end());
  }
  return out;
}

void expectIdentical(const Outcome& serial, const Outcome& concurrent) {
  EXPECT_EQ(serial.solver, concurrent.solver);
  EXPECT_EQ(serial.iterations, concurrent.iterations);
  // Bit-identical: exact comparisons.
  EXPECT_EQ(serial.initial_chi2, concurrent.initial_chi2);
  EXPECT_EQ(serial.final_chi2, concurrent.final_chi2);
  ASSERT_EQ(serial.estimates.size(), concurrent.estimates.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < serial.estimates.size(); ++k) {
    differing += serial.estimates[k] != concurrent.estimates[k] ? 1 : 0;
  }
  EXPECT_EQ(differing, 0u);
}

/// The solvers, sharing one cache of block orderings whose threshold the 3000-pose graphs
/// pass: the two optimizers look up and replace its entries at the same time.
solvers::SolverOptions sharedCacheOptions() {
  solvers::SolverOptions options;
  solvers::OrderingCacheOptions cache;
  cache.min_blocks = 1000;
  options.ordering_cache = std::make_shared<solvers::OrderingCache>(cache);
  return options;
}

TEST(Optimizer_Concurrency, TwoOptimizersInTwoThreadsMatchSerialRuns) {
  SolverRegistry registry;
  solvers::registerSolvers(registry, sharedCacheOptions());
  // The default solver on one graph, CHOLMOD (METIS ordering) on the other when this build
  // has it.
  const std::string second = solvers::haveSuiteSparse() ? "cholmod:metis" : "block-llt:amd";
  const Outcome serial_a = optimizeSimulated(1, "auto", registry);
  const Outcome serial_b = optimizeSimulated(2, second, registry);
  Outcome concurrent_a, concurrent_b;
  std::thread a([&] { concurrent_a = optimizeSimulated(1, "auto", registry); });
  std::thread b([&] { concurrent_b = optimizeSimulated(2, second, registry); });
  a.join();
  b.join();
  SCOPED_TRACE(serial_a.solver + " / " + serial_b.solver);
  expectIdentical(serial_a, concurrent_a);
  expectIdentical(serial_b, concurrent_b);
  EXPECT_NE(serial_a.final_chi2, serial_b.final_chi2);  // two different problems
}

#ifdef GRAPHSLAM_TEST_HAVE_CHOLMOD
// The CHOLMOD solvers leave SuiteSparse's process-wide allocation hooks alone unless the
// application installed its own (installCholmodPrefaultingAllocator).
TEST(Optimizer_Concurrency, CholmodLeavesSuiteSparseAllocatorAlone) {
  if (solvers::cholmodPrefaultingAllocatorInstalled()) GTEST_SKIP() << "opt-in made";
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  const auto malloc_before = SuiteSparse_config.malloc_func;
  const auto calloc_before = SuiteSparse_config.calloc_func;
  const Outcome out = optimizeSimulated(3, "cholmod", registry);
  EXPECT_EQ(out.solver.rfind("cholmod", 0), 0u) << out.solver;
  EXPECT_EQ(SuiteSparse_config.malloc_func, malloc_before);
  EXPECT_EQ(SuiteSparse_config.calloc_func, calloc_before);
  EXPECT_TRUE(SuiteSparse_config.malloc_func == &std::malloc);
  EXPECT_TRUE(SuiteSparse_config.calloc_func == &std::calloc);
  EXPECT_FALSE(solvers::cholmodOpenMpSerialized());
}
#endif

}  // namespace
}  // namespace graphslam
