// SPDX-License-Identifier: MIT
#include "graphslam/drivebot/run.h"

#include <time.h>

#include <chrono>
#include <cmath>

#include "run_checkpoint.h"

namespace graphslam::drivebot {

namespace {

/// CPU time of the calling thread [s].
double threadCpuSeconds() {
  timespec ts{};
  if (::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return std::nan("");
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

bool failed(const Summary& s) {
  return s.status == TerminationStatus::kNumericalFailure ||
         s.status == TerminationStatus::kUnderDetermined;
}

MapSnapshot snapshot(DriveBotSlamSystem& system, long step, double time, double chi2) {
  MapSnapshot m;
  m.step = step;
  m.time = time;
  m.chi2 = chi2;
  m.vehicle = system.currentVehicleEstimate();
  m.marginals = system.landmarkEstimates(m.landmarks);
  (void)system.currentVehicleCovariance(m.vehicle_covariance);
  (void)system.vehicleHistory(m.vehicle_history);
  return m;
}

}  // namespace

RunResult runDriveBot(Simulator& simulator, DriveBotSlamSystem& system, const RunOptions& options) {
  using Clock = std::chrono::steady_clock;
  detail::checkCheckpointOptions(options);
  RunResult result;
  result.optimizer = system.usesIncremental() ? "incremental" : "batch";
  if (!options.resume_path.empty()) detail::resumeRun(simulator, system, options, result);
  long last_checkpoint = result.steps.empty() ? 0 : result.steps.back().step;
  auto stop = [&](long step, const Summary& s) {
    result.failed = true;
    result.failed_step = step;
    result.failed_time = simulator.time();
    result.failure = s;
  };
  auto timed_optimize = [&](int iterations, StepRecord* record, bool batch = false) {
    const double cpu0 = threadCpuSeconds();
    const auto t0 = Clock::now();
    Summary s = batch ? system.optimizeBatch(iterations) : system.optimize(iterations);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const double cpu = threadCpuSeconds() - cpu0;
    // An incremental update leaves the chi2 to the caller: computed here, not timed.
    if (std::isnan(s.final_chi2)) s.final_chi2 = system.chi2();
    result.total_optimization_time += seconds;
    result.total_optimization_cpu_time += cpu;
    ++result.optimizations;
    if (record) {
      record->optimized = true;
      record->chi2 = s.final_chi2;
      record->optimization_time = seconds;
      record->optimization_cpu_time = cpu;
      record->iterations = s.iterations;
    }
    return s;
  };

  while (simulator.keepRunning()) {
    const std::vector<Event>& events = simulator.events();
    StepRecord rec;
    rec.step = simulator.stepCount();
    rec.time = simulator.time();
    rec.truth = simulator.truth().x;
    rec.waypoint_index = simulator.truth().waypoint_index;
    for (const Event& e : events) {
      rec.observations += e.observations.size();
      rec.gps = rec.gps || e.type == EventType::kGps;
      rec.compass = rec.compass || e.type == EventType::kCompass;
    }

    std::vector<int> closing;
    if (options.snapshot_loop_closure && !result.loop_closure) {
      closing = system.loopClosureLandmarks(events);
    }
    if (!closing.empty()) {
      LoopClosure lc;
      lc.step = rec.step;
      lc.landmark_ids = closing;
      const Summary before = timed_optimize(0, nullptr);
      if (failed(before)) {
        stop(rec.step, before);
        break;
      }
      lc.before = snapshot(system, rec.step - 1, system.currentTime(), before.final_chi2);
      system.processEvents(events);
      const Summary after = timed_optimize(0, &rec);
      if (failed(after)) {
        stop(rec.step, after);
        break;
      }
      lc.after = snapshot(system, rec.step, system.currentTime(), after.final_chi2);
      result.loop_closure = std::move(lc);
    } else {
      system.processEvents(events);
    }
    if (system.recommendOptimization()) {
      const Summary s = timed_optimize(0, &rec);
      result.final_summary = s;
      if (failed(s)) {
        stop(rec.step, s);
        break;
      }
    }
    rec.online = system.currentVehicleEstimate();
    if (options.online_covariance && rec.optimized) {
      Eigen::Matrix3d cov;
      if (system.currentVehicleCovariance(cov).ok()) rec.online_variance = cov.diagonal();
    }
    rec.vertices = system.graph().numVertices();
    rec.edges = system.graph().numEdges();
    result.steps.push_back(rec);
    if (options.progress) options.progress(result.steps.back());
    if (options.checkpoint_every > 0 && rec.optimized &&
        rec.step - last_checkpoint >= options.checkpoint_every) {
      detail::saveRunCheckpoint(system, options, result);
      last_checkpoint = rec.step;
    }
    simulator.step();
  }
  if (!result.failed && options.final_iterations > 0) {
    // The end-of-run optimisation is a batch one (from the online estimates): its summary
    // has the chi2 and iterations the outputs report.
    result.final_summary = timed_optimize(options.final_iterations, nullptr, true);
    if (failed(result.final_summary)) stop(simulator.stepCount(), result.final_summary);
  }
  result.statistics = system.statistics();
  result.constraints = system.constraints();
  if (!result.failed) {
    result.history_marginals = system.vehicleHistory(result.history);
    result.landmark_marginals = system.landmarkEstimates(result.landmarks);
  }
  return result;
}

}  // namespace graphslam::drivebot
