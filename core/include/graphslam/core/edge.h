// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "graphslam/core/parameter.h"
#include "graphslam/core/robust_kernel.h"
#include "graphslam/core/vertex.h"

namespace graphslam {

/// Where one (vertex a, vertex b) block of J_a^T Omega J_b lives inside the CSC value array
/// of H. The block is stored column-major with a column stride of `stride`; when
/// `transposed` is set the stored block is (b, a) and receives the transpose.
/// `offset` is -1 when either vertex is fixed (the block is not part of the system).
struct HessianBlockRef {
  int offset = -1;
  int stride = 0;
  bool transposed = false;
};

/// Everything an edge needs to add its contribution to H and b, filled by the optimizer.
/// `blocks` lists the pairs (a, b) with a <= b of the edge's vertex slots in row-major
/// upper-triangle order: (0,0), (0,1), ..., (0,n-1), (1,1), ..., (n-1,n-1).
/// `b_offsets[k]` is the first row of slot k in b, or -1 when that vertex is fixed.
struct QuadraticFormTarget {
  double* hessian = nullptr;
  double* gradient = nullptr;
  const HessianBlockRef* blocks = nullptr;
  const int* b_offsets = nullptr;
};

/// Step of the central differences used by the numeric Jacobian defaults.
inline constexpr double kNumericJacobianStep = 1e-6;

/// Index of the pair (a, b), a <= b, in `QuadraticFormTarget::blocks` for an edge of
/// arity n.
constexpr int upperPairIndex(int a, int b, int n) { return a * n - a * (a - 1) / 2 + (b - a); }

/// The vertex ids of an edge, slot by slot: a read-only view of the edge's storage (valid
/// while the edge lives and its ids do not change), convertible to a vector.
class VertexIdView {
 public:
  VertexIdView(const VertexId* data, std::size_t size) : data_(data), size_(size) {}
  [[nodiscard]] const VertexId* begin() const { return data_; }
  [[nodiscard]] const VertexId* end() const { return data_ + size_; }
  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] bool empty() const { return size_ == 0; }
  VertexId operator[](std::size_t slot) const { return data_[slot]; }
  operator std::vector<VertexId>() const { return {begin(), end()}; }  // NOLINT: implicit

 private:
  const VertexId* data_;
  std::size_t size_;
};

/// A measurement: an error function of the estimates of its vertices, weighted by an
/// information matrix. chi2 = e^T Omega e.
///
/// The framework hooks are `computeError()` (stores e at the current estimates) and
/// `linearizeOplus()` (stores de/d(delta) for every vertex). Types derive from the
/// fixed-size bases (`FixedEdge`, `BaseUnaryEdge`, `BaseBinaryEdge`) or, for dynamic
/// arity, `BaseMultiEdge`, which implement the rest.
class Edge {
 public:
  /// `arity` is the number of vertices, or -1 when it is set per instance (multi-edges).
  Edge(int dimension, int arity) : dimension_(dimension), arity_(arity) {
    if (arity > 0) resizeVertices(static_cast<std::size_t>(arity));
  }
  virtual ~Edge() { resizeVertices(0); }
  Edge(const Edge&) = delete;
  Edge& operator=(const Edge&) = delete;

  /// Error (residual) dimension.
  [[nodiscard]] int dimension() const { return dimension_; }
  /// Number of vertices the type takes, -1 for dynamic arity.
  [[nodiscard]] int arity() const { return arity_; }

  [[nodiscard]] std::size_t numVertices() const { return num_vertices_; }
  [[nodiscard]] VertexIdView vertexIds() const { return {ids(), num_vertices_}; }
  /// Throws std::out_of_range for a slot the edge does not have.
  [[nodiscard]] VertexId vertexId(std::size_t slot) const;
  /// Before the edge is added to a graph. Throws graphslam::Error on a wrong count (or one
  /// the type refuses in resizeForVertices).
  void setVertexIds(std::vector<VertexId> ids);
  void setVertexId(std::size_t slot, VertexId id);

  /// g2o's line layout for the edges whose sizes follow their number of vertices
  /// (EDGE_SE2_LOTSOFXY, EDGE_SE3_LOTSOFXYZ): `TAG id... || count parameter-id...
  /// measurement... information...`, the vertex ids ended by the token "||" and followed by
  /// the count this returns for `num_vertices` vertices (for those two, the number of
  /// observed points, num_vertices - 1). A type with this layout returns a count >= 0 for
  /// every number of vertices, 0 included; -1 (the default) means the plain layout,
  /// `TAG id... parameter-id... measurement... information...`.
  [[nodiscard]] virtual int separatedCount(std::size_t /*num_vertices*/) const { return -1; }
  /// Number of parameters (shared constants such as a sensor offset, see Parameter) the
  /// type refers to by id; in a `.g2o` line their ids follow the vertex ids. Default: none
  /// (`ParameterizedEdge` adds them).
  [[nodiscard]] virtual int numParameters() const { return 0; }
  /// Throws std::out_of_range for a slot the type does not have.
  [[nodiscard]] ParameterId parameterId(std::size_t slot) const;
  /// Before the edge is added to a graph. Throws graphslam::Error for a slot the type does
  /// not have or once the edge is in a graph.
  void setParameterId(std::size_t slot, ParameterId id);
  /// Parameter in `slot`, resolved by the graph (nullptr before insertion).
  [[nodiscard]] const Parameter* parameter(std::size_t slot) const;
  /// Whether `p` has the type parameter slot `slot` expects (checked by Graph::addEdge).
  [[nodiscard]] virtual bool acceptsParameter(std::size_t /*slot*/, const Parameter& /*p*/) const {
    return false;
  }

  /// Vertex in `slot`, resolved by the graph (nullptr before insertion).
  [[nodiscard]] const Vertex* vertex(std::size_t slot) const { return vertices()[slot]; }
  [[nodiscard]] bool allVerticesFixed() const;

  /// Whether `v` has the type slot `slot` expects (checked by Graph::addEdge).
  [[nodiscard]] virtual bool acceptsVertex(std::size_t slot, const Vertex& v) const = 0;
  /// Human-readable name of the vertex type a slot expects, for diagnostics.
  [[nodiscard]] virtual std::string expectedVertexType(std::size_t slot) const = 0;

  /// Framework hook: compute and store the error at the current estimates.
  virtual void computeError() = 0;
  /// Framework hook: compute and store the Jacobians at the current estimates. With
  /// Optimizer::Options::threads > 1, computeError() and linearizeOplus() of different
  /// edges run concurrently: they may read the vertices and must write only the edge.
  virtual void linearizeOplus() = 0;
  /// Whether the last linearizeOplus() perturbed vertex estimates in place (the numeric
  /// Jacobian of a type that overrides computeError() instead of providing evaluate() or
  /// analytic Jacobians). Such edges are linearised serially, after the others.
  [[nodiscard]] virtual bool perturbsVerticesInPlace() const { return false; }
  /// e^T Omega e of the stored error.
  [[nodiscard]] virtual double chi2() const = 0;

  /// Inactive edges stay in the graph (and in the files written from it) but are left out
  /// of the optimisation: not in H, b or the objective, and a vertex whose edges are all
  /// inactive is not optimised (g2o's edge levels, with one level). Set through
  /// Graph::setEdgeActive.
  [[nodiscard]] bool active() const { return active_; }

  /// The robust kernel applied to this edge (none by default: plain least squares).
  void setRobustKernel(std::shared_ptr<const RobustKernel> kernel) {
    robust_kernel_ = std::move(kernel);
  }
  [[nodiscard]] const RobustKernel* robustKernel() const { return robust_kernel_.get(); }
  [[nodiscard]] const std::shared_ptr<const RobustKernel>& sharedRobustKernel() const {
    return robust_kernel_;
  }
  /// The edge's term of the objective: rho(chi2()) with a robust kernel, chi2() without.
  [[nodiscard]] double robustChi2() const {
    if (!robust_kernel_) return chi2();
    double rho[3];
    robust_kernel_->robustify(chi2(), rho);
    return rho[0];
  }
  /// The factor rho'(chi2()) on the information in H and b (1 without a kernel).
  [[nodiscard]] double robustWeight() const {
    if (!robust_kernel_) return 1.0;
    double rho[3];
    robust_kernel_->robustify(chi2(), rho);
    return rho[1];
  }
  /// Adds J_a^T Omega J_b into H and J_a^T Omega e into b (gradient), from the stored
  /// error and Jacobians; Omega scaled by robustWeight() when the edge has a kernel.
  virtual void constructQuadraticForm(const QuadraticFormTarget& target) const = 0;

  /// Stored error, `dimension()` doubles.
  [[nodiscard]] virtual const double* errorData() const = 0;
  /// Stored Jacobian of slot `slot`: dimension() x vertex(slot)->dimension(), column-major.
  [[nodiscard]] virtual const double* jacobianData(std::size_t slot) const = 0;

  /// Flat measurement (what a `.g2o` line holds between the ids and the information).
  [[nodiscard]] virtual int measurementDataDimension() const = 0;
  virtual void getMeasurementData(double* data) const = 0;
  virtual void setMeasurementData(const double* data) = 0;
  /// Constants of the edge's model that are neither measurement nor information (a time
  /// step, a sensor offset): written in the `.g2o` line between the measurement and the
  /// information. Default: none. setParameterData may throw graphslam::Error for a value
  /// the type cannot take (the loader reports it with the file and line).
  [[nodiscard]] virtual int parameterDataDimension() const { return 0; }
  virtual void getParameterData(double* /*data*/) const {}
  virtual void setParameterData(const double* /*data*/) {}
  /// Information matrix, dimension() x dimension(), column-major.
  [[nodiscard]] virtual const double* informationData() const = 0;
  virtual void setInformationData(const double* data) = 0;

 protected:
  /// A parameter slot: the id read from the file and the parameter the graph resolved.
  struct ParameterSlot {
    ParameterId id = -1;
    const Parameter* parameter = nullptr;
  };
  /// The type's numParameters() slots (storage of ParameterizedEdge); null for none.
  [[nodiscard]] virtual ParameterSlot* parameterSlots() { return nullptr; }
  [[nodiscard]] const ParameterSlot* parameterSlots() const {
    return const_cast<Edge*>(this)->parameterSlots();
  }

  /// Called by setVertexIds with the new number of vertices: a dynamic-arity type whose
  /// error dimension follows it (g2o's EDGE_SE2_LOTSOFXY) resizes its error, measurement and
  /// information here (setDimension), and may throw graphslam::Error for a count it cannot
  /// take. Default: nothing (the dimension is the type's).
  virtual void resizeForVertices(std::size_t /*num_vertices*/) {}
  /// Sets the error dimension of a type whose dimension is chosen per instance; only before
  /// the edge is in a graph (throws graphslam::Error after).
  void setDimension(int dimension);
  /// Writable access to the vertex in `slot` (nullptr before insertion into a graph), for
  /// methods that initialise a vertex from the measurement (odometry chaining, landmark
  /// initialisation). Never use it in computeError() or linearizeOplus().
  [[nodiscard]] Vertex* mutableVertex(std::size_t slot) {
    return slot < num_vertices_ ? vertices()[slot] : nullptr;
  }

  /// Central-difference Jacobian of the error w.r.t. the vertex in `slot`, perturbing
  /// that vertex in place (push, oplus, computeError, pop); for types whose error is only
  /// available through computeError(). Writes dimension() x vertex dimension values,
  /// column-major, to `jacobian`. Leaves the stored error as computeError() makes it at
  /// the unperturbed estimate's neighbours: callers restore it.
  void numericJacobianInPlace(std::size_t slot, double* jacobian);

 private:
  friend class Graph;
  /// Up to this many vertices, their ids and pointers live inside the edge: no heap block
  /// for the usual unary and binary edges, which keeps large graphs smaller.
  static constexpr std::size_t kInlineVertices = 2;
  [[nodiscard]] const VertexId* ids() const {
    return num_vertices_ <= kInlineVertices ? inline_ids_ : heap_ids_;
  }
  [[nodiscard]] VertexId* ids() {
    return num_vertices_ <= kInlineVertices ? inline_ids_ : heap_ids_;
  }
  [[nodiscard]] Vertex* const* vertices() const {
    return num_vertices_ <= kInlineVertices ? inline_vertices_ : heap_vertices_;
  }
  [[nodiscard]] Vertex** vertices() {
    return num_vertices_ <= kInlineVertices ? inline_vertices_ : heap_vertices_;
  }
  /// n slots with id -1 and no vertex (the previous ones dropped).
  void resizeVertices(std::size_t n);

  std::shared_ptr<const RobustKernel> robust_kernel_;
  int dimension_;
  int arity_;
  std::uint32_t num_vertices_ = 0;
  bool in_graph_ = false;  // vertices resolved by Graph::addEdge
  bool active_ = true;
  union {
    VertexId inline_ids_[kInlineVertices];
    VertexId* heap_ids_;
  };
  union {
    Vertex* inline_vertices_[kInlineVertices];
    Vertex** heap_vertices_;
  };
};

}  // namespace graphslam
