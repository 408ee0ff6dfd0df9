// SPDX-License-Identifier: MIT
// graphslam calibrate: measures the factorisation backends the "auto" solver chooses among
// on systems of the shapes SLAM makes (2D and 3D pose graphs, landmark graphs, point grids,
// scalar systems) and of sizes from a few hundred unknowns to a few hundred thousand, and
// writes the fitted cost model (solvers::CostModel) that auto's choices follow.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "cli_common.h"
#include "graphslam/optimizer/linear_system.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/simulator3d.h"
#include "graphslam/solvers/cost_model.h"
#include "graphslam/solvers/ordering.h"
#include "graphslam/support/file_util.h"
#include "graphslam/types_slam2d/edge_pointxy.h"
#include "graphslam/types_slam2d/edge_prior_xy.h"
#include "graphslam/types_slam2d/vertex_xy.h"

namespace graphslam::apps {

namespace {

using Clock = std::chrono::steady_clock;

/// A system to measure: H (upper triangle, full diagonal blocks) and its description.
struct System {
  std::string name;
  std::vector<int> col_ptr, row_idx, block_starts;
  std::vector<double> values;
  int num_blocks = 0;
  [[nodiscard]] SparseStructure structure() const {
    SparseStructure s;
    s.n = static_cast<int>(block_starts.back());
    s.col_ptr = col_ptr.data();
    s.row_idx = row_idx.data();
    s.block_starts = block_starts.data();
    s.num_blocks = num_blocks;
    return s;
  }
};

/// H of `graph` at its estimates (vertex 0 fixed: the gauge).
System systemOf(Graph graph, std::string name) {
  graph.vertex(graph.vertices().begin()->first)->setFixed(true);
  LinearSystem ls;
  ls.update(graph);
  ls.linearize();
  ls.assembleHessian();
  const SparseStructure s = ls.hessianStructure();
  System out;
  out.name = std::move(name);
  out.col_ptr.assign(s.col_ptr, s.col_ptr + s.n + 1);
  out.row_idx.assign(s.row_idx, s.row_idx + s.col_ptr[s.n]);
  out.block_starts.assign(s.block_starts, s.block_starts + s.num_blocks + 1);
  out.num_blocks = s.num_blocks;
  out.values.assign(ls.hessianValues().begin(), ls.hessianValues().end());
  return out;
}

/// An n x n grid of 2D points joined to their right and lower neighbours, one prior.
Graph pointGrid(int side) {
  Graph g;
  for (int i = 0; i < side * side; ++i) {
    auto v = std::make_unique<types_slam2d::VertexXY>();
    v->setId(i);
    v->setEstimate(Eigen::Vector2d(i % side, i / side));
    g.addVertex(std::move(v));
  }
  auto add = [&](int a, int b) {
    auto e = std::make_unique<types_slam2d::EdgePointXY>();
    e->setVertexIds({a, b});
    e->setMeasurement(Eigen::Vector2d(b % side - a % side, b / side - a / side));
    e->setInformation(Eigen::Matrix2d::Identity());
    g.addEdge(std::move(e));
  };
  for (int i = 0; i < side * side; ++i) {
    if ((i + 1) % side != 0) add(i, i + 1);
    if (i + side < side * side) add(i, i + side);
  }
  return g;
}

/// The scalar system of a point grid: one unknown per point (a weighted Laplacian plus the
/// identity), the shape of the isotropic path's H_s.
System scalarGrid(int side) {
  const int n = side * side;
  System out;
  out.name = "scalar grid " + std::to_string(side) + "x" + std::to_string(side);
  out.num_blocks = n;
  out.col_ptr.push_back(0);
  for (int c = 0; c < n; ++c) {
    for (int r : {c - side, c - 1}) {
      if (r >= 0 && (r != c - 1 || c % side != 0)) {
        out.row_idx.push_back(r);
        out.values.push_back(-1.0);
      }
    }
    out.row_idx.push_back(c);
    out.values.push_back(5.0);
    out.col_ptr.push_back(static_cast<int>(out.row_idx.size()));
  }
  for (int b = 0; b <= n; ++b) out.block_starts.push_back(b);
  return out;
}

/// Every system of the calibration, smallest first; `quick` keeps the small ones.
std::vector<std::function<System()>> systems(bool quick) {
  std::vector<std::function<System()>> out;
  const int scale = quick ? 1 : 0;
  for (int poses : {300, 1000, 3000, 10000, 30000}) {
    if (scale && poses > 1000) break;
    out.push_back([poses] {
      simulation::ManhattanOptions o;
      o.num_poses = poses;
      o.seed = 101;
      return systemOf(std::move(simulation::simulateManhattan(o).graph),
                      "2D poses " + std::to_string(poses));
    });
    out.push_back([poses] {
      simulation::ManhattanOptions o;
      o.num_poses = poses;
      o.num_landmarks = poses / 10;
      o.seed = 102;
      return systemOf(std::move(simulation::simulateManhattan(o).graph),
                      "2D poses " + std::to_string(poses) + " + landmarks");
    });
  }
  for (int poses : {200, 800, 2500, 8000}) {
    if (scale && poses > 800) break;
    for (auto shape : {simulation::PoseGraph3dOptions::Shape::kSphere,
                       simulation::PoseGraph3dOptions::Shape::kGrid}) {
      out.push_back([poses, shape] {
        simulation::PoseGraph3dOptions o;
        o.num_poses = poses;
        o.shape = shape;
        o.seed = 103;
        return systemOf(std::move(simulation::simulatePoseGraph3d(o).graph),
                        "3D poses " + std::to_string(poses));
      });
    }
  }
  for (int side : {20, 50, 120, 250}) {
    if (scale && side > 50) break;
    out.push_back([side] { return systemOf(pointGrid(side), "points " + std::to_string(side)); });
    out.push_back([side] { return scalarGrid(side); });
  }
  return out;
}

/// Median seconds of `run` over repeats (at least 3, more within `budget` seconds).
double medianSeconds(const std::function<bool()>& run, double budget) {
  std::vector<double> times;
  const auto start = Clock::now();
  while (
      times.size() < 3 ||
      (times.size() < 25 && std::chrono::duration<double>(Clock::now() - start).count() < budget)) {
    const auto t0 = Clock::now();
    if (!run()) return -1.0;
    times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::nth_element(times.begin(), times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2),
                   times.end());
  return times[times.size() / 2];
}

/// What measure() times and skips.
struct Budget {
  double seconds = 0.3;  ///< of repeats per system and backend (at least 3 runs)
  /// A backend whose factorisation took longer than this is not timed on systems of as
  /// many flops or more (the model has what it needs from it; the run stays short).
  double slowest = 1.0;
  std::map<std::string, double> slow_from;  ///< backend -> flops where it passed `slowest`
};

/// The samples of one system: every backend's factorisation, and METIS's ordering.
void measure(const System& sys, const SolverRegistry& solvers, Budget& budget,
             std::vector<solvers::CostSample>& samples) {
  const SparseStructure s = sys.structure();
  int block = 1;
  for (int b = 0; b < s.num_blocks; ++b) {
    block = std::max(block, s.block_starts[b + 1] - s.block_starts[b]);
  }
  const auto perm = solvers::fillReducingOrdering(Ordering::kAmd, s);
  const double flops = solvers::predictCholesky(s, perm).flops;
  const std::string llt = "block-llt-" + std::to_string(block > 3 ? 6 : block);
  for (const auto& [spec, line] : {std::pair<std::string, std::string>{"block-llt:amd", llt},
                                   {"eigen-ldlt:amd", "eigen-ldlt"},
                                   {"cholmod:amd", "cholmod-supernodal"}}) {
    if (!solvers.contains(spec) || (spec == "block-llt:amd" && block > 6)) continue;
    const auto slow = budget.slow_from.find(spec);
    if (slow != budget.slow_from.end() && flops >= slow->second) continue;
    auto solver = solvers.create(spec);
    if (!solver->analyze(s).ok()) continue;
    const double seconds =
        medianSeconds([&] { return solver->factorize(sys.values.data()).ok(); }, budget.seconds);
    if (seconds > budget.slowest) budget.slow_from[spec] = flops;
    if (seconds > 0) samples.push_back({line, static_cast<double>(s.n), flops, seconds});
    std::printf("  %-28s %-20s n %-8d flops %-10.3g %.3e s\n", sys.name.c_str(), spec.c_str(), s.n,
                flops, seconds);
  }
  if (solvers.contains("cholmod")) {
    const double seconds =
        medianSeconds([&] { return !solvers::fillReducingOrdering(Ordering::kMetis, s).empty(); },
                      budget.seconds);
    samples.push_back({"metis", static_cast<double>(s.num_blocks),
                       static_cast<double>(s.col_ptr[s.n]) / (block * block), seconds});
  }
}

/// The processor's name (/proc/cpuinfo), for the model's description.
std::string processorName() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown processor";
}

}  // namespace

int cmdCalibrate(const std::vector<std::string>& args) {
  std::string output;
  Budget budget;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("output,o", po::value(&output),
                                                 "write the cost model here")(
      "seconds", doubleValue(&budget.seconds, budget.seconds),
      "seconds of repeated factorisations per system and backend (at least 3 each)")(
      "slowest", doubleValue(&budget.slowest, budget.slowest),
      "a backend slower than this (seconds per factorisation) is not timed on larger "
      "systems")("quick", "small systems only (a few seconds; a coarse model for tests)");
  const auto vm = parse(args, desc);
  if (vm.count("help")) {
    printHelp(
        "usage: graphslam calibrate [-o MODEL.txt] [--seconds S] [--quick]\n"
        "Times block-llt, eigen-ldlt and supernodal CHOLMOD (and METIS's ordering) on "
        "simulated systems\nand fits the cost model the default solver chooses by "
        "(GRAPHSLAM_CALIBRATION=MODEL.txt makes the\ntool use it; the built-in one is "
        "solvers/calibration.txt).",
        desc);
    return kExitOk;
  }
  if (!(budget.seconds > 0.0)) throw UsageError("--seconds must be positive");
  if (!(budget.slowest > 0.0)) throw UsageError("--slowest must be positive");
  Registries reg;
  loadRegistries(reg, {});
  std::vector<solvers::CostSample> samples;
  for (const auto& make : systems(vm.count("quick") > 0)) {
    measure(make(), reg.solvers, budget, samples);
    std::fflush(stdout);
  }
  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
  const solvers::CostModel model = solvers::fitCostModel(
      samples, std::string("graphslam calibrate") + (vm.count("quick") ? " --quick" : "") + ", " +
                   date + ", " + processorName() + ", " + std::to_string(samples.size()) +
                   " measurements");
  std::ostringstream text;
  model.write(text);
  std::cout << text.str();
  if (!output.empty()) {
    support::writeFileAtomically(output, [&](std::ostream& out) { out << text.str(); });
    std::cout << "wrote " << output << "\n";
  }
  return kExitOk;
}

}  // namespace graphslam::apps
