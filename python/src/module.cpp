// SPDX-License-Identifier: MIT
// The _graphslam extension module: the process's registries, the exceptions, the listings
// and process settings; each part of the API is bound in its own file (graph.cpp, io.cpp,
// optimize.cpp, trajectory.cpp, eval.cpp, simulation.cpp, incremental.cpp, custom_edge.cpp).
#include <pybind11/stl.h>

#include <cstdlib>
#include <mutex>

#include "common.h"
#include "graphslam/io/graph_file.h"
#include "graphslam/solvers/process.h"
#include "graphslam/support/error.h"
#include "graphslam/support/large_array.h"
#include "graphslam/support/logging.h"

namespace graphslam::python {

host::Registries& registries() {
  // Leaked on purpose: graphs Python holds at interpreter exit use the types' code.
  static host::Registries* reg = [] {
    auto* r = new host::Registries;
    host::registerBuiltins(*r);
    return r;
  }();
  return *reg;
}

namespace {

PyObject* g_error = nullptr;
PyObject* g_registry_error = nullptr;
PyObject* g_input_error = nullptr;

PyObject* newException(py::module_& m, const char* name, const char* doc, PyObject* bases) {
  const std::string qualified = std::string("graphslam.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases, nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.add_object(name, py::reinterpret_borrow<py::object>(type));
  return type;  // the reference stays for the process's lifetime
}

py::list typeEntries(TypeRegistry::Kind kind) {
  py::list out;
  for (const auto* e : registries().types.entries()) {
    if (e->kind == kind) out.append(e->tag);
  }
  return out;
}

}  // namespace

void bindErrors(py::module_& m) {
  g_error = newException(m, "Error",
                         "Base of the errors the graphslam library reports (graphslam::Error): "
                         "API misuse or unusable input; the message is the library's.",
                         PyExc_RuntimeError);
  py::tuple registry_bases = py::make_tuple(py::handle(g_error), py::handle(PyExc_LookupError));
  g_registry_error = newException(
      m, "RegistryError",
      "A name the registries do not know (a tag, solver, kernel, format) or a registration "
      "they refuse (graphslam::RegistryError).",
      registry_bases.ptr());
  py::tuple input_bases = py::make_tuple(py::handle(g_error), py::handle(PyExc_ValueError));
  g_input_error = newException(
      m, "InputError",
      "Input the library cannot use (graphslam::InputError); the message names the file and "
      "line (FILE:LINE: ...) or the vertex ids whenever they are known.",
      input_bases.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(g_input_error, e.what());
    } catch (const RegistryError& e) {
      PyErr_SetString(g_registry_error, e.what());
    } catch (const Error& e) {
      PyErr_SetString(g_error, e.what());
    }
  });
}

namespace {

void bindRegistryListings(py::module_& m) {
  m.def(
      "vertex_tags", [] { return typeEntries(TypeRegistry::Kind::kVertex); },
      "The registered vertex tags (\"VERTEX_SE2\", \"VERTEX_SE3:QUAT\", ...), sorted.");
  m.def(
      "edge_tags", [] { return typeEntries(TypeRegistry::Kind::kEdge); },
      "The registered edge tags (\"EDGE_SE2\", ...), sorted.");
  m.def(
      "parameter_tags", [] { return typeEntries(TypeRegistry::Kind::kParameter); },
      "The registered parameter tags (\"PARAMS_SE2OFFSET\", ...), sorted.");
  m.def(
      "solvers",
      [] {
        py::list out;
        for (const auto* e : registries().solvers.entries()) out.append(e->name);
        return out;
      },
      "The registered linear solvers (names for optimize(solver=...)), sorted.");
  m.def(
      "kernels",
      [] {
        py::dict out;
        for (const auto* e : registries().kernels.entries())
          out[py::str(e->name)] = e->default_width;
        return out;
      },
      "The registered robust kernels: {name: default width} "
      "(optimize(robust_kernel=\"NAME[:WIDTH]\")).");
  m.def(
      "graph_formats",
      [] {
        py::list out;
        for (const auto* f : registries().formats.formats<io::GraphFile>()) {
          py::dict d;
          d["name"] = f->name;
          d["description"] = f->description;
          d["extensions"] = f->extensions;
          d["read"] = static_cast<bool>(f->read);
          d["write"] = static_cast<bool>(f->write);
          out.append(d);
        }
        return out;
      },
      "The graph file formats: a list of dicts (name, description, extensions, read, write).");
}

void bindProcess(py::module_& m) {
  m.def(
      "load_plugins",
      [](const std::vector<std::string>& files) { host::loadPlugins(registries(), files); },
      py::arg("files") = std::vector<std::string>{},
      "Loads the plugins of GRAPHSLAM_PLUGIN_PATH's folders, then `files` (shared libraries "
      "exporting graphslam_plugin_register): their types, solvers and kernels become usable by "
      "tag and name. Raises graphslam.Error naming a file that fails to load or registers a "
      "name that is taken.");
  m.def(
      "configure_process",
      [](bool prefault, bool serialize_cholmod_openmp, bool retain_large_arrays) {
        if (prefault) solvers::installCholmodPrefaultingAllocator();
        if (serialize_cholmod_openmp) solvers::serializeCholmodOpenMp(true);
        if (retain_large_arrays) support::setLargeArrayRetention(support::LargeArrayRetention{});
      },
      py::arg("prefault") = true, py::arg("serialize_cholmod_openmp") = true,
      py::arg("retain_large_arrays") = true,
      "Opts this process into the settings the graphslam tool makes at start-up for speed "
      "(the library makes none by itself): CHOLMOD's large allocations faulted in on two "
      "threads, CHOLMOD's OpenMP loops serial, freed huge-page arrays kept for the next "
      "optimisation. Call it once, before the first optimisation.");
  m.def(
      "set_blas_threads", [](int threads) { return solvers::setBlasThreads(threads); },
      py::arg("threads"),
      "Sets the BLAS's thread count (OpenBLAS); returns False when the loaded BLAS has no such "
      "setting.");
  m.def(
      "set_log_level",
      [](const std::string& level) {
        using support::LogLevel;
        if (level == "debug") return support::setLogLevel(LogLevel::kDebug);
        if (level == "info") return support::setLogLevel(LogLevel::kInfo);
        if (level == "warning") return support::setLogLevel(LogLevel::kWarning);
        if (level == "error") return support::setLogLevel(LogLevel::kError);
        throw py::value_error("log level must be debug, info, warning or error, not '" + level +
                              "'");
      },
      py::arg("level"),
      "The library's log threshold (debug, info, warning, error; default warning); messages "
      "go to standard error.");
}

}  // namespace

}  // namespace graphslam::python

PYBIND11_MODULE(_graphslam, m) {
  using namespace graphslam::python;
  m.doc() =
      "graphslam: graph-based SLAM (the C++ library's Python binding). Graphs, files, "
      "optimisation, marginal covariances, trajectory evaluation, simulators.";
  m.attr("__version__") = GRAPHSLAM_VERSION;
  bindErrors(m);
  bindRegistryListings(m);
  bindProcess(m);
  bindGraph(m);
  bindIo(m);
  bindOptimize(m);
  bindTrajectory(m);
  bindEval(m);
  bindSimulation(m);
  bindIncremental(m);
  bindCustomEdges(m);
  bindDrivebot(m);
  bindCertifyView(m);
}
