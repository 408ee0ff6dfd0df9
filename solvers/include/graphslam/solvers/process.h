// SPDX-License-Identifier: MIT
// Process-wide settings an application may opt into, typically once at start-up. The
// library never makes them by itself: without these calls, using the solvers changes
// nothing outside the objects the caller owns.
#pragma once

#include <cstddef>

namespace graphslam::solvers {

/// Tuning of installCholmodPrefaultingAllocator().
struct CholmodPrefaultOptions {
  /// SuiteSparse allocations of at least this many bytes are faulted in on two threads.
  /// First-touch page faults are most of the cost of CHOLMOD's first factorisation of a
  /// large factor; smaller allocations are not worth a thread.
  std::size_t min_bytes = std::size_t{32} << 20;
};

/// Points SuiteSparse's allocation hooks (SuiteSparse_config.malloc_func and calloc_func,
/// which every SuiteSparse user in the process shares) at functions that, for large
/// allocations, write to every page on two threads right away, so that the kernel's
/// page faults of a large factor run in parallel. Affects every user of SuiteSparse in
/// the process. Call it before any SuiteSparse work starts, not while another thread
/// runs some; later calls only change `options`. Since the hooks point into the solvers
/// library, this pins it in the process (it is not unloaded afterwards, even by a plugin
/// host that closes it). Does nothing in a build without SuiteSparse.
void installCholmodPrefaultingAllocator(const CholmodPrefaultOptions& options = {});

/// Whether installCholmodPrefaultingAllocator() was called in this process.
[[nodiscard]] bool cholmodPrefaultingAllocatorInstalled();

/// With `on`, the CHOLMOD solvers run their calls into CHOLMOD with the process's OpenMP
/// max-active-levels set to 0 (the first of concurrent calls saves the setting, the last
/// restores it): CHOLMOD's OpenMP loops then run serially. The packaged CHOLMOD
/// (SuiteSparse 5) asks for a fixed 4 OpenMP threads in every supernode's scatter loop,
/// whatever OMP_NUM_THREADS says, and its cholmod_common has no setting for it; on
/// machines with few cores their hand-offs make the supernodal factorisation slower than
/// serial (its BLAS calls keep their own threads). While such a call runs, OpenMP regions
/// of other threads of the process run serially too: an application opts in only when
/// that is acceptable. Without SuiteSparse, or without an OpenMP runtime loaded in the
/// process, it does nothing.
void serializeCholmodOpenMp(bool on = true);

/// Whether serializeCholmodOpenMp(true) is in effect.
[[nodiscard]] bool cholmodOpenMpSerialized();

/// Makes the C heap keep freed memory for reuse (glibc: no separate mappings for large
/// blocks, M_MMAP_MAX 0, and no trimming of the heap's top, M_TRIM_THRESHOLD at its
/// largest). For work that allocates and frees factors of similar sizes over and over (the
/// submap solver factorises every submap once or twice per step): the kernel then does not
/// fault fresh pages in for every factor. The process's resident memory stays at its peak
/// instead of shrinking when memory is freed. Does nothing with another C library.
void retainFreedMemory();

/// Sets the number of threads (at least 1) of the process's BLAS: OpenBLAS's
/// openblas_set_num_threads when it is loaded (which overrides OPENBLAS_NUM_THREADS for every
/// BLAS call of the process from then on); before the BLAS is loaded (graphslam loads it on
/// first use), OPENBLAS_NUM_THREADS for it to read when it loads. Returns false, changing
/// nothing, when the loaded BLAS has no such setting (the reference BLAS, ATLAS).
bool setBlasThreads(int threads);

}  // namespace graphslam::solvers
