// SPDX-License-Identifier: MIT
// graphslam.drivebot: the DriveBot simulator and online SLAM system (UCL COMP0130
// coursework 2, docs/DRIVEBOT.md) run from Python: a scenario, the sensors, how often to
// optimise; the run's records as numpy arrays and its graph as a graphslam.Graph.
#include <pybind11/stl.h>

#include <cmath>

#include "common.h"
#include "graphslam/core/graph_copy.h"
#include "graphslam/drivebot/run.h"
#include "graphslam/drivebot/scenario.h"
#include "graphslam/drivebot/simulator.h"
#include "graphslam/drivebot/slam_system.h"
#include "graphslam/incremental/linear_prior_edge.h"

namespace graphslam::python {

namespace {

using namespace graphslam::drivebot;

py::array_t<double> rows3(const std::vector<Eigen::Vector3d>& v) {
  auto a = newArray({static_cast<py::ssize_t>(v.size()), 3});
  for (std::size_t k = 0; k < v.size(); ++k) {
    for (int i = 0; i < 3; ++i) a.mutable_data()[3 * k + i] = v[k][i];
  }
  return a;
}

py::dict stepArrays(const std::vector<StepRecord>& steps) {
  std::vector<double> time, chi2;
  std::vector<Eigen::Vector3d> truth, online;
  std::vector<VertexId> step, optimized;
  for (const StepRecord& s : steps) {
    step.push_back(static_cast<VertexId>(s.step));
    time.push_back(s.time);
    truth.push_back(s.truth);
    online.push_back(s.online);
    optimized.push_back(s.optimized ? 1 : 0);
    chi2.push_back(s.chi2);
  }
  py::dict d;
  d["step"] = toIdArray(step);
  d["time"] = toArray(time);
  d["truth"] = rows3(truth);
  d["online"] = rows3(online);
  d["optimized"] = toIdArray(optimized).attr("astype")("bool");
  d["chi2"] = toArray(chi2);
  return d;
}

/// The fixed-lag window of run()'s arguments; `policy` says what becomes of landmarks.
incremental::WindowOptions windowOptions(std::size_t states, std::size_t slack, double seconds,
                                         const std::string& policy) {
  if (!(seconds >= 0 && std::isfinite(seconds))) {
    throw py::value_error("window_seconds must be a finite number >= 0 (0: off)");
  }
  incremental::WindowOptions w;
  w.states = states;
  w.slack = slack;
  w.seconds = seconds;
  if (policy == "anew") {
    w.reinitialize_landmarks = true;
  } else if (policy == "keep") {
    w.keep_landmarks = true;
  } else if (policy != "leave") {
    throw py::value_error("landmarks is 'leave', 'anew' or 'keep', not '" + policy + "'");
  }
  return w;
}

py::object run(const std::string& scenario, const std::string& data_dir, std::uint64_t seed,
               const std::vector<std::string>& sensors, int optimize_every, long max_steps,
               int final_iterations, const std::string& optimizer, std::size_t window,
               std::size_t window_slack, double window_seconds, const std::string& policy,
               const std::string& checkpoint, long checkpoint_every, const std::string& resume) {
  if (optimize_every < 0 || final_iterations < 0) {
    throw py::value_error("optimize_every and final_iterations must be >= 0");
  }
  if (max_steps < 1) throw py::value_error("max_steps must be at least 1");
  if (optimizer != "incremental" && optimizer != "batch") {
    throw py::value_error("optimizer is 'incremental' or 'batch', not '" + optimizer + "'");
  }
  SimulatorConfig sim;
  sim.seed = seed;
  sim.max_steps = max_steps;
  for (const std::string& s : sensors) {
    if (s == "gps") {
      sim.enable_gps = true;
    } else if (s == "compass") {
      sim.enable_compass = true;
    } else if (s == "laser") {
      sim.enable_laser = true;
    } else {
      throw py::value_error("sensors are gps, compass and laser, not '" + s + "'");
    }
  }
  SlamSystemOptions slam;
  slam.optimize_every = optimize_every;
  slam.incremental = optimizer == "incremental";
  slam.incremental_options.window = windowOptions(window, window_slack, window_seconds, policy);
  RunOptions options;
  options.final_iterations = final_iterations;
  if (checkpoint_every < 0 || checkpoint.empty() != (checkpoint_every == 0)) {
    throw py::value_error("checkpoint and checkpoint_every (>= 1) go together");
  }
  options.checkpoint_path = checkpoint;
  options.checkpoint_every = checkpoint_every;
  options.resume_path = resume;
  options.types = &registries().types;
  // What decides the run: a checkpoint is resumed only under the same.
  options.settings = scenario + " " + data_dir + " seed " + std::to_string(seed) + " every " +
                     std::to_string(optimize_every) + " steps " + std::to_string(max_steps) + " " +
                     optimizer + " window " + std::to_string(window) + "/" +
                     std::to_string(window_slack) + "/" + std::to_string(window_seconds) + " " +
                     policy;
  for (const std::string& sensor : sensors) options.settings += " " + sensor;
  Simulator simulator(findScenario(scenario, data_dir), sim);
  DriveBotSlamSystem system(registries().solvers, slam);
  RunResult r;
  {
    py::gil_scoped_release release;
    r = runDriveBot(simulator, system, options);
  }
  py::dict d;
  d["steps"] = stepArrays(r.steps);
  d["optimizer"] = r.optimizer;
  d["failed"] = r.failed;
  d["message"] = r.failed ? r.failure.message : r.final_summary.message;
  d["final_chi2"] = r.final_summary.final_chi2;
  d["optimizations"] = r.optimizations;
  d["optimization_time"] = r.total_optimization_time;
  d["marginalized"] = system.marginalizedCount();
  d["refused_observations"] = system.refusedObservations();
  d["history"] = rows3(r.history.x);
  d["history_variance"] = rows3(r.history.variance);
  std::vector<VertexId> ids;
  auto landmarks = newArray({static_cast<py::ssize_t>(r.landmarks.size()), 2});
  auto covariances = newArray({static_cast<py::ssize_t>(r.landmarks.size()), 2, 2});
  for (std::size_t k = 0; k < r.landmarks.size(); ++k) {
    ids.push_back(r.landmarks[k].landmark_id);
    landmarks.mutable_data()[2 * k] = r.landmarks[k].x.x();
    landmarks.mutable_data()[2 * k + 1] = r.landmarks[k].x.y();
    const Eigen::Matrix2d& c = r.landmarks[k].covariance;
    const double cells[4] = {c(0, 0), c(0, 1), c(1, 0), c(1, 1)};
    std::copy(cells, cells + 4, covariances.mutable_data() + 4 * k);
  }
  d["landmark_ids"] = toIdArray(ids);
  d["landmarks"] = landmarks;
  d["landmark_covariances"] = covariances;
  auto g = std::make_shared<PyGraph>();
  g->graph = incremental::copyWithoutPriors(system.graph(), registries().types);
  d["graph"] = g;
  static const auto* ns = new py::object(py::module_::import("types").attr("SimpleNamespace"));
  return (*ns)(**d);
}

}  // namespace

void bindDrivebot(py::module_& m) {
  py::module_ db = m.def_submodule(
      "drivebot", "The DriveBot simulator and online SLAM system (docs/DRIVEBOT.md).");
  db.def("scenarios", &builtinScenarioNames, "The built-in scenario names (q1_b ... q3_a).");
  db.def("run", &run, py::arg("scenario") = "q1_b", py::arg("data_dir") = "", py::arg("seed") = 0,
         py::arg("sensors") = std::vector<std::string>{}, py::arg("optimize_every") = 0,
         py::arg("max_steps") = 1L << 40, py::arg("final_iterations") = 20,
         py::arg("optimizer") = "incremental", py::arg("window") = 0, py::arg("window_slack") = 0,
         py::arg("window_seconds") = 0.0, py::arg("landmarks") = "leave",
         py::arg("checkpoint") = "", py::arg("checkpoint_every") = 0, py::arg("resume") = "",
         "Simulates the vehicle through `scenario` (a built-in name, a folder with x0.txt, wp.txt "
         "and lm.txt, or a name under data_dir) with odometry and the `sensors` (gps, compass, "
         "laser), runs the online SLAM system (optimising every `optimize_every` steps, 0: at "
         "the end only) with the `optimizer` of the per-step optimisations (\"incremental\" or "
         "\"batch\"; the end-of-run one is a batch one), and returns a namespace: optimizer (the "
         "one used: modes that remove edges fall back to batch), steps (dict of arrays: step, "
         "time, truth "
         "(N, 3), online (N, 3), optimized, chi2), failed, message, final_chi2, optimizations, "
         "optimization_time, history (the smoothed vehicle poses), history_variance, "
         "landmark_ids, landmarks (L, 2), landmark_covariances (L, 2, 2) and the graph. "
         "`window` (vehicle states) or `window_seconds` make the system a fixed-lag smoother "
         "(the tool's --window, --window-slack, --window-seconds; docs/DRIVEBOT.md): history "
         "then holds each state as it left the window (its variance NaN), `landmarks` says what "
         "becomes of a landmark whose observers all left (\"leave\": later sightings dropped, "
         "counted in refused_observations; \"anew\": started again; \"keep\": it stays), "
         "marginalized counts the vertices that left, and graph is the window's (without its "
         "marginalisation priors). `checkpoint` with `checkpoint_every` N writes the run's "
         "state there at the first optimised step once N steps have passed since the last; "
         "`resume` continues from such a file (written with the same arguments; the simulator "
         "is replayed to its step) to the estimates of the run that wrote it, bit for bit "
         "(graphslam.InputError for a file it cannot resume).");
}

}  // namespace graphslam::python
