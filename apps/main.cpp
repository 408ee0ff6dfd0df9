// SPDX-License-Identifier: MIT
// The graphslam launcher: answers --help and --version itself and loads the tool's commands
// (libgraphslam_tool.so, with the library's modules behind it) only to run one, so that
// what a command does not need is never loaded. A static build links the commands in.
#include <dlfcn.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "commands.h"

#ifndef GRAPHSLAM_TOOL_LIBRARY
extern "C" int graphslam_tool_run(int argc, char** argv);
#endif

namespace {

constexpr int kExitBadInput = 2;
constexpr int kExitFailed = 1;

#ifdef GRAPHSLAM_TOOL_LIBRARY
/// The folder of the running executable ("" when it cannot be read).
std::string ownFolder() {
  char path[4096];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return {};
  path[n] = '\0';
  std::string s(path);
  return s.substr(0, s.find_last_of('/') + 1);
}

/// graphslam_tool_run from the commands library: beside the executable in the build tree,
/// in <libdir>/graphslam of an install tree.
using Run = int (*)(int, char**);
Run loadCommands(std::string& error) {
  const std::string folder = ownFolder();
  for (const std::string& candidate :
       {folder + GRAPHSLAM_TOOL_LIBRARY, folder + GRAPHSLAM_TOOL_LIBRARY_INSTALLED}) {
    if (::access(candidate.c_str(), F_OK) != 0) continue;
    void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      error = candidate + ": " + (why ? why : "unknown reason");
      return nullptr;
    }
    if (auto run = reinterpret_cast<Run>(dlsym(handle, "graphslam_tool_run"))) return run;
    error = candidate + ": no entry graphslam_tool_run";
    return nullptr;
  }
  error = "not found beside " + folder;
  return nullptr;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  using graphslam::apps::kMainUsage;
  if (argc < 2) {
    std::fputs(kMainUsage, stderr);
    return kExitBadInput;
  }
  const char* command = argv[1];
  if (!std::strcmp(command, "--help") || !std::strcmp(command, "-h") ||
      !std::strcmp(command, "help")) {
    std::fputs(kMainUsage, stdout);
    return 0;
  }
  if (!std::strcmp(command, "--version")) {
    std::printf("graphslam %s\n", GRAPHSLAM_VERSION);
    return 0;
  }
  if (!graphslam::apps::isCommand(command)) {
    std::fprintf(stderr, "graphslam: unknown command '%s'\n\n%s", command, kMainUsage);
    return kExitBadInput;
  }
#ifdef GRAPHSLAM_TOOL_LIBRARY
  std::string error;
  const auto run = loadCommands(error);
  if (!run) {
    std::fprintf(stderr, "graphslam: cannot load its commands (%s): reinstall or rebuild\n",
                 error.c_str());
    return kExitFailed;
  }
  return run(argc, argv);
#else
  return graphslam_tool_run(argc, argv);
#endif
}
