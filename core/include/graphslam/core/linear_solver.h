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
/// Only the upper triangle is meaningful; the diagonal blocks are stored full (both
/// triangles), and solvers must ignore entries below the diagonal. Row indices are
/// sorted within each column. `block_starts` (size num_blocks + 1) gives the first column
/// of every variable block (one block per vertex), so solvers can order on the block
/// graph. The arrays stay valid and unchanged until the next analyze().
struct SparseStructure {
  int n = 0;
  const int* col_ptr = nullptr;  ///< n + 1 entries
  const int* row_idx = nullptr;  ///< col_ptr[n] entries
  const int* block_starts = nullptr;
  int num_blocks = 0;

  [[nodiscard]] std::size_t nnz() const { return n ? static_cast<std::size_t>(col_ptr[n]) : 0u; }
};

/// Sparse linear solver for the optimizer's normal equations: `analyze()` once per
/// structure (ordering + symbolic factorisation), `factorize()` every iteration on new
/// values, `solve()` for each right-hand side.
class LinearSolver {
 public:
  virtual ~LinearSolver() = default;

  [[nodiscard]] virtual std::string name() const = 0;
  [[nodiscard]] virtual SystemForm form() const { return SystemForm::kNormalEquations; }

  [[nodiscard]] virtual LinearSolverResult analyze(const SparseStructure& structure) = 0;
  /// `values` has structure.nnz() entries in the order of `row_idx`.
  [[nodiscard]] virtual LinearSolverResult factorize(const double* values) = 0;
  /// Solves H x = rhs with the last factorisation; rhs and x have n entries (may alias).
  [[nodiscard]] virtual LinearSolverResult solve(const double* rhs, double* x) = 0;

  /// Non-zeros of the last factor (0 if unknown), for reports.
  [[nodiscard]] virtual std::size_t factorNonZeros() const { return 0; }
};

/// Maps solver names to factories. Filled by explicit registration functions
/// (`solvers::registerSolvers(registry)`) and plugins.
class SolverRegistry {
 public:
  using Factory = std::function<std::unique_ptr<LinearSolver>()>;
  struct Entry {
    std::string name;
    std::string description;
    std::string origin;
    Factory factory;
  };

  /// Throws RegistryError on a duplicate or malformed name or a null factory.
  void registerSolver(const std::string& name, const std::string& description, Factory factory);
  void setOrigin(std::string origin) { origin_ = std::move(origin); }

  [[nodiscard]] bool contains(const std::string& name) const { return entries_.count(name) != 0; }
  /// Throws RegistryError naming the known solvers when `name` is unknown.
  [[nodiscard]] std::unique_ptr<LinearSolver> create(const std::string& name) const;
  [[nodiscard]] std::vector<const Entry*> entries() const;

 private:
  std::map<std::string, Entry> entries_;
  std::string origin_;
};

}  // namespace graphslam
