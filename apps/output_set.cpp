// SPDX-License-Identifier: MIT
#include "output_set.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "cli_common.h"
#include "graphslam/core/error.h"

namespace graphslam::apps {

namespace fs = std::filesystem;

namespace {
/// The path in a form that compares equal for the same file (its folder resolved).
std::string canonical(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::path(path), ec);
  return ec ? path : p.string();
}
}  // namespace

OutputSet::OutputSet(std::vector<std::string> paths, const std::vector<std::string>& inputs) {
  paths.erase(std::remove(paths.begin(), paths.end(), std::string()), paths.end());
  std::vector<std::string> seen;
  for (const std::string& p : inputs) {
    if (!p.empty()) seen.push_back(canonical(p));
  }
  const std::size_t num_inputs = seen.size();
  for (const std::string& path : paths) {
    const std::string c = canonical(path);
    const auto it = std::find(seen.begin(), seen.end(), c);
    if (it != seen.end()) {
      throw UsageError(path + ": " +
                       (it - seen.begin() < static_cast<std::ptrdiff_t>(num_inputs)
                            ? "is an input of the command: refusing to overwrite it"
                            : "is named for two outputs"));
    }
    seen.push_back(c);
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw UsageError(path + ": is a folder, not a file name");
    const fs::path dir =
        fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
    if (!fs::is_directory(dir, ec)) {
      throw UsageError(path + ": the folder " + dir.string() + " does not exist");
    }
    if (::access(dir.c_str(), W_OK) != 0) {
      throw UsageError(path + ": cannot write in " + dir.string() + ": " + std::strerror(errno));
    }
    paths_.push_back(path);
    const fs::path name = fs::path(path).filename();
    staged_.push_back(
        (dir / (".graphslam-" + std::to_string(::getpid()) + "-" + name.string())).string());
  }
}

OutputSet::~OutputSet() {
  if (!done_) abort();
}

std::string OutputSet::staged(const std::string& path) const {
  const auto it = std::find(paths_.begin(), paths_.end(), path);
  if (it == paths_.end()) throw Error("internal: output " + path + " was not declared");
  return staged_[static_cast<std::size_t>(it - paths_.begin())];
}

void OutputSet::commit() {
  std::string failed;
  for (std::size_t k = 0; k < paths_.size(); ++k) {
    std::error_code ec;
    if (!fs::exists(staged_[k], ec)) continue;  // not written (an optional output)
    fs::rename(staged_[k], paths_[k], ec);
    if (ec) failed += (failed.empty() ? "" : ", ") + paths_[k] + " (" + ec.message() + ")";
  }
  done_ = true;
  if (!failed.empty()) {
    abort();
    throw Error("could not put the outputs in place: " + failed);
  }
}

void OutputSet::abort() {
  for (const std::string& s : staged_) std::remove(s.c_str());
}

}  // namespace graphslam::apps
