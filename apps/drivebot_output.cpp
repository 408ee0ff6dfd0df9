// SPDX-License-Identifier: MIT
// graphslam drivebot's output: the report and the files of a run.
#include "drivebot_output.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "graphslam/diagnostics/graph_checks.h"
#include "graphslam/io/g2o.h"
#include "graphslam/support/file_util.h"

namespace graphslam::apps {

using namespace graphslam::drivebot;

namespace {

std::string num(double v) { return std::isfinite(v) ? support::formatDouble(v) : "nan"; }

double wrapPi(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a - kPi;
}

void writeSteps(const std::string& path, const RunResult& r) {
  const bool aligned = r.history.time.size() == r.steps.size();
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "step,time,waypoint,true_x,true_y,true_psi,x,y,psi,var_x,var_y,var_psi,online_x,"
           "online_y,online_psi,online_var_x,online_var_y,online_var_psi,optimized,chi2,"
           "optimization_time,optimization_cpu_time,iterations,vertices,edges,observations,gps,"
           "compass\n";
    for (std::size_t k = 0; k < r.steps.size(); ++k) {
      const StepRecord& s = r.steps[k];
      out << s.step << ',' << num(s.time) << ',' << s.waypoint_index;
      for (int i = 0; i < 3; ++i) out << ',' << num(s.truth[i]);
      for (int i = 0; i < 3; ++i) out << ',' << (aligned ? num(r.history.x[k][i]) : "nan");
      for (int i = 0; i < 3; ++i) out << ',' << (aligned ? num(r.history.variance[k][i]) : "nan");
      for (int i = 0; i < 3; ++i) out << ',' << num(s.online[i]);
      for (int i = 0; i < 3; ++i) out << ',' << num(s.online_variance[i]);
      out << ',' << (s.optimized ? 1 : 0) << ',' << num(s.chi2) << ',' << num(s.optimization_time)
          << ',' << num(s.optimization_cpu_time) << ',' << s.iterations << ',' << s.vertices << ','
          << s.edges << ',' << s.observations << ',' << (s.gps ? 1 : 0) << ','
          << (s.compass ? 1 : 0) << '\n';
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
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "phase,step,time,chi2,vehicle_x,vehicle_y,vehicle_psi,vehicle_det,vehicle_cov_xx,"
           "vehicle_cov_xy,vehicle_cov_yy,closing_landmarks,"
        << kLandmarkHeader;
    std::string closing;
    for (int id : lc.landmark_ids) closing += (closing.empty() ? "" : " ") + std::to_string(id);
    for (const auto* m : {&lc.before, &lc.after}) {
      std::ostringstream prefix;
      prefix << (m == &lc.before ? "before" : "after") << ',' << m->step << ',' << num(m->time)
             << ',' << num(m->chi2) << ',' << num(m->vehicle[0]) << ',' << num(m->vehicle[1]) << ','
             << num(m->vehicle[2]) << ','
             << num(m->vehicle_covariance.topLeftCorner<2, 2>().determinant()) << ','
             << num(m->vehicle_covariance(0, 0)) << ',' << num(m->vehicle_covariance(0, 1)) << ','
             << num(m->vehicle_covariance(1, 1)) << ',' << closing << ',';
      writeLandmarks(out, m->landmarks, scenario, prefix.str().c_str());
    }
  });
}

/// Every vehicle vertex's covariance diagonal just before and just after the closure.
void writeLoopClosureVehicle(const std::string& path, const LoopClosure& lc) {
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "phase,step,time,x,y,psi,var_x,var_y,var_psi\n";
    for (const auto* m : {&lc.before, &lc.after}) {
      const VehicleHistory& h = m->vehicle_history;
      for (std::size_t k = 0; k < h.time.size(); ++k) {
        out << (m == &lc.before ? "before," : "after,") << m->step << ',' << num(h.time[k]);
        for (int i = 0; i < 3; ++i) out << ',' << num(h.x[k][i]);
        for (int i = 0; i < 3; ++i) out << ',' << num(h.variance[k][i]);
        out << '\n';
      }
    }
  });
}

void writeStatistics(const std::string& path, const GraphStatistics& g) {
  support::writeFileAtomically(path, [&](std::ostream& out) {
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

void writeScenario(const std::string& path, const Scenario& scenario) {
  support::writeFileAtomically(path, [&](std::ostream& out) {
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
}

void writeSummary(const std::string& path, const RunResult& r) {
  support::writeFileAtomically(path, [&](std::ostream& out) {
    const Summary& f = r.final_summary;
    out << "quantity,value\noptimizer," << r.optimizer << "\nsteps," << r.steps.size()
        << "\noptimizations," << r.optimizations << "\ntotal_optimization_time,"
        << num(r.total_optimization_time) << "\ntotal_optimization_cpu_time,"
        << num(r.total_optimization_cpu_time) << "\nfinal_status," << toString(f.status)
        << "\nfinal_chi2," << num(f.final_chi2) << "\nfinal_iterations," << f.iterations
        << "\nfinal_time," << num(f.total_time) << "\nvehicle_marginals_time,"
        << num(r.history_marginals.total_time) << "\nlandmark_marginals_time,"
        << num(r.landmark_marginals.total_time) << "\n";
  });
}

double median(std::vector<double> t) {
  if (t.empty()) return std::nan("");
  std::nth_element(t.begin(), t.begin() + static_cast<long>(t.size() / 2), t.end());
  return t[t.size() / 2];
}

/// Median CPU and wall time of the optimisations of the steps [first, last) of the run
/// (indices into RunResult::steps); NaN when none optimised there.
std::pair<double, double> medianOptimizationTimes(const RunResult& r, std::size_t first,
                                                  std::size_t last) {
  std::vector<double> cpu, wall;
  for (std::size_t k = first; k < last && k < r.steps.size(); ++k) {
    if (!r.steps[k].optimized) continue;
    cpu.push_back(r.steps[k].optimization_cpu_time);
    wall.push_back(r.steps[k].optimization_time);
  }
  return {median(cpu), median(wall)};
}

/// "optimisation: N runs, ... ; median per step ... (first quarter of the steps) ..."
void printOptimizationLine(const RunResult& r) {
  std::printf("optimisation:  %d runs, %.3f s CPU (%.3f s wall) in total", r.optimizations,
              r.total_optimization_cpu_time, r.total_optimization_time);
  const std::size_t n = r.steps.size(), quarter = n / 4;
  const auto first = medianOptimizationTimes(r, 0, quarter);
  const auto last = medianOptimizationTimes(r, n - quarter, n);
  if (quarter > 0 && std::isfinite(first.first) && std::isfinite(last.first)) {
    std::printf(
        "; median per optimisation %.3f ms CPU (%.3f ms wall) in the first quarter of the "
        "steps, %.3f ms CPU (%.3f ms wall) in the last",
        1e3 * first.first, 1e3 * first.second, 1e3 * last.first, 1e3 * last.second);
  }
  std::printf("\n");
}

}  // namespace

void printDrivebotReport(const Scenario& scenario, const RunResult& r, bool laser) {
  const auto& g = r.statistics;
  std::printf("steps:         %zu (t = %.1f s), last waypoint index %d of %zu\n", r.steps.size(),
              r.steps.empty() ? 0.0 : r.steps.back().time,
              r.steps.empty() ? 0 : r.steps.back().waypoint_index, scenario.waypoints.size());
  std::printf(
      "graph:         %zu vehicle vertices, %zu landmark vertices, %zu edges (%zu prediction, "
      "%zu landmark observation, %zu GPS, %zu compass, %zu prior)\n",
      g.vehicle_vertices, g.landmark_vertices, g.edges, g.prediction_edges, g.observation_edges,
      g.gps_edges, g.compass_edges, g.prior_edges);
  if (laser) {
    std::printf(
        "observations:  %zu received, %zu in the graph; %.3f per vehicle vertex, %.1f per "
        "landmark\n",
        g.observations_received, g.observation_edges, g.observations_per_vehicle_vertex,
        g.observations_per_landmark);
  }
  printOptimizationLine(r);
  std::printf("final:         %s, chi2 %.6g, %d iterations\n", toString(r.final_summary.status),
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
    const Eigen::Vector3d vb = lc.before.vehicle_covariance.diagonal();
    const Eigen::Vector3d va = lc.after.vehicle_covariance.diagonal();
    std::printf(
        "  vehicle: var x %.4g -> %.4g m^2, var y %.4g -> %.4g m^2, var psi %.4g -> %.4g rad^2\n",
        vb[0], va[0], vb[1], va[1], vb[2], va[2]);
  }
}

void writeDrivebotResults(const std::string& out_dir, const Scenario& scenario, const RunResult& r,
                          const Graph& graph, const TypeRegistry& types) {
  writeSteps(out_dir + "/steps.csv", r);
  support::writeFileAtomically(out_dir + "/landmarks.csv", [&](std::ostream& out) {
    out << kLandmarkHeader;
    writeLandmarks(out, r.landmarks, scenario, "");
  });
  writeScenario(out_dir + "/scenario.csv", scenario);
  writeStatistics(out_dir + "/graph_stats.csv", r.statistics);
  writeSummary(out_dir + "/summary.csv", r);
  if (r.loop_closure) {
    writeLoopClosure(out_dir + "/loop_closure.csv", *r.loop_closure, scenario);
    writeLoopClosureVehicle(out_dir + "/loop_closure_vehicle.csv", *r.loop_closure);
  }
  io::saveG2o(out_dir + "/final.g2o", graph, types);
}

}  // namespace graphslam::apps
