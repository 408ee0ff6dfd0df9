// SPDX-License-Identifier: MIT
// graphslam simulate: a seeded Manhattan-world graph or 3D pose graph and its ground truth.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "graphslam/io/g2o.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/simulator3d.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam2d/vertex_xy.h"
#include "graphslam/types_slam3d/vertex_se3.h"
#include "output_set.h"

namespace graphslam::apps {

namespace {

/// Bounds on what `simulate` makes, checked before simulating (the simulator would
/// otherwise run on for minutes and then be killed, or fail to allocate).
struct SimulateLimits {
  /// Largest share of this machine's physical memory the simulated graph may take; the
  /// rest is left to the writer and the system.
  double memory_fraction = 0.75;
  /// Memory of a simulated 3D pose graph per pose, in bytes: its VERTEX_SE3 and about 2.5
  /// EDGE_SE3:QUAT (measured: simulate --3d sphere --poses 100000 peaks at 292 MB resident).
  double bytes_per_pose3d = 2900.0;
};

/// This machine's physical memory in bytes (0 when unknown).
double physicalMemory() {
  return static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
         static_cast<double>(::sysconf(_SC_PAGESIZE));
}

/// Refuses a graph of about `bytes` (described by `what`) that would not fit in
/// SimulateLimits::memory_fraction of this machine's memory.
void checkMemory(double bytes, const std::string& what, const SimulateLimits& limits = {}) {
  const double memory = physicalMemory();
  if (memory > 0 && bytes > limits.memory_fraction * memory) {
    char text[160];
    std::snprintf(text, sizeof text,
                  " would take about %.1f GB, more than this machine's memory allows (%.1f GB "
                  "of %.1f GB)",
                  bytes / 1e9, limits.memory_fraction * memory / 1e9, memory / 1e9);
    throw UsageError(what + text);
  }
}

void checkSimulationSize(const simulation::ManhattanOptions& sim) {
  const simulation::ManhattanSize size = simulation::estimateSize(sim);
  char what[160];
  std::snprintf(what, sizeof what, "%d poses and %d landmarks (about %.3g landmark observations)",
                sim.num_poses, sim.num_landmarks, size.observations);
  checkMemory(size.bytes, what);
}

/// Writes `result`'s graph to `output` (staged in `outputs`), prints its size, and when
/// `truth` is named sets the true estimates with `setTruth(graph)` and writes it there too;
/// then puts both in place together.
template <typename Result, typename SetTruth>
int writeSimulated(Result& result, const std::string& summary, const std::string& output,
                   const std::string& truth, OutputSet& outputs, SetTruth setTruth) {
  Registries reg;
  loadRegistries(reg, {});
  io::saveG2o(outputs.staged(output), result.graph, reg.types);
  std::string report = "wrote " + output + ": " + std::to_string(result.graph.numVertices()) +
                       " vertices, " + std::to_string(result.graph.numEdges()) + " edges (" +
                       summary + ")\n";
  if (!truth.empty()) {
    setTruth(result.graph);
    io::saveG2o(outputs.staged(truth), result.graph, reg.types);
    report += "wrote " + truth + " (ground truth)\n";
  }
  outputs.commit();
  std::cout << report;
  return kExitOk;
}

/// The options of --3d SHAPE, checked (the shape, the memory it would take).
simulation::PoseGraph3dOptions options3d(const std::string& shape,
                                         const simulation::ManhattanOptions& sim) {
  simulation::PoseGraph3dOptions o;
  if (shape == "sphere") {
    o.shape = simulation::PoseGraph3dOptions::Shape::kSphere;
  } else if (shape == "grid") {
    o.shape = simulation::PoseGraph3dOptions::Shape::kGrid;
  } else {
    throw UsageError("--3d must be sphere or grid, not '" + shape + "'");
  }
  checkMemory(SimulateLimits{}.bytes_per_pose3d * sim.num_poses,
              std::to_string(sim.num_poses) + " 3D poses");
  // Every point is tested against every pose (simulatePoseGraph3d): bounded like the poses.
  constexpr long long kMaxPointPoseTests = 20000000000LL;
  if (static_cast<long long>(sim.num_landmarks) * sim.num_poses > kMaxPointPoseTests) {
    throw UsageError(
        "--landmarks x --poses: at most 2e10 in 3D (each point is placed against "
        "every pose)");
  }
  o.num_poses = sim.num_poses;
  o.num_points = sim.num_landmarks;
  o.seed = sim.seed;
  return o;
}

/// The 3D pose graph of `o`: written to `output`, its ground truth to `truth`.
int simulate3d(const simulation::PoseGraph3dOptions& o, const std::string& output,
               const std::string& truth, OutputSet& outputs) {
  auto result = simulation::simulatePoseGraph3d(o);
  const std::string summary = std::to_string(result.num_loop_closures) + " loop closures, " +
                              std::to_string(result.num_point_observations) + " point observations";
  return writeSimulated(result, summary, output, truth, outputs, [&](Graph& graph) {
    for (int i = 0; i < o.num_poses; ++i) {
      static_cast<types_slam3d::VertexSE3*>(graph.vertex(i))
          ->setEstimate(result.true_poses[static_cast<std::size_t>(i)]);
    }
    for (std::size_t m = 0; m < result.true_points.size(); ++m) {
      static_cast<types_slam3d::VertexPointXYZ*>(graph.vertex(o.num_poses + static_cast<int>(m)))
          ->setEstimate(result.true_points[m]);
    }
  });
}

/// The Manhattan world: written to `output`, its ground truth to `truth`.
int simulate2d(const simulation::ManhattanOptions& sim, const std::string& output,
               const std::string& truth, OutputSet& outputs) {
  auto result = simulation::simulateManhattan(sim);
  const std::string summary = std::to_string(result.num_loop_closures) + " loop closures, " +
                              std::to_string(result.num_observations) + " landmark observations";
  return writeSimulated(result, summary, output, truth, outputs, [&](Graph& graph) {
    for (int i = 0; i < sim.num_poses; ++i) {
      static_cast<types_slam2d::VertexSE2*>(graph.vertex(i))->setEstimate(result.true_poses[i]);
    }
    for (std::size_t k = 0; k < result.true_landmarks.size(); ++k) {
      static_cast<types_slam2d::VertexXY*>(graph.vertex(sim.num_poses + static_cast<int>(k)))
          ->setEstimate(result.true_landmarks[k]);
    }
  });
}

}  // namespace

int cmdSimulate(const std::vector<std::string>& args) {
  std::string output, truth, shape3d;
  double noise_scale = 1.0;
  simulation::ManhattanOptions sim;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("output,o", po::value(&output),
                                                 "write the graph (odometry initial guess) here")(
      "truth", po::value(&truth), "write the ground truth graph (same edges, true vertices) here")(
      "poses", po::value(&sim.num_poses)->default_value(sim.num_poses), "number of poses")(
      "landmarks", po::value(&sim.num_landmarks)->default_value(0), "number of landmarks")(
      "seed", po::value(&sim.seed)->default_value(sim.seed), "random seed")(
      "world-size", po::value(&sim.world_size)->default_value(0),
      "side of the square world in grid cells (0: automatic)")(
      "noise-scale", po::value(&noise_scale)->default_value(1.0),
      "multiply every noise standard deviation (odometry, loop closures, landmarks; 2D and "
      "3D) by this; the edges' information follows")(
      "3d", po::value(&shape3d),
      "an SE(3) pose graph instead: sphere (rings of poses, loop closures between rings) or "
      "grid (a snake through a cubic lattice, loop closures to lattice neighbours); "
      "--landmarks adds 3D points seen from the poses within 15 m (EDGE_SE3_TRACKXYZ)");
  const auto vm = parse(args, desc);
  if (vm.count("help")) {
    printHelp(
        "usage: graphslam simulate -o OUT.g2o [--truth GT.g2o] [--poses N] [--landmarks L] [--seed "
        "S] [--3d sphere|grid] [--noise-scale F]\n"
        "Writes a seeded synthetic Manhattan-world pose graph, optionally with landmarks, or a "
        "3D pose graph.",
        desc);
    return kExitOk;
  }
  if (output.empty()) throw UsageError("simulate needs -o OUT.g2o");
  if (sim.num_poses < 2) throw UsageError("--poses must be at least 2");
  if (sim.num_landmarks < 0) throw UsageError("--landmarks must be at least 0");
  if (sim.world_size < 0) throw UsageError("--world-size must be at least 0 (0: automatic)");
  if (!(noise_scale > 0.0) || !std::isfinite(noise_scale)) {
    throw UsageError("--noise-scale must be a positive finite number");
  }
  sim.sigma_xy *= noise_scale;
  sim.sigma_theta *= noise_scale;
  sim.sigma_landmark *= noise_scale;
  if (!truth.empty() && truth == output) {
    throw UsageError("--truth and -o name the same file, " + output);
  }
  // Both files checked before the work (OutputSet also tells other spellings of one file
  // apart) and put in place together.
  const bool is3d = vm.count("3d") > 0;
  simulation::PoseGraph3dOptions o3d;
  if (is3d) {
    o3d = options3d(shape3d, sim);
    o3d.sigma_translation *= noise_scale;
    o3d.sigma_rotation *= noise_scale;
  } else {
    checkSimulationSize(sim);
  }
  OutputSet outputs({output, truth}, {});
  return outputs.writeAll([&] {
    return is3d ? simulate3d(o3d, output, truth, outputs) : simulate2d(sim, output, truth, outputs);
  });
}

}  // namespace graphslam::apps
