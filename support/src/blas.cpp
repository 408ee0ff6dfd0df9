// SPDX-License-Identifier: MIT
#include "graphslam/support/blas.h"

#include <dlfcn.h>

#include <atomic>
#include <mutex>
#include <string>

#include "graphslam/support/error.h"

namespace graphslam::support::blas {

namespace {

// The libraries CMake found, by their run-time names (empty: none).
#ifdef GRAPHSLAM_LAPACK_LIBRARY
constexpr const char* kLapack = GRAPHSLAM_LAPACK_LIBRARY;
constexpr const char* kBlas = GRAPHSLAM_BLAS_LIBRARY;
#else
constexpr const char* kLapack = "";
constexpr const char* kBlas = "";
#endif

std::atomic<bool> g_loaded{false};

void* open(const char* name) {
  void* handle = dlopen(name, RTLD_NOW | RTLD_GLOBAL);
  if (!handle) {
    const char* why = dlerror();
    throw Error(std::string("cannot load the BLAS/LAPACK library ") + name + ": " +
                (why ? why : "unknown reason"));
  }
  return handle;
}

template <typename F>
void resolve(F& f, const char* symbol, void* lapack, void* blas) {
  void* p = dlsym(lapack, symbol);
  if (!p) p = dlsym(blas, symbol);
  if (!p) throw Error(std::string("the BLAS/LAPACK libraries lack ") + symbol);
  f = reinterpret_cast<F>(p);
}

Functions load() {
  if (!configured()) throw Error("graphslam was built without BLAS/LAPACK");
  // Kept loaded for the process's lifetime (the handles are never closed).
  void* lapack = open(kLapack);
  void* blas = open(kBlas);
  Functions f;
  resolve(f.dsyrk, "dsyrk_", lapack, blas);
  resolve(f.dpotrf, "dpotrf_", lapack, blas);
  resolve(f.dtrsm, "dtrsm_", lapack, blas);
  resolve(f.dtrsv, "dtrsv_", lapack, blas);
  resolve(f.dgemv, "dgemv_", lapack, blas);
  g_loaded.store(true);
  return f;
}

}  // namespace

bool configured() { return kLapack[0] != '\0' && kBlas[0] != '\0'; }

bool loaded() { return g_loaded.load(); }

const Functions& functions() {
  static const Functions f = load();  // thread-safe initialisation; retried after a throw
  return f;
}

}  // namespace graphslam::support::blas
