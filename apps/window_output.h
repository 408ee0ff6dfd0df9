// SPDX-License-Identifier: MIT
// What the fixed-lag window and checkpoints need in the tool (incremental, drivebot): the
// --marginalised-out file and the window's options.
#pragma once

#include <boost/program_options.hpp>
#include <fstream>
#include <string>

#include "graphslam/core/graph.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/incremental/incremental_optimizer.h"
#include "graphslam/incremental/linear_prior_edge.h"

namespace graphslam::apps {

/// The --marginalised-out file: each marginalised vertex appended as a `.g2o` vertex line
/// (tag, id, estimate, line parameters) as it leaves the window. It is a stream, not an
/// output put in place at the end: a checkpoint records its length, and a resumed run cuts
/// it back to that length before appending, so that it ends as the uninterrupted run's.
class MarginalisedOut {
 public:
  /// Nothing is written when `path` is empty.
  MarginalisedOut(std::string path, const TypeRegistry& types);
  /// Sets the window's on_marginalised to append here.
  void attach(incremental::WindowOptions& window);
  /// Starts the file empty (a new run).
  void start();
  /// Flushes and returns the length to record in a checkpoint.
  [[nodiscard]] std::string note();
  /// Cuts the file back to the length in `note` and appends from there. Throws
  /// graphslam::InputError when the file is shorter (not the one the checkpoint saw).
  void resume(const std::string& note);

 private:
  void write(const Vertex& v);
  std::string path_;
  const TypeRegistry& types_;
  std::ofstream out_;
};

/// The fixed-lag window's options of the tool (incremental, drivebot), bound to `window`
/// and `marginalised_out`: --window N, --window-slack B, --window-seconds S,
/// --marginalised-out FILE, --reinitialise-landmarks, --keep-landmarks. `states` names the
/// window's states in the help ("poses", "vehicle states").
void addWindowOptions(boost::program_options::options_description& desc,
                      incremental::WindowOptions& window, std::string& marginalised_out,
                      const std::string& states);
/// Refuses (UsageError) a combination of them that means nothing.
void checkWindowOptions(const incremental::WindowOptions& window,
                        const std::string& marginalised_out);

}  // namespace graphslam::apps
