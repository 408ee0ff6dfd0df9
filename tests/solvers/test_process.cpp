// SPDX-License-Identifier: MIT
// The process-wide settings of graphslam/solvers/process.h that the tests can observe.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include "graphslam/solvers/process.h"

namespace graphslam {
namespace {

TEST(Solvers_Process, SetBlasThreadsReachesOpenBlas) {
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

}  // namespace
}  // namespace graphslam
