// SPDX-License-Identifier: MIT
#pragma once

#include <functional>
#include <string>

namespace graphslam::support {

/// Severity of a library log message.
enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3 };

/// Receives every library log message at or above the current threshold.
using LogSink = std::function<void(LogLevel, const std::string&)>;

/// Replaces the process-wide sink (the default writes warnings and errors to stderr).
/// Passing an empty function restores the default sink.
void setLogSink(LogSink sink);

/// Messages below `level` are dropped before they reach the sink (default kWarning).
void setLogLevel(LogLevel level);

/// Sends `message` to the sink when `level` passes the threshold. Library code never
/// writes to stdout/stderr directly.
void log(LogLevel level, const std::string& message);

/// "debug", "info", "warning", "error".
[[nodiscard]] const char* toString(LogLevel level);

}  // namespace graphslam::support
