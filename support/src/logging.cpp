// SPDX-License-Identifier: MIT
#include "graphslam/support/logging.h"

#include <cstdio>
#include <mutex>

namespace graphslam::support {

namespace {
struct LogState {
  std::mutex mutex;
  LogSink sink;
  LogLevel level = LogLevel::kWarning;
};
LogState& state() {
  static LogState s;
  return s;
}
}  // namespace

const char* toString(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug:
      return "debug";
    case LogLevel::kInfo:
      return "info";
    case LogLevel::kWarning:
      return "warning";
    case LogLevel::kError:
      return "error";
  }
  return "?";
}

void setLogSink(LogSink sink) {
  std::lock_guard<std::mutex> lock(state().mutex);
  state().sink = std::move(sink);
}

void setLogLevel(LogLevel level) {
  std::lock_guard<std::mutex> lock(state().mutex);
  state().level = level;
}

void log(LogLevel level, const std::string& message) {
  std::lock_guard<std::mutex> lock(state().mutex);
  if (static_cast<int>(level) < static_cast<int>(state().level)) return;
  if (state().sink) {
    state().sink(level, message);
  } else {
    std::fprintf(stderr, "graphslam %s: %s\n", toString(level), message.c_str());
  }
}

}  // namespace graphslam::support
