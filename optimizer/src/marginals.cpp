// SPDX-License-Identifier: MIT
#include "graphslam/optimizer/marginals.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "graphslam/support/error.h"
#include "hessian_structure.h"
#include "timing.h"

namespace graphslam {

const char* toString(MarginalStatus status) {
  switch (status) {
    case MarginalStatus::kSuccess:
      return "success";
    case MarginalStatus::kUnconstrained:
      return "vertex without edges";
    case MarginalStatus::kSingular:
      return "singular";
  }
  return "?";
}

std::string MarginalSummary::report() const {
  std::ostringstream s;
  s << "marginals:     " << toString(status);
  if (!message.empty()) s << " (" << message << ")";
  s << "\n               " << system_dimension << " unknowns, nnz(L) " << factor_nonzeros << ", "
    << inverse_entries << " entries of the inverse, " << back_substitutions
    << " back-substitutions";
  s.precision(4);
  s << "\n               time " << total_time << " s (linearize " << time_linearize
    << ", factorize " << time_factorize << ", inverse " << time_inverse << ")";
  if (!gauge_fixed.empty()) {
    s << "\n               gauge: vertex";
    for (VertexId id : gauge_fixed) s << ' ' << id;
    s << " fixed (zero covariance; the others are relative to it)";
  }
  return s.str();
}

namespace {

using detail::Clock;
using detail::seconds;

using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Perm = Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>;
using Ldlt = Eigen::SimplicialLDLT<SpMat, Eigen::Upper, Eigen::NaturalOrdering<int>>;

/// A pivot d_k of L D L^T counts as zero when d_k <= tolerance * H_kk: the column adds
/// (almost) nothing that the columns before it did not already determine.
constexpr double kRelativePivotTolerance = 1e-12;

std::string idList(const std::vector<VertexId>& ids) {
  std::string s;
  for (VertexId id : ids) s += (s.empty() ? "" : " ") + std::to_string(id);
  return s;
}

}  // namespace

struct MarginalCovariance::Impl {
  detail::HessianStructure structure;
  const Graph* built_for = nullptr;  ///< graph the structure was built for
  /// Column of every active vertex in the unpermuted system (taken right after build()).
  std::unordered_map<VertexId, int> column_of;
  std::vector<int> order;  ///< order[k] = unpermuted column at position k
  Perm p;                  ///< unpermuted column -> position
  SpMat permuted;
  Ldlt factor;
  bool pattern_done = false;
  support::LargeVector<double> values;
  std::vector<double> gradient;
  // Selected inverse on the pattern of L: sigma[q] pairs with L's value q, plus diagonal.
  std::vector<double> sigma;
  std::vector<double> sigma_diag;
  std::vector<char> needed;
  std::vector<int> slot_of;  // scratch: position of a row inside the current column
  std::vector<double> z;

  void rebuild(Graph& graph, const Options& options) {
    structure.build(graph);
    column_of.clear();
    const auto& vertices = structure.activeVertices();
    for (std::size_t b = 0; b < vertices.size(); ++b)
      column_of.emplace(vertices[b]->id(), structure.blockStarts()[b]);
    const int n = structure.dimension();
    const SolverRegistry::OrderingFunction* ordering =
        options.solvers ? options.solvers->ordering(options.ordering) : nullptr;
    if (ordering && n > 0) {
      order = (*ordering)(structure.sparseStructure());
    } else {
      order.resize(static_cast<std::size_t>(n));
      std::iota(order.begin(), order.end(), 0);
    }
    p.resize(n);
    for (int k = 0; k < n; ++k) p.indices()[order[k]] = k;
    pattern_done = false;
    built_for = &graph;
  }

  /// Permuted H = L D L^T. Returns the first unpermuted column with a (near) zero pivot,
  /// or -1.
  int factorize() {
    const SparseStructure s = structure.sparseStructure();
    const Eigen::Map<const SpMat> h(s.n, s.n, static_cast<int>(s.nnz()), s.col_ptr, s.row_idx,
                                    values.data());
    permuted.resize(s.n, s.n);
    permuted.selfadjointView<Eigen::Upper>() = h.selfadjointView<Eigen::Upper>().twistedBy(p);
    if (!pattern_done) {
      factor.analyzePattern(permuted);
      pattern_done = true;
    }
    factor.factorize(permuted);
    // After a failure (an exact zero pivot) only the pivots up to it are valid; the scan
    // stops there at the latest.
    const auto& d = factor.vectorD();
    const auto& diag_pos = structure.diagonalPositions();
    for (int k = 0; k < s.n; ++k) {
      const double hkk = values[static_cast<std::size_t>(diag_pos[order[k]])];
      if (!(d[k] > kRelativePivotTolerance * hkk) || !(hkk > 0.0)) return order[k];
    }
    return factor.info() == Eigen::Success ? -1 : (s.n > 0 ? order[0] : -1);
  }

  /// Entry (i, j) of H^-1 in permuted numbering from the selected inverse, or nullptr when
  /// (i, j) is outside the pattern of L or its column was not computed.
  const double* entry(int i, int j) const {
    if (i == j) return needed[j] ? &sigma_diag[j] : nullptr;
    if (i < j) std::swap(i, j);
    if (!needed[j]) return nullptr;
    const SpMat& l = factor.matrixL().nestedExpression();
    const int* rows = l.innerIndexPtr();
    const int begin = l.outerIndexPtr()[j];
    const int end = l.outerIndexPtr()[j + 1];
    const int* at = std::lower_bound(rows + begin, rows + end, i);
    if (at == rows + end || *at != i) return nullptr;
    return &sigma[static_cast<std::size_t>(at - rows)];
  }

  /// Takahashi recursion over the pattern of L for the columns marked in `needed` (closed
  /// under elimination-tree ancestors), from the last column to the first:
  ///   S_ij = -sum_{k in L_j} L_kj S_ik  (i in L_j),   S_jj = 1/d_j - sum_{k in L_j} L_kj S_kj.
  /// Every S_ik needed lies in a later column on the pattern (L's pattern is chordal).
  std::size_t selectedInverse() {
    const SpMat& l = factor.matrixL().nestedExpression();
    const int n = static_cast<int>(l.cols());
    const int* lp = l.outerIndexPtr();
    const int* li = l.innerIndexPtr();
    const double* lx = l.valuePtr();
    const auto& d = factor.vectorD();
    sigma.assign(static_cast<std::size_t>(lp[n]), 0.0);
    sigma_diag.assign(static_cast<std::size_t>(n), 0.0);
    slot_of.assign(static_cast<std::size_t>(n), -1);
    std::size_t computed = 0;
    for (int j = n - 1; j >= 0; --j) {
      if (!needed[j]) continue;
      const int begin = lp[j];
      const int m = lp[j + 1] - begin;
      z.assign(static_cast<std::size_t>(m), 0.0);
      for (int t = 0; t < m; ++t) slot_of[li[begin + t]] = t;
      const int last = m > 0 ? li[begin + m - 1] : -1;  // rows are sorted
      for (int t = 0; t < m; ++t) {
        const int k = li[begin + t];
        const double lkj = lx[begin + t];
        z[t] -= lkj * sigma_diag[k];
        // Pairs (r, k), r > k, both in L_j: S_rk is stored in column k at row r.
        for (int q = lp[k]; q < lp[k + 1] && li[q] <= last; ++q) {
          const int u = slot_of[li[q]];
          if (u < 0) continue;
          z[u] -= lkj * sigma[q];
          z[t] -= lx[begin + u] * sigma[q];
        }
      }
      double diag = 1.0 / d[j];
      for (int t = 0; t < m; ++t) {
        sigma[static_cast<std::size_t>(begin + t)] = z[t];
        diag -= lx[begin + t] * z[t];
        slot_of[li[begin + t]] = -1;
      }
      sigma_diag[j] = diag;
      computed += static_cast<std::size_t>(m) + 1;
    }
    return computed;
  }

  /// Parent of column j in the elimination tree: the first row of L_j (-1 for a root).
  static int parent(const SpMat& l, int j) {
    const int begin = l.outerIndexPtr()[j];
    return begin < l.outerIndexPtr()[j + 1] ? l.innerIndexPtr()[begin] : -1;
  }

  /// Marks the columns of H^-1 the recursion needs for the blocks of `ids`: their own
  /// columns and all their elimination-tree ancestors (parent = first row of L_j).
  void markNeeded(const std::vector<VertexId>& ids, const std::map<VertexId, int>& dims) {
    const SpMat& l = factor.matrixL().nestedExpression();
    const int n = static_cast<int>(l.cols());
    needed.assign(static_cast<std::size_t>(n), 0);
    for (VertexId id : ids) {
      const auto it = column_of.find(id);
      if (it == column_of.end()) continue;
      for (int c = 0; c < dims.at(id); ++c) {
        for (int j = p.indices()[it->second + c]; j >= 0 && !needed[j]; j = parent(l, j)) {
          needed[j] = 1;
        }
      }
    }
  }

  /// Cov(a, b) from the selected inverse; false when an entry lies outside its pattern.
  bool blockFromInverse(int col_a, int dim_a, int col_b, int dim_b, Eigen::MatrixXd& out) const {
    out.resize(dim_a, dim_b);
    for (int r = 0; r < dim_a; ++r) {
      for (int c = 0; c < dim_b; ++c) {
        const double* v = entry(p.indices()[col_a + r], p.indices()[col_b + c]);
        if (!v) return false;
        out(r, c) = *v;
      }
    }
    return true;
  }

  /// Builds the structure (when stale), linearises and factorises H at the current
  /// estimates. False, with the summary's failure set, when a vertex group has no anchor
  /// or H is not positive definite.
  bool factorizeAt(Graph& graph, const Options& options, MarginalSummary& summary) {
    const auto t0 = Clock::now();
    if (built_for != &graph || structure.stale(graph)) rebuild(graph, options);
    const int n = structure.dimension();
    summary.system_dimension = n;
    for (const auto& group : structure.unanchoredGroups()) {
      summary.bad_vertices.insert(summary.bad_vertices.end(), group.begin(), group.end());
    }
    if (!summary.bad_vertices.empty()) {
      summary.status = MarginalStatus::kSingular;
      summary.message =
          "vertices with no anchor (no fixed vertex, no unary edge) have no bounded covariance: " +
          idList(summary.bad_vertices);
      return false;
    }
    if (n == 0) return true;
    for (Edge* e : structure.activeEdges()) e->linearizeOplus();
    structure.assemble(values, gradient);
    const auto t1 = Clock::now();
    summary.time_linearize = seconds(t0, t1);
    const int bad = factorize();
    summary.time_factorize = seconds(t1, Clock::now());
    summary.factor_nonzeros =
        static_cast<std::size_t>(factor.matrixL().nestedExpression().nonZeros());
    if (bad < 0) return true;
    const VertexId id = structure.vertexOfColumn(bad);
    summary.status = MarginalStatus::kSingular;
    summary.bad_vertices.push_back(id);
    summary.message = "H is not positive definite at vertex " + std::to_string(id) +
                      ": it (or a group of vertices eliminated before it) is not determined "
                      "by its measurements";
    return false;
  }

  /// The diagonal blocks of `ids` (zero for fixed vertices).
  void diagonalBlocks(const std::vector<VertexId>& ids, const std::map<VertexId, int>& dims,
                      std::map<VertexId, Eigen::MatrixXd>& blocks) const {
    for (VertexId id : ids) {
      const int d = dims.at(id);
      Eigen::MatrixXd block = Eigen::MatrixXd::Zero(d, d);
      if (column_of.count(id) != 0) {
        const int c = column_of.at(id);
        const bool in_pattern = blockFromInverse(c, d, c, d, block);
        if (!in_pattern) throw Error("marginals: internal error, diagonal block outside L");
      }
      blocks[id] = std::move(block);
    }
  }

  /// Cross blocks: from the selected inverse when on L's pattern, else by solving
  /// L D L^T x = e_c for each column c of b (grouped by b). Returns the solves made.
  int crossBlocks(const std::vector<std::pair<VertexId, VertexId>>& cross_pairs,
                  const std::map<VertexId, int>& dims,
                  std::map<std::pair<VertexId, VertexId>, Eigen::MatrixXd>& cross) const {
    auto missing = [&](VertexId id) { return column_of.count(id) == 0; };
    std::map<VertexId, std::vector<std::pair<VertexId, VertexId>>> solve_for;
    for (const auto& [a, b] : cross_pairs) {
      Eigen::MatrixXd block = Eigen::MatrixXd::Zero(dims.at(a), dims.at(b));
      if (!missing(a) && !missing(b) &&
          !blockFromInverse(column_of.at(a), dims.at(a), column_of.at(b), dims.at(b), block)) {
        solve_for[b].emplace_back(a, b);
        continue;
      }
      cross[{a, b}] = std::move(block);
    }
    const int n = structure.dimension();
    Eigen::VectorXd rhs(n);
    Eigen::VectorXd x(n);
    int solves = 0;
    for (const auto& [b, pairs] : solve_for) {
      const int db = dims.at(b);
      const int cb = column_of.at(b);
      for (const auto& pair : pairs) cross[pair] = Eigen::MatrixXd::Zero(dims.at(pair.first), db);
      for (int c = 0; c < db; ++c) {
        rhs.setZero();
        rhs[p.indices()[cb + c]] = 1.0;
        x = factor.solve(rhs);
        ++solves;
        for (const auto& pair : pairs) {
          const int ca = column_of.at(pair.first);
          Eigen::MatrixXd& block = cross[pair];
          for (int r = 0; r < block.rows(); ++r) block(r, c) = x[p.indices()[ca + r]];
        }
      }
    }
    return solves;
  }
};

MarginalCovariance::MarginalCovariance() : MarginalCovariance(Options{}) {}
MarginalCovariance::MarginalCovariance(Options options)
    : options_(options), impl_(std::make_unique<Impl>()) {}
MarginalCovariance::~MarginalCovariance() = default;

MarginalSummary MarginalCovariance::computeAll(Graph& graph) {
  std::vector<VertexId> ids;
  ids.reserve(graph.numVertices());
  for (const auto& [id, v] : graph.vertices()) ids.push_back(id);
  return compute(graph, ids);
}

MarginalSummary MarginalCovariance::compute(
    Graph& graph, const std::vector<VertexId>& vertex_ids,
    const std::vector<std::pair<VertexId, VertexId>>& cross_pairs) {
  const auto t_start = Clock::now();
  blocks_.clear();
  cross_.clear();
  MarginalSummary summary;
  Impl& im = *impl_;

  std::map<VertexId, int> dims;  // every vertex involved, with its dimension
  auto require = [&](VertexId id) {
    const Vertex* v = graph.vertex(id);
    if (!v) throw Error("marginals: vertex " + std::to_string(id) + " is not in the graph");
    dims.emplace(id, v->dimension());
  };
  for (VertexId id : vertex_ids) require(id);
  for (const auto& [a, b] : cross_pairs) {
    require(a);
    require(b);
  }

  const detail::GaugeFix gauge(graph, options_.fix_gauge);
  summary.gauge_fixed = gauge.fixedIds();

  for (const auto& [id, dim] : dims) {
    const Vertex* v = graph.vertex(id);
    if (!v->fixed() && v->edges().empty()) summary.bad_vertices.push_back(id);
  }
  if (!summary.bad_vertices.empty()) {
    summary.status = MarginalStatus::kUnconstrained;
    summary.message =
        "vertices without edges have no bounded covariance: " + idList(summary.bad_vertices);
    summary.total_time = seconds(t_start, Clock::now());
    return summary;
  }

  if (!im.factorizeAt(graph, options_, summary)) {
    summary.total_time = seconds(t_start, Clock::now());
    return summary;
  }

  const auto t2 = Clock::now();
  // Columns of the recursion: requested vertices and both sides of every cross pair.
  if (im.structure.dimension() > 0) {
    std::vector<VertexId> involved;
    for (const auto& [id, dim] : dims) involved.push_back(id);
    im.markNeeded(involved, dims);
    summary.inverse_entries = im.selectedInverse();
  }
  im.diagonalBlocks(vertex_ids, dims, blocks_);
  summary.back_substitutions = im.crossBlocks(cross_pairs, dims, cross_);
  summary.time_inverse = seconds(t2, Clock::now());
  summary.total_time = seconds(t_start, Clock::now());
  return summary;
}

const Eigen::MatrixXd& MarginalCovariance::block(VertexId id) const {
  const auto it = blocks_.find(id);
  if (it == blocks_.end()) {
    throw Error("marginals: no covariance of vertex " + std::to_string(id) +
                " (not requested, or the last compute() failed)");
  }
  return it->second;
}

Eigen::MatrixXd MarginalCovariance::crossBlock(VertexId a, VertexId b) const {
  if (const auto it = cross_.find({a, b}); it != cross_.end()) return it->second;
  if (const auto it = cross_.find({b, a}); it != cross_.end()) return it->second.transpose();
  if (a == b) return block(a);
  throw Error("marginals: no cross covariance of vertices " + std::to_string(a) + " and " +
              std::to_string(b) + " (not requested, or the last compute() failed)");
}

}  // namespace graphslam
