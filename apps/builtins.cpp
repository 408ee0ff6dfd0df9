// SPDX-License-Identifier: MIT
#include "builtins.h"

#include <sys/resource.h>

#include <csignal>
#include <cstdlib>
#include <iostream>
#include <memory>

#include "graphslam/solvers/process.h"
#include "graphslam/support/error.h"
#include "graphslam/support/large_array.h"
#include "graphslam/support/signal_cleanup.h"

namespace graphslam::apps {

void exitOutOfMemory(const std::string& command) {
  std::cout.flush();
  std::cerr << "graphslam " << command
            << ": out of memory: the work needs more memory than this process may use\n";
  std::cerr.flush();
  std::_Exit(1);
}

void oneBlasThreadUnlessSet() {
  if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr) (void)solvers::setBlasThreads(1);
}

void configureProcess() {
  // Under a file size limit (ulimit -f) a write past it fails with EFBIG, reported with the
  // file's name and the staged outputs removed, instead of SIGXFSZ ending the process.
  std::signal(SIGXFSZ, SIG_IGN);
  // SIGINT, SIGTERM and SIGHUP remove the temporary files of the outputs being written.
  support::removeTemporariesOnSignal();
  // Under an address-space limit (ulimit -v) OpenBLAS's worker threads, each reserving its
  // buffers, could fail to and then loop forever at shutdown after the output was written:
  // BLAS runs on one thread there (OPENBLAS_NUM_THREADS still decides when set).
  struct rlimit address_space {};
  if (::getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY) {
    oneBlasThreadUnlessSet();
  }
  solvers::installCholmodPrefaultingAllocator();
  solvers::serializeCholmodOpenMp();
  support::setLargeArrayRetention(support::LargeArrayRetention{});
}

}  // namespace graphslam::apps
