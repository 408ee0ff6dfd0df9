// SPDX-License-Identifier: MIT
// graphslam.Graph: building a graph in code (vertices, edges, parameters by tag, with numpy
// values checked before they reach the library), changing and inspecting it.
#include <pybind11/stl.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <unordered_set>

#include "common.h"
#include "graph_types.h"
#include "graphslam/core/graph_copy.h"
#include "graphslam/support/error.h"

namespace graphslam::python {

namespace {

std::mutex g_tag_mutex;

template <typename Make>
const TagType& cachedType(std::unordered_map<std::string, TagType>& cache, const std::string& tag,
                          Make make) {
  std::lock_guard<std::mutex> lock(g_tag_mutex);
  auto it = cache.find(tag);
  if (it == cache.end()) it = cache.emplace(tag, make()).first;
  return it->second;
}

}  // namespace

const TagType& vertexTagType(const std::string& tag) {
  static std::unordered_map<std::string, TagType> cache;
  return cachedType(cache, tag, [&] {
    const auto v = registries().types.createVertex(tag);
    TagType t;
    t.type = std::type_index(typeid(*v));
    t.data_dimension = v->estimateDataDimension();
    t.parameter_dimension = v->parameterDataDimension();
    t.dimension = v->dimension();
    return t;
  });
}

const TagType& edgeTagType(const std::string& tag) {
  static std::unordered_map<std::string, TagType> cache;
  return cachedType(cache, tag, [&] {
    const auto e = registries().types.createEdge(tag);
    TagType t;
    t.type = std::type_index(typeid(*e));
    t.data_dimension = e->measurementDataDimension();
    t.parameter_dimension = e->parameterDataDimension();
    t.arity = e->arity();
    t.dimension = e->dimension();
    return t;
  });
}

std::string tagOf(const Vertex& v) {
  const std::string* t = registries().types.tagOf(v);
  return t ? *t : std::string("?");
}

/// The registered vertex tags slot `slot` of `edge` accepts ("VERTEX_XY"), for messages.
std::string expectedTag(const Edge& edge, std::size_t slot) {
  std::string tags;
  for (const auto* entry : registries().types.entries()) {
    if (entry->kind != TypeRegistry::Kind::kVertex) continue;
    if (edge.acceptsVertex(slot, *entry->make_vertex())) tags += (tags.empty() ? "" : " or ") + entry->tag;
  }
  return tags.empty() ? edge.expectedVertexType(slot) : tags;
}

std::string tagOf(const Edge& e) {
  const std::string* t = registries().types.tagOf(e);
  return t ? *t : std::string("?");
}

namespace {

std::string idsText(const std::vector<VertexId>& ids) {
  std::string s;
  for (std::size_t k = 0; k < ids.size(); ++k) s += (k ? ", " : "") + std::to_string(ids[k]);
  return s;
}

/// Checks an information matrix (symmetric, positive definite) and returns it.
Eigen::MatrixXd informationArg(const py::handle& obj, int d, const std::string& what) {
  if (obj.is_none()) return Eigen::MatrixXd::Identity(d, d);
  Eigen::MatrixXd info = matrixArg(obj, what, d, d);
  const double scale = std::max(1.0, info.cwiseAbs().maxCoeff());
  if ((info - info.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    throw py::value_error(what + " is not symmetric");
  }
  if (Eigen::LLT<Eigen::MatrixXd>(info).info() != Eigen::Success) {
    throw py::value_error(what + " is not positive definite");
  }
  return info;
}

}  // namespace

/// A new edge of `tag` with its ids, measurement, information and parameters set (every
/// value checked); not yet in a graph.
std::unique_ptr<Edge> makeEdge(const std::string& tag, const std::vector<VertexId>& ids,
                               const py::handle& measurement, const py::handle& information,
                               const std::vector<int>& parameter_ids, const py::handle& parameters) {
  auto edge = registries().types.createEdge(tag);
  edge->setVertexIds(ids);
  const std::string what = tag + " (vertices " + idsText(ids) + ")";
  const Eigen::VectorXd z =
      vectorArg(measurement, "the measurement of " + what, edge->measurementDataDimension());
  edge->setMeasurementData(z.data());
  if (static_cast<int>(parameter_ids.size()) != edge->numParameters()) {
    throw py::value_error(what + " takes " + std::to_string(edge->numParameters()) +
                          " parameter ids, not " + std::to_string(parameter_ids.size()));
  }
  for (std::size_t k = 0; k < parameter_ids.size(); ++k) edge->setParameterId(k, parameter_ids[k]);
  if (!parameters.is_none()) {
    const Eigen::VectorXd p =
        vectorArg(parameters, "the parameters of " + what, edge->parameterDataDimension());
    edge->setParameterData(p.data());
  }
  const Eigen::MatrixXd info = informationArg(information, edge->dimension(), "the information of " + what);
  edge->setInformationData(info.data());
  return edge;
}

std::vector<VertexId> vertexIdList(const py::handle& obj, const std::string& what) {
  auto a = idArray(obj, what);
  if (a.ndim() != 1) shapeError(what, "(k,)", a);
  std::vector<VertexId> ids(static_cast<std::size_t>(a.size()));
  for (py::ssize_t k = 0; k < a.size(); ++k) ids[k] = toVertexId(a.data()[k], what);
  return ids;
}

std::unique_ptr<Vertex> makeVertex(const std::string& tag, std::int64_t id, const py::handle& estimate,
                                   bool fixed, const py::handle& parameters) {
  auto v = registries().types.createVertex(tag);
  v->setId(toVertexId(id, "vertex id"));
  const std::string what = tag + " " + std::to_string(id);
  if (!estimate.is_none()) {
    const Eigen::VectorXd x = vectorArg(estimate, "the estimate of " + what, v->estimateDataDimension());
    v->setEstimateData(x.data());
  }
  if (!parameters.is_none()) {
    const Eigen::VectorXd p = vectorArg(parameters, "the parameters of " + what, v->parameterDataDimension());
    v->setParameterData(p.data());
  }
  v->setFixed(fixed);
  return v;
}

namespace {

Edge& edgeAt(PyGraph& g, std::int64_t index) {
  const auto n = static_cast<std::int64_t>(g.graph.numEdges());
  if (index < 0) index += n;
  if (index < 0 || index >= n) {
    throw py::index_error("edge index " + std::to_string(index) + " out of range (" +
                          std::to_string(n) + " edges)");
  }
  return *g.graph.edges()[static_cast<std::size_t>(index)];
}

Vertex& vertexAt(PyGraph& g, std::int64_t id) {
  Vertex* v = g.graph.vertex(toVertexId(id, "vertex id"));
  if (v == nullptr) throw py::key_error("vertex " + std::to_string(id) + " is not in the graph");
  return *v;
}

void addVertex(PyGraph& g, const std::string& tag, std::int64_t id, const py::handle& estimate,
               bool fixed, const py::handle& parameters) {
  g.checkIdle();
  const std::uint64_t before = g.graph.structureVersion();
  g.noteAddedVertex(g.graph.addVertex(makeVertex(tag, id, estimate, fixed, parameters)), tag, before);
}

std::int64_t addEdge(PyGraph& g, const std::string& tag, const py::handle& vertex_ids,
                     const py::handle& measurement, const py::handle& information,
                     const std::vector<int>& parameter_ids, const py::handle& parameters) {
  g.checkIdle();
  const std::vector<VertexId> ids = vertexIdList(vertex_ids, "vertex_ids");
  auto edge = makeEdge(tag, ids, measurement, information, parameter_ids, parameters);
  for (std::size_t s = 0; s < ids.size(); ++s) {
    const Vertex* v = g.graph.vertex(ids[s]);
    if (v != nullptr && !edge->acceptsVertex(s, *v)) {
      throw InputError(tag + ": vertex " + std::to_string(ids[s]) + " is " + tagOf(*v) + ", not " +
                       expectedTag(*edge, s) + " (slot " + std::to_string(s) + ")");
    }
  }
  const bool had_lines = !g.edge_lines.empty();
  const std::uint64_t before = g.graph.structureVersion();
  g.graph.addEdge(std::move(edge));
  g.keepIndex(before);
  if (had_lines) g.edge_lines.push_back(0);
  return static_cast<std::int64_t>(g.graph.numEdges()) - 1;
}

void addParameter(PyGraph& g, const std::string& tag, int id, const py::handle& values) {
  g.checkIdle();
  auto p = registries().types.createParameter(tag);
  p->setId(id);
  const Eigen::VectorXd x = vectorArg(values, "the values of " + tag + " " + std::to_string(id),
                                      p->dataDimension());
  p->setData(x.data());
  g.graph.addParameter(std::move(p));
}

std::size_t removeEdges(PyGraph& g, const py::handle& indices) {
  g.checkIdle();
  auto a = idArray(indices, "edge indices");
  const auto n = static_cast<std::int64_t>(g.graph.numEdges());
  std::unordered_set<const Edge*> gone;
  std::vector<bool> removed(static_cast<std::size_t>(n), false);
  for (py::ssize_t k = 0; k < a.size(); ++k) {
    std::int64_t i = a.data()[k];
    if (i < 0) i += n;
    if (i < 0 || i >= n) throw py::index_error("edge index " + std::to_string(a.data()[k]) + " out of range");
    gone.insert(g.graph.edges()[static_cast<std::size_t>(i)].get());
    removed[static_cast<std::size_t>(i)] = true;
  }
  if (g.edge_lines.size() == static_cast<std::size_t>(n)) {
    std::vector<std::size_t> kept;
    for (std::size_t k = 0; k < removed.size(); ++k) {
      if (!removed[k]) kept.push_back(g.edge_lines[k]);
    }
    g.edge_lines.swap(kept);
  }
  const std::uint64_t before = g.graph.structureVersion();
  const std::size_t count = g.graph.removeEdges([&](const Edge& e) { return gone.count(&e) != 0; });
  g.keepIndex(before);
  return count;
}

bool removeVertex(PyGraph& g, std::int64_t id) {
  g.checkIdle();
  const Vertex* v = g.graph.vertex(toVertexId(id, "vertex id"));
  if (v == nullptr) return false;
  if (g.edge_lines.size() == g.graph.numEdges()) {
    std::unordered_set<const Edge*> gone(v->edges().begin(), v->edges().end());
    std::vector<std::size_t> kept;
    for (std::size_t k = 0; k < g.graph.numEdges(); ++k) {
      if (!gone.count(g.graph.edges()[k].get())) kept.push_back(g.edge_lines[k]);
    }
    g.edge_lines.swap(kept);
  }
  return g.graph.removeVertex(static_cast<VertexId>(id));
}

void fixVertices(PyGraph& g, const py::handle& ids, bool fixed) {
  g.checkIdle();
  std::vector<Vertex*> vs;
  if (py::isinstance<py::int_>(ids)) {
    vs.push_back(&vertexAt(g, ids.cast<std::int64_t>()));
  } else {
    auto a = idArray(ids, "vertex ids");
    for (py::ssize_t k = 0; k < a.size(); ++k) vs.push_back(&vertexAt(g, a.data()[k]));
  }
  for (Vertex* v : vs) v->setFixed(fixed);
}

py::dict edgeDict(PyGraph& g, std::int64_t index) {
  g.checkReadable();
  const Edge& e = edgeAt(g, index);
  const std::size_t i = static_cast<std::size_t>(index < 0 ? index + g.graph.numEdges() : index);
  py::dict d;
  d["tag"] = tagOf(e);
  d["vertex_ids"] = std::vector<VertexId>(e.vertexIds().begin(), e.vertexIds().end());
  auto z = newArray({e.measurementDataDimension()});
  e.getMeasurementData(z.mutable_data());
  d["measurement"] = z;
  const int n = e.dimension();
  Eigen::Map<const Eigen::MatrixXd> info(e.informationData(), n, n);
  d["information"] = toArray(info);
  if (e.parameterDataDimension() > 0) {
    auto p = newArray({e.parameterDataDimension()});
    e.getParameterData(p.mutable_data());
    d["parameters"] = p;
  }
  std::vector<int> pids;
  for (int k = 0; k < e.numParameters(); ++k) pids.push_back(e.parameterId(static_cast<std::size_t>(k)));
  d["parameter_ids"] = pids;
  d["active"] = e.active();
  d["robust"] = e.robustKernel() != nullptr;
  d["line"] = i < g.edge_lines.size() && g.edge_lines[i] > 0 ? py::object(py::int_(g.edge_lines[i]))
                                                             : py::object(py::none());
  return d;
}

py::dict counts(const PyGraph& g) {
  std::map<std::string, std::size_t> n;
  for (const auto& [id, v] : g.graph.vertices()) ++n[tagOf(*v)];
  for (const auto& e : g.graph.edges()) ++n[tagOf(*e)];
  py::dict out;
  for (const auto& [tag, k] : n) out[py::str(tag)] = k;
  return out;
}

std::shared_ptr<PyGraph> copyOf(PyGraph& g) {
  g.checkIdle();
  auto out = std::make_shared<PyGraph>();
  out->graph = incremental::copyGraph(g.graph, registries().types);
  out->path = g.path;
  out->format = g.format;
  out->edge_lines = g.edge_lines;
  out->keep_initial_guess = g.keep_initial_guess;
  out->ground_truth = g.ground_truth;
  out->created_vertices = g.created_vertices;
  return out;
}

void bindConstruction(py::class_<PyGraph, std::shared_ptr<PyGraph>>& c) {
  c.def(py::init([] {
          auto g = std::make_shared<PyGraph>();
          g->indexed = true;  // the (empty) index of the empty graph
          return g;
        }),
        "An empty graph. Add vertices and edges by their .g2o tags (graphslam.vertex_tags(), "
        "graphslam.edge_tags()).");
  c.def("add_vertex", &addVertex, py::arg("tag"), py::arg("id"), py::arg("estimate") = py::none(),
        py::arg("fixed") = false, py::arg("parameters") = py::none(),
        "Adds a vertex of `tag` (\"VERTEX_SE2\", \"VERTEX_XY\", \"VERTEX_SE3:QUAT\", ...) with its "
        "estimate as the .g2o line holds it (SE2: x, y, theta; SE3:QUAT: x, y, z, qx, qy, qz, qw; "
        "None: the type's default). `parameters`: the line's extra constants (VERTEX_VEHICLE's "
        "time). Raises ValueError for a wrong size or NaN, graphslam.Error for a duplicate id.");
  c.def("add_edge", &addEdge, py::arg("tag"), py::arg("vertex_ids"), py::arg("measurement"),
        py::arg("information") = py::none(), py::arg("parameter_ids") = std::vector<int>{},
        py::arg("parameters") = py::none(),
        "Adds an edge of `tag` (\"EDGE_SE2\", \"EDGE_SE2_XY\", \"EDGE_SE3:QUAT\", ...) joining "
        "`vertex_ids`, with its measurement as the .g2o line holds it and its information "
        "matrix (d x d, symmetric positive definite; None: identity). Returns the edge's index "
        "(graph.edge(i), remove_edge(i)). Raises ValueError for wrong shapes, NaN or an "
        "information that is not positive definite, graphslam.Error for a missing vertex or a "
        "vertex of the wrong type.");
  c.def("add_parameter", &addParameter, py::arg("tag"), py::arg("id"), py::arg("values"),
        "Adds a shared parameter (\"PARAMS_SE2OFFSET\", \"PARAMS_SE3OFFSET\": a sensor's pose on "
        "the robot) that edges refer to by id (add_edge(parameter_ids=...)).");
  c.def("remove_vertex", &removeVertex, py::arg("id"),
        "Removes a vertex and its edges; False when the id is not in the graph.");
  c.def(
      "remove_edge", [](PyGraph& g, std::int64_t i) { (void)edgeAt(g, i); removeEdges(g, py::int_(i)); },
      py::arg("index"),
      "Removes edge `index` (later edges move down by one). Raises IndexError when out of range.");
  c.def("remove_edges", &removeEdges, py::arg("indices"),
        "Removes the edges of the given indices (an array or list) at once; returns how many.");
  c.def("fix", &fixVertices, py::arg("ids"), py::arg("fixed") = true,
        "Holds the vertex (an id, or an array of ids) constant in the optimisation (fixed=False "
        "frees it). Raises KeyError for an id that is not in the graph.");
  c.def(
      "set_edge_active",
      [](PyGraph& g, std::int64_t i, bool active) {
        g.checkIdle();
        g.graph.setEdgeActive(edgeAt(g, i), active);
      },
      py::arg("index"), py::arg("active"),
      "Includes edge `index` in the optimisation or leaves it out (it stays in the graph).");
  c.def("copy", &copyOf, "An independent copy of the graph (estimates as they are now).");
}

void bindInspection(py::class_<PyGraph, std::shared_ptr<PyGraph>>& c) {
  c.def_property_readonly("num_vertices", [](const PyGraph& g) { return g.graph.numVertices(); },
                          "Number of vertices.");
  c.def_property_readonly("num_edges", [](const PyGraph& g) { return g.graph.numEdges(); },
                          "Number of edges.");
  c.def_property_readonly("path", [](const PyGraph& g) { return g.path; },
                          "The file the graph was read from (\"\" for a graph built in code).");
  c.def_property_readonly("format", [](const PyGraph& g) { return g.format; },
                          "The format of that file (\"g2o\", \"toro\", \"isam\", \"npz\", ...).");
  c.def_property("keep_initial_guess", [](const PyGraph& g) { return g.keep_initial_guess; },
                 [](PyGraph& g, bool keep) { g.keep_initial_guess = keep; },
                 "Whether optimize(init=\"auto\") keeps the estimates (graphs built in code, .npz "
                 "files) or replaces them by the global initialisation (pose-graph files, as the "
                 "graphslam tool does).");
  c.def_property_readonly("created_vertices", [](const PyGraph& g) { return g.created_vertices; },
                          "Vertices the reader created from edges (edges-only files).");
  c.def("has_vertex", [](const PyGraph& g, std::int64_t id) {
          return g.graph.hasVertex(toVertexId(id, "vertex id"));
        }, py::arg("id"), "Whether the graph has vertex `id`.");
  c.def("__contains__", [](const PyGraph& g, std::int64_t id) {
    return g.graph.hasVertex(toVertexId(id, "vertex id"));
  });
  c.def("vertex_tag", [](PyGraph& g, std::int64_t id) { return tagOf(vertexAt(g, id)); },
        py::arg("id"), "The tag of vertex `id`.");
  c.def("is_fixed", [](PyGraph& g, std::int64_t id) { return vertexAt(g, id).fixed(); },
        py::arg("id"), "Whether vertex `id` is fixed.");
  c.def("edge", &edgeDict, py::arg("index"),
        "Edge `index` as a dict: tag, vertex_ids, measurement, information, parameters (when the "
        "type has any), parameter_ids, active, robust, line (its line in the file, or None).");
  c.def("counts", &counts, "The number of vertices and edges of each tag: {tag: count}.");
  c.def(
      "chi2",
      [](PyGraph& g) {
        g.checkIdle();
        return g.graph.chi2();
      },
      "Sum of e^T Omega e over the active edges at the current estimates (robust kernels "
      "ignored).");
  c.def("__repr__", [](const PyGraph& g) {
    return "<graphslam.Graph " + std::to_string(g.graph.numVertices()) + " vertices, " +
           std::to_string(g.graph.numEdges()) + " edges" + (g.path.empty() ? "" : " from " + g.path) + ">";
  });
}

}  // namespace

void bindGraphArrays(py::class_<PyGraph, std::shared_ptr<PyGraph>>& c);

void bindGraph(py::module_& m) {
  py::class_<PyGraph, std::shared_ptr<PyGraph>> c(
      m, "Graph",
      "A factor graph: vertices (estimates) and edges (measurements with information "
      "matrices), by .g2o tags. Read one with graphslam.load(path) or build it in code.");
  bindConstruction(c);
  bindInspection(c);
  bindGraphArrays(c);
}

}  // namespace graphslam::python
