// SPDX-License-Identifier: MIT
// All or nothing for a command's output files: checked before the work starts, written to
// temporary files beside them, renamed into place together at the end.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "graphslam/support/signal_cleanup.h"

namespace graphslam::apps {

class OutputSet {
 public:
  /// Checks `paths` (empty entries skipped) before any work: each one's folder exists and
  /// is writable, no path is an existing folder, none is one of `inputs`, none appears
  /// twice. Throws UsageError naming the path and the reason. Removes the temporary files
  /// of these outputs that a killed run (no longer running) left in their folders.
  OutputSet(std::vector<std::string> paths, const std::vector<std::string>& inputs);
  /// Removes the temporary files of an unfinished set.
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  /// Where to write `path` now: a temporary file in its folder that keeps its name's end
  /// (a plot's extension still selects its format). `path` must be one of the set's.
  [[nodiscard]] std::string staged(const std::string& path) const;
  /// Renames every staged file that was written into place. If a rename fails, the ones
  /// done are left and the error names the rest.
  void commit();
  /// Removes every temporary file (for a failure path that ends the process without
  /// running destructors).
  void abort();
  /// Runs `write` (which writes the staged files and commits); a graphslam::Error it throws
  /// removes the staged files and is thrown again naming each output by its own path, not
  /// its staging file's.
  int writeAll(const std::function<int()>& write);

 private:
  std::vector<std::string> paths_;
  std::vector<std::string> staged_;
  /// The staged files, removed on SIGINT/SIGTERM/SIGHUP (support/signal_cleanup.h).
  std::vector<std::unique_ptr<support::TemporaryFile>> on_signal_;
  bool done_ = false;
};

/// All or nothing for a command whose outputs are the files it writes into one folder (the
/// folder is created; files of other names in it are left alone): they are written into a
/// hidden staging folder inside it and moved into it together at the end.
class OutputFolder {
 public:
  /// Creates `dir` (and its parents) and the staging folder in it, and removes the staging
  /// folders that killed runs (no longer running) left. Throws Error naming the folder.
  explicit OutputFolder(std::string dir);
  /// Removes the staging folder of an unfinished run.
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// The staging folder: where the outputs are written now.
  [[nodiscard]] const std::string& staged() const { return staged_; }
  /// The list file in the staging folder where the writers name outputs this run did not
  /// make (a plot with nothing to draw), one file name per line: commit() removes files of
  /// those names that an earlier run left in the folder.
  [[nodiscard]] std::string notWrittenList() const;
  /// Moves every file of the staging folder into the folder (replacing files of the same
  /// names), removes the files its not-written list names, then the staging folder.
  void commit();

 private:
  std::string dir_;
  std::string staged_;
  bool done_ = false;
};

}  // namespace graphslam::apps
