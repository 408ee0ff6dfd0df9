// SPDX-License-Identifier: MIT
// Edge types written in Python: an error function of the vertices' estimates (numpy arrays
// of their .g2o data) and the measurement, registered under a tag in the process's type
// registry like any C++ type (Graph.add_edge, load, save, optimize). Jacobians are central
// differences on the vertices' own updates (BaseMultiEdge's in-place numeric Jacobian); the
// error is evaluated with the GIL taken back, so these edges are linearised serially.
//
// The registry maps C++ types to tags one to one, so each Python type gets a C++ class of
// its own: PyEdge<K> for K < kMaxPythonEdgeTypes.
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <mutex>
#include <typeindex>
#include <utility>

#include "common.h"
#include "graph_types.h"
#include "graphslam/core/base_multi_edge.h"
#include "graphslam/support/error.h"

namespace graphslam::python {

namespace {

constexpr std::size_t kMaxPythonEdgeTypes = 32;

/// One registered Python edge type.
struct PyEdgeType {
  std::string tag;
  int dimension = 0;
  int measurement_dimension = 0;
  std::vector<std::string> vertex_tags;
  std::vector<std::type_index> vertex_types;
  std::vector<int> vertex_data;  ///< estimate data size per slot
  py::object error;              ///< error(estimates: list of arrays, measurement) -> (dimension,)
};

std::array<PyEdgeType*, kMaxPythonEdgeTypes> g_types{};  // leaked: the registry outlives all
std::mutex g_types_mutex;

template <std::size_t K>
class PyEdge final : public BaseMultiEdge<Eigen::Dynamic, Eigen::VectorXd> {
 public:
  PyEdge() : type_(*g_types[K]) {
    setErrorDimension(type_.dimension);
    mutableMeasurement().setZero(type_.measurement_dimension);
  }

  void computeError() override {
    py::gil_scoped_acquire gil;
    py::list estimates;
    for (std::size_t i = 0; i < numVertices(); ++i) {
      auto x = newArray({static_cast<py::ssize_t>(type_.vertex_data[i])});
      vertex(i)->getEstimateData(x.mutable_data());
      estimates.append(x);
    }
    auto z = newArray({static_cast<py::ssize_t>(type_.measurement_dimension)});
    getMeasurementData(z.mutable_data());
    // A Python exception leaves as py::error_already_set: the caller sees it as raised.
    py::object e = type_.error(estimates, z);
    const auto a = doubleArray(e, type_.tag + ".error's result", true);
    if (a.size() != type_.dimension) {
      throw py::value_error(type_.tag + ".error returned " + std::to_string(a.size()) +
                            " values, not its dimension " + std::to_string(type_.dimension));
    }
    mutableError() = Eigen::Map<const Eigen::VectorXd>(a.data(), type_.dimension);
  }

  [[nodiscard]] bool acceptsVertex(std::size_t slot, const Vertex& v) const override {
    return slot < type_.vertex_types.size() && std::type_index(typeid(v)) == type_.vertex_types[slot];
  }
  [[nodiscard]] std::string expectedVertexType(std::size_t slot) const override {
    return slot < type_.vertex_tags.size() ? type_.vertex_tags[slot] : std::string("no vertex");
  }

 protected:
  void resizeForVertices(std::size_t n) override {
    if (n != type_.vertex_tags.size()) {
      throw Error(type_.tag + " joins " + std::to_string(type_.vertex_tags.size()) + " vertices, not " +
                  std::to_string(n));
    }
  }

 private:
  const PyEdgeType& type_;
};

template <std::size_t K>
void registerSlot(const std::string& tag) {
  registries().types.registerEdgeFactory(tag, std::type_index(typeid(PyEdge<K>)),
                                         [] { return std::unique_ptr<Edge>(std::make_unique<PyEdge<K>>()); });
}

template <std::size_t... K>
void registerSlotAt(std::size_t k, const std::string& tag, std::index_sequence<K...>) {
  ((k == K ? registerSlot<K>(tag) : void()), ...);
}

void registerEdge(const std::string& tag, const std::vector<std::string>& vertex_tags, int dimension,
                  const py::object& measurement_dimension, const py::object& error) {
  if (!PyCallable_Check(error.ptr())) throw py::type_error("error must be callable");
  if (dimension < 1) throw py::value_error("dimension must be at least 1");
  if (vertex_tags.empty()) throw py::value_error("vertex_tags must name at least one vertex tag");
  auto type = std::make_unique<PyEdgeType>();
  type->tag = tag;
  type->dimension = dimension;
  type->measurement_dimension = measurement_dimension.is_none() ? dimension : measurement_dimension.cast<int>();
  if (type->measurement_dimension < 0) throw py::value_error("measurement_dimension must be >= 0");
  type->vertex_tags = vertex_tags;
  for (const std::string& vt : vertex_tags) {
    const TagType& t = vertexTagType(vt);  // RegistryError for an unknown tag
    type->vertex_types.push_back(t.type);
    type->vertex_data.push_back(t.data_dimension);
  }
  type->error = error;
  std::lock_guard<std::mutex> lock(g_types_mutex);
  std::size_t k = 0;
  while (k < kMaxPythonEdgeTypes && g_types[k] != nullptr) ++k;
  if (k == kMaxPythonEdgeTypes) {
    throw py::value_error("at most " + std::to_string(kMaxPythonEdgeTypes) +
                          " Python edge types can be registered in a process");
  }
  if (registries().types.contains(tag)) {
    throw RegistryError("the tag " + tag + " is already registered");
  }
  g_types[k] = type.release();
  try {
    registries().types.setOrigin("python");
    registerSlotAt(k, tag, std::make_index_sequence<kMaxPythonEdgeTypes>{});
  } catch (...) {
    delete g_types[k];
    g_types[k] = nullptr;
    throw;
  }
}

}  // namespace

void bindCustomEdges(py::module_& m) {
  m.def("_register_edge", &registerEdge, py::arg("tag"), py::arg("vertex_tags"), py::arg("dimension"),
        py::arg("measurement_dimension"), py::arg("error"),
        "Registers an edge type written in Python (use graphslam.register_edge with a "
        "graphslam.CustomEdge subclass).");
}

}  // namespace graphslam::python
