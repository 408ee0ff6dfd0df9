// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "graphslam/support/signal_cleanup.h"

using namespace graphslam;

namespace {

/// In a child process: registers `registered` (and not `kept`), creates both, raises `sig`.
/// Returns the child's wait status.
int interruptedChild(const std::string& registered, const std::string& kept, int sig) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    support::removeTemporariesOnSignal();
    const support::TemporaryFile guard(registered);
    std::ofstream(registered) << "partial output";
    std::ofstream(kept) << "finished output";
    ::raise(sig);
    ::_exit(0);  // not reached: the signal ends the process
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

}  // namespace

TEST(Support_SignalCleanup, InterruptedWritesLeaveNoTemporaryFiles) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("graphslam-signal-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    const std::string tmp = (dir / ".graphslam-tmp").string();
    const std::string kept = (dir / "kept").string();
    const int status = interruptedChild(tmp, kept, sig);
    // The process still ends by the signal (its parent sees why), without the staged file.
    ASSERT_TRUE(WIFSIGNALED(status)) << sig;
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_FALSE(std::filesystem::exists(tmp)) << sig;
    EXPECT_TRUE(std::filesystem::exists(kept)) << sig;
  }
  std::filesystem::remove_all(dir);
}

TEST(Support_SignalCleanup, AGuardGoneLeavesTheFileAlone) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("graphslam-signal-done-" + std::to_string(::getpid()));
  const pid_t pid = ::fork();
  if (pid == 0) {
    support::removeTemporariesOnSignal();
    { const support::TemporaryFile guard(path.string()); }
    std::ofstream(path) << "renamed into place";
    ::raise(SIGTERM);
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status));
  EXPECT_TRUE(std::filesystem::exists(path));
  std::filesystem::remove(path);
}
