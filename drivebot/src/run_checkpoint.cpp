// SPDX-License-Identifier: MIT
#include "run_checkpoint.h"

#include "graphslam/incremental/checkpoint_bytes.h"
#include "graphslam/support/error.h"

namespace graphslam::drivebot::detail {

namespace {

using incremental::ByteReader;
using incremental::ByteWriter;

constexpr char kRunMark[] = "DRIVEBOT-RUN-1";

void putVector(ByteWriter& w, const Eigen::Vector3d& v) { w.putDoubles(v.data(), 3); }

Eigen::Vector3d getVector(ByteReader& r) {
  const std::vector<double> v = r.getDoubles(3);
  return {v[0], v[1], v[2]};
}

void putRecord(ByteWriter& w, const StepRecord& s) {
  w.put<std::int64_t>(s.step);
  w.put(s.time);
  putVector(w, s.truth);
  w.put<std::int64_t>(s.waypoint_index);
  putVector(w, s.online);
  putVector(w, s.online_variance);
  w.put<std::uint8_t>(s.optimized ? 1 : 0);
  w.put(s.chi2);
  w.put(s.optimization_time);
  w.put(s.optimization_cpu_time);
  w.put<std::int64_t>(s.iterations);
  w.put<std::uint64_t>(s.vertices);
  w.put<std::uint64_t>(s.edges);
  w.put<std::uint64_t>(s.observations);
  w.put<std::uint8_t>(static_cast<std::uint8_t>((s.gps ? 1 : 0) | (s.compass ? 2 : 0)));
}

StepRecord getRecord(ByteReader& r) {
  StepRecord s;
  s.step = static_cast<long>(r.get<std::int64_t>());
  s.time = r.get<double>();
  s.truth = getVector(r);
  s.waypoint_index = static_cast<int>(r.get<std::int64_t>());
  s.online = getVector(r);
  s.online_variance = getVector(r);
  s.optimized = r.get<std::uint8_t>() != 0;
  s.chi2 = r.get<double>();
  s.optimization_time = r.get<double>();
  s.optimization_cpu_time = r.get<double>();
  s.iterations = static_cast<int>(r.get<std::int64_t>());
  s.vertices = r.get<std::uint64_t>();
  s.edges = r.get<std::uint64_t>();
  s.observations = r.get<std::uint64_t>();
  const auto sensors = r.get<std::uint8_t>();
  s.gps = (sensors & 1) != 0;
  s.compass = (sensors & 2) != 0;
  return s;
}

}  // namespace

void checkCheckpointOptions(const RunOptions& options) {
  const bool checkpoints = options.checkpoint_every > 0 || !options.resume_path.empty();
  if (options.checkpoint_every < 0 ||
      options.checkpoint_path.empty() != (options.checkpoint_every == 0)) {
    throw Error("DriveBot run: checkpoint_path and checkpoint_every (>= 1) go together");
  }
  if (checkpoints && options.types == nullptr) {
    throw Error("DriveBot run: checkpoints need the type registry (RunOptions::types)");
  }
  if (checkpoints && options.snapshot_loop_closure) {
    throw Error("DriveBot run: checkpoints do not hold the loop-closure snapshots yet");
  }
}

void saveRunCheckpoint(DriveBotSlamSystem& system, const RunOptions& options,
                       const RunResult& result) {
  ByteWriter w;
  w.putString(kRunMark);
  w.putString(options.settings);
  w.put<std::uint64_t>(result.steps.size());
  for (const StepRecord& s : result.steps) putRecord(w, s);
  w.put(result.total_optimization_time);
  w.put(result.total_optimization_cpu_time);
  w.put<std::int64_t>(result.optimizations);
  w.putString(options.on_checkpoint ? options.on_checkpoint() : std::string());
  system.saveCheckpoint(options.checkpoint_path, *options.types, w.bytes());
}

void resumeRun(Simulator& simulator, DriveBotSlamSystem& system, const RunOptions& options,
               RunResult& result) {
  const std::string note = system.loadCheckpoint(options.resume_path, *options.types);
  ByteReader r(note, options.resume_path);
  if (r.getString() != kRunMark) r.fail("not the checkpoint of a DriveBot run");
  if (r.getString() != options.settings) {
    r.fail("it was written by a run with other settings than this one's (" + options.settings +
           ")");
  }
  result.steps.resize(r.get<std::uint64_t>());
  for (StepRecord& s : result.steps) s = getRecord(r);
  result.total_optimization_time = r.get<double>();
  result.total_optimization_cpu_time = r.get<double>();
  result.optimizations = static_cast<int>(r.get<std::int64_t>());
  const std::string caller = r.getString();
  if (!r.done()) r.fail("bytes after the run's records (inconsistent file)");
  if (result.steps.empty()) r.fail("it holds no step");
  if (options.on_resume) options.on_resume(caller);
  const long last = result.steps.back().step;
  while (simulator.keepRunning() && simulator.stepCount() <= last) simulator.step();
  if (simulator.stepCount() != last + 1) {
    r.fail("its step " + std::to_string(last) + " is past the end of this run's drive");
  }
}

}  // namespace graphslam::drivebot::detail
