// SPDX-License-Identifier: MIT
// numpy conversions with their checks (shapes, dtypes, finiteness: ValueError, never a
// crash), and the PyGraph helpers.
#include <cmath>
#include <limits>
#include <sstream>

#include "common.h"
#include "graph_types.h"

namespace graphslam::python {

void PyGraph::checkIdle() const {
  if (busy.load()) {
    throw std::runtime_error(
        "the graph is in use by another thread (an optimisation or a covariance computation): "
        "wait for it to end before changing or reading it");
  }
}

void PyGraph::syncEdgeLines() {
  if (!edge_lines.empty() && edge_lines.size() != graph.numEdges()) edge_lines.clear();
}

void PyGraph::indexVertices() {
  // Vertex types are few: a short list of (type, vertices) found in the walk, tags after.
  std::vector<std::pair<std::type_index, TagVertices>> by_type;
  for (const auto& [id, v] : graph.vertices()) {
    const std::type_index type(typeid(*v));
    std::size_t k = 0;
    while (k < by_type.size() && by_type[k].first != type) ++k;
    if (k == by_type.size()) by_type.emplace_back(type, TagVertices{});
    by_type[k].second.vertices.push_back(v.get());
    by_type[k].second.ids.push_back(id);
  }
  tag_vertices.clear();
  for (auto& [type, list] : by_type) {
    const std::string* tag = registries().types.tagOf(*list.vertices.front());
    if (tag != nullptr) tag_vertices[*tag] = std::move(list);
  }
  index_version = graph.structureVersion();
  indexed = true;
}

void PyGraph::noteAddedVertex(Vertex& v, const std::string& tag, std::uint64_t version_before) {
  if (!indexed || index_version != version_before) return;
  if (graph.vertices().rbegin()->first != v.id()) return;  // not in id order: stale
  TagVertices& list = tag_vertices[tag];
  list.vertices.push_back(&v);
  list.ids.push_back(v.id());
  index_version = graph.structureVersion();
}

const PyGraph::TagVertices& PyGraph::verticesOf(const std::string& tag) {
  (void)vertexTagType(tag);  // RegistryError for a tag that is not a vertex tag
  if (!indexed || index_version != graph.structureVersion()) indexVertices();
  static const TagVertices kNone;
  const auto it = tag_vertices.find(tag);
  return it == tag_vertices.end() ? kNone : it->second;
}

BusyGraph::BusyGraph(PyGraph& g) : g_(g) {
  bool expected = false;
  if (!g_.busy.compare_exchange_strong(expected, true)) g_.checkIdle();
}

BusyGraph::~BusyGraph() { g_.busy.store(false); }

std::string shapeText(const py::array& a) {
  std::ostringstream s;
  s << "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s << (k ? ", " : "") << a.shape(k);
  if (a.ndim() == 1) s << ",";
  s << ")";
  return s.str();
}

void shapeError(const std::string& what, const std::string& expected, const py::array& got) {
  throw py::value_error(what + " must have shape " + expected + ", not " + shapeText(got));
}

namespace {

py::array asArray(const py::handle& obj, const std::string& what) {
  if (obj.is_none()) throw py::value_error(what + " must be an array of numbers, not None");
  if (py::isinstance<py::str>(obj) || py::isinstance<py::bytes>(obj)) {
    throw py::value_error(what + " must be an array of numbers, not a string");
  }
  // Leaked: a static py::object would be released after the interpreter is gone.
  static const auto* asarray = new py::object(py::module_::import("numpy").attr("asarray"));
  py::object a;
  try {
    a = (*asarray)(obj);
  } catch (py::error_already_set& e) {
    throw py::value_error(what + " must be an array of numbers (" + std::string(e.what()) + ")");
  }
  return py::reinterpret_steal<py::array>(a.release());
}

std::string dtypeText(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

}  // namespace

DoubleArray doubleArray(const py::handle& obj, const std::string& what, bool allow_nonfinite) {
  py::array a = asArray(obj, what);
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw py::value_error(what + " must hold real numbers, not dtype " + dtypeText(a));
  }
  auto out = DoubleArray::ensure(a);
  if (!out) throw py::value_error(what + " cannot be converted to float64");
  if (!allow_nonfinite) {
    const double* p = out.data();
    for (py::ssize_t k = 0; k < out.size(); ++k) {
      if (!std::isfinite(p[k])) {
        throw py::value_error(what + " holds " + (std::isnan(p[k]) ? "NaN" : "an infinity") +
                              " (flat index " + std::to_string(k) + ")");
      }
    }
  }
  return out;
}

IdArray idArray(const py::handle& obj, const std::string& what) {
  py::array a = asArray(obj, what);
  const char kind = a.dtype().kind();
  if (kind == 'f') {
    auto d = doubleArray(a, what);
    const double* p = d.data();
    for (py::ssize_t k = 0; k < d.size(); ++k) {
      if (p[k] != std::floor(p[k])) {
        throw py::value_error(what + " must hold integer ids, not " + std::to_string(p[k]));
      }
    }
  } else if (kind != 'i' && kind != 'u') {
    throw py::value_error(what + " must hold integer ids, not dtype " + dtypeText(a));
  }
  auto out = IdArray::ensure(a);
  if (!out) throw py::value_error(what + " cannot be converted to int64");
  return out;
}

VertexId toVertexId(std::int64_t id, const std::string& what) {
  if (id < std::numeric_limits<VertexId>::min() || id > std::numeric_limits<VertexId>::max()) {
    throw py::value_error(what + " " + std::to_string(id) + " is out of the range of vertex ids");
  }
  return static_cast<VertexId>(id);
}

Eigen::MatrixXd matrixArg(const py::handle& obj, const std::string& what, long rows, long cols) {
  auto a = doubleArray(obj, what);
  const std::string expected = "(" + (rows < 0 ? std::string("N") : std::to_string(rows)) + ", " +
                               (cols < 0 ? std::string("M") : std::to_string(cols)) + ")";
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || (cols >= 0 && a.shape(1) != cols)) {
    shapeError(what, expected, a);
  }
  Eigen::MatrixXd m(a.shape(0), a.shape(1));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    for (py::ssize_t j = 0; j < a.shape(1); ++j) m(i, j) = r(i, j);
  }
  return m;
}

Eigen::VectorXd vectorArg(const py::handle& obj, const std::string& what, long size) {
  auto a = doubleArray(obj, what);
  const bool column = a.ndim() == 2 && (a.shape(0) == 1 || a.shape(1) == 1);
  if (!(a.ndim() == 1 || column) || (size >= 0 && a.size() != size)) {
    shapeError(what, "(" + (size < 0 ? std::string("N") : std::to_string(size)) + ",)", a);
  }
  Eigen::VectorXd v(a.size());
  for (py::ssize_t k = 0; k < a.size(); ++k) v[k] = a.data()[k];
  return v;
}

std::string pathArg(const py::handle& obj) {
  if (py::isinstance<py::str>(obj)) return obj.cast<std::string>();
  if (py::hasattr(obj, "__fspath__")) {
    py::object p = py::module_::import("os").attr("fspath")(obj);
    if (py::isinstance<py::str>(p)) return p.cast<std::string>();
  }
  throw py::type_error("a path must be a str or an os.PathLike, not " +
                       py::str(obj.get_type().attr("__name__")).cast<std::string>());
}

py::array_t<double> newArray(std::vector<py::ssize_t> shape) {
  return py::array_t<double>(std::move(shape));
}

py::array_t<double> toArray(const Eigen::MatrixXd& m) {
  py::array_t<double> out({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto w = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) w(i, j) = m(i, j);
  }
  return out;
}

py::array_t<double> toArray(const std::vector<double>& v) {
  py::array_t<double> out(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

py::array_t<std::int64_t> toIdArray(const std::vector<VertexId>& ids) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(ids.size()));
  std::int64_t* p = out.mutable_data();
  for (std::size_t k = 0; k < ids.size(); ++k) p[k] = ids[k];
  return out;
}

}  // namespace graphslam::python
