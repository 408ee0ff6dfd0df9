// SPDX-License-Identifier: MIT
// The process-wide settings of graphslam/solvers/process.h that the tests can observe.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include "graphslam/core/linear_solver.h"
#include "graphslam/solvers/process.h"
#include "graphslam/solvers/register.h"
#include "graphslam/support/blas.h"

namespace graphslam {
namespace {

TEST(Solvers_Process, SetBlasThreadsReachesOpenBlas) {
  // BLAS is loaded on first use: load it as a factorisation would.
  if (support::blas::configured()) (void)support::blas::functions();
  using GetThreads = int (*)();
  const auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  if (get == nullptr) {
    EXPECT_FALSE(solvers::setBlasThreads(1));
    GTEST_SKIP() << "the BLAS in this process (if any) is not OpenBLAS";
  }
  const int before = get();
  ASSERT_TRUE(solvers::setBlasThreads(1));
  EXPECT_EQ(get(), 1);
  ASSERT_TRUE(solvers::setBlasThreads(2));
  EXPECT_EQ(get(), 2);
  (void)solvers::setBlasThreads(before);
}

bool loadedInProcess(const char* library) {
  void* handle = dlopen(library, RTLD_NOW | RTLD_NOLOAD);
  if (handle) dlclose(handle);
  return handle != nullptr;
}

// CHOLMOD (and with it BLAS and LAPACK) is loaded by the first solver that needs it, not
// with the solvers library: registering and using the others leaves it out of the process.
TEST(Solvers_Process, SuiteSparseIsLoadedOnFirstUse) {
  if (!solvers::haveSuiteSparse()) GTEST_SKIP() << "built without SuiteSparse";
  if (loadedInProcess("libcholmod.so.3")) GTEST_SKIP() << "an earlier test of this process loaded it";
  SolverRegistry registry;
  solvers::registerSolvers(registry);
  (void)registry.create("block-llt");
  (void)registry.create("eigen-ldlt");
  EXPECT_FALSE(loadedInProcess("libcholmod.so.3"));
  (void)registry.create("cholmod");
  EXPECT_TRUE(loadedInProcess("libcholmod.so.3"));
  EXPECT_TRUE(loadedInProcess("libgraphslam_solvers_suitesparse.so"));
}

}  // namespace
}  // namespace graphslam
