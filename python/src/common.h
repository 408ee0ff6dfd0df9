// SPDX-License-Identifier: MIT
// Shared pieces of the Python bindings (the _graphslam extension): the process's registries,
// the graph object Python holds, and the conversions between numpy arrays and the library's
// flat data, each checking shapes, dtypes and finiteness and raising ValueError.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/host/registries.h"
#include "graphslam/io/coursework_npz.h"
#include "graphslam/io/trajectory.h"

namespace graphslam::python {

namespace py = pybind11;

/// The registries of the process: the library's modules (host::registerBuiltins) and the
/// plugins loaded by graphslam.load_plugins. Made on first use and never destroyed: graphs
/// that Python still holds at exit refer to the types' code.
host::Registries& registries();

/// A graph as Python holds it: the library's Graph and what came with it from a file.
struct PyGraph {
  Graph graph;
  std::string path;    ///< the file it was read from ("" when built in code)
  std::string format;  ///< the registry name of that file's format
  /// The file line of each edge, in graph edge order (0: no line, an edge added in code);
  /// empty when the format has none.
  std::vector<std::size_t> edge_lines;
  /// The estimates are a deliberate initial guess that optimize(init="auto") keeps: true
  /// for graphs built in code and .npz files, false for pose-graph files (whose estimates
  /// the tool replaces by the global initialisation).
  bool keep_initial_guess = true;
  io::PointGroundTruth ground_truth;
  std::size_t created_vertices = 0;
  /// The vertices of each tag in id order (an index), kept while the graph's structure does
  /// not change (Graph::structureVersion), and across edge changes (keepIndex): bulk reads
  /// of a large graph then walk a vector instead of the graph's map. Made by one walk of
  /// the map for every tag at once; load() makes it while it reads.
  struct TagVertices {
    std::vector<Vertex*> vertices;
    std::vector<VertexId> ids;
  };
  std::map<std::string, TagVertices> tag_vertices;
  std::uint64_t index_version = 0;
  bool indexed = false;
  /// The vertices of `tag` (a registered vertex tag), the index made again when stale.
  const TagVertices& verticesOf(const std::string& tag);
  /// Makes the index (one walk of the graph's vertices). No Python: may run without the GIL.
  void indexVertices();
  /// After `v` was added (of `tag`): an index valid at `version_before` takes it when its id
  /// is the graph's largest (vertices added in id order), else it is made again when needed.
  void noteAddedVertex(Vertex& v, const std::string& tag, std::uint64_t version_before);
  /// After a change of edges only: the index stays valid if it was at `version_before`.
  void keepIndex(std::uint64_t version_before) {
    if (indexed && index_version == version_before) index_version = graph.structureVersion();
  }

  /// Set while the library works on the graph without the GIL (optimize, marginals):
  /// other Python threads may not change it meanwhile.
  std::atomic<bool> busy{false};
  /// Set while an optimisation waits for its Python callback: the graph may then be read
  /// (estimates for a live plot), not changed.
  std::atomic<bool> paused{false};

  /// Throws RuntimeError when the graph is in use by another thread.
  void checkIdle() const;
  /// The same, except while the library waits for a callback.
  void checkReadable() const {
    if (!paused.load()) checkIdle();
  }
  /// Keeps edge_lines in step with the edges after `graph` changed them.
  void syncEdgeLines();
  /// "FILE" or "graph" for messages.
  [[nodiscard]] std::string name() const { return path.empty() ? std::string("graph") : path; }
};

/// Marks a graph busy for a scope (throws RuntimeError when it already is).
class BusyGraph {
 public:
  explicit BusyGraph(PyGraph& g);
  ~BusyGraph();
  BusyGraph(const BusyGraph&) = delete;
  BusyGraph& operator=(const BusyGraph&) = delete;

 private:
  PyGraph& g_;
};

/// C-contiguous numpy arrays of the checked argument conversions.
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IdArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

/// A C-contiguous float64 array made from `obj` (a numpy array of a real dtype, a list, a
/// number). Raises ValueError naming `what` for other dtypes, objects that are not numbers
/// and (unless allow_nonfinite) NaN or infinity.
DoubleArray doubleArray(const py::handle& obj, const std::string& what,
                        bool allow_nonfinite = false);
/// The same for integer ids (int64): floats must be whole numbers.
IdArray idArray(const py::handle& obj, const std::string& what);
/// A VertexId from a Python integer; ValueError when it does not fit.
VertexId toVertexId(std::int64_t id, const std::string& what);
/// Raises ValueError "WHAT must have shape (..): got (..)".
[[noreturn]] void shapeError(const std::string& what, const std::string& expected,
                             const py::array& got);
/// "(3, 4)" of an array.
std::string shapeText(const py::array& a);
/// A (rows x cols) matrix of a 2-D array (ValueError for another shape; -1: any size).
Eigen::MatrixXd matrixArg(const py::handle& obj, const std::string& what, long rows, long cols);
/// A vector of `size` numbers (-1: any) from a 1-D array (or a (size, 1) / (1, size) one).
Eigen::VectorXd vectorArg(const py::handle& obj, const std::string& what, long size);

/// A file name from a str or an os.PathLike (pathlib.Path); TypeError otherwise.
std::string pathArg(const py::handle& obj);

/// A new numpy array of doubles of the given shape (uninitialised).
py::array_t<double> newArray(std::vector<py::ssize_t> shape);
/// A numpy array holding a copy of an Eigen matrix (rows x cols).
py::array_t<double> toArray(const Eigen::MatrixXd& m);
/// A 1-D numpy array holding a copy of the values.
py::array_t<double> toArray(const std::vector<double>& v);
py::array_t<std::int64_t> toIdArray(const std::vector<VertexId>& ids);

/// A trajectory from Python: a graphslam.Trajectory, a path (TUM, KITTI by extension, or a
/// graph file's poses), or an array: (N, 3) planar poses (x, y, theta), (N, 8) TUM rows
/// (t x y z qx qy qz qw), (N, 4, 4) or (N, 3, 4) pose matrices. `kitti` is set when the
/// trajectory has no timestamps of its own (KITTI files), so it is not associated by time.
io::Trajectory trajectoryArg(const py::handle& obj, const std::string& what, bool* kitti = nullptr);

// Registration of each part of the module.
void bindErrors(py::module_& m);
void bindGraph(py::module_& m);
void bindIo(py::module_& m);
void bindOptimize(py::module_& m);
void bindTrajectory(py::module_& m);
void bindEval(py::module_& m);
void bindSimulation(py::module_& m);
void bindIncremental(py::module_& m);
void bindCustomEdges(py::module_& m);
void bindDrivebot(py::module_& m);
void bindCertifyView(py::module_& m);

}  // namespace graphslam::python
