// SPDX-License-Identifier: MIT
// graphslam.Trajectory: timestamped SE(3) poses (io::Trajectory) to and from numpy arrays,
// TUM and KITTI files, graphs.
#include <pybind11/stl.h>

#include <Eigen/Geometry>
#include <cmath>

#include "common.h"
#include "graphslam/io/graph_file.h"
#include "graphslam/io/trajectory.h"

namespace graphslam::python {

namespace {

using io::Trajectory;

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::vector<double> timestampsArg(const py::handle& obj, py::ssize_t n) {
  std::vector<double> t(static_cast<std::size_t>(n));
  if (obj.is_none()) {
    for (py::ssize_t k = 0; k < n; ++k) t[static_cast<std::size_t>(k)] = static_cast<double>(k);
    return t;
  }
  const Eigen::VectorXd v = vectorArg(obj, "the timestamps", n);
  for (py::ssize_t k = 0; k < n; ++k) t[static_cast<std::size_t>(k)] = v[k];
  return t;
}

Eigen::Isometry3d poseFromMatrix(const double* p, int rows, py::ssize_t index) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = p[r * 4 + c];
  }
  const Eigen::Matrix3d R = T.linear();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > io::kRotationTolerance ||
      R.determinant() <= 0) {
    throw py::value_error("pose " + std::to_string(index) + " has no rotation in its 3 x 3 block");
  }
  if (rows == 4) {
    const double* last = p + 12;
    if (last[0] != 0 || last[1] != 0 || last[2] != 0 || last[3] != 1) {
      throw py::value_error("pose " + std::to_string(index) + ": the last row must be 0 0 0 1");
    }
  }
  return T;
}

Trajectory fromMatrices(const py::handle& poses_obj, const py::handle& timestamps) {
  auto a = doubleArray(poses_obj, "the poses");
  if (a.ndim() != 3 || (a.shape(1) != 4 && a.shape(1) != 3) || a.shape(2) != 4) {
    shapeError("the poses", "(N, 4, 4) or (N, 3, 4)", a);
  }
  const py::ssize_t n = a.shape(0);
  const int rows = static_cast<int>(a.shape(1));
  std::vector<Eigen::Isometry3d> poses;
  poses.reserve(static_cast<std::size_t>(n));
  for (py::ssize_t k = 0; k < n; ++k) poses.push_back(poseFromMatrix(a.data() + k * rows * 4, rows, k));
  return Trajectory(timestampsArg(timestamps, n), std::move(poses));
}

Trajectory fromSe2(const py::handle& obj, const py::handle& timestamps) {
  const Eigen::MatrixXd p = matrixArg(obj, "the SE(2) poses", -1, 3);
  const Eigen::Matrix3Xd cols = p.transpose();
  return io::trajectoryFromSE2(cols, timestampsArg(timestamps, p.rows()));
}

Trajectory fromTum(const py::handle& obj) {
  const Eigen::MatrixXd rows = matrixArg(obj, "the TUM rows", -1, 8);
  Trajectory t;
  for (Eigen::Index k = 0; k < rows.rows(); ++k) {
    Eigen::Quaterniond q(rows(k, 7), rows(k, 4), rows(k, 5), rows(k, 6));
    const double norm = q.norm();
    if (std::abs(norm - 1.0) > io::kQuaternionNormTolerance) {
      throw py::value_error("TUM row " + std::to_string(k) + ": the quaternion's norm is " +
                            std::to_string(norm) + ", not 1");
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = rows.block<1, 3>(k, 1).transpose();
    t.append(rows(k, 0), T);
  }
  return t;
}

Trajectory readFile(const std::string& path, const std::string& format, bool* kitti) {
  std::string f = format;
  if (f == "auto") f = endsWith(path, ".kitti") ? "kitti" : (endsWith(path, ".txt") || endsWith(path, ".tum")) ? "tum" : "graph";
  if (kitti) *kitti = f == "kitti";
  if (f == "tum") return io::readTum(path);
  if (f == "kitti") return io::readKitti(path);
  if (f != "graph") throw py::value_error("format must be auto, tum, kitti or graph, not '" + format + "'");
  io::ReadContext context;
  context.types = &registries().types;
  context.load.create_missing_vertices = true;
  return io::trajectoryFromGraph(io::readGraph(path, registries().formats, context).graph);
}

py::array_t<double> posesArray(const Trajectory& t) {
  const auto n = static_cast<py::ssize_t>(t.size());
  auto out = newArray({n, 4, 4});
  double* p = out.mutable_data();
  for (py::ssize_t k = 0; k < n; ++k) {
    const Eigen::Matrix4d& m = t.poses()[static_cast<std::size_t>(k)].matrix();
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) p[k * 16 + r * 4 + c] = m(r, c);
    }
  }
  return out;
}

py::array_t<double> se2Array(const Trajectory& t) {
  const auto n = static_cast<py::ssize_t>(t.size());
  auto out = newArray({n, 3});
  double* p = out.mutable_data();
  for (py::ssize_t k = 0; k < n; ++k) {
    const Eigen::Isometry3d& T = t.poses()[static_cast<std::size_t>(k)];
    p[3 * k] = T.translation().x();
    p[3 * k + 1] = T.translation().y();
    p[3 * k + 2] = std::atan2(T.linear()(1, 0), T.linear()(0, 0));
  }
  return out;
}

py::array_t<double> tumArray(const Trajectory& t) {
  const auto n = static_cast<py::ssize_t>(t.size());
  auto out = newArray({n, 8});
  double* p = out.mutable_data();
  for (py::ssize_t k = 0; k < n; ++k) {
    const Eigen::Isometry3d& T = t.poses()[static_cast<std::size_t>(k)];
    Eigen::Quaterniond q(T.linear());
    if (q.w() < 0) q.coeffs() *= -1.0;
    const double row[8] = {t.timestamps()[static_cast<std::size_t>(k)], T.translation().x(),
                           T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w()};
    std::copy(row, row + 8, p + 8 * k);
  }
  return out;
}

}  // namespace

io::Trajectory trajectoryArg(const py::handle& obj, const std::string& what, bool* kitti) {
  if (kitti) *kitti = false;
  if (py::isinstance<Trajectory>(obj)) return obj.cast<Trajectory>();
  if (py::isinstance<py::str>(obj) || py::hasattr(obj, "__fspath__")) {
    return readFile(pathArg(obj), "auto", kitti);
  }
  auto a = doubleArray(obj, what);
  if (a.ndim() == 3) return fromMatrices(a, py::none());
  if (a.ndim() == 2 && a.shape(1) == 3) return fromSe2(a, py::none());
  if (a.ndim() == 2 && a.shape(1) == 8) return fromTum(a);
  shapeError(what, "(N, 3) SE(2) poses, (N, 8) TUM rows or (N, 4, 4) pose matrices", a);
}

void bindTrajectory(py::module_& m) {
  py::class_<Trajectory> c(m, "Trajectory",
                           "Timestamped SE(3) poses (body to world), as TUM and KITTI files hold "
                           "them; what graphslam.eval compares.");
  c.def(py::init(&fromMatrices), py::arg("poses"), py::arg("timestamps") = py::none(),
        "From pose matrices (N, 4, 4) or (N, 3, 4) and timestamps (N,) (default 0..N-1).");
  c.def_static("from_se2", &fromSe2, py::arg("poses"), py::arg("timestamps") = py::none(),
               "From planar poses (N, 3) of (x, y, theta): rotation about z, z = 0.");
  c.def_static("from_tum", &fromTum, py::arg("rows"),
               "From TUM rows (N, 8): t x y z qx qy qz qw.");
  c.def_static(
      "from_graph",
      [](PyGraph& g) {
        g.checkIdle();
        return io::trajectoryFromGraph(g.graph);
      },
      py::arg("graph"),
      "The VERTEX_SE2 and VERTEX_SE3:QUAT estimates of a graph in id order (timestamp = id).");
  c.def_static(
      "read", [](const py::handle& path, const std::string& format) { return readFile(pathArg(path), format, nullptr); },
      py::arg("path"), py::arg("format") = "auto",
      "Reads a trajectory: TUM (.txt, .tum), KITTI (.kitti) or a graph file's poses (every "
      "other name); `format` tum, kitti or graph overrides the extension. Raises "
      "graphslam.InputError (FILE:LINE).");
  c.def("__len__", &Trajectory::size);
  c.def_property_readonly("timestamps", [](const Trajectory& t) { return toArray(t.timestamps()); },
                          "Timestamps (N,).");
  c.def_property_readonly("poses", &posesArray, "Pose matrices (N, 4, 4).");
  c.def_property_readonly(
      "positions", [](const Trajectory& t) { return toArray(Eigen::MatrixXd(t.positions().transpose())); },
      "Positions (N, 3).");
  c.def("to_se2", &se2Array, "Planar poses (N, 3): x, y and the yaw atan2(R10, R00).");
  c.def("to_tum", &tumArray, "TUM rows (N, 8): t x y z qx qy qz qw (qw >= 0).");
  c.def("path_length", &Trajectory::pathLength, "Arc length of the positions.");
  c.def(
      "write_tum", [](const Trajectory& t, const py::handle& path) { io::writeTum(pathArg(path), t); },
      py::arg("path"), "Writes a TUM file (shortest decimal forms that read back exactly).");
  c.def(
      "write_kitti", [](const Trajectory& t, const py::handle& path) { io::writeKitti(pathArg(path), t); },
      py::arg("path"), "Writes a KITTI pose file (timestamps are not stored).");
  c.def(
      "transform",
      [](Trajectory& t, const py::handle& T, bool right) {
        const Eigen::MatrixXd m = matrixArg(T, "the transform", 4, 4);
        Eigen::Isometry3d iso;
        iso.matrix() = m;
        t.transform(iso, right);
      },
      py::arg("transform"), py::arg("right") = false,
      "Applies a 4 x 4 transform to every pose: T * pose (right=False) or pose * T.");
  c.def("scale", &Trajectory::scale, py::arg("factor"), "Scales every translation.");
  c.def("__repr__", [](const Trajectory& t) {
    return "<graphslam.Trajectory " + std::to_string(t.size()) + " poses>";
  });
}

}  // namespace graphslam::python
