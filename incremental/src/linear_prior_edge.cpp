// SPDX-License-Identifier: MIT
// LinearPriorEdge and marginalizeVertices: the Schur complement of leaving vertices kept as
// a dense prior on the vertices that stay.
#include "graphslam/incremental/linear_prior_edge.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <map>
#include <numeric>
#include <set>

#include "graphslam/core/graph_copy.h"
#include "graphslam/support/error.h"

namespace graphslam::incremental {

namespace {

// Step of the central differences of Vertex::minus in LinearPriorEdge::linearizeOplus().
constexpr double kMinusStep = 1e-6;

}  // namespace

LinearPriorEdge::LinearPriorEdge(std::vector<int> dims, Eigen::MatrixXd jacobian,
                                 Eigen::VectorXd offset, std::vector<double> linearization_point)
    : dims_(std::move(dims)),
      jacobian_(std::move(jacobian)),
      offset_(std::move(offset)),
      x_lin_(std::move(linearization_point)) {
  const int columns = std::accumulate(dims_.begin(), dims_.end(), 0);
  if (dims_.empty() || jacobian_.cols() != columns || jacobian_.rows() != offset_.size() ||
      jacobian_.rows() == 0) {
    throw Error(
        "LinearPriorEdge: the Jacobian must be rows x (sum of the slot dimensions) and "
        "the offset have its rows");
  }
  for (int d : dims_) {
    offsets_.push_back(offsets_.empty() ? 0 : offsets_.back() + dims_[offsets_.size() - 1]);
    (void)d;
  }
}

void LinearPriorEdge::resizeForVertices(std::size_t num_vertices) {
  if (num_vertices != dims_.size()) {
    throw Error("LinearPriorEdge: " + std::to_string(dims_.size()) + " vertices expected, got " +
                std::to_string(num_vertices));
  }
  setErrorDimension(static_cast<int>(jacobian_.rows()));
}

bool LinearPriorEdge::acceptsVertex(std::size_t slot, const Vertex& v) const {
  return slot < dims_.size() && v.dimension() == dims_[slot];
}

std::string LinearPriorEdge::expectedVertexType(std::size_t slot) const {
  return "a vertex of dimension " + std::to_string(slot < dims_.size() ? dims_[slot] : 0) +
         " with Vertex::minus";
}

void LinearPriorEdge::tangentOf(std::size_t slot, const double* step, double* delta) const {
  if (data_offsets_.size() != dims_.size()) {
    // The flat estimate sizes are known once the vertices are: fill the offsets lazily.
    auto& offsets = data_offsets_;
    offsets.clear();
    int at = 0;
    for (std::size_t s = 0; s < dims_.size(); ++s) {
      offsets.push_back(at);
      at += vertex(s)->estimateDataDimension();
    }
    if (static_cast<std::size_t>(at) != x_lin_.size()) {
      throw Error("LinearPriorEdge: the linearisation point has " + std::to_string(x_lin_.size()) +
                  " values, the vertices' estimates " + std::to_string(at));
    }
  }
  if (!vertex(slot)->minus(x_lin_.data() + data_offsets_[slot], step, delta)) {
    throw Error("LinearPriorEdge: the type of vertex " + std::to_string(vertexId(slot)) +
                " does not define Vertex::minus, which a marginalisation prior needs");
  }
}

void LinearPriorEdge::computeError() {
  Eigen::VectorXd d(jacobian_.cols());
  for (std::size_t s = 0; s < dims_.size(); ++s) tangentOf(s, nullptr, d.data() + offsets_[s]);
  mutableError() = jacobian_ * d + offset_;
}

void LinearPriorEdge::linearizeOplus() {
  for (std::size_t s = 0; s < dims_.size(); ++s) {
    const int d = dims_[s];
    Eigen::MatrixXd derivative(d, d);
    Eigen::VectorXd step = Eigen::VectorXd::Zero(d);
    Eigen::VectorXd plus(d), minus(d);
    for (int c = 0; c < d; ++c) {
      step[c] = kMinusStep;
      tangentOf(s, step.data(), plus.data());
      step[c] = -kMinusStep;
      tangentOf(s, step.data(), minus.data());
      step[c] = 0.0;
      derivative.col(c) = (plus - minus) / (2.0 * kMinusStep);
    }
    jacobian(s) = jacobian_.middleCols(offsets_[s], d) * derivative;
  }
}

namespace {

// The dense quadratic form of a set of edges over the free vertices they touch.
struct DenseSystem {
  std::map<VertexId, int> column;  // first column of each free vertex
  std::vector<VertexId> order;     // the vertices by column
  Eigen::MatrixXd h;
  Eigen::VectorXd g;
};

// Columns: the leaving vertices first (by id), then the separator (by id).
DenseSystem layout(Graph& graph, const std::set<VertexId>& leaving, const std::vector<Edge*>& edges,
                   int& leaving_columns) {
  DenseSystem sys;
  std::set<VertexId> separator;
  for (Edge* e : edges) {
    for (VertexId id : e->vertexIds()) {
      if (!leaving.count(id) && !graph.vertex(id)->fixed()) separator.insert(id);
    }
  }
  int at = 0;
  for (VertexId id : leaving) {
    if (graph.vertex(id)->fixed()) continue;
    sys.column[id] = at;
    sys.order.push_back(id);
    at += graph.vertex(id)->dimension();
  }
  leaving_columns = at;
  for (VertexId id : separator) {
    sys.column[id] = at;
    sys.order.push_back(id);
    at += graph.vertex(id)->dimension();
  }
  sys.h = Eigen::MatrixXd::Zero(at, at);
  sys.g = Eigen::VectorXd::Zero(at);
  return sys;
}

// Adds each edge's J^T Omega J and J^T Omega e at the current estimates.
void accumulate(Graph& graph, const std::vector<Edge*>& edges, DenseSystem& sys) {
  std::vector<HessianBlockRef> refs;
  std::vector<int> offsets;
  for (Edge* e : edges) {
    e->computeError();
    e->linearizeOplus();
    if (e->perturbsVerticesInPlace()) e->computeError();
    const int n = static_cast<int>(e->numVertices());
    offsets.assign(static_cast<std::size_t>(n), -1);
    int dim = 0;
    for (int s = 0; s < n; ++s) {
      const Vertex* v = graph.vertex(e->vertexId(static_cast<std::size_t>(s)));
      if (v->fixed()) continue;
      offsets[static_cast<std::size_t>(s)] = dim;
      dim += v->dimension();
    }
    Eigen::MatrixXd local = Eigen::MatrixXd::Zero(dim, dim);
    Eigen::VectorXd grad = Eigen::VectorXd::Zero(dim);
    refs.assign(static_cast<std::size_t>(n * (n + 1) / 2), HessianBlockRef{});
    for (int a = 0; a < n; ++a) {
      for (int b = a; b < n; ++b) {
        if (offsets[a] < 0 || offsets[b] < 0) continue;
        refs[upperPairIndex(a, b, n)] = HessianBlockRef{offsets[a] + offsets[b] * dim, dim, false};
      }
    }
    e->constructQuadraticForm(
        QuadraticFormTarget{local.data(), grad.data(), refs.data(), offsets.data()});
    local.triangularView<Eigen::StrictlyLower>() = local.transpose();
    for (int a = 0; a < n; ++a) {
      if (offsets[a] < 0) continue;
      const Vertex* va = graph.vertex(e->vertexId(static_cast<std::size_t>(a)));
      const int ca = sys.column.at(va->id());
      sys.g.segment(ca, va->dimension()) += grad.segment(offsets[a], va->dimension());
      for (int b = 0; b < n; ++b) {
        if (offsets[b] < 0) continue;
        const Vertex* vb = graph.vertex(e->vertexId(static_cast<std::size_t>(b)));
        sys.h.block(ca, sys.column.at(vb->id()), va->dimension(), vb->dimension()) +=
            local.block(offsets[a], offsets[b], va->dimension(), vb->dimension());
      }
    }
  }
}

// The pseudo-inverse of a symmetric positive semi-definite matrix.
Eigen::MatrixXd pseudoInverse(const Eigen::MatrixXd& a, double tolerance) {
  if (a.size() == 0) return a;  // only fixed vertices leave
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(a);
  const Eigen::VectorXd& l = eig.eigenvalues();
  const double cut = tolerance * std::max(l.maxCoeff(), 0.0);
  Eigen::VectorXd inv(l.size());
  for (Eigen::Index i = 0; i < l.size(); ++i) inv[i] = l[i] > cut ? 1.0 / l[i] : 0.0;
  return eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

Marginalization marginalizeVertices(Graph& graph, const std::vector<VertexId>& leaving_ids,
                                    double rank_tolerance) {
  const std::set<VertexId> leaving(leaving_ids.begin(), leaving_ids.end());
  std::vector<Edge*> edges;  // active edges touching a leaving vertex, in graph order
  for (VertexId id : leaving) {
    if (!graph.hasVertex(id))
      throw Error("marginalize: vertex " + std::to_string(id) + " is unknown");
  }
  int removed = 0;
  for (const auto& e : graph.edges()) {
    const auto ids = e->vertexIds();
    if (std::none_of(ids.begin(), ids.end(), [&](VertexId id) { return leaving.count(id) != 0; }))
      continue;
    ++removed;
    if (e->active()) edges.push_back(e.get());
  }
  int m = 0;
  DenseSystem sys = layout(graph, leaving, edges, m);
  Marginalization result;
  result.removed_edges = removed;
  const int s = static_cast<int>(sys.h.rows()) - m;
  std::unique_ptr<LinearPriorEdge> prior;
  if (s > 0) {
    for (std::size_t k = 0; k < sys.order.size(); ++k) {
      if (sys.column[sys.order[k]] < m) continue;
      const Vertex& v = *graph.vertex(sys.order[k]);
      std::vector<double> probe(static_cast<std::size_t>(v.estimateDataDimension()));
      std::vector<double> delta(static_cast<std::size_t>(v.dimension()));
      v.getEstimateData(probe.data());
      if (!v.minus(probe.data(), nullptr, delta.data())) {
        throw Error("marginalize: the type of vertex " + std::to_string(v.id()) +
                    " does not define Vertex::minus, which the prior on it needs");
      }
    }
    accumulate(graph, edges, sys);
    const Eigen::MatrixXd hmm_inv = pseudoInverse(sys.h.topLeftCorner(m, m), rank_tolerance);
    const Eigen::MatrixXd hsm = sys.h.bottomLeftCorner(s, m);
    Eigen::MatrixXd schur = sys.h.bottomRightCorner(s, s) - hsm * hmm_inv * hsm.transpose();
    schur = 0.5 * (schur + schur.transpose());
    const Eigen::VectorXd gs = sys.g.tail(s) - hsm * (hmm_inv * sys.g.head(m));
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(schur);
    const Eigen::VectorXd& l = eig.eigenvalues();
    const double cut = rank_tolerance * std::max(l.maxCoeff(), 0.0);
    std::vector<Eigen::Index> kept;
    for (Eigen::Index i = l.size() - 1; i >= 0; --i) {
      if (l[i] > cut) kept.push_back(i);
    }
    if (!kept.empty()) {
      const auto rank = static_cast<Eigen::Index>(kept.size());
      Eigen::MatrixXd jacobian(rank, s);
      Eigen::VectorXd offset(rank);
      for (Eigen::Index r = 0; r < rank; ++r) {
        const Eigen::VectorXd u = eig.eigenvectors().col(kept[static_cast<std::size_t>(r)]);
        const double root = std::sqrt(l[kept[static_cast<std::size_t>(r)]]);
        jacobian.row(r) = root * u.transpose();
        offset[r] = u.dot(gs) / root;
      }
      std::vector<int> dims;
      std::vector<VertexId> ids;
      std::vector<double> x_lin;
      for (VertexId id : sys.order) {
        if (sys.column[id] < m) continue;
        const Vertex& v = *graph.vertex(id);
        dims.push_back(v.dimension());
        ids.push_back(id);
        const std::size_t at = x_lin.size();
        x_lin.resize(at + static_cast<std::size_t>(v.estimateDataDimension()));
        v.getEstimateData(x_lin.data() + at);
      }
      prior = std::make_unique<LinearPriorEdge>(std::move(dims), std::move(jacobian),
                                                std::move(offset), std::move(x_lin));
      prior->setVertexIds(ids);
      result.separator = ids;
      result.prior_rank = static_cast<int>(rank);
    }
  }
  for (VertexId id : leaving) graph.removeVertex(id);
  if (prior) graph.addEdge(std::move(prior));
  return result;
}

Graph copyWithoutPriors(const Graph& graph, const TypeRegistry& types) {
  Graph copy;
  for (const auto& [id, p] : graph.parameters()) copy.addParameter(copyParameter(*p, types));
  for (const auto& [id, v] : graph.vertices()) copy.addVertex(copyVertex(*v, types));
  for (const auto& e : graph.edges()) {
    if (dynamic_cast<const LinearPriorEdge*>(e.get())) continue;
    Edge& c = copy.addEdge(copyEdge(*e, types));
    if (!e->active()) copy.setEdgeActive(c, false);
  }
  return copy;
}

}  // namespace graphslam::incremental
