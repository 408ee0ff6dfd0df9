// SPDX-License-Identifier: MIT
// The state of IncrementalOptimizer (its pimpl), shared by the files that implement it:
// incremental_optimizer.cpp (updates), window.cpp (fixed-lag marginalisation),
// checkpoint.cpp (save and resume).
#pragma once

#include <deque>
#include <map>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "block_factor.h"
#include "graphslam/incremental/incremental_optimizer.h"

namespace graphslam::incremental::detail {

// Where a factor's block H(other, v) of a variable v lies in the factor's `hessian`.
struct Link {
  int factor = -1;
  int other = -1;  // the other variable
  int row = 0;     // first row of `other` in the factor's hessian
  int col = 0;     // first column of v there
  int rows = 0;    // dimension of `other`
};

// A free vertex of the system (node of the factor with the same index): its linearisation
// point (flat estimate data), the factors (edges) that touch it, and what assembling its
// column of H needs: the sums over its factors of the diagonal block H(v, v) and of -g_v,
// kept up to date as factors are linearised, and the places of the off-diagonal blocks. So
// assembling a column reads the factors' data only for the rows that come after it (a
// landmark seen from many poses is eliminated after most of them).
struct Variable {
  Vertex* vertex = nullptr;
  std::vector<double> theta0;
  std::vector<int> factors;
  std::vector<double> diagonal;  // dim x dim, column-major
  std::vector<double> rhs;       // dim
  std::vector<Link> links;       // per factor, one per other free vertex of it
  // Changes of the sums since they were last summed afresh (kResumPerFactor).
  std::size_t sum_changes = 0;
};

// An edge with its quadratic form at the linearisation points of its vertices, kept as a
// dense matrix over its free vertices (both triangles) and the gradient J^T Omega e.
struct Factor {
  Edge* edge = nullptr;
  std::vector<int> vars;     // per slot, -1 for a fixed vertex
  std::vector<int> offsets;  // per slot, first row in `hessian`, -1 for a fixed vertex
  int dim = 0;
  std::vector<double> hessian;
  std::vector<double> gradient;
};

}  // namespace graphslam::incremental::detail

namespace graphslam::incremental {

struct IncrementalOptimizer::Impl {
  using Link = detail::Link;
  using Variable = detail::Variable;
  using Factor = detail::Factor;

  explicit Impl(Graph& g, const Options& o) : graph(g), options(o) {}

  bool update();
  bool refine(double threshold);
  bool solve(std::vector<int> touched, const std::vector<int>& last, double threshold,
             bool relinearize, int max_passes);
  std::vector<int> relinearizeVertices(const std::vector<int>& far);
  void rebuild();
  void integrateNewEdges(std::vector<int>& touched);
  int variableFor(Vertex& v);
  void linearize(const std::vector<int>& factor_ids, std::vector<int>& changed_nodes);
  void addDiagonal(const Factor& f, double sign);
  void resum(int var);
  void assemble(int p, ColumnBuilder& builder) const;
  void applySteps(const std::vector<int>& nodes, double threshold, std::vector<int>& far);
  void defer(const std::vector<int>& far);
  void takeDeferred(double threshold, std::vector<int>& far);
  void relinearizeDeferred(std::vector<int>& touched);
  void remember(int var);
  void restoreAfterFailure(int node);
  // window.cpp
  void applyWindow();
  std::vector<VertexId> marginalizeStates(const std::vector<VertexId>& leaving);
  void markMarginalized(VertexId id);
  [[nodiscard]] bool isMarginalized(VertexId id) const;

  Graph& graph;
  const Options& options;
  std::unordered_map<VertexId, int> var_of;
  std::vector<Variable> vars;
  std::vector<Factor> factors;
  std::vector<Edge*> new_edges;
  bool needs_rebuild = true;
  bool anchored = false;
  std::uint64_t version = 0;
  BlockFactor factor;
  UpdateStats stats;
  UpdateFailure failure;
  bool ready = false;  // a successful update() made the factor
  bool built = false;  // an update() ran
  long update_count = 0;
  // Estimates before this update: the variables and their estimate data, back to back.
  std::vector<int> undo;
  std::vector<double> undo_data;
  std::vector<char> remembered;  // per variable: in the undo log
  std::vector<char> moved_flag;  // per variable: at its linearisation point for linearize()
  // Variables whose step exceeded the threshold at an update that did not check
  // (relinearize_skip): the next check relinearises those still beyond it.
  std::vector<int> deferred;
  std::vector<char> deferred_flag;  // per variable: in `deferred`
  // The fixed-lag window: its states oldest first, and the ids marginalised so far as
  // disjoint ranges [first, last] by first (states of a stream have consecutive ids mostly,
  // so this stays small where a set of ids would grow with the run).
  std::deque<WindowState> states;
  std::unordered_set<VertexId> state_ids;
  std::map<VertexId, VertexId> marginalized;
  // Marginalised landmarks (vertices that were not states), apart: with
  // reinitialize_landmarks one may be added again (and leaves this set).
  std::set<VertexId> marginalized_landmarks;
  std::size_t marginalized_count = 0;
};

}  // namespace graphslam::incremental
