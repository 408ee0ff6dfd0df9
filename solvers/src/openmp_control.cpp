// SPDX-License-Identifier: MIT
#include "openmp_control.h"

#include <dlfcn.h>

#include <atomic>
#include <mutex>

namespace graphslam::solvers::detail {

namespace {

/// The OpenMP runtime's entry points, found in the running process (CHOLMOD brings its
/// own libgomp); null when none is loaded, and then there is nothing to serialise.
struct OpenMpApi {
  int (*get_levels)() = nullptr;
  void (*set_levels)(int) = nullptr;
  OpenMpApi() {
    get_levels = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
    set_levels = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"));
    if (!get_levels || !set_levels) get_levels = nullptr, set_levels = nullptr;
  }
};

const OpenMpApi& api() {
  static const OpenMpApi instance;
  return instance;
}

std::atomic<bool> g_enabled{false};
std::mutex g_mutex;
int g_depth = 0;
int g_saved = 0;

}  // namespace

void SerialOpenMp::enable(bool on) { g_enabled.store(on); }

bool SerialOpenMp::enabled() { return g_enabled.load(); }

SerialOpenMp::SerialOpenMp() {
  if (!g_enabled.load() || !api().set_levels) return;
  active_ = true;
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (g_depth++ == 0) {
    g_saved = api().get_levels();
    api().set_levels(0);
  }
}

SerialOpenMp::~SerialOpenMp() {
  if (!active_) return;
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (--g_depth == 0) api().set_levels(g_saved);
}

}  // namespace graphslam::solvers::detail
