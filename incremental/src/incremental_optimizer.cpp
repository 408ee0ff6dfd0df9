// SPDX-License-Identifier: MIT
#include "graphslam/incremental/incremental_optimizer.h"

#include <algorithm>
#include <unordered_map>

#include "graphslam/optimizer/linear_system.h"
#include "graphslam/support/error.h"
#include "optimizer_impl.h"

namespace graphslam::incremental {

namespace {

// A variable's sums are summed afresh once they have changed more than this many times per
// factor, plus the slack (so a variable with few factors is not resummed at every change):
// the rounding of adding and taking back blocks then never builds up beyond that of a few
// fresh sums, and resumming costs a constant share of the changes.
constexpr std::size_t kResumPerFactor = 4;
constexpr std::size_t kResumSlack = 16;

}  // namespace

IncrementalOptimizer::IncrementalOptimizer(Graph& graph, Options options)
    : graph_(graph), options_(options), impl_(std::make_unique<Impl>(graph_, options_)) {
  if (!(options_.relinearize_threshold >= 0.0) || options_.max_passes < 1 ||
      options_.refine_max_passes < 1 || options_.relinearize_skip < 1 ||
      !(options_.backsubstitution_fraction >= 0.0) || options_.chain_min_front_rows < 1) {
    throw Error(
        "IncrementalOptimizer: an option is out of its range (relinearize_threshold and "
        "backsubstitution_fraction >= 0, max_passes and refine_max_passes >= 1, "
        "relinearize_skip >= 1, "
        "chain_min_front_rows >= 1)");
  }
  if (options_.window.keep_landmarks && options_.window.reinitialize_landmarks) {
    throw Error(
        "IncrementalOptimizer: WindowOptions::keep_landmarks and reinitialize_landmarks "
        "exclude each other (a kept landmark never leaves, so it is never seen again after "
        "leaving)");
  }
  impl_->version = graph_.structureVersion();
  impl_->factor.setChainMinFrontRows(options_.chain_min_front_rows);
}

IncrementalOptimizer::~IncrementalOptimizer() = default;

Vertex& IncrementalOptimizer::addVertex(std::unique_ptr<Vertex> vertex) {
  if (vertex && options_.window.reinitialize_landmarks &&
      impl_->marginalized_landmarks.erase(vertex->id()) != 0) {
    // A landmark seen again: a new vertex under its old id.
  } else if (vertex && impl_->isMarginalized(vertex->id())) {
    throw InputError("vertex " + std::to_string(vertex->id()) +
                     " refused: a vertex with this id was marginalised (it left the "
                     "fixed-lag window)");
  }
  const bool in_sync = graph_.structureVersion() == impl_->version;
  Vertex& v = graph_.addVertex(std::move(vertex));
  if (in_sync) impl_->version = graph_.structureVersion();
  return v;
}

Edge& IncrementalOptimizer::addEdge(std::unique_ptr<Edge> edge) {
  if (edge) {
    for (VertexId id : edge->vertexIds()) {
      if (!impl_->isMarginalized(id)) continue;
      throw InputError("edge to vertex " + std::to_string(id) +
                       " refused: that vertex was marginalised (it left the fixed-lag window)");
    }
  }
  const bool in_sync = graph_.structureVersion() == impl_->version;
  Edge& e = graph_.addEdge(std::move(edge));
  if (in_sync) impl_->version = graph_.structureVersion();
  impl_->new_edges.push_back(&e);
  return e;
}

bool IncrementalOptimizer::removeEdge(const Edge* edge) {
  impl_->new_edges.erase(std::remove(impl_->new_edges.begin(), impl_->new_edges.end(), edge),
                         impl_->new_edges.end());
  const bool in_sync = graph_.structureVersion() == impl_->version;
  if (!graph_.removeEdge(edge)) return false;
  if (in_sync) impl_->version = graph_.structureVersion();
  impl_->needs_rebuild = true;
  ++impl_->stats.removed_edges;
  return true;
}

bool IncrementalOptimizer::update() { return impl_->update(); }
bool IncrementalOptimizer::refine(double threshold) {
  if (!(threshold >= 0.0)) throw Error("IncrementalOptimizer::refine: the threshold must be >= 0");
  return impl_->refine(threshold);
}
const UpdateStats& IncrementalOptimizer::lastStats() const { return impl_->stats; }
const UpdateFailure& IncrementalOptimizer::failure() const { return impl_->failure; }
double IncrementalOptimizer::chi2() {
  double sum = 0.0;
  for (const auto& e : graph_.edges()) {
    if (!e->active()) continue;
    e->computeError();
    sum += e->robustChi2();
  }
  return sum;
}
std::size_t IncrementalOptimizer::factorColumns() const { return impl_->factor.size(); }
std::size_t IncrementalOptimizer::factorBlocks() const { return impl_->factor.offDiagonalBlocks(); }

Eigen::MatrixXd IncrementalOptimizer::marginalCovariance(VertexId id) const {
  if (!impl_->ready || impl_->needs_rebuild) {
    throw Error("marginalCovariance: no successful update() since the graph changed");
  }
  const auto it = impl_->var_of.find(id);
  if (it == impl_->var_of.end()) {
    throw Error("marginalCovariance: vertex " + std::to_string(id) +
                " is not a free vertex of the optimisation (fixed, unknown or without edges)");
  }
  return impl_->factor.inverseBlock(it->second);
}

// ---------------------------------------------------------------------------------------

bool IncrementalOptimizer::Impl::update() {
  const int removed = stats.removed_edges;
  stats = UpdateStats{};
  stats.removed_edges = removed;
  failure = UpdateFailure{};
  if (graph.structureVersion() != version) needs_rebuild = true;
  stats.rebuilt = needs_rebuild && built;
  built = true;
  if (needs_rebuild) rebuild();
  if (!anchored) anchored = fixGaugeIfFree(graph) != nullptr || !graph.edges().empty();
  std::vector<int> touched;
  const std::size_t vars_before = vars.size();
  integrateNewEdges(touched);
  stats.new_vertices = static_cast<int>(vars.size() - vars_before);
  std::vector<int> last;  // the vertices of the new edges: kept last in the order
  for (int id : touched) {
    for (int var : factors[id].vars) {
      if (var >= 0) last.push_back(var);
    }
  }
  const bool check = options.relinearize_skip <= 1 || update_count % options.relinearize_skip == 0;
  ++update_count;
  // With one pass per update there is no second pass for the deferred vertices to join:
  // they are relinearised before the first, with the new edges (iSAM2's order).
  if (check && options.max_passes == 1) relinearizeDeferred(touched);
  return solve(std::move(touched), last, options.relinearize_threshold, check, options.max_passes);
}

bool IncrementalOptimizer::Impl::refine(double threshold) {
  // After a marginalisation the factor is rebuilt first (an update without new edges).
  if (ready && needs_rebuild && new_edges.empty() && graph.structureVersion() == version) {
    if (!update()) return false;
  }
  stats = UpdateStats{};
  failure = UpdateFailure{};
  if (!ready || !new_edges.empty() || graph.structureVersion() != version) {
    throw Error("IncrementalOptimizer::refine: call update() after changing the graph first");
  }
  std::vector<int> far;
  for (std::size_t var = 0; var < vars.size(); ++var) {
    const auto x = factor.solution(static_cast<int>(var));
    if (x.cwiseAbs().maxCoeff() > threshold) far.push_back(static_cast<int>(var));
  }
  if (far.empty()) return true;
  return solve(relinearizeVertices(far), {}, threshold, true, options.refine_max_passes);
}

// Relinearise-and-solve passes, at most `max_passes`: the factors in `touched` are
// linearised, their columns and ancestors eliminated again and the system solved; vertices
// whose step exceeds `threshold` are relinearised for the next pass (when `relinearize` is
// set) or, after the last, deferred to the next update that checks.
bool IncrementalOptimizer::Impl::solve(std::vector<int> touched, const std::vector<int>& last,
                                       double threshold, bool relinearize, int max_passes) {
  const auto neighbors = [this](int node, std::vector<int>& out) {
    for (const Link& l : vars[node].links) out.push_back(l.other);
  };
  const auto assembler = [this](int node, ColumnBuilder& b) { assemble(node, b); };
  std::vector<int> nodes;
  std::vector<int> far;
  for (stats.passes = 1;; ++stats.passes) {
    nodes.clear();
    linearize(touched, nodes);
    const BlockFactor::Result r = factor.refactor(nodes, last, neighbors, assembler);
    stats.eliminated_columns += r.eliminated;
    if (r.failed >= 0) {
      restoreAfterFailure(r.failed);
      return false;
    }
    far.clear();
    applySteps(factor.solve(threshold * options.backsubstitution_fraction), threshold, far);
    if (!relinearize) {
      defer(far);
      break;
    }
    if (stats.passes == 1) takeDeferred(threshold, far);
    if (far.empty()) break;
    if (stats.passes == max_passes) {
      stats.pass_limit_reached = true;
      defer(far);
      break;
    }
    touched = relinearizeVertices(far);
  }
  for (int var : undo) remembered[var] = 0;
  undo.clear();
  undo_data.clear();
  version = graph.structureVersion();
  ready = true;
  applyWindow();
  return true;
}

// Moves the linearisation points of `far` to their current estimates; returns their factors.
std::vector<int> IncrementalOptimizer::Impl::relinearizeVertices(const std::vector<int>& far) {
  std::vector<int> touched;
  for (int var : far) {
    Variable& v = vars[var];
    v.vertex->getEstimateData(v.theta0.data());
    factor.zeroSolution(var);
    touched.insert(touched.end(), v.factors.begin(), v.factors.end());
  }
  stats.relinearized_vertices += static_cast<int>(far.size());
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  return touched;
}

void IncrementalOptimizer::Impl::rebuild() {
  var_of.clear();
  vars.clear();
  factors.clear();
  factor.clear();
  new_edges.clear();
  remembered.clear();
  moved_flag.clear();
  deferred.clear();
  deferred_flag.clear();
  for (const auto& e : graph.edges()) new_edges.push_back(e.get());
  needs_rebuild = false;
}

int IncrementalOptimizer::Impl::variableFor(Vertex& v) {
  const auto [it, inserted] = var_of.emplace(v.id(), static_cast<int>(vars.size()));
  if (!inserted) return it->second;
  Variable var;
  var.vertex = &v;
  var.theta0.resize(v.estimateDataDimension());
  v.getEstimateData(var.theta0.data());
  var.diagonal.assign(static_cast<std::size_t>(v.dimension()) * v.dimension(), 0.0);
  var.rhs.assign(v.dimension(), 0.0);
  factor.add(v.dimension());  // node id == variable index
  vars.push_back(std::move(var));
  remembered.push_back(0);
  moved_flag.push_back(0);
  deferred_flag.push_back(0);
  return it->second;
}

// New edges become factors; their free vertices not yet in the system become variables (new
// nodes of the factor, ordered by the next refactor). `touched` receives the new factors.
void IncrementalOptimizer::Impl::integrateNewEdges(std::vector<int>& touched) {
  for (Edge* e : new_edges) {
    if (!e->active()) continue;
    Factor f;
    f.edge = e;
    const std::size_t n = e->numVertices();
    for (std::size_t s = 0; s < n; ++s) {
      Vertex* v = graph.vertex(e->vertexId(s));
      if (v->fixed()) {
        f.vars.push_back(-1);
        f.offsets.push_back(-1);
        continue;
      }
      f.vars.push_back(variableFor(*v));
      f.offsets.push_back(f.dim);
      f.dim += v->dimension();
    }
    const int id = static_cast<int>(factors.size());
    for (std::size_t a = 0; a < n; ++a) {
      if (f.vars[a] < 0) continue;
      Variable& v = vars[f.vars[a]];
      v.factors.push_back(id);
      for (std::size_t b = 0; b < n; ++b) {
        if (b == a || f.vars[b] < 0) continue;
        v.links.push_back(
            Link{id, f.vars[b], f.offsets[b], f.offsets[a], vars[f.vars[b]].vertex->dimension()});
      }
    }
    factors.push_back(std::move(f));
    touched.push_back(id);
    ++stats.new_edges;
  }
  new_edges.clear();
}

// Linearises the factors at the linearisation points of their vertices (a vertex holding
// theta0 + x with x != 0 is moved to theta0 for it and back after) and collects the
// nodes whose columns of H change.
void IncrementalOptimizer::Impl::linearize(const std::vector<int>& factor_ids,
                                           std::vector<int>& changed_nodes) {
  std::vector<int> moved;
  for (int id : factor_ids) {
    for (int var : factors[id].vars) {
      if (var < 0 || moved_flag[var] != 0) continue;
      if (factor.solution(var).cwiseAbs().maxCoeff() == 0.0) continue;
      moved_flag[var] = 1;
      moved.push_back(var);
      vars[var].vertex->setEstimateData(vars[var].theta0.data());
    }
  }
  std::vector<HessianBlockRef> refs;
  for (int id : factor_ids) {
    Factor& f = factors[id];
    Edge& e = *f.edge;
    e.computeError();
    e.linearizeOplus();
    if (e.perturbsVerticesInPlace()) e.computeError();
    const int n = static_cast<int>(f.vars.size());
    refs.assign(static_cast<std::size_t>(n * (n + 1) / 2), HessianBlockRef{});
    for (int a = 0; a < n; ++a) {
      for (int b = a; b < n; ++b) {
        if (f.offsets[a] < 0 || f.offsets[b] < 0) continue;
        refs[upperPairIndex(a, b, n)] =
            HessianBlockRef{f.offsets[a] + f.offsets[b] * f.dim, f.dim, false};
      }
    }
    if (!f.hessian.empty()) addDiagonal(f, -1.0);
    f.hessian.assign(static_cast<std::size_t>(f.dim) * f.dim, 0.0);
    f.gradient.assign(f.dim, 0.0);
    e.constructQuadraticForm(
        QuadraticFormTarget{f.hessian.data(), f.gradient.data(), refs.data(), f.offsets.data()});
    for (int c = 0; c < f.dim; ++c) {
      for (int r = c + 1; r < f.dim; ++r) f.hessian[r + c * f.dim] = f.hessian[c + r * f.dim];
    }
    addDiagonal(f, 1.0);
    for (int var : f.vars) {
      if (var >= 0) changed_nodes.push_back(var);
    }
  }
  for (int var : moved) {
    Variable& v = vars[var];
    v.vertex->oplus(factor.solution(var).data());
    moved_flag[var] = 0;
  }
  stats.relinearized_edges += static_cast<int>(factor_ids.size());
  std::sort(changed_nodes.begin(), changed_nodes.end());
  changed_nodes.erase(std::unique(changed_nodes.begin(), changed_nodes.end()), changed_nodes.end());
  for (int var : changed_nodes) {
    if (vars[var].sum_changes > kResumPerFactor * vars[var].factors.size() + kResumSlack)
      resum(var);
  }
}

// Adds (sign 1) or takes back (-1) a factor's diagonal blocks and gradients in its
// variables' sums.
void IncrementalOptimizer::Impl::addDiagonal(const Factor& f, double sign) {
  // Plain loops: the blocks are a vertex's few rows, below what Eigen's block expressions
  // pay for themselves.
  for (std::size_t a = 0; a < f.vars.size(); ++a) {
    if (f.vars[a] < 0) continue;
    Variable& v = vars[f.vars[a]];
    const auto d = static_cast<std::size_t>(v.rhs.size());
    const auto at = static_cast<std::size_t>(f.offsets[a]);
    const auto ld = static_cast<std::size_t>(f.dim);
    for (std::size_t c = 0; c < d; ++c) {
      const double* h = f.hessian.data() + at + (at + c) * ld;
      double* out = v.diagonal.data() + c * d;
      for (std::size_t r = 0; r < d; ++r) out[r] += sign * h[r];
      v.rhs[c] -= sign * f.gradient[at + c];
    }
    ++v.sum_changes;
  }
}

// Sums a variable's diagonal block and right-hand side afresh from its factors.
void IncrementalOptimizer::Impl::resum(int var) {
  Variable& v = vars[var];
  const int d = static_cast<int>(v.rhs.size());
  Eigen::Map<Eigen::MatrixXd> diagonal(v.diagonal.data(), d, d);
  Eigen::Map<Eigen::VectorXd> rhs(v.rhs.data(), d);
  diagonal.setZero();
  rhs.setZero();
  for (int id : v.factors) {
    const Factor& f = factors[id];
    if (f.hessian.empty()) continue;
    const int at = f.offsets[static_cast<std::size_t>(std::find(f.vars.begin(), f.vars.end(), var) -
                                                      f.vars.begin())];
    diagonal +=
        Eigen::Map<const Eigen::MatrixXd>(f.hessian.data(), f.dim, f.dim).block(at, at, d, d);
    rhs -= Eigen::Map<const Eigen::VectorXd>(f.gradient.data() + at, d);
  }
  v.sum_changes = 0;
}

// Column p of H (rows at or after p) and -g_p: the sums kept for p's vertex and the blocks of
// its factors' rows that come after p.
void IncrementalOptimizer::Impl::assemble(int p, ColumnBuilder& builder) const {
  const Variable& v = vars[p];
  const int dp = static_cast<int>(v.rhs.size());
  builder.rhs() += Eigen::Map<const Eigen::VectorXd>(v.rhs.data(), dp);
  builder.block(p) += Eigen::Map<const Eigen::MatrixXd>(v.diagonal.data(), dp, dp);
  const long long position = factor.position(p);
  for (const Link& l : v.links) {
    if (factor.position(l.other) < position) continue;
    const Factor& f = factors[l.factor];
    builder.block(l.other) += Eigen::Map<const Eigen::MatrixXd>(f.hessian.data(), f.dim, f.dim)
                                  .block(l.row, l.col, l.rows, dp);
  }
}

// Sets the vertices of the given nodes to theta0 + x and lists those whose step x exceeds
// `threshold`.
void IncrementalOptimizer::Impl::applySteps(const std::vector<int>& nodes, double threshold,
                                            std::vector<int>& far) {
  for (int var : nodes) {
    Variable& v = vars[var];
    remember(var);
    const auto x = factor.solution(var);
    v.vertex->setEstimateData(v.theta0.data());
    v.vertex->oplus(x.data());
    if (x.cwiseAbs().maxCoeff() > threshold) far.push_back(var);
  }
}

void IncrementalOptimizer::Impl::defer(const std::vector<int>& far) {
  for (int var : far) {
    if (deferred_flag[var] != 0) continue;
    deferred_flag[var] = 1;
    deferred.push_back(var);
  }
}

// Adds to `far` the deferred variables whose step still exceeds `threshold` (those solved in
// this pass are there already).
void IncrementalOptimizer::Impl::takeDeferred(double threshold, std::vector<int>& far) {
  for (int var : far) deferred_flag[var] = 0;
  for (int var : deferred) {
    if (deferred_flag[var] == 0) continue;
    deferred_flag[var] = 0;
    if (factor.solution(var).cwiseAbs().maxCoeff() > threshold) far.push_back(var);
  }
  deferred.clear();
}

// Relinearises the deferred variables whose step still exceeds the threshold and adds their
// factors to `touched`.
void IncrementalOptimizer::Impl::relinearizeDeferred(std::vector<int>& touched) {
  std::vector<int> far;
  takeDeferred(options.relinearize_threshold, far);
  if (far.empty()) return;
  const std::vector<int> more = relinearizeVertices(far);
  touched.insert(touched.end(), more.begin(), more.end());
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
}

void IncrementalOptimizer::Impl::remember(int var) {
  if (remembered[var] != 0) return;
  remembered[var] = 1;
  const Vertex& v = *vars[var].vertex;
  const std::size_t at = undo_data.size();
  undo_data.resize(at + static_cast<std::size_t>(v.estimateDataDimension()));
  v.getEstimateData(undo_data.data() + at);
  undo.push_back(var);
}

void IncrementalOptimizer::Impl::restoreAfterFailure(int node) {
  const Vertex& v = *vars[node].vertex;
  failure.vertex = v.id();
  failure.message = "update: the system is not positive definite at vertex " +
                    std::to_string(v.id()) +
                    ": its edges do not determine it (or an information matrix is not positive "
                    "definite); the estimates are those before the update";
  const double* data = undo_data.data();
  for (int var : undo) {
    Vertex& v = *vars[var].vertex;
    v.setEstimateData(data);
    data += v.estimateDataDimension();
  }
  undo.clear();
  undo_data.clear();
  needs_rebuild = true;
  ready = false;
}

}  // namespace graphslam::incremental
