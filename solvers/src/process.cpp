// SPDX-License-Identifier: MIT
// The process-wide opt-ins of graphslam/solvers/process.h.
#include "graphslam/solvers/process.h"

#include <dlfcn.h>

#include <atomic>
#include <climits>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#ifdef GRAPHSLAM_HAVE_CHOLMOD
#include <SuiteSparse_config.h>

#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>

#include "graphslam/support/blas.h"
#include "openmp_control.h"
#endif

namespace graphslam::solvers {

#ifdef GRAPHSLAM_HAVE_CHOLMOD

namespace {

std::atomic<std::size_t> g_prefault_bytes{CholmodPrefaultOptions{}.min_bytes};
std::atomic<bool> g_prefault_installed{false};

/// Writes a zero into every page of [p, p + size) (the memory of a fresh allocation:
/// malloc's is undefined, calloc's is zero already), half of them on a second thread.
void prefault(void* p, std::size_t size) {
  constexpr std::size_t kPage = 4096;
  auto touch = [p](std::size_t from, std::size_t to) {
    volatile char* c = static_cast<char*>(p);
    for (std::size_t i = from; i < to; i += kPage) c[i] = 0;
  };
  const std::size_t half = (size / 2) / kPage * kPage;
  std::thread second(touch, half, size);
  touch(0, half);
  second.join();
}

void* prefaultingMalloc(std::size_t size) {
  void* p = std::malloc(size);
  if (p && size >= g_prefault_bytes.load(std::memory_order_relaxed)) prefault(p, size);
  return p;
}

void* prefaultingCalloc(std::size_t count, std::size_t size) {
  void* p = std::calloc(count, size);
  if (p && count * size >= g_prefault_bytes.load(std::memory_order_relaxed)) {
    prefault(p, count * size);
  }
  return p;
}

/// Marks this library as never to be unloaded: SuiteSparse's hooks now point into it.
/// The handle is kept on purpose (dlopen of a loaded object only adds the flag).
void pinThisLibrary() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&prefaultingMalloc), &info) && info.dli_fname) {
    (void)dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
  }
}

}  // namespace

void installCholmodPrefaultingAllocator(const CholmodPrefaultOptions& options) {
  g_prefault_bytes.store(options.min_bytes, std::memory_order_relaxed);
  static std::once_flag once;
  std::call_once(once, [] {
    pinThisLibrary();
    SuiteSparse_config.malloc_func = prefaultingMalloc;
    SuiteSparse_config.calloc_func = prefaultingCalloc;
    g_prefault_installed.store(true);
  });
}

bool cholmodPrefaultingAllocatorInstalled() { return g_prefault_installed.load(); }

void serializeCholmodOpenMp(bool on) { detail::SerialOpenMp::enable(on); }

bool cholmodOpenMpSerialized() { return detail::SerialOpenMp::enabled(); }

#else

void installCholmodPrefaultingAllocator(const CholmodPrefaultOptions& /*options*/) {}
bool cholmodPrefaultingAllocatorInstalled() { return false; }
void serializeCholmodOpenMp(bool /*on*/) {}
bool cholmodOpenMpSerialized() { return false; }

#endif

void retainFreedMemory() {
#ifdef __GLIBC__
  (void)mallopt(M_MMAP_MAX, 0);
  (void)mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
}

bool setBlasThreads(int threads) {
  using SetThreads = void (*)(int);
  const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set != nullptr) {
    set(threads);
    return true;
  }
  // Not loaded yet (the library loads BLAS on first use): OpenBLAS reads its thread count
  // from the environment when it loads.
  if (support::blas::loaded()) return false;  // loaded, and not OpenBLAS
  return ::setenv("OPENBLAS_NUM_THREADS", std::to_string(threads).c_str(), 1) == 0;
}

}  // namespace graphslam::solvers
