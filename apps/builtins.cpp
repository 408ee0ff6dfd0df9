// SPDX-License-Identifier: MIT
#include "builtins.h"

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
  solvers::installCholmodPrefaultingAllocator();
  solvers::serializeCholmodOpenMp();
  support::setLargeArrayRetention(support::LargeArrayRetention{});
}

}  // namespace graphslam::apps
