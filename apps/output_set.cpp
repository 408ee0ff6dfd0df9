// SPDX-License-Identifier: MIT
#include "output_set.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "cli_common.h"
#include "graphslam/support/error.h"

namespace graphslam::apps {

namespace fs = std::filesystem;

namespace {
/// The path in a form that compares equal for the same file (its folder resolved).
std::string canonical(const std::string& path) {
  std::error_code ec;
  // Absolute first: weakly_canonical leaves a relative path whose first element does not
  // exist relative, so "x.g2o" and "./x.g2o" would differ.
  const fs::path p = fs::weakly_canonical(fs::absolute(fs::path(path), ec), ec);
  return ec ? path : p.string();
}
/// The digits at the start of `s` as a process id, -1 when there are none; `rest` is what
/// follows them.
long leadingPid(std::string_view s, std::string_view& rest) {
  std::size_t n = 0;
  while (n < s.size() && n < 10 && s[n] >= '0' && s[n] <= '9') ++n;
  rest = s.substr(n);
  return n == 0 ? -1 : std::stol(std::string(s.substr(0, n)));
}

/// Whether `entry` is a temporary file that a killed run left for the output `name`:
/// ".graphslam-PID-NAME" (staged) or that with ".tmp.PID" appended (being written), or
/// "NAME.tmp.PID" (written in place), each of a process that no longer runs.
bool staleTemporary(const std::string& entry, const std::string& name) {
  const auto dead = [](long pid) {
    return pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
  };
  const auto tmpOfDead = [&](std::string_view s) {  // "" or ".tmp.PID" of a dead process
    if (s.empty()) return true;
    if (s.substr(0, 5) != ".tmp.") return false;
    std::string_view rest;
    return dead(leadingPid(s.substr(5), rest)) && rest.empty();
  };
  std::string_view s = entry;
  const std::string_view prefix = ".graphslam-";
  if (s.substr(0, prefix.size()) == prefix) {
    std::string_view rest;
    const long pid = leadingPid(s.substr(prefix.size()), rest);
    if (rest.substr(0, 1 + name.size()) != "-" + name || !dead(pid)) return false;
    return tmpOfDead(rest.substr(1 + name.size()));
  }
  return s.size() > name.size() && s.substr(0, name.size()) == name &&
         s.substr(name.size()).substr(0, 5) == ".tmp." && tmpOfDead(s.substr(name.size()));
}

/// Removes what a run that was killed (SIGKILL, power loss) while writing `path` left
/// beside it: its temporary files (or staging folders) never hold a finished output.
void removeStaleTemporaries(const fs::path& dir, const std::string& name) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    if (staleTemporary(entry, name)) stale.push_back(it->path());
  }
  for (const fs::path& p : stale) fs::remove_all(p, ec);
}

/// Moves the entries of folder `from` into folder `to`: files replace files of the same
/// name, a folder is merged into the folder of its name. Appends what could not be moved to
/// `failed`.
void moveEntries(const fs::path& from, const fs::path& to, std::string& failed) {
  std::error_code ec;
  std::vector<fs::path> entries;  // listed first: the folder changes as they move out
  for (fs::directory_iterator it(from, ec), end; !ec && it != end; it.increment(ec)) {
    entries.push_back(it->path());
  }
  for (const fs::path& entry : entries) {
    const fs::path target = to / entry.filename();
    std::error_code move_ec;
    if (fs::is_directory(entry) && fs::is_directory(target)) {
      moveEntries(entry, target, failed);
      continue;
    }
    fs::rename(entry, target, move_ec);
    if (move_ec) failed += (failed.empty() ? "" : ", ") + target.string();
  }
}

/// The end of an OutputFolder's staging folder's name (".graphslam-PID-staging"), and the
/// name of its not-written list in it.
constexpr const char* kStagingName = "staging";
constexpr const char* kNotWrittenName = ".not-written";

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
    removeStaleTemporaries(dir, name.string());
    staged_.push_back(
        (dir / (".graphslam-" + std::to_string(::getpid()) + "-" + name.string())).string());
    on_signal_.push_back(std::make_unique<support::TemporaryFile>(staged_.back()));
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

int OutputSet::writeAll(const std::function<int()>& write) {
  try {
    return write();
  } catch (const Error& e) {
    abort();
    std::string message = e.what();
    for (std::size_t k = 0; k < paths_.size(); ++k) {
      for (std::size_t at; (at = message.find(staged_[k])) != std::string::npos;) {
        message.replace(at, staged_[k].size(), paths_[k]);
      }
    }
    throw Error(message);
  }
}

void OutputSet::abort() {
  for (const std::string& s : staged_) std::remove(s.c_str());
}

OutputFolder::OutputFolder(std::string dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_)) {
    throw Error("cannot create the output directory '" + dir_ + "'" +
                (ec ? ": " + ec.message() : std::string(": a file of that name exists")));
  }
  if (::access(dir_.c_str(), W_OK) != 0) {
    throw Error("cannot write in the output directory '" + dir_ + "': " + std::strerror(errno));
  }
  removeStaleTemporaries(dir_, kStagingName);
  staged_ =
      (fs::path(dir_) / (".graphslam-" + std::to_string(::getpid()) + "-" + kStagingName)).string();
  fs::remove_all(staged_, ec);
  if (!fs::create_directory(staged_, ec)) {
    throw Error("cannot create a folder in the output directory '" + dir_ + "': " + ec.message());
  }
}

OutputFolder::~OutputFolder() {
  std::error_code ec;
  if (!done_) fs::remove_all(staged_, ec);
}

std::string OutputFolder::notWrittenList() const {
  return (fs::path(staged_) / kNotWrittenName).string();
}

void OutputFolder::commit() {
  std::error_code ec;
  std::vector<std::string> not_written;
  if (std::ifstream list(notWrittenList()); list) {
    for (std::string name; std::getline(list, name);) {
      if (!name.empty() && name.find('/') == std::string::npos) not_written.push_back(name);
    }
    list.close();
    fs::remove(notWrittenList(), ec);
  }
  std::string failed;
  moveEntries(staged_, dir_, failed);
  for (const std::string& name : not_written) fs::remove(fs::path(dir_) / name, ec);
  done_ = true;
  fs::remove_all(staged_, ec);
  if (!failed.empty()) throw Error("could not put the outputs in place: " + failed);
}

}  // namespace graphslam::apps
