// SPDX-License-Identifier: MIT
#include "plotting.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "graphslam/core/error.h"

namespace graphslam::apps {

namespace {

/// Runs argv without a shell; returns the exit status (-1 if it could not start).
int run(const std::vector<std::string>& argv, bool quiet) {
  std::fflush(nullptr);  // the child must not inherit (and re-emit) buffered output
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    if (quiet) {
      std::freopen("/dev/null", "w", stdout);
      std::freopen("/dev/null", "w", stderr);
    }
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));  // execvp's API
    args.push_back(nullptr);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  if (::waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string plotDir() {
  if (const char* env = std::getenv("GRAPHSLAM_PLOT_DIR"); env && *env) return env;
  return GRAPHSLAM_PLOT_DIR;
}

}  // namespace

std::string findPlotPython() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("GRAPHSLAM_PYTHON"); env && *env) candidates.emplace_back(env);
  candidates.emplace_back("/usr/bin/python3");
  candidates.emplace_back("python3");
  for (const auto& py : candidates) {
    if (run({py, "-c", "import matplotlib"}, true) == 0) return py;
  }
  return {};
}

void runPlotScript(const std::string& script, const std::vector<std::string>& args) {
  const std::string python = findPlotPython();
  if (python.empty()) {
    throw Error(
        "plotting needs Python 3 with matplotlib, and none was found (tried $GRAPHSLAM_PYTHON, "
        "/usr/bin/python3, python3): install it with 'apt-get install python3-matplotlib'");
  }
  std::vector<std::string> argv{python, plotDir() + "/" + script};
  argv.insert(argv.end(), args.begin(), args.end());
  const int rc = run(argv, false);
  if (rc != 0) throw Error("plot script " + script + " failed (exit " + std::to_string(rc) + ")");
}

}  // namespace graphslam::apps
