// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"

namespace graphslam {

/// Outcome of MarginalCovariance::compute().
enum class MarginalStatus {
  kSuccess,
  /// A requested non-fixed vertex has no edge: nothing bounds its covariance.
  kUnconstrained,
  /// H is not positive definite at the current estimate: some vertices are not determined
  /// by their edges (no anchor, too few or degenerate measurements).
  kSingular,
};

[[nodiscard]] const char* toString(MarginalStatus status);

/// What MarginalCovariance::compute() did.
struct MarginalSummary {
  MarginalStatus status = MarginalStatus::kSuccess;
  std::string message;  ///< names the offending vertex ids on failure
  /// Vertices the failure is about (the ones without edges, or where H is singular).
  std::vector<VertexId> bad_vertices;
  /// Vertex fixed for the computation to remove the gauge freedom (see Options::fix_gauge):
  /// its covariance is zero and every other one is relative to it.
  std::vector<VertexId> gauge_fixed;
  int system_dimension = 0;         ///< unknowns of H (non-fixed vertices with edges)
  std::size_t factor_nonzeros = 0;  ///< strictly lower entries of L
  std::size_t inverse_entries = 0;  ///< entries of H^-1 computed by the recursion
  int back_substitutions = 0;       ///< solves for cross blocks outside L's pattern
  double time_linearize = 0.0;      ///< Jacobians and assembly of H [s]
  double time_factorize = 0.0;      ///< ordering (when the structure changed) and LDL^T [s]
  double time_inverse = 0.0;        ///< selected inverse, blocks, back-substitutions [s]
  double total_time = 0.0;          ///< of compute() [s]

  [[nodiscard]] bool ok() const { return status == MarginalStatus::kSuccess; }
  /// Multi-line human-readable report.
  [[nodiscard]] std::string report() const;
};

/// Marginal covariances of vertex estimates: blocks of H^-1, with H = sum J^T Omega J the
/// Gauss-Newton Hessian at the current estimates (the Laplace approximation of the
/// posterior around them). Covariances are in each vertex's tangent space (the `plus`
/// update), in the vertex's dimension order.
///
/// H is factorised as P H P^T = L D L^T (Eigen's simplicial LDL^T, P the fill-reducing
/// block ordering of Options::solvers);
/// the entries of H^-1 on the pattern of L are then computed by the Takahashi recursion
/// (the selected inverse, as g2o's MarginalCovarianceCholesky), only for the columns
/// the requested blocks need: the elimination-tree ancestors of their columns. No dense
/// inverse is formed: all diagonal blocks of a large graph cost about as much as one more
/// factorisation. Cross blocks whose entries fall outside L's pattern (vertices that
/// share no edge and no fill) are computed by back-substitution, one solve with L D L^T
/// per column of the second vertex.
///
/// Fixed vertices have zero covariance. The structure (ordering, symbolic factorisation)
/// is kept between calls and rebuilt when the graph changes, so repeated calls on a
/// growing graph (online SLAM) pay only for the numeric work.
class MarginalCovariance {
 public:
  struct Options {
    /// As Optimizer::Options::fix_gauge: with no fixed vertex and no unary edge, fix the
    /// lowest id during the computation (reported in MarginalSummary::gauge_fixed).
    bool fix_gauge = true;
    /// H is factorised in the fill-reducing order `ordering` that this registry provides
    /// (solvers::registerEigenSolvers registers the solvers module's block orderings);
    /// without a registry, or when it has none for `ordering`, in the natural (id) order,
    /// which fills L far more on graphs with loop closures.
    const SolverRegistry* solvers = nullptr;
    Ordering ordering = Ordering::kAmd;
  };

  MarginalCovariance();
  explicit MarginalCovariance(Options options);
  ~MarginalCovariance();
  MarginalCovariance(const MarginalCovariance&) = delete;
  MarginalCovariance& operator=(const MarginalCovariance&) = delete;

  /// Computes the covariance blocks of `vertex_ids` and the cross blocks of `cross_pairs`
  /// (a, b) at the current estimates. Re-linearises every edge (the edges' stored
  /// Jacobians change; estimates and fixed flags are left as they were). Throws graphslam::Error
  /// when an id is not in the graph. Numerical failures are reported in the summary, naming vertex
  /// ids; the previous results are cleared either way.
  [[nodiscard]] MarginalSummary compute(
      Graph& graph, const std::vector<VertexId>& vertex_ids,
      const std::vector<std::pair<VertexId, VertexId>>& cross_pairs = {});
  /// compute() for every vertex of the graph.
  [[nodiscard]] MarginalSummary computeAll(Graph& graph);

  [[nodiscard]] bool hasBlock(VertexId id) const { return blocks_.count(id) != 0; }
  /// Covariance of vertex `id`, dimension x dimension (zero for a fixed vertex). Throws
  /// graphslam::Error when the last compute() did not produce it.
  [[nodiscard]] const Eigen::MatrixXd& block(VertexId id) const;
  /// Cov(x_a, x_b), dim(a) x dim(b), for a pair requested as (a, b) or (b, a). Throws
  /// graphslam::Error when the last compute() did not produce it.
  [[nodiscard]] Eigen::MatrixXd crossBlock(VertexId a, VertexId b) const;
  /// All blocks of the last compute(), by vertex id.
  [[nodiscard]] const std::map<VertexId, Eigen::MatrixXd>& blocks() const { return blocks_; }

 private:
  struct Impl;
  Options options_;
  std::unique_ptr<Impl> impl_;
  std::map<VertexId, Eigen::MatrixXd> blocks_;
  std::map<std::pair<VertexId, VertexId>, Eigen::MatrixXd> cross_;
};

}  // namespace graphslam
