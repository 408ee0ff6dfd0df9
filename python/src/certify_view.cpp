// SPDX-License-Identifier: MIT
// graphslam.certify / graphslam.verify_certificate (SE-Sync's certificate of global
// optimality, the certify module) and graphslam.write_view (the view module's page).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "common.h"
#include "graphslam/certify/certify.h"
#include "graphslam/view/scene.h"

namespace graphslam::python {

namespace {

py::object reportOf(const certify::CertificateReport& r) {
  py::list steps;
  for (const certify::StaircaseStep& s : r.steps) {
    py::dict d;
    d["rank"] = s.rank;
    d["iterations"] = s.iterations;
    d["inner_iterations"] = s.inner_iterations;
    d["objective"] = s.objective;
    d["gradient_norm"] = s.gradient_norm;
    d["lambda_min"] = s.lambda_min;
    d["solve_time"] = s.solve_time;
    d["verify_time"] = s.verify_time;
    steps.append(d);
  }
  py::dict d;
  d["certified"] = r.certified;
  d["reason"] = r.reason;
  d["dimension"] = r.dimension;
  d["poses"] = r.poses;
  d["measurements"] = r.measurements;
  d["objective"] = r.objective;
  d["relaxation"] = r.relaxation;
  d["dual_bound"] = r.dual_bound;
  d["suboptimality"] = r.suboptimality;
  d["lambda_min"] = r.lambda_min;
  d["residual"] = r.residual;
  d["tolerance"] = r.tolerance;
  d["eigensolver_converged"] = r.eigensolver_converged;
  d["rank"] = r.rank;
  d["steps"] = steps;
  d["setup_time"] = r.setup_time;
  d["solve_time"] = r.solve_time;
  d["verify_time"] = r.verify_time;
  d["total_time"] = r.total_time;
  d["text"] = r.report();
  static const auto* ns = new py::object(py::module_::import("types").attr("SimpleNamespace"));
  return (*ns)(**d);
}

certify::Options certifyOptions(const std::string& start, int initial_rank, int max_rank) {
  certify::Options o;
  if (start == "chordal") {
    o.start = certify::Options::Start::kChordal;
  } else if (start == "estimates") {
    o.start = certify::Options::Start::kEstimates;
  } else {
    throw py::value_error("start is 'chordal' or 'estimates', not '" + start + "'");
  }
  if (initial_rank < 2 || max_rank < initial_rank) {
    throw py::value_error("need 2 <= initial_rank <= max_rank");
  }
  o.initial_rank = initial_rank;
  o.max_rank = max_rank;
  return o;
}

py::object certifyGraph(PyGraph& g, const std::string& start, int initial_rank, int max_rank) {
  const certify::Options options = certifyOptions(start, initial_rank, max_rank);
  BusyGraph busy(g);
  certify::CertificateReport r;
  {
    py::gil_scoped_release release;
    r = certify::certify(g.graph, options);
  }
  return reportOf(r);
}

py::object verifyGraph(PyGraph& g) {
  BusyGraph busy(g);
  certify::CertificateReport r;
  {
    py::gil_scoped_release release;
    r = certify::verifyEstimates(g.graph);
  }
  return reportOf(r);
}

void writeView(PyGraph& g, const std::string& path, const std::string& title,
               const std::map<VertexId, Eigen::MatrixXd>& covariances) {
  BusyGraph busy(g);
  view::Options options;
  options.title = title.empty() ? g.name() : title;
  view::Scene scene(g.graph, registries().types, options);
  if (!g.path.empty()) scene.setSourceLines(g.path, {}, g.edge_lines);
  for (const auto& [id, block] : covariances) {
    if (!g.graph.vertex(id)) {
      throw py::value_error("covariances: no vertex " + std::to_string(id) + " in the graph");
    }
    scene.addCovariance(id, block);
  }
  py::gil_scoped_release release;
  scene.writePage(path);
}

}  // namespace

void bindCertifyView(py::module_& m) {
  m.def("certify", &certifyGraph, py::arg("graph"), py::arg("start") = "chordal",
        py::arg("initial_rank") = 5, py::arg("max_rank") = 10,
        "Certifies the pose graph's global optimum of SE-Sync's objective (isotropic "
        "weights from the information matrices, not the file's chi2; README \"What certify "
        "proves\"), as `graphslam certify` does, and writes the rounded solution into the "
        "graph. Returns a namespace: certified, reason, objective (F(x)), dual_bound, "
        "suboptimality, lambda_min, residual, tolerance, rank, steps (one dict per rank), "
        "the times and text (the tool's report). Raises InputError for graphs the method "
        "does not support (landmarks, other edge types, a disconnected graph).");
  m.def("verify_certificate", &verifyGraph, py::arg("graph"),
        "The certificate of the graph's current rotations as they are (no solve): "
        "certified only when they are SE-Sync's global optimum. Returns the namespace of "
        "certify().");
  m.def("write_view", &writeView, py::arg("graph"), py::arg("path"), py::arg("title") = "",
        py::arg("covariances") = std::map<VertexId, Eigen::MatrixXd>{},
        "Writes one self-contained HTML page to explore the graph (`graphslam view`, "
        "docs/VIEW.md): its current estimate, edges by kind and chi2, the file line of "
        "each edge read from a file, and the 3-sigma ellipse of each {vertex id: "
        "covariance block} given (e.g. from marginals()). Atomic: on an error no file is "
        "left.");
}

}  // namespace graphslam::python
