// SPDX-License-Identifier: MIT
#include "drivebot_longrun.h"

#include <cstdio>

#include "cli_common.h"
#include "graphslam/support/file_util.h"

namespace graphslam::apps {

void addLongRunOptions(po::options_description& desc, DrivebotLongRun& o) {
  addWindowOptions(desc, o.window, o.marginalised_out, "vehicle states");
  desc.add_options()("checkpoint", po::value(&o.checkpoint),
                     "write the run's state here (atomically; with --checkpoint-every)")(
      "checkpoint-every", po::value(&o.checkpoint_every)->default_value(0),
      "write the checkpoint at the first optimised step once N steps have passed since the "
      "last")("resume", po::value(&o.resume),
              "continue from this checkpoint (written by a run with the same settings; "
              "the simulator is replayed to its step)");
}

void checkLongRunOptions(const DrivebotLongRun& o, bool loop_closure_snapshot) {
  checkWindowOptions(o.window, o.marginalised_out);
  if (o.checkpoint_every < 0 || o.checkpoint.empty() != (o.checkpoint_every == 0)) {
    throw UsageError("--checkpoint FILE and --checkpoint-every N (N >= 1) go together");
  }
  if (loop_closure_snapshot && (!o.checkpoint.empty() || !o.resume.empty())) {
    throw UsageError(
        "--checkpoint and --resume: not with --loop-closure (its snapshots are "
        "not held by checkpoints yet)");
  }
}

std::string optionValueText(const boost::any& v) {
  if (const auto* s = boost::any_cast<std::string>(&v)) return *s;
  if (const auto* i = boost::any_cast<int>(&v)) return std::to_string(*i);
  if (const auto* l = boost::any_cast<long>(&v)) return std::to_string(*l);
  if (const auto* u = boost::any_cast<std::uint64_t>(&v)) return std::to_string(*u);
  if (const auto* d = boost::any_cast<double>(&v)) return support::formatDouble(*d);
  if (const auto* b = boost::any_cast<bool>(&v)) return *b ? "on" : "off";
  return {};
}

std::string runSettings(const po::variables_map& vm) {
  std::string settings;
  for (const auto& [key, value] : vm) {
    if (key == "out" || key == "plot" || key == "log-chi2" || key == "view" || key == "quiet" ||
        key == "checkpoint" || key == "checkpoint-every" || key == "resume" ||
        key == "marginalised-out" || key == "help") {
      continue;
    }
    const std::string text = optionValueText(value.value());
    settings += (settings.empty() ? "--" : " --") + key + (text.empty() ? "" : " " + text);
  }
  return settings;
}

void attachLongRun(const DrivebotLongRun& o, MarginalisedOut& marginalised,
                   drivebot::RunOptions& run, const TypeRegistry& types,
                   const std::string& settings) {
  run.checkpoint_path = o.checkpoint;
  run.checkpoint_every = o.checkpoint_every;
  run.resume_path = o.resume;
  run.types = &types;
  run.settings = settings;
  run.on_checkpoint = [&marginalised] { return marginalised.note(); };
  run.on_resume = [&marginalised](const std::string& note) { marginalised.resume(note); };
  if (o.resume.empty()) marginalised.start();
}

void printWindowReport(const drivebot::DriveBotSlamSystem& system) {
  if (!system.windowed()) return;
  const incremental::WindowOptions& w = system.options().incremental_options.window;
  std::printf("window:        %zu vertices marginalised, %zu in the graph at the end%s",
              system.marginalizedCount(), system.graph().numVertices(),
              w.keep_landmarks ? " (landmarks kept)" : "");
  if (system.refusedObservations() > 0) {
    std::printf("; %zu observations of landmarks that had left dropped",
                system.refusedObservations());
  }
  std::printf("\n");
}

}  // namespace graphslam::apps
