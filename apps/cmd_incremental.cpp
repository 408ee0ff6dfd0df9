// SPDX-License-Identifier: MIT
// graphslam incremental: replays a graph pose by pose through the IncrementalOptimizer
// (incremental/replay.h) and compares the end with the batch optimum.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "builtins.h"
#include "cli_common.h"
#include "graphslam/incremental/replay.h"
#include "graphslam/io/g2o.h"
#include "graphslam/support/file_util.h"
#include "input.h"
#include "output_set.h"
#include "plotting.h"
#include "view_output.h"
#include "window_output.h"

namespace graphslam::apps {

namespace {

constexpr const char* kIncrementalUsage =
    "usage: graphslam incremental IN.g2o [-o OUT.g2o] [--stats FILE.csv] [--plot FILE.png]\n"
    "                             [--relinearize-threshold X] [--relinearize-skip N]\n"
    "                             [--max-passes N] [--backsubstitution-fraction F]\n"
    "                             [--check-every N]\n"
    "                             [--window N | --window-seconds S] [--marginalised-out FILE]\n"
    "                             [--window-slack B]\n"
    "                             [--reinitialise-landmarks | --keep-landmarks]\n"
    "                             [--checkpoint FILE --checkpoint-every N] [--resume FILE]\n"
    "                             [--refine X] [--no-batch] [--plugin LIB]... [-q]\n"
    "Replays a graph as a robot builds it, through the incremental optimizer: poses in id\n"
    "order, pose k composed from the current estimate of pose k-1 and their odometry edge,\n"
    "with every edge whose largest pose endpoint is k (landmarks with their first observation,\n"
    "placed by it), then one update per step, timed. Prints the steps, the total update time,\n"
    "the per-step p50 / p90 / p99 / max, the final chi2, and the batch optimum (optimize's\n"
    "defaults on the whole file, for scale) with its time and the relative difference.\n"
    "Then --refine X (default 1e-6; 0: off) relinearises until no step exceeds X, which ends\n"
    "at the batch optimum (timed apart from the steps and reported after them).\n"
    "-o writes the replayed graph; --stats one CSV line per step; --plot the per-step time and\n"
    "chi2 against the step (chi2 is then computed after every step, outside the timed part).\n"
    "Fixed-lag smoothing (--window, --window-seconds): poses older than the window are\n"
    "marginalised with the landmarks only they see (--keep-landmarks: the landmarks stay),\n"
    "their information kept as a dense prior on what they connect to (first-estimate\n"
    "caveats: docs/ARCHITECTURE.md); edges reaching a marginalised vertex are refused and\n"
    "counted. Checkpoints (--checkpoint) are written\n"
    "atomically; --resume continues a killed run from its last one and reaches the same\n"
    "estimates bit for bit as the run that was not killed.";

/// The options of graphslam incremental.
struct IncrementalCliOptions {
  std::string input, output, stats, plot, view;
  std::vector<std::string> plugins;
  int check_every = 0;
  std::string marginalised_out;
  bool quiet = false;  ///< -q: the summary only, without the input's description
  bool batch = true;   ///< --no-batch: no batch optimum for scale
  incremental::ReplayOptions replay;
};

/// Parses and checks the options; false after --help.
bool parseIncrementalOptions(const std::vector<std::string>& args, IncrementalCliOptions& o) {
  incremental::Options& opt = o.replay.optimizer;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("input", po::value(&o.input), "input .g2o file")(
      "output,o", po::value(&o.output), "write the replayed graph here (atomically)")(
      "stats", po::value(&o.stats),
      "write one CSV line per step: step, pose id, new edges and landmarks, update time, "
      "passes (and whether their limit was reached), relinearised vertices and edges, "
      "eliminated columns, full rebuild, chi2 (and the checks')")(
      "plot", po::value(&o.plot), "draw the per-step time (log scale) and chi2 into this PNG")(
      "view", po::value(&o.view),
      "write a self-contained web page of the replayed graph here (docs/VIEW.md)")(
      "relinearize-threshold", doubleValue(&opt.relinearize_threshold, opt.relinearize_threshold),
      "relinearise a vertex when an entry of its step from its linearisation point exceeds "
      "this (metres, radians)")(
      "relinearize-skip", po::value(&opt.relinearize_skip)->default_value(opt.relinearize_skip),
      "check for vertices to relinearise at every N-th update only (iSAM2's "
      "relinearizeSkip; the others solve at the current linearisation points)")(
      "max-passes", po::value(&opt.max_passes)->default_value(opt.max_passes),
      "relinearise-and-solve passes per update at most; the vertices still beyond the "
      "threshold are relinearised at the next update that checks (1: iSAM2's one solve per "
      "update, relinearising at its start)")(
      "backsubstitution-fraction",
      doubleValue(&opt.backsubstitution_fraction, opt.backsubstitution_fraction),
      "back-substitution keeps a vertex's new step only when it differs from the old by more "
      "than this fraction of the relinearisation threshold (iSAM2's wildfire; 0: always)")(
      "check-every", po::value(&o.check_every)->default_value(0),
      "every N steps, compare the estimates with a batch solve of the same graph (outside the "
      "timed part; 0: never)")(
      "refine", doubleValue(&o.replay.refine_threshold, 1e-6),
      "after the last step, relinearise every vertex whose step exceeds this and solve again "
      "until none does (the optimizer's refine(); timed apart; 0: off)")(
      "checkpoint", po::value(&o.replay.checkpoint_path),
      "write the optimizer's state here (atomically; with --checkpoint-every)")(
      "checkpoint-every", po::value(&o.replay.checkpoint_every)->default_value(0),
      "write the checkpoint after every N-th step")(
      "resume", po::value(&o.replay.resume_path),
      "continue from this checkpoint (written by a run on the same input with the same "
      "options)")("plugin", po::value(&o.plugins)->composing(),
                  "load types from this shared library (repeatable)")(
      "no-batch",
      "skip the batch optimum of the whole file (for long streams: it needs the "
      "memory and time of a batch solve)")(
      "quiet,q", "print only the summary (not the input's description and notes)");
  addWindowOptions(desc, opt.window, o.marginalised_out, "poses");
  po::positional_options_description pos;
  pos.add("input", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(kIncrementalUsage, desc);
    return false;
  }
  if (o.input.empty()) throw UsageError("incremental needs an input file IN.g2o");
  o.quiet = vm.count("quiet") != 0;
  o.batch = vm.count("no-batch") == 0;
  if (!(opt.relinearize_threshold >= 0 && std::isfinite(opt.relinearize_threshold))) {
    throw UsageError("--relinearize-threshold must be a finite number >= 0");
  }
  if (opt.relinearize_skip < 1) throw UsageError("--relinearize-skip must be at least 1");
  if (opt.max_passes < 1) throw UsageError("--max-passes must be at least 1");
  if (!(opt.backsubstitution_fraction >= 0 && std::isfinite(opt.backsubstitution_fraction))) {
    throw UsageError("--backsubstitution-fraction must be a finite number >= 0");
  }
  if (o.check_every < 0) throw UsageError("--check-every must be at least 0 (0: never)");
  if (!(o.replay.refine_threshold >= 0 && std::isfinite(o.replay.refine_threshold))) {
    throw UsageError("--refine must be a finite number >= 0 (0: off)");
  }
  checkWindowOptions(opt.window, o.marginalised_out);
  const bool window = opt.window.enabled();
  if (window && o.check_every > 0) {
    throw UsageError(
        "--check-every compares with a batch solve of the whole graph: not with "
        "--window or --window-seconds");
  }
  if (o.replay.checkpoint_path.empty() != (o.replay.checkpoint_every == 0)) {
    throw UsageError("--checkpoint FILE and --checkpoint-every N (N >= 1) go together");
  }
  o.replay.record_chi2 = !o.stats.empty() || !o.plot.empty();
  return true;
}

/// The process's resident set size in kB (/proc/self/statm; 0 where it cannot be read).
long residentKilobytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  long pages = 0, resident = 0;
  const int n = std::fscanf(f, "%ld %ld", &pages, &resident);
  std::fclose(f);
  return n == 2 ? resident * (sysconf(_SC_PAGESIZE) / 1024) : 0;
}

/// What --check-every found at one step.
struct StepCheck {
  std::size_t step = 0;
  incremental::BatchComparison comparison;
};

/// The p-th percentile (nearest rank) of `values`, sorted.
double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const double rank = std::ceil(p / 100.0 * static_cast<double>(sorted.size()));
  const std::size_t k = static_cast<std::size_t>(std::max(rank, 1.0)) - 1;
  return sorted[std::min(k, sorted.size() - 1)];
}

void printReplay(const incremental::ReplayResult& r, const IncrementalCliOptions& o) {
  std::printf(
      "replay: %zu steps (poses %s), %zu landmarks, relinearize threshold %g, relinearize skip "
      "%d, max passes %d, back-substitution fraction %g\n",
      r.steps.size(), r.pose_tag.c_str(), r.num_landmarks, o.replay.optimizer.relinearize_threshold,
      o.replay.optimizer.relinearize_skip, o.replay.optimizer.max_passes,
      o.replay.optimizer.backsubstitution_fraction);
  if (r.initialised_from_file > 0 || r.gaps > 0) {
    std::printf(
        "  file's estimate kept: %d vertices their first edge does not determine, %d poses "
        "without odometry to the previous one\n",
        r.initialised_from_file, r.gaps);
  }
  std::vector<double> ms;
  for (const auto& s : r.steps) ms.push_back(1e3 * s.seconds);
  std::sort(ms.begin(), ms.end());
  std::printf(
      "update time: %.4f s in all; per step p50 %.3f ms  p90 %.3f ms  p99 %.3f ms  max %.3f ms\n",
      r.total_seconds, percentile(ms, 50), percentile(ms, 90), percentile(ms, 99),
      ms.empty() ? 0.0 : ms.back());
  std::printf("final chi2: %.10g (incremental)\n", r.final_chi2);
  if (o.replay.refine_threshold > 0) {
    std::printf("after refine(%g): chi2 %.10g in %.4f s (%d passes, %d vertices relinearised)\n",
                o.replay.refine_threshold, r.refined_chi2, r.refine_seconds, r.refine_stats.passes,
                r.refine_stats.relinearized_vertices);
  }
}

std::string formatGap(double gap);

void printWindow(const incremental::ReplayResult& r, const IncrementalCliOptions& o) {
  if (!o.replay.resume_path.empty()) {
    std::printf("resumed from %s at step %zu\n", o.replay.resume_path.c_str(), r.first_step);
  }
  const incremental::WindowOptions& w = o.replay.optimizer.window;
  if (!w.enabled()) return;
  std::string bounds;
  if (w.states > 0) bounds = std::to_string(w.states) + " poses";
  if (w.seconds > 0) bounds += (bounds.empty() ? "" : ", ") + formatGap(w.seconds) + " s";
  if (w.keep_landmarks) bounds += ", landmarks kept";
  std::printf(
      "window: %s; %zu vertices marginalised, %zu in the graph at the end (its chi2 "
      "holds the marginalisation prior: not comparable with the batch optimum)\n",
      bounds.c_str(), r.marginalized, r.window_vertices);
  if (r.refused_edges > 0) {
    std::printf("  %zu edges reaching marginalised vertices refused, the first: %s\n",
                r.refused_edges, r.first_refusal.c_str());
  }
}

void printChecks(const std::vector<StepCheck>& checks, int every) {
  if (checks.empty()) return;
  const StepCheck* gap = nullptr;
  const StepCheck* diff = nullptr;
  const StepCheck* failed = nullptr;
  std::size_t num_failed = 0;
  for (const auto& c : checks) {
    if (!c.comparison.ok()) {
      if (!failed) failed = &c;
      ++num_failed;
      continue;
    }
    if (!gap || c.comparison.relative_gap > gap->comparison.relative_gap) gap = &c;
    if (!diff || c.comparison.max_difference > diff->comparison.max_difference) diff = &c;
  }
  std::printf("checks against a batch solve of the same graph (every %d steps, %zu checks):\n",
              every, checks.size());
  if (gap) {
    std::printf(
        "  largest relative chi2 gap %.3g (step %zu: %.10g against %.10g); largest estimate "
        "difference %.3g (vertex %d at step %zu)\n",
        gap->comparison.relative_gap, gap->step, gap->comparison.chi2, gap->comparison.batch_chi2,
        diff->comparison.max_difference, diff->comparison.worst_vertex, diff->step);
  }
  if (failed) {
    std::printf("  %zu batch solves failed, the first at step %zu: %s\n", num_failed, failed->step,
                failed->comparison.summary.message.c_str());
  }
}

/// The batch optimum of the whole file, as `optimize` reaches it with its defaults.
Summary runBatch(LoadedInput& in, const Registries& reg) {
  std::printf("batch, for scale (optimize's defaults on the whole file):\n");
  applyInitialGuess(in, in.graph, "auto", reg.solvers);
  Optimizer optimizer(in.graph, reg.solvers);
  return optimizer.optimize();
}

std::string formatGap(double gap) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", gap);
  return text;
}

std::string csvNumber(double value) {
  return std::isfinite(value) ? support::formatDouble(value) : "";
}

void writeStepsCsv(const std::string& path, const incremental::ReplayResult& r,
                   const std::vector<StepCheck>& checks, const std::vector<long>& rss) {
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "step,pose,new_edges,new_landmarks,seconds,passes,pass_limit_reached,"
           "relinearized_vertices,relinearized_edges,eliminated_columns,rebuilt,chi2,batch_chi2,"
           "estimate_difference,rss_kb\n";
    auto check = checks.begin();
    for (std::size_t k = 0; k < r.steps.size(); ++k) {
      const incremental::ReplayStep& s = r.steps[k];
      const incremental::UpdateStats& u = s.stats;
      out << k << ',' << s.pose << ',' << s.new_edges << ',' << s.new_landmarks << ','
          << support::formatDouble(s.seconds) << ',' << u.passes << ','
          << (u.pass_limit_reached ? 1 : 0) << ',' << u.relinearized_vertices << ','
          << u.relinearized_edges << ',' << u.eliminated_columns << ',' << (u.rebuilt ? 1 : 0)
          << ',' << csvNumber(s.chi2) << ',';
      while (check != checks.end() && check->step < k) ++check;
      if (check != checks.end() && check->step == k && check->comparison.ok()) {
        out << csvNumber(check->comparison.batch_chi2) << ','
            << csvNumber(check->comparison.max_difference);
      } else {
        out << ',';
      }
      out << ',' << (k < rss.size() ? std::to_string(rss[k]) : std::string()) << '\n';
    }
  });
}

void plotSteps(const std::string& png, const std::string& shown, const IncrementalCliOptions& o,
               const incremental::ReplayResult& r, const std::vector<StepCheck>& checks,
               const Summary& batch) {
  const std::string data = png + ".steps.csv";
  const TemporaryFile remove_data{data};
  writeStepsCsv(data, r, checks, {});
  char figures[160];
  std::snprintf(figures, sizeof figures,
                ": incremental replay, %zu steps, %.4g s of updates; final chi2 %.10g (batch "
                "optimum %.10g)",
                r.steps.size(), r.total_seconds, r.final_chi2, batch.final_cost);
  const std::string title = std::filesystem::path(o.input).filename().string() + figures;
  runPlotScript("plot_incremental.py", {data, png, title});
  std::printf("wrote %s\n", shown.c_str());
}

}  // namespace

int cmdIncremental(const std::vector<std::string>& args) {
  IncrementalCliOptions o;
  if (!parseIncrementalOptions(args, o)) return kExitOk;
  oneBlasThreadUnlessSet();
  Registries reg;
  loadRegistries(reg, o.plugins);
  OutputSet outputs({o.output, o.stats, o.plot, o.view}, {o.input});
  if (!o.plot.empty() && findPlotPython().empty()) {
    throw UsageError(
        "--plot needs Python 3 with matplotlib, and none was found (tried "
        "$GRAPHSLAM_PYTHON, /usr/bin/python3, python3)");
  }
  LoadedInput in = loadInput(o.input, reg);
  if (!o.quiet) {
    std::printf("%s: %s, %zu vertices, %zu edges\n", o.input.c_str(), in.description.c_str(),
                in.graph.numVertices(), in.graph.numEdges());
    for (const auto& note : in.notes) std::printf("  %s\n", note.c_str());
  }
  std::vector<StepCheck> checks;
  std::vector<long> rss;  // resident set size after each step (kB), for --stats
  o.replay.after_step = [&](std::size_t step, const incremental::ReplayStep&, const Graph& g) {
    if (!o.stats.empty()) rss.push_back(residentKilobytes());
    if (o.check_every <= 0 || (step + 1) % static_cast<std::size_t>(o.check_every) != 0) return;
    checks.push_back({step, incremental::compareWithBatch(g, reg.types, reg.solvers)});
  };
  MarginalisedOut marginalised(o.marginalised_out, reg.types);
  marginalised.attach(o.replay.optimizer.window);
  if (o.replay.resume_path.empty()) marginalised.start();
  o.replay.checkpoint_note = [&] { return marginalised.note(); };
  o.replay.on_resume = [&](const std::string& note) { marginalised.resume(note); };
  Graph replayed;
  const incremental::ReplayResult r =
      incremental::replayGraph(in.graph, reg.types, replayed, o.replay);
  if (!r.ok) {
    std::cerr << "graphslam incremental: the replay failed at " << r.error
              << "\nno output written\n";
    outputs.abort();
    return kExitFailed;
  }
  printReplay(r, o);
  printWindow(r, o);
  printChecks(checks, o.check_every);
  const auto write = [&](const Summary& batch) {
    return outputs.writeAll([&] {
      if (!o.stats.empty()) writeStepsCsv(outputs.staged(o.stats), r, checks, rss);
      if (!o.output.empty()) {
        io::saveG2o(outputs.staged(o.output), incremental::copyWithoutPriors(replayed, reg.types),
                    reg.types);
        std::printf("wrote %s\n", o.output.c_str());
      }
      if (!o.plot.empty()) plotSteps(outputs.staged(o.plot), o.plot, o, r, checks, batch);
      if (!o.view.empty()) {
        writeGraphView(outputs.staged(o.view), replayed, reg,
                       std::filesystem::path(o.input).filename().string() + " (incremental)",
                       {{"replay", std::to_string(r.steps.size()) + " steps"},
                        {"final chi2", support::formatDouble(r.final_chi2)},
                        {"batch optimum", support::formatDouble(batch.final_cost)}},
                       in.vertex_lines, in.path);
        std::printf("wrote %s\n", o.view.c_str());
      }
      outputs.commit();
      return kExitOk;
    });
  };
  if (!o.batch) {
    Summary none;
    none.final_cost = std::nan("");
    return write(none);
  }
  const Summary batch = runBatch(in, reg);
  if (!batch.succeeded() && batch.status != TerminationStatus::kNoProgress) {
    std::cerr << "graphslam incremental: the batch optimizer failed: " << toString(batch.status)
              << ": " << batch.message << "\nno output written\n";
    outputs.abort();
    return kExitFailed;
  }
  const auto gap = [&](double chi2) {
    return batch.final_cost != 0.0 ? (chi2 - batch.final_cost) / batch.final_cost : chi2;
  };
  std::printf("batch optimum: chi2 %.10g in %.4f s (%s, %d iterations)\n", batch.final_cost,
              batch.total_time, toString(batch.status), batch.iterations);
  std::printf("relative difference: %.3g (final chi2 - batch optimum) / batch optimum%s\n",
              gap(r.final_chi2),
              o.replay.refine_threshold > 0
                  ? ("; after refine " + formatGap(gap(r.refined_chi2))).c_str()
                  : "");
  return write(batch);
}

}  // namespace graphslam::apps
