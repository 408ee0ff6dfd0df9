// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace graphslam::apps {

/// The tool's process-wide settings, made once at start-up (the library makes none by
/// itself): SuiteSparse's allocations faulted in on two threads, CHOLMOD's OpenMP loops
/// serial, freed huge-page arrays kept for the next optimisation, SIGXFSZ ignored (a
/// write past a file size limit then fails with EFBIG and is reported), the temporaries of
/// outputs removed on SIGINT/SIGTERM/SIGHUP, and BLAS on one thread under an address-space
/// limit.
void configureProcess();

/// For the commands that run the incremental optimizer: BLAS on one thread unless
/// OPENBLAS_NUM_THREADS says otherwise. Its fronts are small for BLAS's threads: on two cores
/// they doubled the CPU time of sphere2500's replay and did not shorten it.
void oneBlasThreadUnlessSet();

/// Reports "graphslam COMMAND: out of memory ..." and ends the process with exit code 1
/// without the libraries' shutdown: after an allocation failure OpenBLAS's can wait forever
/// for a worker thread.
[[noreturn]] void exitOutOfMemory(const std::string& command);

}  // namespace graphslam::apps
