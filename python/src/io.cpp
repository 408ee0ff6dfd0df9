// SPDX-License-Identifier: MIT
// Reading and writing graphs through the io module's format registry (.g2o 2D/3D, TORO,
// iSAM, the CMU homework's .npz, the relative-pose matrix), and the relative-pose helpers.
#include <pybind11/stl.h>

#include "common.h"
#include "graphslam/io/graph_file.h"
#include "graphslam/io/relative_poses.h"
#include "graphslam/io/trajectory.h"

namespace graphslam::python {

namespace {

InformationRepair parseRepair(const std::string& text) {
  if (text == "refuse") return InformationRepair::kRefuse;
  if (text == "nearest-pd") return InformationRepair::kNearestPd;
  if (text == "isotropic") return InformationRepair::kIsotropic;
  throw py::value_error("information must be refuse, nearest-pd or isotropic, not '" + text + "'");
}

std::shared_ptr<PyGraph> load(const py::handle& path_obj, const std::string& format,
                              const std::string& npz_model, int threads,
                              const std::string& information, bool create_missing_vertices,
                              const std::map<std::string, std::string>& choices) {
  const std::string path = pathArg(path_obj);
  if (threads < 1 || threads > 256) throw py::value_error("threads must be between 1 and 256");
  io::ReadContext context;
  context.types = &registries().types;
  context.load.threads = threads;
  context.load.information = parseRepair(information);
  context.load.create_missing_vertices = create_missing_vertices;
  context.choices = choices;
  context.choices["npz-model"] = npz_model;
  io::GraphFile in;
  auto g = std::make_shared<PyGraph>();
  {
    py::gil_scoped_release release;
    in = io::readGraph(path, registries().formats, context, format);
    g->graph = std::move(in.graph);
    g->indexVertices();
  }
  g->path = in.path;
  g->format = in.format;
  g->edge_lines = std::move(in.edge_lines);
  g->keep_initial_guess = in.keep_initial_guess;
  g->ground_truth = std::move(in.ground_truth);
  g->created_vertices = in.created_vertices;
  return g;
}

void save(PyGraph& g, const py::handle& path_obj, const std::string& format) {
  g.checkIdle();
  const std::string path = pathArg(path_obj);
  io::WriteContext context;
  context.types = &registries().types;
  py::gil_scoped_release release;
  io::writeGraph(path, g.graph, registries().formats, context, format);
}

/// (N, 3) rows (dx, dy, dtheta) as the library's 3 x N matrix.
Eigen::Matrix3Xd relativeArg(const py::handle& obj) {
  const Eigen::MatrixXd rows = matrixArg(obj, "the relative poses", -1, 3);
  return rows.transpose();
}

}  // namespace

void bindIo(py::module_& m) {
  m.def("load", &load, py::arg("path"), py::arg("format") = "auto", py::arg("npz_model") = "auto",
        py::arg("threads") = 1, py::arg("information") = "refuse",
        py::arg("create_missing_vertices") = true,
        py::arg("choices") = std::map<std::string, std::string>{},
        "Reads a graph file: .g2o (2D and 3D tags), TORO (.graph), iSAM (.txt), the CMU "
        "homework's .npz, the relative-pose matrix; `format` \"auto\" detects it by extension "
        "and content (or name one of graphslam.graph_formats()). As the graphslam tool reads "
        "it: vertices that only edges name are created (create_missing_vertices). "
        "`npz_model`: auto, linear or bearing-range (.npz observations); `information`: refuse, "
        "nearest-pd or isotropic (information matrices that are not positive definite); "
        "`threads`: .g2o parsing threads; `choices`: format-specific options by name. Raises "
        "graphslam.InputError holding every diagnostic (FILE:LINE: ...).");
  auto graph = py::reinterpret_borrow<py::class_<PyGraph, std::shared_ptr<PyGraph>>>(m.attr("Graph"));
  graph.def("save", &save, py::arg("path"), py::arg("format") = "auto",
            "Writes the graph (format by extension: .g2o unless another graph format claims it; "
            "or name one), atomically: a temporary file renamed into place. Raises "
            "graphslam.Error naming the path.");
  m.def(
      "pose_graph_from_relative_poses",
      [](const py::handle& relative, bool last_closes_loop, const py::handle& information) {
        io::RelativePoseGraphOptions options;
        options.last_column_closes_loop = last_closes_loop;
        if (!information.is_none()) options.information = matrixArg(information, "information", 3, 3);
        auto g = std::make_shared<PyGraph>();
        g->graph = io::poseGraphFromRelativePoses(relativeArg(relative), options);
        return g;
      },
      py::arg("relative"), py::arg("last_closes_loop") = true, py::arg("information") = py::none(),
      "An SE(2) pose graph from relative poses: row k of `relative` (N, 3) is (dx, dy, dtheta) "
      "of T_k^-1 T_k+1. Vertices by dead reckoning from the identity, odometry edges k -> k+1, "
      "and (last_closes_loop) the last row as the loop closure N-1 -> 0, as in the SE(2) "
      "homework. `information`: 3 x 3 for every edge (identity by default).");
  m.def(
      "read_relative_poses",
      [](const py::handle& path) {
        const Eigen::Matrix3Xd m3 = io::readMatrix3xN(pathArg(path));
        return toArray(Eigen::MatrixXd(m3.transpose()));
      },
      py::arg("path"),
      "Reads a matrix file of 3 rows of N numbers (the ShanghaiTech homework's relative poses) "
      "as an (N, 3) array of (dx, dy, dtheta) rows. Raises graphslam.InputError (FILE:LINE).");
  m.def(
      "dead_reckon_se2",
      [](const py::handle& relative) {
        const Eigen::Matrix3Xd poses = io::deadReckonSE2(relativeArg(relative));
        return toArray(Eigen::MatrixXd(poses.transpose()));
      },
      py::arg("relative"),
      "Composes relative SE(2) poses (N, 3) from the identity: (N + 1, 3) poses (x, y, theta), "
      "theta in (-pi, pi].");
}

}  // namespace graphslam::python
