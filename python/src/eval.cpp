// SPDX-License-Identifier: MIT
// graphslam.eval: APE and RPE as evo defines them (eval::computeApe / computeRpe), on
// trajectories given as graphslam.Trajectory, arrays or files; statistics, Umeyama, and the
// position errors of a graph against its file's ground truth.
#include <pybind11/stl.h>

#include <map>

#include "common.h"
#include "graphslam/eval/point_errors.h"
#include "graphslam/eval/trajectory_metrics.h"

namespace graphslam::python {

namespace {

using namespace graphslam::eval;

PoseRelation parseRelation(const std::string& r) {
  PoseRelation relation{};
  if (!poseRelationFromName(r, &relation)) {
    throw py::value_error(std::string("pose_relation must be ") + kPoseRelationNames + ", not '" +
                          r + "'");
  }
  return relation;
}

DeltaUnit parseUnit(const std::string& u) {
  if (u == "f") return DeltaUnit::kFrames;
  if (u == "m") return DeltaUnit::kMeters;
  if (u == "rad") return DeltaUnit::kRadians;
  if (u == "deg") return DeltaUnit::kDegrees;
  throw py::value_error("delta_unit must be f, m, rad or deg, not '" + u + "'");
}

py::dict statsDict(const ErrorStatistics& s) {
  py::dict d;
  d["max"] = s.max;
  d["mean"] = s.mean;
  d["median"] = s.median;
  d["min"] = s.min;
  d["rmse"] = s.rmse;
  d["sse"] = s.sse;
  d["std"] = s.std_dev;
  return d;
}

/// The common part of the APE and RPE results.
struct EvalResult {
  std::string metric;
  py::array_t<double> errors;
  ErrorStatistics statistics;
  io::Trajectory reference, estimate;
  UmeyamaResult umeyama;
  Eigen::Isometry3d origin_transform = Eigen::Isometry3d::Identity();
  py::object id_pairs = py::none();
};

/// The options APE and RPE share (evo's association and alignment flags), into `o`.
template <typename Options>
void fillCommon(Options& o, const std::string& relation, bool align, bool correct_scale,
                bool align_origin, int n_to_align, double t_max_diff, double t_offset,
                const py::object& associate, bool kitti) {
  o.pose_relation = parseRelation(relation);
  o.associate = associate.is_none() ? !kitti : associate.cast<bool>();
  o.association.max_diff = t_max_diff;
  o.association.offset_2 = t_offset;
  o.alignment.mode = align ? (correct_scale ? AlignmentMode::kSim3 : AlignmentMode::kSE3)
                           : (correct_scale ? AlignmentMode::kScaleOnly : AlignmentMode::kNone);
  o.alignment.align_origin = align_origin;
  o.alignment.num_poses = n_to_align;
}

/// The two trajectories, and whether either has no timestamps of its own (KITTI).
struct Inputs {
  io::Trajectory reference, estimate;
  bool kitti = false;
};

Inputs inputs(const py::handle& reference, const py::handle& estimate) {
  Inputs in;
  bool kitti_ref = false, kitti_est = false;
  in.reference = trajectoryArg(reference, "the reference", &kitti_ref);
  in.estimate = trajectoryArg(estimate, "the estimate", &kitti_est);
  in.kitti = kitti_ref || kitti_est;
  return in;
}

template <typename R>
EvalResult take(const std::string& metric, const R& r) {
  EvalResult e;
  e.metric = metric;
  e.errors = toArray(r.errors);
  e.statistics = r.statistics;
  e.reference = r.reference;
  e.estimate = r.estimate;
  e.umeyama = r.umeyama;
  e.origin_transform = r.origin_transform;
  return e;
}

EvalResult ape(const py::handle& reference, const py::handle& estimate, const std::string& relation,
               bool align, bool correct_scale, bool align_origin, int n_to_align, double t_max_diff,
               double t_offset, const py::object& associate) {
  const Inputs in = inputs(reference, estimate);
  ApeOptions o;
  fillCommon(o, relation, align, correct_scale, align_origin, n_to_align, t_max_diff, t_offset,
             associate, in.kitti);
  ApeResult r;
  {
    py::gil_scoped_release release;
    r = computeApe(in.reference, in.estimate, o);
  }
  return take("ape", r);
}

EvalResult rpe(const py::handle& reference, const py::handle& estimate, const std::string& relation,
               double delta, const std::string& delta_unit, bool all_pairs, double rel_delta_tol,
               bool pairs_from_reference, bool align, bool correct_scale, bool align_origin,
               int n_to_align, double t_max_diff, double t_offset, const py::object& associate) {
  const Inputs in = inputs(reference, estimate);
  RpeOptions o;
  fillCommon(o, relation, align, correct_scale, align_origin, n_to_align, t_max_diff, t_offset,
             associate, in.kitti);
  o.delta = delta;
  o.delta_unit = parseUnit(delta_unit);
  o.all_pairs = all_pairs;
  o.rel_delta_tol = rel_delta_tol;
  o.pairs_from_reference = pairs_from_reference;
  RpeResult r;
  {
    py::gil_scoped_release release;
    r = computeRpe(in.reference, in.estimate, o);
  }
  EvalResult e = take("rpe", r);
  py::array_t<std::int64_t> pairs({static_cast<py::ssize_t>(r.id_pairs.size()), py::ssize_t{2}});
  for (std::size_t k = 0; k < r.id_pairs.size(); ++k) {
    pairs.mutable_data()[2 * k] = static_cast<std::int64_t>(r.id_pairs[k].first);
    pairs.mutable_data()[2 * k + 1] = static_cast<std::int64_t>(r.id_pairs[k].second);
  }
  e.id_pairs = pairs;
  return e;
}

void bindResult(py::module_& ev) {
  py::class_<EvalResult> c(ev, "Result",
                           "APE or RPE: the errors, their statistics (evo's seven) and the poses "
                           "compared (associated, the estimate aligned).");
  c.def_readonly("metric", &EvalResult::metric, "\"ape\" or \"rpe\".");
  c.def_readonly("errors", &EvalResult::errors, "One error per pose (APE) or pair (RPE).");
  c.def_property_readonly(
      "statistics", [](const EvalResult& e) { return statsDict(e.statistics); },
      "{max, mean, median, min, rmse, sse, std} (std: population).");
  c.def_property_readonly(
      "rmse", [](const EvalResult& e) { return e.statistics.rmse; }, "sqrt(mean(e^2)).");
  c.def_property_readonly(
      "mean", [](const EvalResult& e) { return e.statistics.mean; }, "Mean error.");
  c.def_property_readonly(
      "median", [](const EvalResult& e) { return e.statistics.median; }, "Median error.");
  c.def_property_readonly(
      "max", [](const EvalResult& e) { return e.statistics.max; }, "Largest error.");
  c.def_property_readonly(
      "min", [](const EvalResult& e) { return e.statistics.min; }, "Smallest error.");
  c.def_property_readonly(
      "std", [](const EvalResult& e) { return e.statistics.std_dev; },
      "Population standard deviation.");
  c.def_property_readonly(
      "sse", [](const EvalResult& e) { return e.statistics.sse; }, "Sum of e^2.");
  c.def_readonly("reference", &EvalResult::reference, "The associated reference (Trajectory).");
  c.def_readonly("estimate", &EvalResult::estimate,
                 "The associated, aligned estimate (Trajectory).");
  c.def_property_readonly(
      "rotation", [](const EvalResult& e) { return toArray(e.umeyama.rotation); },
      "Umeyama rotation applied to the estimate (3 x 3; identity without alignment).");
  c.def_property_readonly(
      "translation",
      [](const EvalResult& e) { return toArray(Eigen::MatrixXd(e.umeyama.translation)); },
      "Umeyama translation (3 x 1).");
  c.def_property_readonly(
      "scale", [](const EvalResult& e) { return e.umeyama.scale; }, "Umeyama scale.");
  c.def_property_readonly(
      "origin_transform", [](const EvalResult& e) { return toArray(e.origin_transform.matrix()); },
      "The align_origin transform applied (4 x 4).");
  c.def_readonly("id_pairs", &EvalResult::id_pairs,
                 "RPE: the compared index pairs (M, 2); None for APE.");
  c.def("__repr__", [](const EvalResult& e) {
    return "<graphslam.eval.Result " + e.metric + " rmse " + std::to_string(e.statistics.rmse) +
           ", " + std::to_string(e.errors.size()) + " errors>";
  });
}

}  // namespace

void bindEval(py::module_& m) {
  py::module_ ev =
      m.def_submodule("eval", "Trajectory evaluation with evo's semantics (APE, RPE).");
  bindResult(ev);
  const char* inputs =
      " `reference`, `estimate`: graphslam.Trajectory, a path (TUM .txt/.tum, KITTI .kitti, or a "
      "graph file's poses) or an array: (N, 3) SE(2) poses, (N, 8) TUM rows, (N, 4, 4) "
      "matrices. Timestamps are associated (t_max_diff, t_offset) unless a KITTI file is "
      "involved or associate=False. align: SE(3) Umeyama (evo -a); correct_scale: Sim(3) with "
      "align, scale only without (evo -s); align_origin (evo --align_origin); n_to_align: "
      "Umeyama on the first N poses only.";
  ev.def("ape", &ape, py::arg("reference"), py::arg("estimate"),
         py::arg("pose_relation") = "trans_part", py::arg("align") = false,
         py::arg("correct_scale") = false, py::arg("align_origin") = false,
         py::arg("n_to_align") = -1, py::arg("t_max_diff") = 0.01, py::arg("t_offset") = 0.0,
         py::arg("associate") = py::none(),
         (std::string("Absolute pose error as evo_ape computes it. pose_relation: trans_part "
                      "(default), rot_part, angle_deg, angle_rad, full, point_distance.") +
          inputs)
             .c_str());
  ev.def("rpe", &rpe, py::arg("reference"), py::arg("estimate"),
         py::arg("pose_relation") = "trans_part", py::arg("delta") = 1.0,
         py::arg("delta_unit") = "f", py::arg("all_pairs") = false, py::arg("rel_delta_tol") = 0.1,
         py::arg("pairs_from_reference") = false, py::arg("align") = false,
         py::arg("correct_scale") = false, py::arg("align_origin") = false,
         py::arg("n_to_align") = -1, py::arg("t_max_diff") = 0.01, py::arg("t_offset") = 0.0,
         py::arg("associate") = py::none(),
         (std::string("Relative pose error as evo_rpe computes it: pairs `delta` apart in "
                      "delta_unit f (frames), m, rad or deg; all_pairs for every such pair. "
                      "pose_relation as ape, plus point_distance_error_ratio.") +
          inputs)
             .c_str());
  ev.def(
      "statistics",
      [](const py::handle& errors) {
        const Eigen::VectorXd e = vectorArg(errors, "the errors", -1);
        return statsDict(computeStatistics(std::vector<double>(e.data(), e.data() + e.size())));
      },
      py::arg("errors"),
      "evo's statistics of an error array: {max, mean, median, min, rmse, sse, std}.");
  ev.def(
      "umeyama",
      [](const py::handle& x, const py::handle& y, bool with_scale) {
        const Eigen::MatrixXd a = matrixArg(x, "x", -1, 3), b = matrixArg(y, "y", -1, 3);
        if (a.rows() != b.rows())
          throw py::value_error("x and y must have the same number of points");
        const UmeyamaResult r = umeyamaAlignment(a.transpose(), b.transpose(), with_scale);
        return py::make_tuple(toArray(r.rotation), toArray(Eigen::MatrixXd(r.translation)),
                              r.scale);
      },
      py::arg("x"), py::arg("y"), py::arg("with_scale") = false,
      "Least-squares (R, t, s) with y ~ s R x + t for point sets (N, 3) (Umeyama 1991, as evo).");
  ev.def(
      "position_errors",
      [](PyGraph& g) {
        g.checkIdle();
        if (g.ground_truth.empty()) throw py::value_error(g.name() + " has no ground truth");
        const GroundTruthErrors e = positionErrors(g.graph, g.ground_truth);
        auto stats = [](const PositionErrorStats& s) {
          py::dict d;
          d["count"] = s.count;
          d["mean"] = s.mean;
          d["rmse"] = s.rmse;
          d["max"] = s.max;
          return d;
        };
        py::dict d;
        d["poses"] = stats(e.poses);
        d["landmarks"] = stats(e.landmarks);
        return d;
      },
      py::arg("graph"),
      "Position errors (m) of a graph's estimates against the ground truth its file came with "
      "(.npz): {poses: {count, mean, rmse, max}, landmarks: {...}}.");
}

}  // namespace graphslam::python
