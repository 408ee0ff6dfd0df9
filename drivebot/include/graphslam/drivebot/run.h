// SPDX-License-Identifier: MIT
// Drives a DriveBot SLAM system with the simulator, step by step, and records what the
// coursework plots (the coursework's minislam.mainLoop).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "graphslam/drivebot/simulator.h"
#include "graphslam/drivebot/slam_system.h"
#include "graphslam/optimizer/marginals.h"
#include "graphslam/optimizer/optimizer.h"

namespace graphslam::drivebot {

/// One simulation step: the ground truth when its events were processed, and what the SLAM
/// system did with them.
struct StepRecord {
  long step = 0;  ///< simulator step (0: the start events)
  double time = 0.0;
  Eigen::Vector3d truth = Eigen::Vector3d::Zero();
  int waypoint_index = 0;
  /// Estimate of the newest vehicle vertex after this step (after its optimisation, if any).
  Eigen::Vector3d online = Eigen::Vector3d::Zero();
  /// Diagonal of its covariance (RunOptions::online_covariance; NaN otherwise).
  Eigen::Vector3d online_variance = Eigen::Vector3d::Constant(std::nan(""));
  bool optimized = false;
  double chi2 = std::nan("");
  double optimization_time = std::nan("");  ///< wall time of optimize() [s]
  /// CPU time of the calling thread in optimize() [s]: unlike the wall time it does not
  /// count the time the thread waited for a core on a busy machine.
  double optimization_cpu_time = std::nan("");
  int iterations = 0;
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t observations = 0;  ///< landmark observations in this step's events
  bool gps = false;              ///< this step's events include a GPS fix
  bool compass = false;          ///< this step's events include a compass reading
};

struct RunOptions {
  /// Iterations of the optimisation after the last step (the coursework's 20; 0: none).
  int final_iterations = 20;
  /// Also compute the marginal covariance of the newest vehicle vertex after every step
  /// that optimised (StepRecord::online_variance).
  bool online_covariance = false;
  /// At the first loop closure (SlamSystemOptions::loop_closure_gap), optimise and take the
  /// landmark covariances just before and just after the closing step's events.
  bool snapshot_loop_closure = false;
  /// Called after every step (progress output is the caller's business).
  std::function<void(const StepRecord&)> progress;

  /// Checkpoints (DriveBotSlamSystem::saveCheckpoint, with the run's records so far) are
  /// written to checkpoint_path at the first step that optimised once checkpoint_every
  /// steps have passed since the last one (0: none). Need `types`; not with
  /// snapshot_loop_closure.
  std::string checkpoint_path;
  long checkpoint_every = 0;
  /// Continue a run from this checkpoint (written by a run with the same scenario,
  /// simulator and system settings): the system is loaded from it, the simulator (which
  /// does not depend on the estimates; deterministic for its seed) is stepped forward to the
  /// step after it, and the records before it come from the file. The run then reaches the
  /// estimates of the run that wrote it, bit for bit. Needs `types`.
  std::string resume_path;
  const TypeRegistry* types = nullptr;
  /// Saved with every checkpoint and compared on resuming, which refuses a checkpoint
  /// written with other settings: whatever decides the run (the tool passes its settings).
  std::string settings;
  /// The caller's own state, saved with a checkpoint (what on_checkpoint returns) and given
  /// back on resuming (on_resume): the tool's --marginalised-out length.
  std::function<std::string()> on_checkpoint;
  std::function<void(const std::string&)> on_resume;
};

/// Estimates around a loop closure.
struct MapSnapshot {
  long step = 0;
  double time = 0.0;
  double chi2 = 0.0;
  Eigen::Vector3d vehicle = Eigen::Vector3d::Zero();
  Eigen::Matrix3d vehicle_covariance = Eigen::Matrix3d::Zero();
  std::vector<LandmarkEstimate> landmarks;
  MarginalSummary marginals;
  /// Every vehicle vertex's estimate and covariance diagonal at this moment.
  VehicleHistory vehicle_history;
};

struct LoopClosure {
  long step = 0;                  ///< the step whose events close the loop
  std::vector<int> landmark_ids;  ///< the landmarks seen again
  MapSnapshot before, after;
};

struct RunResult {
  /// The optimizer of the per-step optimisations: "incremental" or "batch"
  /// (DriveBotSlamSystem::usesIncremental()); the final optimisation is a batch one.
  std::string optimizer;
  std::vector<StepRecord> steps;
  /// Failure of an optimisation (the run stops there): step, and the summary's message.
  bool failed = false;
  long failed_step = -1;
  double failed_time = 0.0;
  Summary failure;
  /// The last optimisation (the end-of-run one when it ran).
  Summary final_summary;
  /// Smoothed history after the run: one entry per vehicle vertex, aligned with `steps`.
  VehicleHistory history;
  MarginalSummary history_marginals;
  std::vector<LandmarkEstimate> landmarks;
  MarginalSummary landmark_marginals;
  std::optional<LoopClosure> loop_closure;
  GraphStatistics statistics;
  /// The constraint check of the last optimisation: vertices without edges were not
  /// estimated (they keep their predictions).
  ConstraintReport constraints;
  double total_optimization_time = 0.0;      ///< wall time, sum over every optimize() call [s]
  double total_optimization_cpu_time = 0.0;  ///< the same as thread CPU time [s]
  int optimizations = 0;
};

/// Runs the simulator to its end: per step, the system processes the step's events, then
/// optimises if it recommends it, then the truth is recorded and the simulator steps. After
/// the loop: one more optimisation (final_iterations), the vehicle history with marginal
/// covariance diagonals and the landmark estimates with covariances. Stops at the first
/// optimisation that fails (RunResult::failed, the summary says why). Throws
/// graphslam::InputError for a checkpoint that cannot be resumed (RunOptions::resume_path).
[[nodiscard]] RunResult runDriveBot(Simulator& simulator, DriveBotSlamSystem& system,
                                    const RunOptions& options);

}  // namespace graphslam::drivebot
