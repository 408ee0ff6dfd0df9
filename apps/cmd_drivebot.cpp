// SPDX-License-Identifier: MIT
// graphslam drivebot: the UCL COMP0130 coursework-2 experiments, one command each.
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "cli_common.h"
#include "graphslam/core/error.h"
#include "graphslam/core/file_util.h"
#include "graphslam/core/graph_checks.h"
#include "graphslam/core/io_g2o.h"
#include "graphslam/core/logging.h"
#include "graphslam/drivebot/run.h"
#include "graphslam/drivebot/scenario.h"
#include "graphslam/drivebot/simulator.h"
#include "graphslam/drivebot/slam_system.h"
#include "plotting.h"

namespace graphslam::apps {

namespace {

using namespace graphslam::drivebot;
using namespace graphslam::types_drivebot;

constexpr double kPi = 3.14159265358979323846;

constexpr const char* kUsage =
    "usage: graphslam drivebot (--scenario NAME | --experiment NAME) --out DIR [--plot]\n"
    "                          [--seed S] [--optimize-every N] [--sensors gps,compass,laser|none]\n"
    "                          [--remove-prediction-edges none|all|keep-first]\n"
    "                          [--prune none|every-second|staggered|keyframe] [--max-steps N]\n"
    "                          [--laser-range R] [--compass-offset A] [...]\n"
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
      {"q3_b_every_second", "q3_a keeping every second observation of each landmark",
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

// ---------------------------------------------------------------------------------------
// Output

std::string num(double v) { return std::isfinite(v) ? formatDouble(v) : "nan"; }

double wrapPi(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a - kPi;
}

void writeSteps(const std::string& path, const RunResult& r) {
  const bool aligned = r.history.time.size() == r.steps.size();
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "step,time,waypoint,true_x,true_y,true_psi,x,y,psi,var_x,var_y,var_psi,online_x,"
           "online_y,online_psi,online_var_x,online_var_y,online_var_psi,optimized,chi2,"
           "optimization_time,iterations,vertices,edges,observations\n";
    for (std::size_t k = 0; k < r.steps.size(); ++k) {
      const StepRecord& s = r.steps[k];
      out << s.step << ',' << num(s.time) << ',' << s.waypoint_index;
      for (int i = 0; i < 3; ++i) out << ',' << num(s.truth[i]);
      for (int i = 0; i < 3; ++i) out << ',' << (aligned ? num(r.history.x[k][i]) : "nan");
      for (int i = 0; i < 3; ++i) out << ',' << (aligned ? num(r.history.variance[k][i]) : "nan");
      for (int i = 0; i < 3; ++i) out << ',' << num(s.online[i]);
      for (int i = 0; i < 3; ++i) out << ',' << num(s.online_variance[i]);
      out << ',' << (s.optimized ? 1 : 0) << ',' << num(s.chi2) << ',' << num(s.optimization_time)
          << ',' << s.iterations << ',' << s.vertices << ',' << s.edges << ',' << s.observations
          << '\n';
    }
  });
}

void writeLandmarks(std::ostream& out, const std::vector<LandmarkEstimate>& landmarks,
                    const Scenario& scenario, const char* prefix) {
  for (const auto& l : landmarks) {
    const Eigen::Vector2d& truth =
        scenario.landmarks.at(static_cast<std::size_t>(l.landmark_id - 1));
    out << prefix << l.landmark_id << ',' << l.vertex << ',' << num(truth[0]) << ','
        << num(truth[1]) << ',' << num(l.x[0]) << ',' << num(l.x[1]) << ','
        << num(l.covariance(0, 0)) << ',' << num(l.covariance(0, 1)) << ','
        << num(l.covariance(1, 1)) << ',' << num(l.covariance.determinant()) << ','
        << l.observations << ',' << l.last_seen_step << '\n';
  }
}

constexpr const char* kLandmarkHeader =
    "landmark,vertex,true_x,true_y,x,y,cov_xx,cov_xy,cov_yy,det,observations,last_seen_step\n";

void writeLoopClosure(const std::string& path, const LoopClosure& lc, const Scenario& scenario) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "phase,step,time,chi2,vehicle_x,vehicle_y,vehicle_psi,vehicle_det,closing_landmarks,"
        << kLandmarkHeader;
    std::string closing;
    for (int id : lc.landmark_ids) closing += (closing.empty() ? "" : " ") + std::to_string(id);
    for (const auto* m : {&lc.before, &lc.after}) {
      std::ostringstream prefix;
      prefix << (m == &lc.before ? "before" : "after") << ',' << m->step << ',' << num(m->time)
             << ',' << num(m->chi2) << ',' << num(m->vehicle[0]) << ',' << num(m->vehicle[1]) << ','
             << num(m->vehicle[2]) << ','
             << num(m->vehicle_covariance.topLeftCorner<2, 2>().determinant()) << ',' << closing
             << ',';
      writeLandmarks(out, m->landmarks, scenario, prefix.str().c_str());
    }
  });
}

void writeStatistics(const std::string& path, const GraphStatistics& g) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "quantity,value\n"
        << "vehicle_vertices," << g.vehicle_vertices << "\nlandmark_vertices,"
        << g.landmark_vertices << "\nedges," << g.edges << "\nprediction_edges,"
        << g.prediction_edges << "\nobservation_edges," << g.observation_edges << "\ngps_edges,"
        << g.gps_edges << "\ncompass_edges," << g.compass_edges << "\nprior_edges," << g.prior_edges
        << "\nobservations_received," << g.observations_received
        << "\nobservations_per_vehicle_vertex," << num(g.observations_per_vehicle_vertex)
        << "\nobservations_per_landmark," << num(g.observations_per_landmark) << "\n";
    for (const auto& [id, n] : g.observations_of_landmark) {
      out << "observations_of_landmark_" << id << ',' << n << "\n";
    }
  });
}

/// Median of the optimisation times of the steps whose target waypoint lies in
/// [first, last) of the route; NaN when none optimised there.
double medianOptimizationTime(const RunResult& r, int first, int last) {
  std::vector<double> t;
  for (const auto& s : r.steps) {
    if (s.optimized && s.waypoint_index >= first && s.waypoint_index < last) {
      t.push_back(s.optimization_time);
    }
  }
  if (t.empty()) return std::nan("");
  std::nth_element(t.begin(), t.begin() + static_cast<long>(t.size() / 2), t.end());
  return t[t.size() / 2];
}

void printReport(const Setup& setup, const Scenario& scenario, const RunResult& r) {
  const auto& g = r.statistics;
  std::printf("steps:         %zu (t = %.1f s), last waypoint index %d of %zu\n", r.steps.size(),
              r.steps.empty() ? 0.0 : r.steps.back().time,
              r.steps.empty() ? 0 : r.steps.back().waypoint_index, scenario.waypoints.size());
  std::printf(
      "graph:         %zu vehicle vertices, %zu landmark vertices, %zu edges (%zu prediction, "
      "%zu landmark observation, %zu GPS, %zu compass, %zu prior)\n",
      g.vehicle_vertices, g.landmark_vertices, g.edges, g.prediction_edges, g.observation_edges,
      g.gps_edges, g.compass_edges, g.prior_edges);
  if (setup.sim.enable_laser) {
    std::printf(
        "observations:  %zu received, %zu in the graph; %.3f per vehicle vertex, %.1f per "
        "landmark\n",
        g.observations_received, g.observation_edges, g.observations_per_vehicle_vertex,
        g.observations_per_landmark);
  }
  const int n_wp = static_cast<int>(scenario.waypoints.size());
  const int quarter = std::max(1, n_wp / 4);
  std::printf("optimisation:  %d runs, %.3f s in total", r.optimizations,
              r.total_optimization_time);
  const double first = medianOptimizationTime(r, 0, quarter);
  const double last = medianOptimizationTime(r, n_wp - quarter, n_wp);
  if (std::isfinite(first) && std::isfinite(last)) {
    std::printf("; median per step %.2f ms (first quarter of the route), %.2f ms (last quarter)",
                1e3 * first, 1e3 * last);
  }
  std::printf("\nfinal:         %s, chi2 %.6g, %d iterations\n", toString(r.final_summary.status),
              r.final_summary.final_chi2, r.final_summary.iterations);
  if (r.history.time.size() == r.steps.size() && !r.steps.empty()) {
    Eigen::Vector3d sq = Eigen::Vector3d::Zero(), mx = Eigen::Vector3d::Zero();
    std::size_t n = 0;
    for (std::size_t k = 0; k < r.steps.size(); ++k) {
      if (std::isnan(r.history.variance[k][0])) continue;  // not estimated
      ++n;
      Eigen::Vector3d e = r.history.x[k] - r.steps[k].truth;
      e[2] = wrapPi(e[2]);
      sq += e.cwiseProduct(e);
      mx = mx.cwiseMax(e.cwiseAbs());
    }
    const Eigen::Vector3d rms = (sq / static_cast<double>(std::max<std::size_t>(n, 1))).cwiseSqrt();
    std::printf(
        "errors:        rms x %.3f m, y %.3f m, psi %.3f deg; max |x| %.3f m, |y| %.3f m, |psi| "
        "%.3f deg\n",
        rms[0], rms[1], rms[2] * 180.0 / kPi, mx[0], mx[1], mx[2] * 180.0 / kPi);
    const Eigen::Vector3d& v = r.history.variance.back();
    std::printf(
        "covariance:    last vehicle state: var x %.4g m^2, var y %.4g m^2, var psi %.4g "
        "rad^2 (marginals in %.3f s)\n",
        v[0], v[1], v[2], r.history_marginals.total_time);
  }
  if (!r.constraints.without_edges.empty()) {
    std::printf(
        "not estimated: %zu vehicle vertices without any edge (no landmark seen that step and "
        "its prediction edges removed) keep their predicted values; covariance NaN: %s\n",
        r.constraints.without_edges.size(),
        formatIdRanges(r.constraints.without_edges, 12).c_str());
  }
  if (!r.landmarks.empty()) {
    std::printf("landmarks:     %zu, covariances in %.4f s\n", r.landmarks.size(),
                r.landmark_marginals.total_time);
  }
  if (r.loop_closure) {
    const LoopClosure& lc = *r.loop_closure;
    std::printf("loop closure:  at step %ld (t = %.1f s), landmarks seen again:", lc.step,
                lc.after.time);
    for (int id : lc.landmark_ids) std::printf(" %d", id);
    std::printf("; all landmark covariances in %.4f s before, %.4f s after",
                lc.before.marginals.total_time, lc.after.marginals.total_time);
    std::printf("\n  landmark  det(P) before  det(P) after  after/before  last seen (step)\n");
    for (const auto& b : lc.before.landmarks) {
      for (const auto& a : lc.after.landmarks) {
        if (a.landmark_id != b.landmark_id) continue;
        const double db = b.covariance.determinant(), da = a.covariance.determinant();
        std::printf("  %8d  %13.4g  %12.4g  %12.4g  %ld\n", b.landmark_id, db, da, da / db,
                    b.last_seen_step - 1);
      }
    }
  }
}

}  // namespace

int cmdDrivebot(const std::vector<std::string>& args) {
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
    ("help,h", "show this help")
    ("list-experiments", "list the experiment presets and exit")
    ("experiment", po::value<std::string>(), "coursework experiment preset (see --list-experiments)")
    ("scenario", po::value<std::string>(), "scenario: built-in name, name under --data, or a directory")
    ("data", po::value<std::string>(), "folder of scenario directories (default: $GRAPHSLAM_DATA or the "
                                        "source tree's ../shared/datasets, + /seeds/comp0130_23-24_cw2_simulations)")
    ("out", po::value<std::string>(), "output directory (created)")
    ("plot", "also draw PNG plots (matplotlib)")
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
    ("max-steps", po::value<long>(), "stop after N steps")
    ("remove-prediction-edges", po::value<std::string>(), "none, all or keep-first (before each optimisation)")
    ("prune", po::value<std::string>(), "landmark observations kept: none, every-second, staggered, keyframe")
    ("prune-every", po::value<int>(), "every-second and staggered keep every N-th sighting (default 2)")
    ("keyframe-distance", po::value<double>(), "m (keyframe pruning; default 2)")
    ("keyframe-angle", po::value<double>(), "deg (keyframe pruning; default 15)")
    ("no-waypoint-quirk", "steer the right way on the step after a waypoint switch")
    ("start-at-x0", "start at the scenario's x0 (the coursework starts at 0, 0, 0)")
    ("online-covariance", "covariance of the newest vehicle state after each optimisation")
    ("loop-closure", "landmark covariances just before and after the first loop closure")
    ("loop-closure-gap", po::value<long>(), "steps between sightings that count as a loop closure (default 200)")
    ("algorithm", po::value<std::string>(), "auto, gn or lm (default auto)")
    ("solver", po::value<std::string>(), "linear solver (default auto)")
    ("quiet,q", "print only the report");
  // clang-format on
  const auto vm = parse(args, desc);
  if (vm.count("help")) {
    printHelp(kUsage, desc);
    return kExitOk;
  }
  if (vm.count("list-experiments")) {
    for (const auto& e : experiments()) std::printf("%-18s %s\n", e.name, e.description);
    return kExitOk;
  }
  auto given = [&](const char* name) { return vm.count(name) && !vm[name].defaulted(); };

  Setup setup;
  if (given("experiment")) {
    const std::string name = vm["experiment"].as<std::string>();
    const auto it = std::find_if(experiments().begin(), experiments().end(),
                                 [&](const Experiment& e) { return name == e.name; });
    if (it == experiments().end()) {
      throw UsageError("unknown experiment '" + name + "' (see --list-experiments)");
    }
    it->apply(setup);
    setup.description = std::string(it->name) + ": " + it->description;
    // Options given beside the preset change it: say so in titles and reports.
    std::string overrides;
    for (const auto& [key, value] : vm) {
      if (value.defaulted() || key == "experiment" || key == "out" || key == "plot" ||
          key == "data" || key == "seed") {
        continue;
      }
      overrides += " --" + key;
      try {
        overrides += " " + value.as<std::string>();
      } catch (const boost::bad_any_cast&) {
        try {
          overrides += " " + std::to_string(value.as<int>());
        } catch (const boost::bad_any_cast&) {
        }
      }
    }
    if (!overrides.empty()) setup.description += " (changed by" + overrides + ")";
  }
  if (given("scenario")) setup.scenario = vm["scenario"].as<std::string>();
  if (setup.scenario.empty())
    throw UsageError("drivebot needs --scenario NAME or --experiment NAME");
  if (!given("out")) throw UsageError("drivebot needs --out DIR");
  const std::string out_dir = vm["out"].as<std::string>();

  SimulatorConfig& sim = setup.sim;
  SlamSystemOptions& slam = setup.slam;
  sim.seed = vm["seed"].as<std::uint64_t>();
  if (given("optimize-every")) slam.optimize_every = vm["optimize-every"].as<int>();
  if (given("iterations")) slam.max_iterations = vm["iterations"].as<int>();
  if (given("final-iterations")) setup.run.final_iterations = vm["final-iterations"].as<int>();
  if (given("sensors")) parseSensors(vm["sensors"].as<std::string>(), sim);
  if (given("gps-period")) sim.gps_period = vm["gps-period"].as<double>();
  if (given("compass-period")) sim.compass_period = vm["compass-period"].as<double>();
  if (given("laser-period")) sim.laser_period = vm["laser-period"].as<double>();
  if (given("laser-range")) sim.laser_range = vm["laser-range"].as<double>();
  if (given("compass-offset"))
    sim.compass_offset = parseAngle(vm["compass-offset"].as<std::string>());
  if (given("compass-bug") && given("compass-fix")) {
    throw UsageError("--compass-bug and --compass-fix exclude each other");
  }
  if (given("compass-bug")) slam.compass_wrap_error = false;
  if (given("compass-fix")) slam.compass_wrap_error = true;
  if (given("no-noise")) sim.perturb_with_noise = false;
  if (given("max-steps")) sim.max_steps = vm["max-steps"].as<long>();
  if (given("remove-prediction-edges")) {
    slam.remove_prediction_edges = parseChoice<PredictionEdgeRemoval>(
        "remove-prediction-edges", vm["remove-prediction-edges"].as<std::string>(),
        {{"none", PredictionEdgeRemoval::kNone},
         {"all", PredictionEdgeRemoval::kAll},
         {"keep-first", PredictionEdgeRemoval::kKeepFirst}});
  }
  if (given("prune")) {
    slam.prune = parseChoice<PruneRule>("prune", vm["prune"].as<std::string>(),
                                        {{"none", PruneRule::kNone},
                                         {"every-second", PruneRule::kEverySecond},
                                         {"staggered", PruneRule::kStaggered},
                                         {"keyframe", PruneRule::kKeyframe}});
  }
  if (given("prune-every")) slam.prune_every = vm["prune-every"].as<int>();
  if (slam.prune_every < 1) throw UsageError("--prune-every must be at least 1");
  if (given("keyframe-distance")) slam.keyframe_distance = vm["keyframe-distance"].as<double>();
  if (given("keyframe-angle")) slam.keyframe_angle = vm["keyframe-angle"].as<double>() * kPi / 180;
  if (given("no-waypoint-quirk")) sim.waypoint_sign_quirk = false;
  if (given("start-at-x0")) sim.start_at_scenario_x0 = true;
  if (given("online-covariance")) setup.run.online_covariance = true;
  if (given("loop-closure")) setup.run.snapshot_loop_closure = true;
  if (given("loop-closure-gap")) slam.loop_closure_gap = vm["loop-closure-gap"].as<long>();
  if (given("algorithm"))
    slam.optimizer.algorithm = parseAlgorithm(vm["algorithm"].as<std::string>());
  if (given("solver")) slam.optimizer.linear_solver = vm["solver"].as<std::string>();
  if (slam.optimize_every < 0) throw UsageError("--optimize-every must be >= 0");
  if (slam.max_iterations < 1) throw UsageError("--iterations must be at least 1");
  if (setup.run.final_iterations < 0) throw UsageError("--final-iterations must be >= 0");
  if (sim.max_steps < 1) throw UsageError("--max-steps must be at least 1");
  for (double p : {sim.gps_period, sim.compass_period, sim.laser_period, sim.laser_range}) {
    if (!(p > 0.0)) throw UsageError("sensor periods and the laser range must be positive");
  }
  slam.gps_offset = sim.gps_offset;
  slam.compass_offset = sim.compass_offset;

  Registries reg;
  loadRegistries(reg, {});
  if (!reg.solvers.contains(slam.optimizer.linear_solver)) {
    throw UsageError("unknown solver '" + slam.optimizer.linear_solver +
                     "' (graphslam list-solvers shows the known ones)");
  }
  const std::string data_dir = given("data") ? vm["data"].as<std::string>() : defaultDataDir();
  const Scenario scenario = findScenario(setup.scenario, data_dir);
  const bool quiet = vm.count("quiet") != 0;

  setLogSink([](LogLevel level, const std::string& msg) {
    if (level >= LogLevel::kWarning) std::fprintf(stderr, "%s: %s\n", toString(level), msg.c_str());
  });
  if (!setup.description.empty()) std::printf("experiment:    %s\n", setup.description.c_str());
  std::printf(
      "scenario:      %s (%s): %zu waypoints, %zu landmarks\n"
      "settings:      seed %llu, sensors %s%s, optimise %s, prediction edges removed: %s, "
      "prune: %s\n",
      scenario.name.c_str(), scenario.source.c_str(), scenario.waypoints.size(),
      scenario.landmarks.size(), static_cast<unsigned long long>(sim.seed), sensorList(sim).c_str(),
      sim.perturb_with_noise ? "" : " (no noise)",
      slam.optimize_every > 0 ? ("every " + std::to_string(slam.optimize_every) + " steps").c_str()
                              : "at the end only",
      toString(slam.remove_prediction_edges), toString(slam.prune));
  std::fflush(stdout);

  {
    std::error_code ec;  // before the run, so a long run does not end in an unwritable place
    std::filesystem::create_directories(out_dir, ec);
    if (ec || !std::filesystem::is_directory(out_dir)) {
      throw Error("cannot create the output directory '" + out_dir + "'" +
                  (ec ? ": " + ec.message() : ""));
    }
  }
  Simulator simulator(scenario, sim);
  DriveBotSlamSystem system(reg.solvers, slam);
  if (!quiet) {
    setup.run.progress = [](const StepRecord& s) {
      if (s.step % 1000 == 0 && s.step > 0) {
        std::printf("  step %6ld  t %7.1f s  vertices %6zu  edges %6zu\n", s.step, s.time,
                    s.vertices, s.edges);
        std::fflush(stdout);
      }
    };
  }
  const RunResult result = runDriveBot(simulator, system, setup.run);
  if (result.failed) {
    std::fprintf(stderr,
                 "graphslam drivebot: optimisation at step %ld (t = %.1f s) failed: %s: %s\n"
                 "no results written\n",
                 result.failed_step, result.failed_time, toString(result.failure.status),
                 result.failure.message.c_str());
    return kExitFailed;
  }
  if (!result.history_marginals.ok()) {
    std::fprintf(stderr, "graphslam drivebot: vehicle covariances: %s\nno results written\n",
                 result.history_marginals.message.c_str());
    return kExitFailed;
  }

  printReport(setup, scenario, result);
  writeSteps(out_dir + "/steps.csv", result);
  writeFileAtomically(out_dir + "/landmarks.csv", [&](std::ostream& out) {
    out << kLandmarkHeader;
    writeLandmarks(out, result.landmarks, scenario, "");
  });
  writeFileAtomically(out_dir + "/scenario.csv", [&](std::ostream& out) {
    out << "kind,index,x,y\n";
    for (std::size_t k = 0; k < scenario.waypoints.size(); ++k) {
      out << "waypoint," << k << ',' << num(scenario.waypoints[k][0]) << ','
          << num(scenario.waypoints[k][1]) << '\n';
    }
    for (std::size_t k = 0; k < scenario.landmarks.size(); ++k) {
      out << "landmark," << k + 1 << ',' << num(scenario.landmarks[k][0]) << ','
          << num(scenario.landmarks[k][1]) << '\n';
    }
  });
  writeStatistics(out_dir + "/graph_stats.csv", result.statistics);
  writeFileAtomically(out_dir + "/summary.csv", [&](std::ostream& out) {
    const Summary& f = result.final_summary;
    out << "quantity,value\nsteps," << result.steps.size() << "\noptimizations,"
        << result.optimizations << "\ntotal_optimization_time,"
        << num(result.total_optimization_time) << "\nfinal_status," << toString(f.status)
        << "\nfinal_chi2," << num(f.final_chi2) << "\nfinal_iterations," << f.iterations
        << "\nfinal_time," << num(f.total_time) << "\nvehicle_marginals_time,"
        << num(result.history_marginals.total_time) << "\nlandmark_marginals_time,"
        << num(result.landmark_marginals.total_time) << "\n";
  });
  if (result.loop_closure) {
    writeLoopClosure(out_dir + "/loop_closure.csv", *result.loop_closure, scenario);
  }
  io::saveG2o(out_dir + "/final.g2o", system.graph(), reg.types);
  std::printf(
      "wrote:         %s/{steps.csv, landmarks.csv, scenario.csv, graph_stats.csv, summary.csv%s, "
      "final.g2o}\n",
      out_dir.c_str(), result.loop_closure ? ", loop_closure.csv" : "");
  if (vm.count("plot")) {
    std::string title = scenario.name;
    if (!setup.description.empty()) title = setup.description;
    runPlotScript("plot_drivebot.py", {out_dir, title});
    std::printf("plots:         %s/*.png\n", out_dir.c_str());
  }
  return kExitOk;
}

}  // namespace graphslam::apps
