// SPDX-License-Identifier: MIT
#include "graphslam/support/signal_cleanup.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <mutex>

namespace graphslam::support {

namespace {

/// The registered paths: a slot's path is complete before `used` says so, and the handler
/// reads only slots marked used (async-signal-safe: no allocation, only unlink).
struct Slot {
  std::atomic<bool> used{false};
  char path[TemporaryFile::kMaxPathBytes];
};
Slot g_slots[TemporaryFile::kMaxTemporaries];
std::mutex g_register;  // registration from several threads

extern "C" void removeAndReraise(int sig) {
  for (Slot& s : g_slots) {
    if (s.used.load(std::memory_order_acquire)) ::unlink(s.path);
  }
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  ::sigaction(sig, &dfl, nullptr);
  ::raise(sig);
}

}  // namespace

void removeTemporariesOnSignal() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction old {};
      ::sigaction(sig, nullptr, &old);
      if (old.sa_handler == SIG_IGN) continue;  // e.g. nohup: stay ignored
      struct sigaction sa {};
      sa.sa_handler = removeAndReraise;
      sigemptyset(&sa.sa_mask);
      ::sigaction(sig, &sa, nullptr);
    }
  });
}

TemporaryFile::TemporaryFile(const std::string& path) {
  if (path.size() >= static_cast<std::size_t>(kMaxPathBytes)) return;
  std::lock_guard<std::mutex> lock(g_register);
  for (int k = 0; k < kMaxTemporaries; ++k) {
    if (g_slots[k].used.load(std::memory_order_relaxed)) continue;
    std::memcpy(g_slots[k].path, path.c_str(), path.size() + 1);
    g_slots[k].used.store(true, std::memory_order_release);
    slot_ = k;
    return;
  }
}

TemporaryFile::~TemporaryFile() {
  if (slot_ < 0) return;
  std::lock_guard<std::mutex> lock(g_register);
  g_slots[slot_].used.store(false, std::memory_order_release);
}

}  // namespace graphslam::support
