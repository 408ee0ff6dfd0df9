// SPDX-License-Identifier: MIT
// graphslam.OptimizeResult, and marginal covariances (graphslam.marginals) as numpy
// matrices.
#include <pybind11/stl.h>

#include <map>

#include "common.h"
#include "graph_types.h"
#include "graphslam/optimizer/marginals.h"
#include "optimize.h"

namespace graphslam::python {

namespace {

py::dict timeDict(const Summary& s) {
  py::dict d;
  d["total"] = s.total_time;
  d["linearize"] = s.time.linearize;
  d["build"] = s.time.build;
  d["factorize"] = s.time.factorize;
  d["solve"] = s.time.solve;
  return d;
}

py::list rejectedList(const OptimizeResult& r) {
  py::list out;
  for (const auto& x : r.rejected) {
    py::dict d;
    d["index"] = x.index;
    d["vertex_ids"] = x.vertex_ids;
    d["chi2"] = x.chi2;
    d["line"] = x.line > 0 ? py::object(py::int_(x.line)) : py::object(py::none());
    out.append(d);
  }
  return out;
}

/// Marginal covariances of chosen vertices (blocks of H^-1 at the current estimates).
struct Marginals {
  std::map<VertexId, Eigen::MatrixXd> blocks;
  std::map<std::pair<VertexId, VertexId>, Eigen::MatrixXd> cross;
  std::vector<VertexId> ids;
  std::vector<VertexId> gauge_fixed;
  double seconds = 0.0;
  std::string report;
};

Marginals marginals(PyGraph& g, const py::object& ids_obj, const py::object& tag,
                    const py::object& cross_obj) {
  std::vector<VertexId> ids;
  if (!ids_obj.is_none()) {
    auto a = idArray(ids_obj, "ids");
    for (py::ssize_t k = 0; k < a.size(); ++k) {
      const VertexId id = toVertexId(a.data()[k], "vertex id");
      if (!g.graph.hasVertex(id)) throw py::key_error("vertex " + std::to_string(id) + " is not in the graph");
      ids.push_back(id);
    }
  } else {
    const std::string t = tag.is_none() ? std::string() : tag.cast<std::string>();
    if (!t.empty()) (void)vertexTagType(t);  // RegistryError for an unknown tag
    for (const auto& [id, v] : g.graph.vertices()) {
      if (!v->fixed() && (t.empty() || tagOf(*v) == t)) ids.push_back(id);
    }
  }
  std::vector<std::pair<VertexId, VertexId>> pairs;
  if (!cross_obj.is_none()) {
    auto a = idArray(cross_obj, "cross_pairs");
    if (a.ndim() != 2 || a.shape(1) != 2) shapeError("cross_pairs", "(M, 2)", a);
    for (py::ssize_t k = 0; k < a.shape(0); ++k) {
      pairs.emplace_back(toVertexId(a.data()[2 * k], "vertex id"), toVertexId(a.data()[2 * k + 1], "vertex id"));
    }
  }
  BusyGraph busy(g);
  MarginalCovariance::Options options;
  options.solvers = &registries().solvers;
  MarginalCovariance mc(options);
  MarginalSummary summary;
  {
    py::gil_scoped_release release;
    summary = mc.compute(g.graph, ids, pairs);
  }
  if (!summary.ok()) {
    throw InputError(g.name() + ": marginal covariances failed (" + toString(summary.status) +
                     "): " + summary.message);
  }
  Marginals out;
  out.blocks = mc.blocks();
  for (const auto& p : pairs) out.cross[p] = mc.crossBlock(p.first, p.second);
  out.ids = ids;
  out.gauge_fixed = summary.gauge_fixed;
  out.seconds = summary.total_time;
  out.report = summary.report();
  return out;
}

const Eigen::MatrixXd& blockOf(const Marginals& m, std::int64_t id) {
  const auto it = m.blocks.find(toVertexId(id, "vertex id"));
  if (it == m.blocks.end()) throw py::key_error("no covariance of vertex " + std::to_string(id) + " was computed");
  return it->second;
}

void bindMarginals(py::module_& m) {
  py::class_<Marginals> c(m, "Marginals",
                          "Marginal covariances: blocks of H^-1 at the estimates, in each "
                          "vertex's tangent space (its update order: SE2 x, y, theta).");
  c.def("__getitem__", [](const Marginals& mg, std::int64_t id) { return toArray(blockOf(mg, id)); },
        py::arg("id"), "The covariance of vertex `id` (D x D).");
  c.def("covariance", [](const Marginals& mg, std::int64_t id) { return toArray(blockOf(mg, id)); },
        py::arg("id"), "The covariance of vertex `id` (D x D).");
  c.def("__contains__", [](const Marginals& mg, std::int64_t id) {
    return mg.blocks.count(toVertexId(id, "vertex id")) != 0;
  });
  c.def("__len__", [](const Marginals& mg) { return mg.ids.size(); });
  c.def(
      "cross",
      [](const Marginals& mg, std::int64_t a, std::int64_t b) {
        const VertexId va = toVertexId(a, "vertex id"), vb = toVertexId(b, "vertex id");
        auto it = mg.cross.find({va, vb});
        if (it != mg.cross.end()) return toArray(it->second);
        it = mg.cross.find({vb, va});
        if (it != mg.cross.end()) return toArray(Eigen::MatrixXd(it->second.transpose()));
        throw py::key_error("the cross covariance of " + std::to_string(a) + " and " +
                            std::to_string(b) + " was not requested (cross_pairs)");
      },
      py::arg("a"), py::arg("b"), "Cov(x_a, x_b) of a pair given in cross_pairs.");
  c.def_property_readonly("ids", [](const Marginals& mg) { return toIdArray(mg.ids); },
                          "The vertices whose covariances were computed.");
  c.def(
      "stack",
      [](const Marginals& mg) {
        if (mg.ids.empty()) return newArray({0, 0, 0});
        const auto d = static_cast<py::ssize_t>(mg.blocks.at(mg.ids[0]).rows());
        auto out = newArray({static_cast<py::ssize_t>(mg.ids.size()), d, d});
        for (std::size_t k = 0; k < mg.ids.size(); ++k) {
          const Eigen::MatrixXd& b = mg.blocks.at(mg.ids[k]);
          if (b.rows() != d) throw py::value_error("the vertices have different dimensions");
          for (py::ssize_t i = 0; i < d; ++i) {
            for (py::ssize_t j = 0; j < d; ++j) out.mutable_data()[(k * d + i) * d + j] = b(i, j);
          }
        }
        return out;
      },
      "Every block in the order of `ids`, as one array (N, D, D).");
  c.def_readonly("gauge_fixed", &Marginals::gauge_fixed,
                 "The vertex fixed for the computation (its covariance is zero, the others relative to it).");
  c.def_readonly("seconds", &Marginals::seconds, "Time of the computation.");
  c.def_readonly("report", &Marginals::report, "The library's report.");
  m.def("marginals", &marginals, py::arg("graph"), py::arg("ids") = py::none(),
        py::arg("tag") = py::none(), py::arg("cross_pairs") = py::none(),
        "Marginal covariances at the current estimates of the vertices `ids` (default: every "
        "non-fixed vertex, of `tag` when given) and the cross blocks of `cross_pairs` (M, 2). "
        "Raises graphslam.InputError naming the vertices when H is singular there or a vertex "
        "has no edge.");
}

}  // namespace

void bindOptimizeResult(py::module_& m) {
  py::class_<OptimizeResult> c(m, "OptimizeResult", "What graphslam.optimize did.");
  c.def_readonly("ok", &OptimizeResult::ok,
                 "True when the estimate is usable: converged, iterations used up or stopped by the callback.");
  c.def_readonly("status", &OptimizeResult::status,
                 "converged, max_iterations, stopped, no_progress, numerical_failure, "
                 "under_determined or singular (H singular at a damped result).");
  c.def_readonly("message", &OptimizeResult::message, "Why it ended (names vertices and lines on failures).");
  c.def_readonly("stopped", &OptimizeResult::stopped, "The callback stopped the run.");
  c.def_property_readonly("initial_chi2", [](const OptimizeResult& r) { return r.summary.initial_chi2; },
                          "sum e^T Omega e before the iterations (after the initial guess).");
  c.def_property_readonly("final_chi2", [](const OptimizeResult& r) { return r.summary.final_chi2; },
                          "sum e^T Omega e at the result.");
  c.def_property_readonly("initial_cost", [](const OptimizeResult& r) { return r.summary.initial_cost; },
                          "The objective (sum rho(chi2) with robust kernels) before.");
  c.def_property_readonly("final_cost", [](const OptimizeResult& r) { return r.summary.final_cost; },
                          "The objective at the result.");
  c.def_property_readonly("iterations", [](const OptimizeResult& r) { return r.summary.iterations; },
                          "Iterations run.");
  c.def_property_readonly(
      "chi2_history",
      [](const OptimizeResult& r) {
        std::vector<double> v;
        for (const auto& it : r.summary.per_iteration) v.push_back(it.chi2);
        return toArray(v);
      },
      "The objective after each iteration.");
  c.def_property_readonly("algorithm", [](const OptimizeResult& r) { return std::string(toString(r.summary.algorithm)); },
                          "The algorithm run.");
  c.def_property_readonly("linear_solver", [](const OptimizeResult& r) { return r.summary.linear_solver; },
                          "The linear solver used (auto names its choice).");
  c.def_property_readonly("time", [](const OptimizeResult& r) { return timeDict(r.summary); },
                          "Seconds of the optimizer: total, linearize, build, factorize, solve.");
  c.def_readonly("seconds", &OptimizeResult::seconds,
                 "Seconds of the whole call (initial guess, checks, outlier rejection, optimizer).");
  c.def_property_readonly("gauge_fixed", [](const OptimizeResult& r) { return r.summary.gauge_fixed; },
                          "Vertices fixed for the run to remove the gauge freedom.");
  c.def_property_readonly("unanchored", [](const OptimizeResult& r) { return r.summary.unanchored; },
                          "Groups of vertices nothing anchors (each was anchored at its first id).");
  c.def_property_readonly("rejected_edges", &rejectedList,
                          "Edges outlier rejection removed: dicts of index (before the removal), "
                          "vertex_ids, chi2, line.");
  c.def_readonly("dropped_vertices", &OptimizeResult::dropped,
                 "Vertices drop_unobservable removed (with their edges).");
  c.def_readonly("initialization", &OptimizeResult::initialization, "What the initial guess did, line by line.");
  c.def_readonly("robust_edges", &OptimizeResult::robust_edges, "Edges given the robust kernel.");
  c.def_property_readonly("failed_vertex", [](const OptimizeResult& r) { return r.summary.failed_vertex; },
                          "On a failed factorisation: the vertex whose column failed (-1: none).");
  c.def_property_readonly("report", [](const OptimizeResult& r) { return r.summary.report(); },
                          "The optimizer's multi-line report (as the graphslam tool prints it).");
  c.def("__repr__", [](const OptimizeResult& r) {
    return "<graphslam.OptimizeResult " + r.status + ", chi2 " + std::to_string(r.summary.initial_chi2) +
           " -> " + std::to_string(r.summary.final_chi2) + ", " + std::to_string(r.summary.iterations) +
           " iterations>";
  });
  bindMarginals(m);
}

}  // namespace graphslam::python
