// SPDX-License-Identifier: MIT
#include "graphslam/diagnostics/observability.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>

#include "graphslam/diagnostics/graph_checks.h"
#include "graphslam/support/fixed_size.h"
#include "graphslam/support/thread_pool.h"
#include "id_index.h"

namespace graphslam {

namespace {

/// Vertices per thread when the blocks are formed in parallel.
constexpr std::size_t kMinVerticesPerThread = 1024;

std::size_t slotOf(const Edge& e, const Vertex& v) {
  for (std::size_t s = 0; s < e.numVertices(); ++s) {
    if (e.vertex(s) == &v) return s;
  }
  return e.numVertices();
}

/// Adds J^T Omega J of edge `e` on the block of its vertex in `slot` to `h` (d x d,
/// column-major; d = D, or `dynamic_d` when D is 0). Omega J is formed on the stack for the
/// usual sizes, in `scratch` otherwise.
template <int D>
void addEdgeBlock(const Edge& e, std::size_t slot, int dynamic_d, std::vector<double>& scratch,
                  double* h) {
  constexpr int kStack = 96;  // a 16 x 6 Omega J
  const int d = D > 0 ? D : dynamic_d;
  const int m = e.dimension();
  const double* j = e.jacobianData(slot);
  const double* omega = e.informationData();
  double stack[kStack];
  double* w = stack;
  if (m * d > kStack) {
    scratch.resize(static_cast<std::size_t>(m * d));
    w = scratch.data();
  }
  for (int b = 0; b < d; ++b) {
    for (int i = 0; i < m; ++i) {
      double sum = 0.0;
      for (int k = 0; k < m; ++k) sum += omega[i + k * m] * j[k + b * m];
      w[i + b * m] = sum;
    }
  }
  for (int b = 0; b < d; ++b) {
    for (int a = 0; a < d; ++a) {
      double sum = 0.0;
      for (int i = 0; i < m; ++i) sum += j[i + a * m] * w[i + b * m];
      h[a + b * d] += sum;
    }
  }
}

/// The sum of J^T Omega J over the active edges of `v`, on its own block: a fixed-size
/// matrix for D > 0, dynamic for D = 0.
template <int D>
auto ownBlock(const Vertex& v, std::vector<double>& scratch) {
  using Matrix = std::conditional_t<D == 0, Eigen::MatrixXd, Eigen::Matrix<double, D, D>>;
  const int d = v.dimension();
  Matrix h = Matrix::Zero(d, d);
  for (const Edge* e : v.edges()) {
    if (e->active()) addEdgeBlock<D>(*e, slotOf(*e, v), d, scratch, h.data());
  }
  return h;
}

/// Rank of a symmetric positive semidefinite block: directions whose eigenvalue is at most
/// `tolerance` times the largest count as zero. -1 when the block is not finite.
template <typename Matrix>
int blockRank(const Matrix& h, double tolerance) {
  if (!h.allFinite()) return -1;
  const double trace = h.trace();
  if (!(trace > 0)) return 0;
  // Cheap certificate: lambda_min >= 1 / tr(H^-1) and lambda_max <= tr(H).
  Eigen::LLT<Matrix> llt(h);
  if (llt.info() == Eigen::Success) {
    Matrix inv_l = Matrix::Identity(h.rows(), h.cols());
    llt.matrixL().solveInPlace(inv_l);
    if (1.0 / (inv_l.squaredNorm() * trace) > tolerance) return static_cast<int>(h.rows());
  }
  Eigen::SelfAdjointEigenSolver<Matrix> eig(h, Eigen::EigenvaluesOnly);
  const auto& lambda = eig.eigenvalues();
  const double largest = lambda.maxCoeff();
  return static_cast<int>((lambda.array() > tolerance * largest).count());
}

/// f(std::integral_constant<int, D>{}) with D = d for the usual vertex dimensions (1, 2, 3:
/// 2D; 6: 3D), whose blocks then get fixed-size arithmetic, D = 0 (dynamic) for the others.
template <typename F>
decltype(auto) withDimension(int d, F&& f) {
  return support::withFixedSize<1, 2, 3, 6>(d, f);
}

/// Rank of a stored d x d block (column-major).
int storedRank(const double* block, int d, double tolerance) {
  return withDimension(d, [&](auto dim) {
    constexpr int D = decltype(dim)::value;
    using Matrix = std::conditional_t<D == 0, Eigen::MatrixXd, Eigen::Matrix<double, D, D>>;
    return blockRank(Matrix(Eigen::Map<const Matrix>(block, d, d)), tolerance);
  });
}

/// The own block of every non-fixed vertex at the current estimates: every active edge's
/// error and Jacobians are evaluated (serially: a g2o-style type's numeric Jacobian
/// perturbs its vertices in place) and added to its vertices' blocks at once, in edge
/// order, so each edge is read once, where it lies in memory (a pass to linearise, then one
/// per vertex through its edge list, took about 1.2 s on a million poses).
struct OwnBlocks {
  std::vector<Vertex*> vertices;  ///< the non-fixed ones, by id
  std::vector<int> dimension;
  std::vector<std::size_t> offset;  ///< of each vertex's d x d block in `values`
  std::vector<int> active_edges;    ///< per vertex
  std::vector<double> values;

  explicit OwnBlocks(Graph& graph) {
    detail::IdIndex index(graph);
    std::size_t total = 0;
    for (const auto& [id, v] : graph.vertices()) {
      if (v->fixed()) continue;
      index.add(id, static_cast<int>(vertices.size()));
      vertices.push_back(v.get());
      dimension.push_back(v->dimension());
      offset.push_back(total);
      total += static_cast<std::size_t>(v->dimension() * v->dimension());
    }
    values.assign(total, 0.0);
    active_edges.assign(vertices.size(), 0);
    std::vector<double> scratch;
    for (const auto& e : graph.edges()) {
      if (!e->active()) continue;
      e->computeError();
      e->linearizeOplus();
      for (std::size_t s = 0; s < e->numVertices(); ++s) {
        const int k = index.find(e->vertexId(s));
        if (k < 0) continue;  // fixed
        ++active_edges[static_cast<std::size_t>(k)];
        const int d = dimension[static_cast<std::size_t>(k)];
        double* block = &values[offset[static_cast<std::size_t>(k)]];
        withDimension(
            d, [&](auto dim) { addEdgeBlock<decltype(dim)::value>(*e, s, d, scratch, block); });
      }
    }
  }
};

/// Rank of the own block of `v` at the current estimate (-1: not finite), from its edges'
/// Jacobians.
int ownRank(const Vertex& v, double tolerance, std::vector<double>& scratch) {
  return withDimension(v.dimension(), [&](auto dim) {
    return blockRank(ownBlock<decltype(dim)::value>(v, scratch), tolerance);
  });
}

/// The block of one edge on its vertex `v`.
Eigen::MatrixXd edgeBlock(const Edge& e, const Vertex& v, std::vector<double>& scratch) {
  const int d = v.dimension();
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(d, d);
  addEdgeBlock<0>(e, slotOf(e, v), d, scratch, h.data());
  return h;
}

std::string idList(const std::vector<VertexId>& ids) {
  std::string out;
  for (std::size_t k = 0; k < ids.size() && k < 5; ++k) {
    out += (k == 0 ? "" : k + 1 == ids.size() ? " and " : ", ") + std::to_string(ids[k]);
  }
  if (ids.size() > 5) out += " and " + std::to_string(ids.size() - 5) + " more";
  return out;
}

/// How the edges of a vertex with one undetermined direction `n` see it once moved along
/// `n`: whether each edge still does not see that direction (a straight line), or sees it
/// again (a curve). Restores the estimate and the edges' errors and Jacobians.
bool straightForEveryEdge(Vertex& v, const Eigen::VectorXd& n, const ObservabilityOptions& o,
                          std::vector<double>& scratch) {
  const Eigen::VectorXd step = o.probe_step * n;
  v.push();
  v.oplus(step.data());
  bool straight = true;
  for (Edge* e : v.edges()) {
    if (!e->active()) continue;
    e->computeError();
    e->linearizeOplus();
    const Eigen::MatrixXd h = edgeBlock(*e, v, scratch);
    // |J n|_Omega relative to |J|_Omega.
    const double seen = n.dot(h * n), all = h.trace();
    if (!(seen <= o.straight_tolerance * o.straight_tolerance * all)) straight = false;
  }
  v.pop();
  for (Edge* e : v.edges()) {
    if (!e->active()) continue;
    e->computeError();
    e->linearizeOplus();
  }
  return straight;
}

/// The largest ratio of largest to smallest eigenvalue among the information matrices of the
/// active edges of `v` (infinite for a singular one).
double informationSpread(const Vertex& v) {
  double spread = 1.0;
  for (const Edge* e : v.edges()) {
    if (!e->active()) continue;
    const int d = e->dimension();
    const Eigen::Map<const Eigen::MatrixXd> info(e->informationData(), d, d);
    if (!info.allFinite()) continue;
    const Eigen::VectorXd lambda =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(info, Eigen::EigenvaluesOnly)
            .eigenvalues()
            .cwiseAbs();
    const double ratio = lambda.maxCoeff() / lambda.minCoeff();
    spread = std::max(spread, std::isnan(ratio) ? 1.0 : ratio);
  }
  return spread;
}

/// Why the active edges of `u` (rank `rank` of its dimension) do not determine it.
std::string reasonFor(Vertex& v, UndeterminedVertex& u, const ObservabilityOptions& o,
                      std::vector<double>& scratch) {
  const int d = v.dimension();
  const std::size_t edges = u.edges.size();
  const std::string from_vertices = u.neighbours.empty() ? std::string()
                                    : u.neighbours.size() == 1
                                        ? " from vertex " + idList(u.neighbours)
                                        : " from vertices " + idList(u.neighbours);
  const std::string from =
      from_vertices.empty() ? from_vertices : " (" + from_vertices.substr(1) + ")";
  if (u.rank < 0) {
    return "its edges' Jacobians are not finite at the current estimate (e.g. a point at the "
           "position it is observed from, or a measurement too large for double arithmetic)";
  }
  const std::string generic =
      (edges == 1 ? std::string("its one edge") + from + " determines only "
                  : "its " + std::to_string(edges) + " edges" + from + " determine only ") +
      std::to_string(u.rank) + " of its " + std::to_string(d) + " directions";
  const double spread = informationSpread(v);
  if (spread * o.rank_tolerance >= 1.0) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", spread);
    return generic + ": the information matrix of one of its edges has eigenvalues " + buf +
           " times apart, more than double arithmetic resolves (an entry mistyped?)";
  }
  if (u.rank != d - 1) return generic;
  // Every edge measuring exactly one direction of the vertex: ranges and bearings.
  for (const Edge* e : v.edges()) {
    if (e->active() && blockRank(edgeBlock(*e, v, scratch), o.rank_tolerance) != 1) return generic;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(ownBlock<0>(v, scratch));
  const Eigen::VectorXd n = eig.eigenvectors().col(0);  // the smallest eigenvalue's
  const bool one = u.neighbours.size() == 1;
  if (straightForEveryEdge(v, n, o, scratch)) {
    if (one) {
      return "seen from one vertex (" + idList(u.neighbours) +
             ") by bearing only: it can slide along the line of sight";
    }
    return "bearing-only edges all along one line (parallel bearings)" + from_vertices +
           ": it can slide along that line";
  }
  if (edges == 1) {
    return "one range-only edge" + from + ": it can move on a circle around " +
           (one ? "vertex " + idList(u.neighbours) : std::string("it"));
  }
  return "range-only edges" + from_vertices +
         " that all lie along one line through it: it can move across that line";
}

/// The details of an undetermined vertex with active edges: its edges (indices found
/// through `index_of`), neighbours, rank and reason.
UndeterminedVertex describeVertex(Vertex& v, const std::vector<std::size_t>& edge_index,
                                  const ObservabilityOptions& o, std::vector<double>& scratch) {
  UndeterminedVertex u;
  u.id = v.id();
  u.dimension = v.dimension();
  u.edges = edge_index;
  for (const Edge* e : v.edges()) {
    if (!e->active()) continue;
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      if (e->vertex(s) != &v) u.neighbours.push_back(e->vertexId(s));
    }
  }
  std::sort(u.neighbours.begin(), u.neighbours.end());
  u.neighbours.erase(std::unique(u.neighbours.begin(), u.neighbours.end()), u.neighbours.end());
  u.rank = ownRank(v, o.rank_tolerance, scratch);
  u.reason = reasonFor(v, u, o, scratch);
  if (u.rank < 0) u.rank = 0;
  return u;
}

/// For each of `vertices`, the indices into graph.edges() of its active edges.
std::vector<std::vector<std::size_t>> edgeIndices(const Graph& graph,
                                                  const std::vector<Vertex*>& vertices) {
  std::unordered_set<const Edge*> wanted;
  for (const Vertex* v : vertices) wanted.insert(v->edges().begin(), v->edges().end());
  std::unordered_map<const Edge*, std::size_t> index;
  const auto& edges = graph.edges();
  for (std::size_t k = 0; k < edges.size(); ++k) {
    if (edges[k]->active() && wanted.count(edges[k].get())) index.emplace(edges[k].get(), k);
  }
  std::vector<std::vector<std::size_t>> out(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    for (const Edge* e : vertices[i]->edges()) {
      if (const auto it = index.find(e); it != index.end()) out[i].push_back(it->second);
    }
    std::sort(out[i].begin(), out[i].end());
  }
  return out;
}

}  // namespace

int ownBlockRank(const Vertex& v, double rank_tolerance) {
  std::vector<double> scratch;
  return ownRank(v, rank_tolerance, scratch);
}

std::vector<VertexId> ObservabilityReport::undeterminedIds() const {
  std::vector<VertexId> ids;
  ids.reserve(undetermined.size());
  for (const auto& u : undetermined) ids.push_back(u.id);
  return ids;
}

std::string ObservabilityReport::describeUndetermined(
    std::size_t max_listed,
    const std::function<std::string(const UndeterminedVertex&)>& note) const {
  if (undetermined.empty()) return {};
  std::string out = std::to_string(undetermined.size()) +
                    (undetermined.size() == 1 ? " vertex is" : " vertices are") +
                    " not determined by the edges:";
  for (std::size_t k = 0; k < undetermined.size() && k < max_listed; ++k) {
    const UndeterminedVertex& u = undetermined[k];
    out += "\n  vertex " + std::to_string(u.id) + (u.tag.empty() ? "" : " (" + u.tag + ")") + ": " +
           u.reason + (note ? note(u) : std::string());
  }
  if (undetermined.size() > max_listed) {
    out += "\n  ... and " + std::to_string(undetermined.size() - max_listed) + " more";
  }
  return out;
}

std::string ObservabilityReport::describeUnanchored() const {
  if (unanchored.empty()) return {};
  std::string lowest;
  for (std::size_t k = 0; k < unanchored.size() && k < 10; ++k) {
    lowest += (k == 0 ? "" : ", ") + std::to_string(anchors.at(k)) + " (" +
              std::to_string(unanchored[k].size()) + " vertices)";
  }
  if (unanchored.size() > 10) lowest += ", ...";
  return "information: " + std::to_string(unanchored.size()) +
         (unanchored.size() == 1 ? " component has" : " components have") +
         " no anchor (no fixed vertex, no prior); the optimizer fixes one vertex of each "
         "(its lowest id of the largest dimension) for the run: " +
         lowest;
}

std::string ObservabilityReport::describe(std::size_t max_listed) const {
  const std::string a = describeUndetermined(max_listed), b = describeUnanchored();
  return a + (!a.empty() && !b.empty() ? "\n" : "") + b;
}

ObservabilityReport checkObservability(Graph& graph, const ObservabilityOptions& options) {
  ObservabilityReport report;
  report.unanchored = checkConstraints(graph).unanchored;
  for (const auto& group : report.unanchored) {
    const Vertex* anchor = nullptr;
    for (VertexId id : group) {
      const Vertex* v = graph.vertex(id);
      if (betterGaugeAnchor(*v, anchor)) anchor = v;
    }
    report.anchors.push_back(anchor != nullptr ? anchor->id() : -1);
  }
  const OwnBlocks blocks(graph);
  support::ThreadPool pool(options.threads);
  std::vector<char> flagged(blocks.vertices.size(), 0);
  pool.parallelFor(
      blocks.vertices.size(), kMinVerticesPerThread, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
          const int d = blocks.dimension[k];
          flagged[k] = blocks.active_edges[k] > 0 &&
                       storedRank(&blocks.values[blocks.offset[k]], d, options.rank_tolerance) < d;
        }
      });
  std::vector<Vertex*> found;
  std::vector<VertexId> without_edges;
  for (std::size_t k = 0; k < blocks.vertices.size(); ++k) {
    if (blocks.active_edges[k] == 0) without_edges.push_back(blocks.vertices[k]->id());
    if (flagged[k]) found.push_back(blocks.vertices[k]);
  }
  const auto indices = edgeIndices(graph, found);
  std::vector<double> scratch;
  for (std::size_t k = 0; k < found.size(); ++k) {
    report.undetermined.push_back(describeVertex(*found[k], indices[k], options, scratch));
  }
  for (VertexId id : without_edges) {
    UndeterminedVertex u;
    u.id = id;
    u.dimension = graph.vertex(id)->dimension();
    u.reason = graph.vertex(id)->edges().empty() ? "no edges" : "no active edges";
    report.undetermined.push_back(std::move(u));
  }
  std::sort(report.undetermined.begin(), report.undetermined.end(),
            [](const auto& a, const auto& b) { return a.id < b.id; });
  if (options.types) {
    for (auto& u : report.undetermined) {
      if (const std::string* tag = options.types->tagOf(*graph.vertex(u.id))) u.tag = *tag;
    }
  }
  // A vertex without edges is not repeated in the groups (checkConstraints leaves it out).
  return report;
}

}  // namespace graphslam
