// SPDX-License-Identifier: MIT
// graphslam.Graph in bulk: estimates, measurements and information of every vertex or edge
// of a tag as numpy arrays, read and written without a Python object per vertex.
#include <pybind11/stl.h>

#include <algorithm>
#include <cstring>

#include <Eigen/Cholesky>

#include "common.h"
#include "graph_types.h"

namespace graphslam::python {

namespace {

py::tuple estimates(PyGraph& g, const std::string& tag) {
  g.checkReadable();
  const int dim = vertexTagType(tag).data_dimension;
  const PyGraph::TagVertices& cached = g.verticesOf(tag);
  const std::vector<Vertex*>& vs = cached.vertices;
  const auto n = static_cast<py::ssize_t>(vs.size());
  py::array_t<std::int64_t> ids(n);
  auto values = newArray({n, dim});
  std::int64_t* pid = ids.mutable_data();
  double* px = values.mutable_data();
  for (py::ssize_t k = 0; k < n; ++k) {
    pid[k] = cached.ids[static_cast<std::size_t>(k)];
    vs[static_cast<std::size_t>(k)]->getEstimateData(px + k * dim);
  }
  return py::make_tuple(ids, values);
}

/// The vertices of `ids`, each checked to be of `tag`'s type; sorted ids are walked along
/// the graph's map (one step per id), others looked up.
std::vector<Vertex*> resolve(PyGraph& g, const std::string& tag, const std::int64_t* ids,
                             std::size_t n) {
  // The ids estimates(tag) returned: the cached vertices, no look-up.
  const PyGraph::TagVertices& cached = g.verticesOf(tag);
  if (cached.ids.size() == n) {
    std::size_t k = 0;
    while (k < n && cached.ids[k] == ids[k]) ++k;
    if (k == n) return cached.vertices;
  }
  const std::type_index type = vertexTagType(tag).type;
  const auto& map = g.graph.vertices();
  std::vector<Vertex*> out(n);
  auto it = map.end();
  for (std::size_t k = 0; k < n; ++k) {
    const VertexId id = toVertexId(ids[k], "vertex id");
    if (it != map.end()) ++it;
    if (it == map.end() || it->first != id) it = map.find(id);
    if (it == map.end()) {
      throw py::key_error("vertex " + std::to_string(id) + " is not in the graph");
    }
    Vertex* v = it->second.get();
    if (std::type_index(typeid(*v)) != type) {
      throw py::value_error("vertex " + std::to_string(id) + " is " + tagOf(*v) + ", not " + tag);
    }
    out[k] = v;
  }
  return out;
}

/// The estimates of `n` vertices of `tag` (n, D), checked.
DoubleArray estimateRows(const py::handle& values_obj, py::ssize_t n, const std::string& tag) {
  const int dim = vertexTagType(tag).data_dimension;
  auto values = doubleArray(values_obj, "the estimates");
  if (values.ndim() != 2 || values.shape(0) != n || values.shape(1) != dim) {
    shapeError("the estimates of " + std::to_string(n) + " " + tag + " vertices",
               "(" + std::to_string(n) + ", " + std::to_string(dim) + ")", values);
  }
  return values;
}

void setEstimates(PyGraph& g, const std::string& tag, const py::handle& ids_obj,
                  const py::handle& values_obj) {
  g.checkIdle();
  const int dim = vertexTagType(tag).data_dimension;
  auto ids = idArray(ids_obj, "ids");
  if (ids.ndim() != 1) shapeError("ids", "(N,)", ids);
  const py::ssize_t n = ids.shape(0);
  const auto values = estimateRows(values_obj, n, tag);
  const std::vector<Vertex*> vs = resolve(g, tag, ids.data(), static_cast<std::size_t>(n));
  const double* px = values.data();
  for (py::ssize_t k = 0; k < n; ++k) vs[static_cast<std::size_t>(k)]->setEstimateData(px + k * dim);
}

py::array_t<double> estimate(PyGraph& g, std::int64_t id) {
  g.checkReadable();
  const Vertex* v = g.graph.vertex(toVertexId(id, "vertex id"));
  if (v == nullptr) throw py::key_error("vertex " + std::to_string(id) + " is not in the graph");
  auto out = newArray({v->estimateDataDimension()});
  v->getEstimateData(out.mutable_data());
  return out;
}

void setEstimate(PyGraph& g, std::int64_t id, const py::handle& value) {
  g.checkIdle();
  Vertex* v = g.graph.vertex(toVertexId(id, "vertex id"));
  if (v == nullptr) throw py::key_error("vertex " + std::to_string(id) + " is not in the graph");
  const Eigen::VectorXd x = vectorArg(value, "the estimate of vertex " + std::to_string(id),
                                      v->estimateDataDimension());
  v->setEstimateData(x.data());
}

py::array_t<std::int64_t> vertexIds(PyGraph& g, const py::object& tag, bool fixed_only) {
  g.checkReadable();
  std::vector<VertexId> ids;
  if (tag.is_none()) {
    for (const auto& [id, v] : g.graph.vertices()) {
      if (!fixed_only || v->fixed()) ids.push_back(id);
    }
  } else {
    for (const Vertex* v : g.verticesOf(tag.cast<std::string>()).vertices) {
      if (!fixed_only || v->fixed()) ids.push_back(v->id());
    }
  }
  return toIdArray(ids);
}

std::vector<std::size_t> edgesOfTag(const PyGraph& g, const std::string& tag) {
  const std::type_index type = edgeTagType(tag).type;
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < g.graph.numEdges(); ++k) {
    if (std::type_index(typeid(*g.graph.edges()[k])) == type) out.push_back(k);
  }
  return out;
}

py::tuple edges(PyGraph& g, const std::string& tag) {
  g.checkReadable();
  const std::vector<std::size_t> idx = edgesOfTag(g, tag);
  const auto n = static_cast<py::ssize_t>(idx.size());
  const auto& all = g.graph.edges();
  py::ssize_t arity = edgeTagType(tag).arity;
  py::ssize_t mdim = edgeTagType(tag).data_dimension;
  if (n > 0) {
    arity = static_cast<py::ssize_t>(all[idx[0]]->numVertices());
    mdim = all[idx[0]]->measurementDataDimension();
  }
  for (std::size_t k : idx) {
    if (static_cast<py::ssize_t>(all[k]->numVertices()) != arity) {
      throw py::value_error("the " + tag + " edges join different numbers of vertices: read them "
                            "one by one with graph.edge(i)");
    }
  }
  py::array_t<std::int64_t> indices(n);
  py::array_t<std::int64_t> ids({n, std::max<py::ssize_t>(arity, 0)});
  auto z = newArray({n, mdim});
  for (py::ssize_t k = 0; k < n; ++k) {
    const Edge& e = *all[idx[static_cast<std::size_t>(k)]];
    indices.mutable_data()[k] = static_cast<std::int64_t>(idx[static_cast<std::size_t>(k)]);
    for (py::ssize_t s = 0; s < arity; ++s) {
      ids.mutable_data()[k * arity + s] = e.vertexId(static_cast<std::size_t>(s));
    }
    e.getMeasurementData(z.mutable_data() + k * mdim);
  }
  return py::make_tuple(indices, ids, z);
}

py::array_t<double> edgeInformation(PyGraph& g, const std::string& tag) {
  g.checkReadable();
  const std::vector<std::size_t> idx = edgesOfTag(g, tag);
  const auto n = static_cast<py::ssize_t>(idx.size());
  py::ssize_t d = edgeTagType(tag).dimension;
  if (n > 0) d = g.graph.edges()[idx[0]]->dimension();
  auto out = newArray({n, d, d});
  for (py::ssize_t k = 0; k < n; ++k) {
    const Edge& e = *g.graph.edges()[idx[static_cast<std::size_t>(k)]];
    if (e.dimension() != d) {
      throw py::value_error("the " + tag + " edges have different dimensions: read them one by "
                            "one with graph.edge(i)");
    }
    // Column-major in the edge; symmetric, so the row-major copy is the same matrix.
    std::memcpy(out.mutable_data() + k * d * d, e.informationData(), sizeof(double) * d * d);
  }
  return out;
}

py::array_t<double> edgeChi2(PyGraph& g) {
  g.checkIdle();
  const auto n = static_cast<py::ssize_t>(g.graph.numEdges());
  auto out = newArray({n});
  for (py::ssize_t k = 0; k < n; ++k) {
    Edge& e = *g.graph.edges()[static_cast<std::size_t>(k)];
    e.computeError();
    out.mutable_data()[k] = e.chi2();
  }
  return out;
}

py::object groundTruth(const PyGraph& g) {
  const io::PointGroundTruth& t = g.ground_truth;
  if (t.empty()) return py::none();
  auto points = [](const std::vector<Eigen::Vector2d>& p) {
    auto a = newArray({static_cast<py::ssize_t>(p.size()), 2});
    for (std::size_t k = 0; k < p.size(); ++k) {
      a.mutable_data()[2 * k] = p[k].x();
      a.mutable_data()[2 * k + 1] = p[k].y();
    }
    return a;
  };
  py::dict d;
  d["pose_ids"] = toIdArray(t.pose_ids);
  d["poses"] = points(t.poses);
  d["landmark_ids"] = toIdArray(t.landmark_ids);
  d["landmarks"] = points(t.landmarks);
  return d;
}

void addVertices(PyGraph& g, const std::string& tag, const py::handle& ids_obj,
                 const py::handle& values_obj, bool fixed) {
  g.checkIdle();
  const int dim = vertexTagType(tag).data_dimension;
  auto ids = idArray(ids_obj, "ids");
  if (ids.ndim() != 1) shapeError("ids", "(N,)", ids);
  const py::ssize_t n = ids.shape(0);
  const auto values = estimateRows(values_obj, n, tag);
  // Every id checked before the first is added: all or nothing.
  std::vector<VertexId> vids(static_cast<std::size_t>(n));
  bool increasing = true;
  for (py::ssize_t k = 0; k < n; ++k) {
    vids[k] = toVertexId(ids.data()[k], "vertex id");
    if (g.graph.hasVertex(vids[k])) {
      throw py::value_error("vertex " + std::to_string(vids[k]) + " is already in the graph");
    }
    if (k > 0 && vids[k] <= vids[k - 1]) increasing = false;
  }
  if (!increasing) {
    std::vector<VertexId> sorted = vids;
    std::sort(sorted.begin(), sorted.end());
    const auto dup = std::adjacent_find(sorted.begin(), sorted.end());
    if (dup != sorted.end()) throw py::value_error("vertex id " + std::to_string(*dup) + " appears twice");
  }
  // New ids above every id of the graph, in order, extend a valid index: no walk after.
  const bool extend = g.indexed && g.index_version == g.graph.structureVersion() && increasing &&
                      (n == 0 || g.graph.numVertices() == 0 || vids[0] > g.graph.vertices().rbegin()->first);
  PyGraph::TagVertices* list = extend ? &g.tag_vertices[tag] : nullptr;
  const auto& types = registries().types;
  for (py::ssize_t k = 0; k < n; ++k) {
    auto v = types.createVertex(tag);
    v->setId(vids[k]);
    v->setEstimateData(values.data() + k * dim);
    v->setFixed(fixed);
    Vertex& added = g.graph.addVertex(std::move(v));
    if (list) {
      list->vertices.push_back(&added);
      list->ids.push_back(vids[k]);
    }
  }
  if (extend) g.index_version = g.graph.structureVersion();
}

py::array_t<std::int64_t> addEdges(PyGraph& g, const std::string& tag, const py::handle& ids_obj,
                                   const py::handle& z_obj, const py::handle& info_obj) {
  g.checkIdle();
  const TagType& t = edgeTagType(tag);
  if (t.arity < 0) throw py::value_error(tag + " edges have no fixed arity: add them with add_edge");
  auto ids = idArray(ids_obj, "vertex_ids");
  if (ids.ndim() != 2 || ids.shape(1) != t.arity) {
    shapeError("vertex_ids of " + tag + " edges", "(M, " + std::to_string(t.arity) + ")", ids);
  }
  const py::ssize_t n = ids.shape(0);
  const py::ssize_t d = t.dimension;
  auto z = doubleArray(z_obj, "the measurements");
  if (z.ndim() != 2 || z.shape(0) != n || z.shape(1) != t.data_dimension) {
    shapeError("the measurements", "(" + std::to_string(n) + ", " + std::to_string(t.data_dimension) + ")", z);
  }
  DoubleArray info;
  const bool shared = info_obj.is_none() || doubleArray(info_obj, "the information").ndim() == 2;
  Eigen::MatrixXd one = Eigen::MatrixXd::Identity(d, d);
  if (!info_obj.is_none()) {
    info = doubleArray(info_obj, "the information");
    if (shared && (info.shape(0) != d || info.shape(1) != d)) {
      shapeError("the information", "(d, d) or (M, d, d) with d = " + std::to_string(d), info);
    }
    if (!shared && (info.ndim() != 3 || info.shape(0) != n || info.shape(1) != d || info.shape(2) != d)) {
      shapeError("the information", "(" + std::to_string(d) + ", " + std::to_string(d) + ") or (" +
                 std::to_string(n) + ", " + std::to_string(d) + ", " + std::to_string(d) + ")", info);
    }
  }
  auto infoOf = [&](py::ssize_t k) -> Eigen::MatrixXd {
    if (info_obj.is_none()) return one;
    Eigen::MatrixXd m(d, d);
    const double* p = info.data() + (shared ? 0 : k * d * d);
    for (py::ssize_t i = 0; i < d; ++i) {
      for (py::ssize_t j = 0; j < d; ++j) m(i, j) = p[i * d + j];
    }
    return m;
  };
  // Every edge checked (vertices, their types, the information) before the first is added.
  const auto proto = registries().types.createEdge(tag);
  std::vector<Eigen::MatrixXd> infos;
  for (py::ssize_t k = 0; k < n; ++k) {
    for (py::ssize_t s = 0; s < t.arity; ++s) {
      const VertexId id = toVertexId(ids.data()[k * t.arity + s], "vertex id");
      const Vertex* v = g.graph.vertex(id);
      if (v == nullptr) {
        throw py::key_error("edge " + std::to_string(k) + ": vertex " + std::to_string(id) + " is not in the graph");
      }
      if (!proto->acceptsVertex(static_cast<std::size_t>(s), *v)) {
        throw py::value_error("edge " + std::to_string(k) + ": vertex " + std::to_string(id) + " is " +
                              tagOf(*v) + ", not " + expectedTag(*proto, static_cast<std::size_t>(s)));
      }
    }
    if (k == 0 || !shared) {
      Eigen::MatrixXd m = infoOf(k);
      const double scale = std::max(1.0, m.cwiseAbs().maxCoeff());
      if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale ||
          Eigen::LLT<Eigen::MatrixXd>(m).info() != Eigen::Success) {
        throw py::value_error("the information of edge " + std::to_string(k) +
                              " is not symmetric positive definite");
      }
      infos.push_back(std::move(m));
    }
  }
  py::array_t<std::int64_t> out(n);
  const bool had_lines = !g.edge_lines.empty();
  const std::uint64_t before = g.graph.structureVersion();
  for (py::ssize_t k = 0; k < n; ++k) {
    auto e = registries().types.createEdge(tag);
    std::vector<VertexId> vs(static_cast<std::size_t>(t.arity));
    for (py::ssize_t s = 0; s < t.arity; ++s) vs[s] = static_cast<VertexId>(ids.data()[k * t.arity + s]);
    e->setVertexIds(vs);
    e->setMeasurementData(z.data() + k * t.data_dimension);
    e->setInformationData(infos[shared ? 0 : k].data());
    g.graph.addEdge(std::move(e));
    if (had_lines) g.edge_lines.push_back(0);
    out.mutable_data()[k] = static_cast<std::int64_t>(g.graph.numEdges()) - 1;
  }
  g.keepIndex(before);
  return out;
}

}  // namespace

void bindGraphArrays(py::class_<PyGraph, std::shared_ptr<PyGraph>>& c) {
  c.def("add_vertices", &addVertices, py::arg("tag"), py::arg("ids"), py::arg("estimates"),
        py::arg("fixed") = false,
        "Adds N vertices of `tag` at once: ids (N,), estimates (N, D). All or nothing: every id "
        "is checked (ValueError for one already in the graph or given twice) first.");
  c.def("add_edges", &addEdges, py::arg("tag"), py::arg("vertex_ids"), py::arg("measurements"),
        py::arg("information") = py::none(),
        "Adds M edges of `tag` at once: vertex_ids (M, k), measurements (M, m), information "
        "(d, d) shared by all, (M, d, d) one each, or None (identity). All or nothing: every "
        "vertex, its type and every information matrix are checked first (KeyError, "
        "ValueError). Returns the new edges' indices.");
  c.def("estimates", &estimates, py::arg("tag"),
        "The estimates of every vertex of `tag`, in id order: (ids, values), ids an int64 array "
        "(N,), values a float64 array (N, D) as the .g2o line holds them (VERTEX_SE2: x, y, "
        "theta; VERTEX_XY: x, y; VERTEX_SE3:QUAT: x, y, z, qx, qy, qz, qw).");
  c.def("set_estimates", &setEstimates, py::arg("tag"), py::arg("ids"), py::arg("values"),
        "Sets the estimates of the vertices `ids` (all of `tag`) from `values` (N, D). Every id "
        "and value is checked before anything changes: KeyError for an id not in the graph, "
        "ValueError for a vertex of another tag, a wrong shape or NaN.");
  c.def("estimate", &estimate, py::arg("id"), "The estimate of vertex `id` (a 1-D array).");
  c.def("set_estimate", &setEstimate, py::arg("id"), py::arg("value"),
        "Sets the estimate of vertex `id`.");
  c.def("vertex_ids", &vertexIds, py::arg("tag") = py::none(), py::arg("fixed_only") = false,
        "The ids of the vertices (of `tag` when given; only the fixed ones with fixed_only), "
        "sorted, as an int64 array.");
  c.def("edges", &edges, py::arg("tag"),
        "The edges of `tag` in graph order: (indices (M,), vertex_ids (M, k), measurements "
        "(M, m)). ValueError when the tag's edges join different numbers of vertices.");
  c.def("edge_information", &edgeInformation, py::arg("tag"),
        "The information matrices of the edges of `tag`, in the order of edges(tag): (M, d, d).");
  c.def("edge_chi2", &edgeChi2,
        "e^T Omega e of every edge at the current estimates, in edge order (inactive edges "
        "included).");
  c.def_property_readonly("ground_truth", &groundTruth,
                          "The ground truth a file came with (CMU homework .npz): a dict with "
                          "pose_ids, poses (N, 2), landmark_ids, landmarks (L, 2); None otherwise.");
}

}  // namespace graphslam::python
