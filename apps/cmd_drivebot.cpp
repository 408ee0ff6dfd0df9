// SPDX-License-Identifier: MIT
// graphslam drivebot: the UCL COMP0130 coursework-2 experiments, one command each.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "builtins.h"
#include "cli_common.h"
#include "drivebot_longrun.h"
#include "drivebot_output.h"
#include "graphslam/drivebot/run.h"
#include "graphslam/drivebot/scenario.h"
#include "graphslam/drivebot/simulator.h"
#include "graphslam/drivebot/slam_system.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "graphslam/support/logging.h"
#include "output_set.h"
#include "plotting.h"
#include "view_output.h"

namespace graphslam::apps {

namespace {

using namespace graphslam::drivebot;
using namespace graphslam::types_drivebot;

constexpr const char* kUsage =
    "usage: graphslam drivebot (--scenario NAME | --experiment NAME) --out DIR [--plot]\n"
    "                          [--seed S] [--optimize-every N] [--sensors gps,compass,laser|none]\n"
    "                          [--remove-prediction-edges none|all|keep-first]\n"
    "                          [--prune none|every-second|coursework|staggered|keyframe]\n"
    "                          [--max-steps N] [--laser-range R] [--compass-offset A] [...]\n"
    "Simulates the DriveBot vehicle of UCL COMP0130 coursework 2 on a scenario, runs the\n"
    "event-driven SLAM system on its events and writes per-step CSV, the final graph (.g2o),\n"
    "graph statistics and, with --plot, PNG plots. --experiment sets everything as the\n"
    "coursework's launcher script did (see --list-experiments); options given explicitly\n"
    "override it. Built-in scenarios: q1_b q1_c q1_d q1_e q2_b q2_c q2_d q3_a; others are read\n"
    "from --data DIR/NAME/{x0,wp,lm}.txt or a directory path.";

/// Everything one run needs; an experiment preset fills it, options override it.
struct Setup {
  std::string scenario;
  std::string description;
  SimulatorConfig sim;
  SlamSystemOptions slam;
  RunOptions run;
};

struct Experiment {
  const char* name;
  const char* description;
  void (*apply)(Setup&);
};

void laser(Setup& s, const char* scenario) {
  s.scenario = scenario;
  s.sim.enable_laser = true;
}

/// The coursework's q3_a launcher: laser range 30 m, optimise every 500 steps.
void q3a(Setup& s) {
  laser(s, "q3_a");
  s.sim.laser_range = 30.0;
  s.slam.optimize_every = 500;
}

void compass075(Setup& s) {
  s.scenario = "q1_c";
  s.sim.enable_compass = true;
  s.sim.compass_offset = 0.75 * kPi;
  s.slam.optimize_every = 20;
}

const std::vector<Experiment>& experiments() {
  static const std::vector<Experiment> list = {
      {"q1_b", "prediction only; optimise once at the end (20 iterations)",
       [](Setup& s) { s.scenario = "q1_b"; }},
      {"q1_c_bug",
       "compass (offset 0.75 pi) with the coursework's unwrapped compass error; optimise every "
       "20 steps",
       [](Setup& s) {
         compass075(s);
         s.slam.compass_wrap_error = false;
       }},
      {"q1_c", "compass (offset 0.75 pi), error wrapped (the fix); optimise every 20 steps",
       compass075},
      {"q1_d", "GPS; optimise once at the end",
       [](Setup& s) {
         s.scenario = "q1_d";
         s.sim.enable_gps = true;
       }},
      {"q1_e_i", "GPS; optimise after every step",
       [](Setup& s) {
         s.scenario = "q1_e";
         s.sim.enable_gps = true;
         s.slam.optimize_every = 1;
       }},
      {"q1_e_ii", "GPS and compass; optimise after every step",
       [](Setup& s) {
         s.scenario = "q1_e";
         s.sim.enable_gps = s.sim.enable_compass = true;
         s.slam.optimize_every = 1;
       }},
      {"q2_b", "laser SLAM; optimise every 5 steps",
       [](Setup& s) {
         laser(s, "q2_b");
         s.slam.optimize_every = 5;
       }},
      {"q2_c", "laser SLAM, four laps; optimise once at the end",
       [](Setup& s) { laser(s, "q2_c"); }},
      {"q2_c_every_step", "laser SLAM, four laps; optimise after every step (timing)",
       [](Setup& s) {
         laser(s, "q2_c");
         s.slam.optimize_every = 1;
       }},
      {"q2_d",
       "laser SLAM without noise, 2000 steps; landmark covariances just before and after the "
       "loop closure",
       [](Setup& s) {
         laser(s, "q2_d");
         s.sim.perturb_with_noise = false;
         s.sim.max_steps = 2000;
         s.run.snapshot_loop_closure = true;
       }},
      {"q2_e_large",
       "laser SLAM on q3-large-test (200 landmarks; read from --data); optimise once at the end",
       [](Setup& s) { laser(s, "q3-large-test"); }},
      {"q3_a", "laser range 30 m, optimise every 500 steps, prediction edges kept", q3a},
      {"q3_a_all", "q3_a removing all prediction edges (fails: nothing anchors the graph)",
       [](Setup& s) {
         q3a(s);
         s.slam.remove_prediction_edges = PredictionEdgeRemoval::kAll;
       }},
      {"q3_a_keep_first", "q3_a removing all prediction edges but the first",
       [](Setup& s) {
         q3a(s);
         s.slam.remove_prediction_edges = PredictionEdgeRemoval::kKeepFirst;
       }},
      {"q3_b_coursework",
       "q3_a pruning as the coursework did: at every optimisation each landmark keeps every "
       "second of its observation edges in the graph",
       [](Setup& s) {
         q3a(s);
         s.slam.prune = PruneRule::kCoursework;
       }},
      {"q3_b_every_second", "q3_a keeping every second observation of each landmark (once)",
       [](Setup& s) {
         q3a(s);
         s.slam.prune = PruneRule::kEverySecond;
       }},
      {"q3_b_staggered",
       "q3_a keeping every second observation of each landmark, staggered across landmarks",
       [](Setup& s) {
         q3a(s);
         s.slam.prune = PruneRule::kStaggered;
       }},
      {"q3_b_keyframe", "q3_a keeping observations at keyframes (2 m / 15 deg) only",
       [](Setup& s) {
         q3a(s);
         s.slam.prune = PruneRule::kKeyframe;
       }},
  };
  return list;
}

std::string defaultDataDir() {
  std::string base;
  if (const char* env = std::getenv("GRAPHSLAM_DATA"); env && *env) {
    base = env;
  } else {
    base = GRAPHSLAM_DEFAULT_DATA_DIR;
  }
  return base + "/seeds/comp0130_23-24_cw2_simulations";
}

/// "0.75pi" or a number of radians.
double parseAngle(const std::string& text) {
  std::string t = text;
  double scale = 1.0;
  if (t.size() > 2 && t.compare(t.size() - 2, 2, "pi") == 0) {
    t = t.substr(0, t.size() - 2);
    scale = kPi;
  }
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != t.size() || !std::isfinite(v)) {
    throw UsageError("'" + text + "' is not an angle (radians, or a multiple of pi like 0.75pi)");
  }
  return v * scale;
}

void parseSensors(const std::string& list, SimulatorConfig& sim) {
  sim.enable_gps = sim.enable_compass = sim.enable_laser = false;
  if (list == "none") return;
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (name == "gps") {
      sim.enable_gps = true;
    } else if (name == "compass") {
      sim.enable_compass = true;
    } else if (name == "laser") {
      sim.enable_laser = true;
    } else if (name != "odometry") {
      throw UsageError(
          "--sensors takes a comma-separated list of gps, compass, laser (odometry "
          "is always on) or none, not '" +
          name + "'");
    }
  }
}

std::string sensorList(const SimulatorConfig& sim) {
  std::string s = "odometry";
  if (sim.enable_gps) s += ", gps";
  if (sim.enable_compass) s += ", compass";
  if (sim.enable_laser) s += ", laser";
  return s;
}

void declareOptions(po::options_description& desc, DrivebotLongRun& longrun) {
  // clang-format off
  desc.add_options()
    ("help,h", "show this help")
    ("list-experiments", "list the experiment presets and exit")
    ("view", po::value<std::string>(), "also write a self-contained web page of the final graph here (docs/VIEW.md)")
    ("experiment", po::value<std::string>(), "coursework experiment preset (see --list-experiments)")
    ("scenario", po::value<std::string>(), "scenario: built-in name, name under --data, or a directory")
    ("data", po::value<std::string>(), "folder of scenario directories (default: $GRAPHSLAM_DATA or the "
                                        "source tree's ../shared/datasets, + /seeds/comp0130_23-24_cw2_simulations)")
    ("out", po::value<std::string>(), "output directory (created)")
    ("plot", "also draw PNG plots (matplotlib)")
    ("log-chi2", "with --plot: chi2 on a log axis (default linear)")
    ("seed", po::value<std::uint64_t>()->default_value(1), "random seed")
    ("optimize-every", po::value<int>(), "optimise every N steps (0: only once at the end)")
    ("iterations", po::value<int>(), "iterations per optimisation (default 50)")
    ("final-iterations", po::value<int>(), "iterations of the end-of-run optimisation (default 20; 0: none)")
    ("sensors", po::value<std::string>(), "gps,compass,laser (any of them; odometry is always on) or none")
    ("gps-period", po::value<double>(), "s (default 1)")
    ("compass-period", po::value<double>(), "s (default 0.1)")
    ("laser-period", po::value<double>(), "s (default 0.1)")
    ("laser-range", po::value<double>(), "m (default 10)")
    ("compass-offset", po::value<std::string>(), "rad, or a multiple of pi (0.75pi)")
    ("compass-bug", "reproduce the coursework's unwrapped compass error")
    ("compass-fix", "wrap the compass error (the default)")
    ("no-noise", "exact measurements (sensor timing stays random)")
    ("max-steps", po::value<long>(),
     "stop after N steps (default: 3 times the steps the scenario's path takes at the "
     "minimum speed, plus 1000; a run that has not reached its last waypoint by then fails)")
    ("remove-prediction-edges", po::value<std::string>(), "none, all or keep-first (before each optimisation)")
    ("prune", po::value<std::string>(), "landmark observations kept: none, every-second (once, on arrival), coursework "
                                        "(halve the graph's at every optimisation), staggered, keyframe")
    ("prune-every", po::value<int>(), "every-second, coursework and staggered keep every N-th sighting (default 2)")
    ("keyframe-distance", po::value<double>(), "m (keyframe pruning; default 2)")
    ("keyframe-angle", po::value<double>(), "deg (keyframe pruning; default 15)")
    ("no-waypoint-quirk", "steer the right way on the step after a waypoint switch")
    ("start-at-x0", "start at the scenario's x0 (the coursework starts at 0, 0, 0)")
    ("online-covariance", "covariance of the newest vehicle state after each optimisation")
    ("loop-closure", "landmark covariances just before and after the first loop closure")
    ("loop-closure-gap", po::value<long>(), "steps between sightings that count as a loop closure (default 200)")
    ("optimizer", po::value<std::string>(),
     "incremental (the default: one incremental update per optimisation) or batch (a batch "
     "optimisation each time, as the coursework; the modes that remove edges always use it)")
    ("algorithm", po::value<std::string>(), "auto, gn, lm or dogleg (default auto)")
    ("solver", po::value<std::string>(), "linear solver (default auto)")
    ("quiet,q", "print only the report");
  // clang-format on
  addLongRunOptions(desc, longrun);
}

/// Whether `name` was given on the command line (not only defaulted).
bool given(const po::variables_map& vm, const char* name) {
  return vm.count(name) && !vm[name].defaulted();
}

/// " --key value" for every option given beside the preset (those that change it).
std::string presetOverrides(const po::variables_map& vm) {
  std::string overrides;
  for (const auto& [key, value] : vm) {
    if (value.defaulted() || key == "experiment" || key == "out" || key == "plot" ||
        key == "log-chi2" || key == "data" || key == "seed" || key == "quiet") {
      continue;
    }
    overrides += " --" + key;
    const std::string text = optionValueText(value.value());
    if (!text.empty()) overrides += " " + text;
  }
  return overrides;
}

/// Applies the preset of --experiment, naming it and the options that change it.
void applyExperiment(const po::variables_map& vm, Setup& setup) {
  const std::string name = vm["experiment"].as<std::string>();
  const auto it = std::find_if(experiments().begin(), experiments().end(),
                               [&](const Experiment& e) { return name == e.name; });
  if (it == experiments().end()) {
    throw UsageError("unknown experiment '" + name + "' (see --list-experiments)");
  }
  it->apply(setup);
  setup.description = std::string(it->name) + ": " + it->description;
  // Options given beside the preset change it: say so in titles and reports.
  const std::string overrides = presetOverrides(vm);
  if (!overrides.empty()) setup.description += " (changed by" + overrides + ")";
}

/// The simulator's options given on the command line.
void applySimulatorOptions(const po::variables_map& vm, SimulatorConfig& sim) {
  if (given(vm, "sensors")) parseSensors(vm["sensors"].as<std::string>(), sim);
  if (given(vm, "gps-period")) sim.gps_period = vm["gps-period"].as<double>();
  if (given(vm, "compass-period")) sim.compass_period = vm["compass-period"].as<double>();
  if (given(vm, "laser-period")) sim.laser_period = vm["laser-period"].as<double>();
  if (given(vm, "laser-range")) sim.laser_range = vm["laser-range"].as<double>();
  if (given(vm, "compass-offset"))
    sim.compass_offset = parseAngle(vm["compass-offset"].as<std::string>());
}

/// The options of the SLAM system and the run given on the command line (in the order they
/// are checked).
void applySlamOptions(const po::variables_map& vm, Setup& setup) {
  SimulatorConfig& sim = setup.sim;
  SlamSystemOptions& slam = setup.slam;
  if (given(vm, "compass-bug") && given(vm, "compass-fix")) {
    throw UsageError("--compass-bug and --compass-fix exclude each other");
  }
  if (given(vm, "compass-bug")) slam.compass_wrap_error = false;
  if (given(vm, "compass-fix")) slam.compass_wrap_error = true;
  if (given(vm, "no-noise")) sim.perturb_with_noise = false;
  if (given(vm, "max-steps")) {
    sim.max_steps = vm["max-steps"].as<long>();
    if (sim.max_steps < 1) throw UsageError("--max-steps must be at least 1");
  }
  if (given(vm, "remove-prediction-edges")) {
    slam.remove_prediction_edges = parseChoice<PredictionEdgeRemoval>(
        "remove-prediction-edges", vm["remove-prediction-edges"].as<std::string>(),
        {{"none", PredictionEdgeRemoval::kNone},
         {"all", PredictionEdgeRemoval::kAll},
         {"keep-first", PredictionEdgeRemoval::kKeepFirst}});
  }
  if (given(vm, "prune")) {
    slam.prune = parseChoice<PruneRule>("prune", vm["prune"].as<std::string>(),
                                        {{"none", PruneRule::kNone},
                                         {"every-second", PruneRule::kEverySecond},
                                         {"coursework", PruneRule::kCoursework},
                                         {"staggered", PruneRule::kStaggered},
                                         {"keyframe", PruneRule::kKeyframe}});
  }
  if (given(vm, "prune-every")) slam.prune_every = vm["prune-every"].as<int>();
  if (slam.prune_every < 1) throw UsageError("--prune-every must be at least 1");
  if (given(vm, "keyframe-distance")) slam.keyframe_distance = vm["keyframe-distance"].as<double>();
  if (given(vm, "keyframe-angle"))
    slam.keyframe_angle = vm["keyframe-angle"].as<double>() * kPi / 180;
  if (given(vm, "no-waypoint-quirk")) sim.waypoint_sign_quirk = false;
  if (given(vm, "start-at-x0")) sim.start_at_scenario_x0 = true;
  if (given(vm, "online-covariance")) setup.run.online_covariance = true;
  if (given(vm, "loop-closure")) setup.run.snapshot_loop_closure = true;
  if (given(vm, "loop-closure-gap")) slam.loop_closure_gap = vm["loop-closure-gap"].as<long>();
  if (given(vm, "optimizer")) {
    slam.incremental = parseChoice<bool>("optimizer", vm["optimizer"].as<std::string>(),
                                         {{"incremental", true}, {"batch", false}});
  }
  if (given(vm, "algorithm"))
    slam.optimizer.algorithm = parseAlgorithm(vm["algorithm"].as<std::string>());
  if (given(vm, "solver")) slam.optimizer.linear_solver = vm["solver"].as<std::string>();
}

void validate(const Setup& setup) {
  const SimulatorConfig& sim = setup.sim;
  const SlamSystemOptions& slam = setup.slam;
  if (slam.optimize_every < 0) throw UsageError("--optimize-every must be >= 0");
  if (slam.max_iterations < 1) throw UsageError("--iterations must be at least 1");
  if (setup.run.final_iterations < 0) throw UsageError("--final-iterations must be >= 0");
  for (double p : {sim.gps_period, sim.compass_period, sim.laser_period, sim.laser_range}) {
    if (!(p > 0.0)) throw UsageError("sensor periods and the laser range must be positive");
  }
}

/// The run's setup: the preset of --experiment, then the options given; validated.
Setup setupFromOptions(const po::variables_map& vm) {
  Setup setup;
  if (given(vm, "experiment")) applyExperiment(vm, setup);
  if (given(vm, "scenario")) setup.scenario = vm["scenario"].as<std::string>();
  if (setup.scenario.empty())
    throw UsageError("drivebot needs --scenario NAME or --experiment NAME");
  if (!given(vm, "out")) throw UsageError("drivebot needs --out DIR");

  SlamSystemOptions& slam = setup.slam;
  setup.sim.seed = vm["seed"].as<std::uint64_t>();
  if (given(vm, "optimize-every")) slam.optimize_every = vm["optimize-every"].as<int>();
  if (given(vm, "iterations")) slam.max_iterations = vm["iterations"].as<int>();
  if (given(vm, "final-iterations")) setup.run.final_iterations = vm["final-iterations"].as<int>();
  applySimulatorOptions(vm, setup.sim);
  applySlamOptions(vm, setup);
  validate(setup);
  slam.gps_offset = setup.sim.gps_offset;
  slam.compass_offset = setup.sim.compass_offset;
  return setup;
}

void printSettings(const Setup& setup, const Scenario& scenario, const char* optimizer) {
  const SimulatorConfig& sim = setup.sim;
  const SlamSystemOptions& slam = setup.slam;
  if (!setup.description.empty()) std::printf("experiment:    %s\n", setup.description.c_str());
  std::printf(
      "scenario:      %s (%s): %zu waypoints, %zu landmarks\n"
      "settings:      seed %llu, sensors %s%s, optimise %s, prediction edges removed: %s, "
      "prune: %s, optimizer: %s\n",
      scenario.name.c_str(), scenario.source.c_str(), scenario.waypoints.size(),
      scenario.landmarks.size(), static_cast<unsigned long long>(sim.seed), sensorList(sim).c_str(),
      sim.perturb_with_noise ? "" : " (no noise)",
      slam.optimize_every > 0 ? ("every " + std::to_string(slam.optimize_every) + " steps").c_str()
                              : "at the end only",
      toString(slam.remove_prediction_edges), toString(slam.prune), optimizer);
  const incremental::WindowOptions& w = slam.incremental_options.window;
  if (w.enabled()) {
    std::printf("window:        fixed-lag smoothing, keeping");
    if (w.states > 0) std::printf(" %zu vehicle states (slack %zu)", w.states, w.slack);
    if (w.seconds > 0) std::printf("%s %g s", w.states > 0 ? " and" : "", w.seconds);
    std::printf("; landmarks %s\n", w.keep_landmarks           ? "kept"
                                    : w.reinitialize_landmarks ? "leave, started anew if seen again"
                                                               : "leave, later sightings dropped");
  }
  std::fflush(stdout);
}

/// Prints why a run has no results and returns false, or returns true.
bool runSucceeded(const RunResult& result) {
  if (result.failed) {
    std::fprintf(stderr,
                 "graphslam drivebot: optimisation at step %ld (t = %.1f s) failed: %s: %s\n"
                 "no results written\n",
                 result.failed_step, result.failed_time, toString(result.failure.status),
                 result.failure.message.c_str());
    return false;
  }
  if (!result.history_marginals.ok()) {
    std::fprintf(stderr, "graphslam drivebot: vehicle covariances: %s\nno results written\n",
                 result.history_marginals.message.c_str());
    return false;
  }
  return true;
}

void printProgress(const StepRecord& s) {
  if (s.step % 1000 == 0 && s.step > 0) {
    std::printf("  step %6ld  t %7.1f s  vertices %6zu  edges %6zu\n", s.step, s.time, s.vertices,
                s.edges);
    std::fflush(stdout);
  }
}

}  // namespace

int cmdDrivebot(const std::vector<std::string>& args) {
  po::options_description desc("options");
  DrivebotLongRun longrun;
  declareOptions(desc, longrun);
  const auto vm = parse(args, desc);
  if (vm.count("help")) {
    printHelp(kUsage, desc);
    return kExitOk;
  }
  if (vm.count("list-experiments")) {
    for (const auto& e : experiments()) std::printf("%-18s %s\n", e.name, e.description);
    return kExitOk;
  }
  Setup setup = setupFromOptions(vm);
  checkLongRunOptions(longrun, setup.run.snapshot_loop_closure);
  setup.slam.incremental_options.window = longrun.window;
  const std::string out_dir = vm["out"].as<std::string>();
  oneBlasThreadUnlessSet();

  Registries reg;
  loadRegistries(reg, {});
  checkSolverSpec(setup.slam.optimizer.linear_solver, reg.solvers);
  const std::string data_dir = given(vm, "data") ? vm["data"].as<std::string>() : defaultDataDir();
  const Scenario scenario = findScenario(setup.scenario, data_dir);

  support::setLogSink([](support::LogLevel level, const std::string& msg) {
    if (level >= support::LogLevel::kWarning)
      std::fprintf(stderr, "%s: %s\n", toString(level), msg.c_str());
  });
  // Created before the run, so a long run does not end in an unwritable place; the results
  // are staged in it and put in place together when all are written.
  OutputFolder outputs(out_dir);
  const std::string view_page = given(vm, "view") ? vm["view"].as<std::string>() : std::string();
  OutputSet view_output({view_page}, {});
  MarginalisedOut marginalised(longrun.marginalised_out, reg.types);
  marginalised.attach(setup.slam.incremental_options.window);
  attachLongRun(longrun, marginalised, setup.run, reg.types, runSettings(vm));
  Simulator simulator(scenario, setup.sim);
  DriveBotSlamSystem system(reg.solvers, setup.slam);
  const char* optimizer = system.usesIncremental() ? "incremental" : "batch";
  printSettings(setup, scenario, optimizer);
  if (vm.count("quiet") == 0) setup.run.progress = printProgress;
  const RunResult result = runDriveBot(simulator, system, setup.run);
  if (!runSucceeded(result)) return kExitFailed;

  printDrivebotReport(scenario, result, setup.sim.enable_laser);
  printWindowReport(system);
  // A window's graph holds its marginalisation priors, which .g2o has no line for.
  const Graph window_graph =
      system.windowed() ? incremental::copyWithoutPriors(system.graph(), reg.types) : Graph();
  const Graph& final_graph = system.windowed() ? window_graph : system.graph();
  writeDrivebotResults(outputs.staged(), scenario, result, final_graph, reg.types);
  if (vm.count("plot")) {
    std::string title = scenario.name;
    if (!setup.description.empty()) title = setup.description;
    title += std::string(" (") + optimizer + " optimizer)";
    std::vector<std::string> args{outputs.staged(), title};
    if (vm.count("log-chi2")) args.emplace_back("--log-chi2");
    // The plot script names the pictures it has nothing to draw for in this list.
    ::setenv("GRAPHSLAM_NOT_WRITTEN_LIST", outputs.notWrittenList().c_str(), 1);
    runPlotScript("plot_drivebot.py", args);
  }
  if (!view_page.empty()) {
    writeGraphView(view_output.staged(view_page), system.graph(), reg,
                   scenario.name + " (DriveBot)",
                   {{"optimizer", optimizer}, {"scenario", scenario.name}});
  }
  outputs.commit();
  view_output.commit();
  if (!view_page.empty()) std::printf("wrote %s\n", view_page.c_str());
  std::printf(
      "wrote:         %s/{steps.csv, landmarks.csv, scenario.csv, graph_stats.csv, summary.csv%s, "
      "final.g2o}\n",
      out_dir.c_str(), result.loop_closure ? ", loop_closure.csv, loop_closure_vehicle.csv" : "");
  if (vm.count("plot")) std::printf("plots:         %s/*.png\n", out_dir.c_str());
  return kExitOk;
}

}  // namespace graphslam::apps
