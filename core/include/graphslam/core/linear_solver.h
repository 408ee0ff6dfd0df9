// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace graphslam {

/// Outcome of a linear-solver call. Numerical failures are statuses, never exceptions.
enum class LinearSolverStatus {
  kSuccess,
  kNotPositiveDefinite,  ///< Cholesky met a non-positive pivot
  kSingular,             ///< zero pivot / rank deficiency
  kFailure,              ///< anything else (out of memory, bad structure)
};

[[nodiscard]] const char* toString(LinearSolverStatus status);

struct LinearSolverResult {
  LinearSolverStatus status = LinearSolverStatus::kSuccess;
  std::string message;
  /// Column (in the caller's, unpermuted numbering) where the factorisation failed, -1
  /// when unknown. The optimizer maps it back to a vertex id.
  int column = -1;

  [[nodiscard]] bool ok() const { return status == LinearSolverStatus::kSuccess; }
  static LinearSolverResult success() { return {}; }
  static LinearSolverResult failure(LinearSolverStatus s, std::string msg, int col = -1) {
    return {s, std::move(msg), col};
  }
};

/// The system a solver consumes.
enum class SystemForm {
  kNormalEquations,  ///< H dx = -b with H = J^T Omega J (Cholesky, LDLT, LU, PCG)
  kJacobian,         ///< whitened J dx ~= -r in the least-squares sense (QR)
};

/// Sparsity structure of a symmetric n x n matrix H in compressed sparse column form.
/// Only the upper triangle is meaningful (the lower one when `lower` is set: only for a
/// solver that asked for it, LinearSolver::preferredBlockOrder); the diagonal blocks are
/// stored full (both triangles), and solvers must ignore entries on the other side of the
/// diagonal. Every stored block is
/// complete (all its entries, structural zeros too), so all columns of a vertex store the
/// same rows. Row indices are
/// sorted within each column. `block_starts` (size num_blocks + 1) gives the first column
/// of every variable block (one block per vertex), so solvers can order on the block
/// graph. The arrays stay valid and unchanged until the next analyze().
struct SparseStructure {
  int n = 0;
  const int* col_ptr = nullptr;  ///< n + 1 entries
  const int* row_idx = nullptr;  ///< col_ptr[n] entries
  const int* block_starts = nullptr;
  int num_blocks = 0;
  /// The lower triangle is stored (rows >= column in every column) instead of the upper.
  bool lower = false;

  [[nodiscard]] std::size_t nnz() const { return n ? static_cast<std::size_t>(col_ptr[n]) : 0u; }
};

/// Sparsity structure of the whitened Jacobian of a least-squares system, m x n, in
/// compressed sparse column form with sorted row indices. Rows [0, damping_row) hold the
/// edges' residuals (each edge's rows are contiguous); the last n rows
/// [damping_row, damping_row + n) are one row per column, holding sqrt(lambda d_j) on the
/// column's last entry (zero without damping), so Levenberg-Marquardt changes values only.
/// `block_starts` as in SparseStructure.
struct JacobianStructure {
  int rows = 0;
  int cols = 0;
  int damping_row = 0;
  const int* col_ptr = nullptr;  ///< cols + 1 entries
  const int* row_idx = nullptr;
  const int* block_starts = nullptr;
  int num_blocks = 0;

  [[nodiscard]] std::size_t nnz() const {
    return cols ? static_cast<std::size_t>(col_ptr[cols]) : 0u;
  }
};

/// Fill-reducing orderings a solver may offer. Orderings are computed on the block graph
/// (one node per vertex) and expanded to scalar columns, except where a backend orders by
/// itself (noted in its description).
enum class Ordering {
  kDefault,  ///< the solver's own choice
  kNatural,  ///< the optimizer's column order (vertices by id)
  kAmd,      ///< approximate minimum degree on the block graph of H
  kColamd,   ///< column approximate minimum degree (on J's block pattern, or H's)
  kMetis,    ///< nested dissection by METIS (through CHOLMOD) on the block graph of H
  kRcm,      ///< reverse Cuthill-McKee on the block graph of H (a small envelope, not fill)
};

[[nodiscard]] const char* toString(Ordering ordering);
/// Parses "natural", "amd", "colamd", "metis", "rcm" or "default"; false for anything else.
[[nodiscard]] bool parseOrdering(const std::string& text, Ordering& ordering);

/// Options every solver factory receives.
struct LinearSolverOptions {
  Ordering ordering = Ordering::kDefault;
};

/// Sparse linear solver. A normal-equations solver (form() == kNormalEquations) gets
/// `analyze()` once per structure (ordering + symbolic factorisation), `factorize()`
/// every iteration on new values and `solve()` for each right-hand side. A Jacobian-form
/// solver (form() == kJacobian, QR) gets the same three calls for the whitened Jacobian:
/// `analyzeJacobian()`, `factorizeJacobian()`, `solveJacobian()`.
class LinearSolver {
 public:
  virtual ~LinearSolver() = default;

  [[nodiscard]] virtual std::string name() const = 0;
  [[nodiscard]] virtual SystemForm form() const { return SystemForm::kNormalEquations; }
  /// The ordering in use (after analyze: the one actually applied).
  [[nodiscard]] virtual Ordering ordering() const { return Ordering::kDefault; }

  /// Asked once per structure, before analyze(), with H's structure in the optimizer's
  /// order (active vertices by id, upper triangle). A solver that returns a permutation of
  /// the blocks (order[k]: the block placed at position k) gets H built in that order and
  /// stored as its lower triangle (SparseStructure::lower); analyze(), factorize() and
  /// solve() then take that matrix, and right-hand sides, solutions and failing columns
  /// are in that order. A factorisation that reads its input as it is (CHOLMOD's
  /// supernodal one in its natural order) so needs no permuted copy of H. Default: empty,
  /// H as it is.
  [[nodiscard]] virtual std::vector<int> preferredBlockOrder(const SparseStructure& structure) {
    (void)structure;
    return {};
  }

  [[nodiscard]] virtual LinearSolverResult analyze(const SparseStructure& structure);
  /// `values` has structure.nnz() entries in the order of `row_idx`.
  [[nodiscard]] virtual LinearSolverResult factorize(const double* values);
  /// Solves H x = rhs with the last factorisation; rhs and x have n entries (may alias).
  [[nodiscard]] virtual LinearSolverResult solve(const double* rhs, double* x);

  [[nodiscard]] virtual LinearSolverResult analyzeJacobian(const JacobianStructure& structure);
  /// `values` has structure.nnz() entries in the order of `row_idx`.
  [[nodiscard]] virtual LinearSolverResult factorizeJacobian(const double* values);
  /// Least-squares solution of J x ~= rhs; rhs has `rows` entries, x has `cols`.
  [[nodiscard]] virtual LinearSolverResult solveJacobian(const double* rhs, double* x);

  /// Non-zeros of the last factor (L, U or R; 0 if unknown), for reports.
  [[nodiscard]] virtual std::size_t factorNonZeros() const { return 0; }

  /// Pattern of the last factor as CSC (upper or lower triangle as the backend stores
  /// it, in the solver's permuted order), for sparsity pictures. False when the backend
  /// cannot export it.
  virtual bool factorPattern(std::vector<int>& col_ptr, std::vector<int>& row_idx) const {
    (void)col_ptr;
    (void)row_idx;
    return false;
  }
};

/// Maps solver names to factories. Filled by explicit registration functions
/// (`solvers::registerSolvers(registry)`) and plugins. A solver is created by name with
/// options, or by a specification "name:ordering" (e.g. "cholmod:metis").
class SolverRegistry {
 public:
  using Factory = std::function<std::unique_ptr<LinearSolver>(const LinearSolverOptions&)>;
  using SimpleFactory = std::function<std::unique_ptr<LinearSolver>()>;
  struct Entry {
    std::string name;
    std::string description;
    std::string origin;
    SystemForm form = SystemForm::kNormalEquations;
    /// Orderings the solver accepts; the first is its default.
    std::vector<Ordering> orderings;
    Factory factory;
  };

  /// Throws RegistryError on a duplicate or malformed name, a null factory or an empty
  /// ordering list.
  void registerSolver(const std::string& name, const std::string& description, SystemForm form,
                      std::vector<Ordering> orderings, Factory factory);
  /// A normal-equations solver with no ordering choice.
  void registerSolver(const std::string& name, const std::string& description,
                      SimpleFactory factory);
  void setOrigin(std::string origin) { origin_ = std::move(origin); }

  /// A fill-reducing ordering of a system's columns: perm[k] = original column placed at
  /// position k. Registered by the solvers module (its block orderings), used by whoever
  /// factorises a system outside a LinearSolver (the marginal covariances).
  using OrderingFunction = std::function<std::vector<int>(const SparseStructure&)>;
  /// Throws RegistryError when `ordering` already has one or `function` is null.
  void registerOrdering(Ordering ordering, OrderingFunction function);
  /// The registered function of `ordering`, or null.
  [[nodiscard]] const OrderingFunction* ordering(Ordering ordering) const;

  /// Whether `spec` ("name" or "name:ordering") names a registered solver and an
  /// ordering it accepts.
  [[nodiscard]] bool contains(const std::string& spec) const;
  /// Creates the solver `spec` names. Throws RegistryError naming the known solvers (or
  /// the orderings it accepts) when `spec` is unknown.
  [[nodiscard]] std::unique_ptr<LinearSolver> create(const std::string& spec) const;
  [[nodiscard]] std::unique_ptr<LinearSolver> create(const std::string& name,
                                                     const LinearSolverOptions& options) const;
  [[nodiscard]] const Entry* find(const std::string& name) const;
  [[nodiscard]] std::vector<const Entry*> entries() const;

 private:
  std::map<std::string, Entry> entries_;
  std::map<Ordering, OrderingFunction> orderings_;
  std::string origin_;
};

}  // namespace graphslam
