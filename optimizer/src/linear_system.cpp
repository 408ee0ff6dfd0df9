// SPDX-License-Identifier: MIT
#include "graphslam/optimizer/linear_system.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "graphslam/support/thread_pool.h"
#include "hessian_structure.h"

namespace graphslam {

namespace {
/// Small dense matrices of at most 16 x 16 without heap allocation.
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 16, 16>;
using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 16, 1>;

/// Where one (edge, slot) block of J_w lives: first value, and the column stride.
struct JacobianBlockRef {
  int offset = -1;  ///< -1 when the slot's vertex is fixed
  int stride = 0;
};
}  // namespace

/// Edges per chunk below which a loop is not worth splitting across threads.
constexpr std::size_t kMinEdgesPerThread = 512;

struct LinearSystem::Impl {
  Graph* graph = nullptr;
  detail::HessianStructure hessian;
  std::unique_ptr<support::ThreadPool> pool = std::make_unique<support::ThreadPool>(1);
  std::vector<double> edge_chi2;
  /// Active edges split by linearize(): those linearised in parallel and those that
  /// perturb vertices in place (serial); empty until a serial pass has classified them.
  bool classified = false;
  std::vector<Edge*> parallel_edges, serial_edges;
  bool jacobian_built = false;
  /// columnOf()'s table, built at its first call after a build.
  bool columns_built = false;
  std::unordered_map<const Vertex*, int> column_of;
  int rows = 0;
  std::vector<int> j_col_ptr, j_row_idx, j_damping_pos;
  std::vector<int> edge_row_start;      // per active edge
  std::vector<std::size_t> slot_start;  // per active edge, into slot_refs
  std::vector<JacobianBlockRef> slot_refs;
  std::vector<int> block_starts;

  void buildJacobian() {
    const auto& vertices = hessian.activeVertices();
    const auto& edges = hessian.activeEdges();
    const int n = hessian.dimension();
    const auto nb = vertices.size();
    block_starts = hessian.blockStarts();
    // The block of a slot's first column (recorded by the structure), via lower_bound.
    auto block_of = [&](int column) {
      return static_cast<std::size_t>(
          std::lower_bound(block_starts.begin(), block_starts.end(), column) -
          block_starts.begin());
    };
    edge_row_start.clear();
    std::vector<std::vector<int>> edges_of(nb);  // active edge indices per block, ascending
    int row = 0;
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const Edge* e = edges[k];
      edge_row_start.push_back(row);
      row += e->dimension();
      const int* columns = hessian.slotColumns(k);
      for (std::size_t s = 0; s < e->numVertices(); ++s) {
        if (columns[s] < 0) continue;
        auto& list = edges_of[block_of(columns[s])];
        if (list.empty() || list.back() != static_cast<int>(k)) list.push_back(static_cast<int>(k));
      }
    }
    rows = row + n;
    std::vector<int> len(nb, 1);  // the damping row
    for (std::size_t b = 0; b < nb; ++b) {
      for (int k : edges_of[b]) len[b] += edges[static_cast<std::size_t>(k)]->dimension();
    }
    j_col_ptr.assign(static_cast<std::size_t>(n) + 1, 0);
    j_row_idx.clear();
    j_damping_pos.assign(static_cast<std::size_t>(n), 0);
    for (std::size_t b = 0; b < nb; ++b) {
      for (int c = block_starts[b]; c < block_starts[b + 1]; ++c) {
        j_col_ptr[c + 1] = j_col_ptr[c] + len[b];
        for (int k : edges_of[b]) {
          const int r0 = edge_row_start[static_cast<std::size_t>(k)];
          for (int i = 0; i < edges[static_cast<std::size_t>(k)]->dimension(); ++i) {
            j_row_idx.push_back(r0 + i);
          }
        }
        j_row_idx.push_back(row + c);
        j_damping_pos[c] = j_col_ptr[c + 1] - 1;
      }
    }
    slot_start.clear();
    slot_refs.clear();
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const Edge* e = edges[k];
      slot_start.push_back(slot_refs.size());
      const int* columns = hessian.slotColumns(k);
      for (std::size_t s = 0; s < e->numVertices(); ++s) {
        JacobianBlockRef ref;
        if (columns[s] >= 0) {
          const std::size_t b = block_of(columns[s]);
          const auto& list = edges_of[b];
          int within = 0;
          for (int other : list) {
            if (other == static_cast<int>(k)) break;
            within += edges[static_cast<std::size_t>(other)]->dimension();
          }
          ref.offset = j_col_ptr[block_starts[b]] + within;
          ref.stride = len[b];
        }
        slot_refs.push_back(ref);
      }
    }
    jacobian_built = true;
  }
};

LinearSystem::LinearSystem() : impl_(std::make_unique<Impl>()) {}
LinearSystem::~LinearSystem() = default;

bool LinearSystem::update(Graph& graph) {
  if (impl_->graph == &graph && !impl_->hessian.stale(graph)) return false;
  impl_->graph = &graph;
  impl_->hessian.build(graph);
  impl_->jacobian_built = false;
  impl_->columns_built = false;
  impl_->classified = false;
  return true;
}

bool LinearSystem::reorder(const std::vector<int>& block_order) {
  Impl& im = *impl_;
  if (!im.graph) return false;
  if (block_order.empty()) {
    if (!im.hessian.reordered()) return true;
    im.hessian.build(*im.graph);
  } else {
    const std::size_t nb = im.hessian.activeVertices().size();
    if (block_order.size() != nb) return false;
    std::vector<char> seen(nb, 0);
    for (int b : block_order) {
      if (b < 0 || static_cast<std::size_t>(b) >= nb || seen[static_cast<std::size_t>(b)]) {
        return false;
      }
      seen[static_cast<std::size_t>(b)] = 1;
    }
    im.hessian.build(*im.graph, &block_order);
  }
  im.jacobian_built = false;
  im.columns_built = false;
  return true;
}

bool LinearSystem::reordered() const { return impl_->hessian.reordered(); }

void LinearSystem::setThreads(int threads) {
  threads = std::max(threads, 1);
  if (threads != impl_->pool->threads())
    impl_->pool = std::make_unique<support::ThreadPool>(threads);
}

int LinearSystem::threads() const { return impl_->pool->threads(); }

double LinearSystem::computeChi2(Graph& graph) {
  const auto& edges = graph.edges();
  auto& chi2 = impl_->edge_chi2;
  chi2.resize(edges.size());
  impl_->pool->parallelFor(edges.size(), kMinEdgesPerThread,
                           [&](std::size_t begin, std::size_t end) {
                             for (std::size_t k = begin; k < end; ++k) {
                               if (!edges[k]->active()) {
                                 chi2[k] = 0.0;
                                 continue;
                               }
                               edges[k]->computeError();
                               chi2[k] = edges[k]->robustChi2();
                             }
                           });
  double sum = 0.0;
  for (double c : chi2) sum += c;
  return sum;
}

double LinearSystem::rawChi2(const Graph& graph) const {
  double sum = 0.0;
  for (const auto& e : graph.edges()) sum += e->active() ? e->chi2() : 0.0;
  return sum;
}

void LinearSystem::linearize() {
  Impl& im = *impl_;
  const auto& edges = im.hessian.activeEdges();
  if (!im.classified) {
    // Serial, and learns which edges perturb vertices in place (asked right after each
    // edge's linearisation, while the edge is in the cache).
    im.parallel_edges.clear();
    im.serial_edges.clear();
    for (Edge* e : edges) {
      e->linearizeOplus();
      if (e->perturbsVerticesInPlace()) im.serial_edges.push_back(e);
    }
    // Without serial edges every active edge runs in parallel: no copy of the list.
    if (!im.serial_edges.empty()) {
      for (Edge* e : edges) {
        if (!e->perturbsVerticesInPlace()) im.parallel_edges.push_back(e);
      }
    }
    std::vector<Edge*>(im.parallel_edges).swap(im.parallel_edges);
    im.classified = true;
    return;
  }
  if (im.pool->threads() == 1) {
    for (Edge* e : edges) e->linearizeOplus();
    return;
  }
  const auto& par = im.serial_edges.empty() ? edges : im.parallel_edges;
  im.pool->parallelFor(par.size(), kMinEdgesPerThread, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) par[k]->linearizeOplus();
  });
  for (Edge* e : im.serial_edges) e->linearizeOplus();
}

void LinearSystem::assembleHessian() { impl_->hessian.assemble(h_values_, gradient_); }

void LinearSystem::assembleJacobian() {
  Impl& im = *impl_;
  if (!im.jacobian_built) im.buildJacobian();
  j_values_.assign(im.j_row_idx.size(), 0.0);
  residual_.assign(static_cast<std::size_t>(im.rows), 0.0);
  gradient_.assign(static_cast<std::size_t>(im.hessian.dimension()), 0.0);
  const auto& edges = im.hessian.activeEdges();
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const Edge* e = edges[k];
    const int d = e->dimension();
    const SmallMatrix info = Eigen::Map<const Eigen::MatrixXd>(e->informationData(), d, d);
    const Eigen::Map<const Eigen::VectorXd> err(e->errorData(), d);
    SmallMatrix w = info.llt().matrixU();  // Omega = U^T U: W = U
    if (e->robustKernel()) w *= std::sqrt(e->robustWeight());
    const SmallVector ew = w * err;
    const int r0 = im.edge_row_start[k];
    for (int i = 0; i < d; ++i) residual_[static_cast<std::size_t>(r0 + i)] = ew[i];
    const int* columns = im.hessian.slotColumns(k);
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      const JacobianBlockRef ref = im.slot_refs[im.slot_start[k] + s];
      if (ref.offset < 0) continue;
      const Vertex* v = e->vertex(s);
      const int dv = v->dimension();
      const Eigen::Map<const Eigen::MatrixXd> jac(e->jacobianData(s), d, dv);
      const SmallMatrix wj = w * jac;
      for (int j = 0; j < dv; ++j) {
        double* col = j_values_.data() + ref.offset + static_cast<std::ptrdiff_t>(j) * ref.stride;
        for (int i = 0; i < d; ++i) col[i] += wj(i, j);
        gradient_[static_cast<std::size_t>(columns[s] + j)] += wj.col(j).dot(ew);
      }
    }
  }
}

int LinearSystem::dimension() const { return impl_->hessian.dimension(); }

SparseStructure LinearSystem::hessianStructure() const { return impl_->hessian.sparseStructure(); }

const std::vector<int>& LinearSystem::hessianDiagonalPositions() const {
  return impl_->hessian.diagonalPositions();
}

JacobianStructure LinearSystem::jacobianStructure() {
  Impl& im = *impl_;
  if (!im.jacobian_built) im.buildJacobian();
  JacobianStructure s;
  s.rows = im.rows;
  s.cols = im.hessian.dimension();
  s.damping_row = im.rows - s.cols;
  s.col_ptr = im.j_col_ptr.data();
  s.row_idx = im.j_row_idx.data();
  s.block_starts = im.block_starts.data();
  s.num_blocks = static_cast<int>(im.hessian.activeVertices().size());
  return s;
}

const std::vector<int>& LinearSystem::jacobianDampingPositions() {
  if (!impl_->jacobian_built) impl_->buildJacobian();
  return impl_->j_damping_pos;
}

const std::vector<int>& LinearSystem::blockStarts() const { return impl_->hessian.blockStarts(); }

int LinearSystem::columnOf(const Vertex& v) const {
  Impl& im = *impl_;
  if (!im.columns_built) {
    im.column_of.clear();
    const auto& vertices = im.hessian.activeVertices();
    const auto& starts = im.hessian.blockStarts();
    for (std::size_t b = 0; b < vertices.size(); ++b) im.column_of.emplace(vertices[b], starts[b]);
    im.columns_built = true;
  }
  const auto it = im.column_of.find(&v);
  return it == im.column_of.end() ? -1 : it->second;
}

const std::vector<Vertex*>& LinearSystem::activeVertices() const {
  return impl_->hessian.activeVertices();
}
const std::vector<Edge*>& LinearSystem::activeEdges() const { return impl_->hessian.activeEdges(); }
VertexId LinearSystem::vertexOfColumn(int col) const { return impl_->hessian.vertexOfColumn(col); }

std::vector<std::vector<VertexId>> LinearSystem::unanchoredGroups(std::size_t max_ids) const {
  return impl_->hessian.unanchoredGroups(max_ids);
}

Vertex* fixGaugeIfFree(Graph& graph) {
  const auto& vertices = graph.vertices();
  const auto& edges = graph.edges();
  if (std::any_of(vertices.begin(), vertices.end(),
                  [](const auto& kv) { return kv.second->fixed(); }) ||
      std::any_of(edges.begin(), edges.end(),
                  [](const auto& e) { return e->active() && e->numVertices() == 1; })) {
    return nullptr;
  }
  // The lowest id among the vertices of the largest dimension (as g2o's findGauge): a
  // landmark of a lower id would leave a pose graph's rotation free.
  Vertex* anchor = nullptr;
  for (const auto& [id, v] : vertices) {
    if (std::none_of(v->edges().begin(), v->edges().end(),
                     [](const Edge* e) { return e->active(); })) {
      continue;
    }
    if (betterGaugeAnchor(*v, anchor)) anchor = v.get();
  }
  if (anchor != nullptr) anchor->setFixed(true);
  return anchor;
}

}  // namespace graphslam
