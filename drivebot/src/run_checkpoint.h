// SPDX-License-Identifier: MIT
// Checkpoints of a DriveBot run (RunOptions::checkpoint_path, resume_path): the SLAM
// system's checkpoint with the run's settings, records and totals in its note.
#pragma once

#include "graphslam/drivebot/run.h"

namespace graphslam::drivebot::detail {

/// Throws graphslam::Error for checkpoint options that do not go together.
void checkCheckpointOptions(const RunOptions& options);
/// Writes RunOptions::checkpoint_path: the system, the settings, the records and totals of
/// `result` so far and the caller's on_checkpoint().
void saveRunCheckpoint(DriveBotSlamSystem& system, const RunOptions& options,
                       const RunResult& result);
/// Loads RunOptions::resume_path into `system` and `result` (records, totals), gives the
/// caller's state to on_resume, and steps `simulator` to the step after the last record.
/// Throws graphslam::InputError naming the file and what is wrong.
void resumeRun(Simulator& simulator, DriveBotSlamSystem& system, const RunOptions& options,
               RunResult& result);

}  // namespace graphslam::drivebot::detail
