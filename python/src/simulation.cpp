// SPDX-License-Identifier: MIT
// Simulators (Manhattan world, SE(3) sphere and grid), wrong loop closures, dead reckoning,
// the global initial guess and the observability check.
#include <pybind11/stl.h>

#include "common.h"
#include "graphslam/diagnostics/observability.h"
#include "graphslam/init/dead_reckoning.h"
#include "graphslam/init/initial_guess.h"
#include "graphslam/simulation/simulator.h"
#include "graphslam/simulation/simulator3d.h"
#include "graphslam/simulation/wrong_loop_closures.h"

namespace graphslam::python {

namespace {

py::object namespaceOf(py::dict values) {
  static const auto* ns = new py::object(py::module_::import("types").attr("SimpleNamespace"));
  return (*ns)(**values);
}

std::shared_ptr<PyGraph> wrap(Graph&& graph) {
  auto g = std::make_shared<PyGraph>();
  g->graph = std::move(graph);
  return g;
}

py::object simulateManhattan(int num_poses, std::uint32_t seed, int world_size, double turn_probability,
                             int min_loop_gap, double loop_probability, double sigma_xy,
                             double sigma_theta, int num_landmarks, double landmark_range,
                             double sigma_landmark) {
  if (num_poses < 2) throw py::value_error("num_poses must be at least 2");
  if (num_landmarks < 0 || world_size < 0 || min_loop_gap < 1) {
    throw py::value_error("num_landmarks and world_size must be >= 0, min_loop_gap >= 1");
  }
  simulation::ManhattanOptions o;
  o.num_poses = num_poses;
  o.seed = seed;
  o.world_size = world_size;
  o.turn_probability = turn_probability;
  o.min_loop_gap = min_loop_gap;
  o.loop_probability = loop_probability;
  o.sigma_xy = sigma_xy;
  o.sigma_theta = sigma_theta;
  o.num_landmarks = num_landmarks;
  o.landmark_range = landmark_range;
  o.sigma_landmark = sigma_landmark;
  simulation::SimulatedGraph s;
  {
    py::gil_scoped_release release;
    s = simulation::simulateManhattan(o);
  }
  auto poses = newArray({static_cast<py::ssize_t>(s.true_poses.size()), 3});
  for (std::size_t k = 0; k < s.true_poses.size(); ++k) {
    poses.mutable_data()[3 * k] = s.true_poses[k].translation().x();
    poses.mutable_data()[3 * k + 1] = s.true_poses[k].translation().y();
    poses.mutable_data()[3 * k + 2] = s.true_poses[k].angle();
  }
  auto landmarks = newArray({static_cast<py::ssize_t>(s.true_landmarks.size()), 2});
  for (std::size_t k = 0; k < s.true_landmarks.size(); ++k) {
    landmarks.mutable_data()[2 * k] = s.true_landmarks[k].x();
    landmarks.mutable_data()[2 * k + 1] = s.true_landmarks[k].y();
  }
  py::dict d;
  d["graph"] = wrap(std::move(s.graph));
  d["true_poses"] = poses;
  d["true_landmarks"] = landmarks;
  d["num_loop_closures"] = s.num_loop_closures;
  d["num_observations"] = s.num_observations;
  return namespaceOf(d);
}

py::object simulate3d(const std::string& shape, int num_poses, std::uint32_t seed, double scale,
                      double loop_probability, double sigma_translation, double sigma_rotation,
                      int num_points, double point_range, double sigma_point) {
  simulation::PoseGraph3dOptions o;
  if (shape == "sphere") {
    o.shape = simulation::PoseGraph3dOptions::Shape::kSphere;
  } else if (shape == "grid") {
    o.shape = simulation::PoseGraph3dOptions::Shape::kGrid;
  } else {
    throw py::value_error("shape must be sphere or grid, not '" + shape + "'");
  }
  if (num_poses < 2 || num_points < 0) throw py::value_error("num_poses must be >= 2 and num_points >= 0");
  o.num_poses = num_poses;
  o.seed = seed;
  o.scale = scale;
  o.loop_probability = loop_probability;
  o.sigma_translation = sigma_translation;
  o.sigma_rotation = sigma_rotation;
  o.num_points = num_points;
  o.point_range = point_range;
  o.sigma_point = sigma_point;
  simulation::SimulatedGraph3d s;
  {
    py::gil_scoped_release release;
    s = simulation::simulatePoseGraph3d(o);
  }
  auto poses = newArray({static_cast<py::ssize_t>(s.true_poses.size()), 7});
  for (std::size_t k = 0; k < s.true_poses.size(); ++k) {
    const Eigen::Vector3d t = s.true_poses[k].translation();
    Eigen::Quaterniond q(s.true_poses[k].quaternion());
    if (q.w() < 0) q.coeffs() *= -1.0;
    const double row[7] = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    std::copy(row, row + 7, poses.mutable_data() + 7 * k);
  }
  auto points = newArray({static_cast<py::ssize_t>(s.true_points.size()), 3});
  for (std::size_t k = 0; k < s.true_points.size(); ++k) {
    for (int i = 0; i < 3; ++i) points.mutable_data()[3 * k + i] = s.true_points[k][i];
  }
  py::dict d;
  d["graph"] = wrap(std::move(s.graph));
  d["true_poses"] = poses;
  d["true_points"] = points;
  d["num_loop_closures"] = s.num_loop_closures;
  d["num_point_observations"] = s.num_point_observations;
  return namespaceOf(d);
}

py::dict observability(PyGraph& g, int threads) {
  g.checkIdle();
  ObservabilityOptions o;
  o.types = &registries().types;
  o.threads = threads;
  const ObservabilityReport r = checkObservability(g.graph, o);
  py::list undetermined;
  for (const auto& u : r.undetermined) {
    py::dict d;
    d["id"] = u.id;
    d["tag"] = u.tag;
    d["dimension"] = u.dimension;
    d["rank"] = u.rank;
    d["reason"] = u.reason;
    d["edges"] = u.edges;
    d["neighbours"] = u.neighbours;
    undetermined.append(d);
  }
  py::dict out;
  out["ok"] = r.ok();
  out["undetermined"] = undetermined;
  out["unanchored"] = r.unanchored;
  out["anchors"] = r.anchors;
  out["description"] = r.describe();
  return out;
}

}  // namespace

void bindSimulation(py::module_& m) {
  m.def("simulate_manhattan", &simulateManhattan, py::arg("num_poses") = 1000, py::arg("seed") = 42,
        py::arg("world_size") = 0, py::arg("turn_probability") = 0.3, py::arg("min_loop_gap") = 10,
        py::arg("loop_probability") = 0.8, py::arg("sigma_xy") = 0.05, py::arg("sigma_theta") = 0.01,
        py::arg("num_landmarks") = 0, py::arg("landmark_range") = 2.0, py::arg("sigma_landmark") = 0.05,
        "The seeded Manhattan-world simulator (the graphslam tool's default graph): a namespace "
        "with graph (VERTEX_SE2 0..N-1 at dead-reckoned estimates, landmarks N.. as VERTEX_XY), "
        "true_poses (N, 3), true_landmarks (L, 2), num_loop_closures, num_observations.");
  m.def("simulate_pose_graph_3d", &simulate3d, py::arg("shape") = "sphere", py::arg("num_poses") = 2500,
        py::arg("seed") = 42, py::arg("scale") = 10.0, py::arg("loop_probability") = 1.0,
        py::arg("sigma_translation") = 0.05, py::arg("sigma_rotation") = 0.01, py::arg("num_points") = 0,
        py::arg("point_range") = 15.0, py::arg("sigma_point") = 0.05,
        "A seeded SE(3) pose graph (sphere as sphere2500, or grid): a namespace with graph, "
        "true_poses (N, 7: x y z qx qy qz qw), true_points (M, 3), num_loop_closures, "
        "num_point_observations.");
  m.def(
      "add_wrong_loop_closures",
      [](PyGraph& g, double fraction, long count, std::uint64_t seed, double translation_range) {
        g.checkIdle();
        simulation::WrongLoopClosureOptions o;
        o.fraction = fraction;
        o.count = count;
        o.seed = seed;
        o.translation_range = translation_range;
        const auto r = simulation::addWrongLoopClosures(g.graph, o);
        if (!g.edge_lines.empty()) g.edge_lines.resize(g.graph.numEdges(), 0);
        std::vector<VertexId> idx(r.edge_indices.begin(), r.edge_indices.end());
        return toIdArray(idx);
      },
      py::arg("graph"), py::arg("fraction") = 0.1, py::arg("count") = -1, py::arg("seed") = 1,
      py::arg("translation_range") = 0.0,
      "Appends seeded random wrong loop closures (EDGE_SE2) to a 2D pose graph: `fraction` of "
      "its loop closures, or exactly `count`. Returns the indices of the added edges.");
  m.def(
      "dead_reckon",
      [](PyGraph& g) {
        g.checkIdle();
        return init::deadReckonGraph(g.graph);
      },
      py::arg("graph"),
      "The odometry chain of an SE(2) graph from its lowest pose: each VERTEX_SE2 composed "
      "from the one before by the EDGE_SE2 joining them; a Trajectory (timestamp = id). Raises "
      "graphslam.Error naming two poses no edge joins.");
  m.def(
      "initialize",
      [](PyGraph& g, const std::string& solver) {
        BusyGraph busy(g);
        py::gil_scoped_release release;
        return init::initializeGraph(g.graph, registries().solvers, solver).lines;
      },
      py::arg("graph"), py::arg("solver") = "auto",
      "The global initial guess in place (SE(2): orientations then positions by linear least "
      "squares; SE(3): chordal); returns what it did, line by line.");
  m.def("check_observability", &observability, py::arg("graph"), py::arg("threads") = 1,
        "Which vertices the edges do not determine, and why: a dict with ok, undetermined "
        "(dicts: id, tag, dimension, rank, reason, edges, neighbours), unanchored groups, "
        "anchors, description.");
}

}  // namespace graphslam::python
