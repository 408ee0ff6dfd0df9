// SPDX-License-Identifier: MIT
// Temporary files removed when the process is interrupted: a tool writing its outputs to
// temporary files (renamed into place at the end) registers them here, and SIGINT, SIGTERM
// or SIGHUP removes them before the process ends as the signal would have ended it.
#pragma once

#include <string>

namespace graphslam::support {

/// Installs the handlers of SIGINT, SIGTERM and SIGHUP (once; later calls do nothing). A
/// handler unlinks every registered file, then ends the process by the same signal.
void removeTemporariesOnSignal();

/// Registers `path` for removal on those signals while the guard lives (at most
/// kMaxTemporaries at once and paths shorter than kMaxPathBytes are registered; others are
/// still removed by the next run writing the same output, as after SIGKILL).
class TemporaryFile {
 public:
  static constexpr int kMaxTemporaries = 64;
  static constexpr int kMaxPathBytes = 4096;

  explicit TemporaryFile(const std::string& path);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

 private:
  int slot_ = -1;
};

}  // namespace graphslam::support
