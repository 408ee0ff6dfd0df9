// SPDX-License-Identifier: MIT
// Private: one submap's linear system, its interior eliminated onto its separator.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "augmented_factor.h"
#include "graphslam/submap/partition.h"

namespace graphslam::submap::detail {

/// What eliminating a submap's interior leaves on its separator variables (the columns of
/// Submap::separators, in that order): with the submap's part of H = [A B; B^T C] (A the
/// interior, damped by lambda I) and of g = [g_I; g_S],
///   schur = C - B^T A^-1 B,   reduced = g_S - B^T A^-1 g_I.
struct Contribution {
  Eigen::MatrixXd schur;     ///< separator_dimension^2, symmetric, full
  Eigen::VectorXd reduced;   ///< separator_dimension
  Eigen::VectorXd gradient;  ///< g_S (undamped, not reduced): the separator's gradient part
  double interior_gradient_squared = 0.0;  ///< |g_I|^2
  double max_diagonal = 0.0;               ///< largest diagonal entry of the undamped A and C
  bool ok = true;
  std::string message;  ///< when !ok: which submap failed and why
};

/// One submap's part of the least-squares problem: its edges' errors and Jacobians (kept by
/// the edges), assembled into its local H and g on demand; nothing of the system is kept
/// between calls unless `keep_factorization` (then the factor of A, B and g_I stay from
/// eliminate() to backSubstitute()), except the supernodal factor's symbolic analysis.
class SubmapSystem {
 public:
  /// `supernodal`: factorise by AugmentedFactor (CHOLMOD) instead of Eigen's simplicial
  /// LL^T of the interior alone.
  SubmapSystem(const Partition& partition, int index, bool keep_factorization, bool supernodal);
  ~SubmapSystem();
  SubmapSystem(SubmapSystem&&) noexcept;
  SubmapSystem& operator=(SubmapSystem&&) = delete;

  [[nodiscard]] int index() const { return index_; }
  [[nodiscard]] const Submap& submap() const { return *submap_; }
  /// computeError() of the submap's edges; their objective sum (robust kernels applied) in
  /// edge order.
  double cost();
  /// Sum of e^T Omega e of the stored errors (robust kernels ignored).
  [[nodiscard]] double rawChi2() const;
  /// linearizeOplus() of the submap's edges (errors must be current). Edges whose numeric
  /// Jacobian perturbs vertices in place are reported: they must not run beside others.
  [[nodiscard]] bool linearize();
  /// Assembles the submap's system from the stored Jacobians, damps A by lambda I,
  /// factorises A and forms the contribution.
  [[nodiscard]] Contribution eliminate(double lambda);
  /// The gradient parts of the contribution only (g_S and |g_I|^2), nothing factorised.
  [[nodiscard]] Contribution gradient() const;
  /// The interior step dx_I = -A^-1 (g_I + B dx_S) for the separator step `separator_step`
  /// (the submap's separator columns, in order); false (with a message) when A does not
  /// factorise. Refactorises unless the factorisation was kept.
  [[nodiscard]] bool backSubstitute(const Eigen::VectorXd& separator_step, double lambda,
                                    Eigen::VectorXd& interior_step, std::string& message);
  /// Saves the interior estimates, then applies `interior_step`.
  void applyInterior(const Eigen::VectorXd& interior_step);
  /// Puts back the estimates saved by applyInterior.
  void restoreInterior();
  /// Estimates of the interior vertices, concatenated (Vertex::getEstimateData), and back.
  [[nodiscard]] std::vector<double> interiorEstimates() const;
  void setInteriorEstimates(const std::vector<double>& data);

 private:
  struct Local;
  struct Factor;
  void assemble(Local& local, double lambda) const;
  [[nodiscard]] std::unique_ptr<Factor> factorize(const Local& local, std::string& message);

  const Partition* partition_;
  const Submap* submap_;
  int index_;
  bool keep_factorization_;
  /// Column of each vertex: interior columns >= 0, separator columns encoded as -2 - col.
  std::unordered_map<const Vertex*, int> columns_;
  /// The elimination order of the interior (indices()[old] = new), computed once.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order_;
  std::unique_ptr<Factor> kept_;
  /// The supernodal factorisation (its analysis made once), when `supernodal`.
  std::unique_ptr<AugmentedFactor> augmented_;
  std::vector<double> saved_;
};

}  // namespace graphslam::submap::detail
