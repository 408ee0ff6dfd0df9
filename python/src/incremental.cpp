// SPDX-License-Identifier: MIT
// graphslam.IncrementalOptimizer: a graph that grows, an estimate after every update()
// (incremental::IncrementalOptimizer), the library working without the GIL.
#include <pybind11/stl.h>

#include "common.h"
#include "graph_types.h"
#include "graphslam/incremental/incremental_optimizer.h"

namespace graphslam::python {

namespace {

/// The optimizer and the graph it works on (kept alive by it).
struct PyIncremental {
  std::shared_ptr<PyGraph> graph;
  std::unique_ptr<incremental::IncrementalOptimizer> optimizer;
};

py::dict statsDict(const incremental::UpdateStats& s) {
  py::dict d;
  d["new_vertices"] = s.new_vertices;
  d["new_edges"] = s.new_edges;
  d["removed_edges"] = s.removed_edges;
  d["passes"] = s.passes;
  d["pass_limit_reached"] = s.pass_limit_reached;
  d["relinearized_vertices"] = s.relinearized_vertices;
  d["relinearized_edges"] = s.relinearized_edges;
  d["eliminated_columns"] = s.eliminated_columns;
  d["rebuilt"] = s.rebuilt;
  return d;
}

std::unique_ptr<PyIncremental> make(const std::shared_ptr<PyGraph>& graph, double relinearize_threshold,
                                    int relinearize_skip, int max_passes) {
  if (!(relinearize_threshold >= 0)) throw py::value_error("relinearize_threshold must be >= 0");
  if (relinearize_skip < 1 || max_passes < 1) {
    throw py::value_error("relinearize_skip and max_passes must be at least 1");
  }
  auto out = std::make_unique<PyIncremental>();
  if (graph) {
    out->graph = graph;
  } else {
    out->graph = std::make_shared<PyGraph>();
    out->graph->indexed = true;  // the (empty) index of the empty graph
  }
  out->graph->checkIdle();
  incremental::Options o;
  o.relinearize_threshold = relinearize_threshold;
  o.relinearize_skip = relinearize_skip;
  o.max_passes = max_passes;
  out->optimizer = std::make_unique<incremental::IncrementalOptimizer>(out->graph->graph, o);
  return out;
}

bool update(PyIncremental& inc, bool refine, double threshold) {
  BusyGraph busy(*inc.graph);
  py::gil_scoped_release release;
  return refine ? inc.optimizer->refine(threshold) : inc.optimizer->update();
}

}  // namespace

void bindIncremental(py::module_& m) {
  py::class_<PyIncremental> c(
      m, "IncrementalOptimizer",
      "Online optimisation of a growing graph: add vertices and edges, call update() for the "
      "new estimate; the work follows what changed (relinearisation of the vertices that moved "
      "more than relinearize_threshold, re-elimination of the affected part of the factor).");
  c.def(py::init(&make), py::arg("graph") = std::shared_ptr<PyGraph>(),
        py::arg("relinearize_threshold") = 0.1, py::arg("relinearize_skip") = 1,
        py::arg("max_passes") = 10,
        "An incremental optimizer over `graph` (a new empty one by default; it may already hold "
        "vertices and edges, which the first update() takes in).");
  c.def_property_readonly("graph", [](const PyIncremental& inc) { return inc.graph; },
                          "The graph (a graphslam.Graph; read its estimates after update()).");
  c.def(
      "add_vertex",
      [](PyIncremental& inc, const std::string& tag, std::int64_t id, const py::handle& estimate,
         bool fixed, const py::handle& parameters) {
        inc.graph->checkIdle();
        const std::uint64_t before = inc.graph->graph.structureVersion();
        Vertex& v = inc.optimizer->addVertex(makeVertex(tag, id, estimate, fixed, parameters));
        inc.graph->noteAddedVertex(v, tag, before);
      },
      py::arg("tag"), py::arg("id"), py::arg("estimate") = py::none(), py::arg("fixed") = false,
      py::arg("parameters") = py::none(), "As Graph.add_vertex, through the optimizer.");
  c.def(
      "add_edge",
      [](PyIncremental& inc, const std::string& tag, const py::handle& ids, const py::handle& z,
         const py::handle& information, const std::vector<int>& parameter_ids, const py::handle& parameters) {
        inc.graph->checkIdle();
        const std::uint64_t before = inc.graph->graph.structureVersion();
        inc.optimizer->addEdge(makeEdge(tag, vertexIdList(ids, "vertex_ids"), z, information,
                                        parameter_ids, parameters));
        inc.graph->keepIndex(before);
        inc.graph->syncEdgeLines();
        return static_cast<std::int64_t>(inc.graph->graph.numEdges()) - 1;
      },
      py::arg("tag"), py::arg("vertex_ids"), py::arg("measurement"), py::arg("information") = py::none(),
      py::arg("parameter_ids") = std::vector<int>{}, py::arg("parameters") = py::none(),
      "As Graph.add_edge, through the optimizer; returns the edge's index.");
  c.def(
      "remove_edge",
      [](PyIncremental& inc, std::int64_t index) {
        inc.graph->checkIdle();
        const auto n = static_cast<std::int64_t>(inc.graph->graph.numEdges());
        if (index < 0) index += n;
        if (index < 0 || index >= n) throw py::index_error("edge index out of range");
        const bool removed = inc.optimizer->removeEdge(inc.graph->graph.edges()[static_cast<std::size_t>(index)].get());
        inc.graph->syncEdgeLines();
        return removed;
      },
      py::arg("index"), "Removes edge `index` through the optimizer.");
  c.def("update", [](PyIncremental& inc) { return update(inc, false, 0.0); },
        "Takes in what was added since the last update and re-solves; False on a numerical "
        "failure (see failure). The estimates are in the graph afterwards.");
  c.def("refine", [](PyIncremental& inc, double threshold) { return update(inc, true, threshold); },
        py::arg("threshold") = 1e-6,
        "Further passes at a smaller relinearisation threshold, towards the batch optimum.");
  c.def_property_readonly("stats", [](PyIncremental& inc) { return statsDict(inc.optimizer->lastStats()); },
                          "What the last update() did (a dict).");
  c.def_property_readonly(
      "failure",
      [](PyIncremental& inc) {
        const auto& f = inc.optimizer->failure();
        py::dict d;
        d["vertex"] = f.vertex;
        d["message"] = f.message;
        return d;
      },
      "Why the last update() failed: {vertex, message}.");
  c.def("chi2", [](PyIncremental& inc) {
          inc.graph->checkIdle();
          return inc.optimizer->chi2();
        }, "chi2 at the current estimates.");
  c.def(
      "marginal_covariance",
      [](PyIncremental& inc, std::int64_t id) {
        inc.graph->checkIdle();
        return toArray(inc.optimizer->marginalCovariance(toVertexId(id, "vertex id")));
      },
      py::arg("id"), "The marginal covariance of vertex `id` from the current factor.");
}

}  // namespace graphslam::python
