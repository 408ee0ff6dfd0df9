// SPDX-License-Identifier: MIT
// `graphslam drivebot`'s long-run options: the fixed-lag window (window_output.h) and
// checkpoints of the run (drivebot::RunOptions::checkpoint_path, resume_path).
#pragma once

#include <boost/program_options.hpp>
#include <string>

#include "graphslam/drivebot/run.h"
#include "graphslam/drivebot/slam_system.h"
#include "window_output.h"

namespace graphslam::apps {

/// The options, bound before the run's setup exists.
struct DrivebotLongRun {
  incremental::WindowOptions window;
  std::string marginalised_out;
  std::string checkpoint;
  long checkpoint_every = 0;
  std::string resume;
};

/// --window, --window-slack, --window-seconds, --marginalised-out, --reinitialise-landmarks,
/// --keep-landmarks, --checkpoint, --checkpoint-every, --resume.
void addLongRunOptions(boost::program_options::options_description& desc, DrivebotLongRun& o);
/// Refuses (UsageError) what does not go together.
void checkLongRunOptions(const DrivebotLongRun& o, bool loop_closure_snapshot);

/// An option's value as the command line would give it (string, integer, double, bool as
/// on/off; empty for other types).
[[nodiscard]] std::string optionValueText(const boost::any& value);

/// The settings a checkpoint is resumed under: every option given that decides the run
/// ("--key value", in name order), without those that only say where outputs go.
[[nodiscard]] std::string runSettings(const boost::program_options::variables_map& vm);

/// The --marginalised-out file and the checkpoint options wired into the run: the file is
/// started anew, or cut back to the checkpoint's length on resuming.
void attachLongRun(const DrivebotLongRun& o, MarginalisedOut& marginalised,
                   drivebot::RunOptions& run, const TypeRegistry& types,
                   const std::string& settings);

/// What the fixed-lag window did, after the run.
void printWindowReport(const drivebot::DriveBotSlamSystem& system);

}  // namespace graphslam::apps
