// SPDX-License-Identifier: MIT
// Factorisations for callers that choose the elimination order themselves, and METIS's
// vertex separator: both through the SuiteSparse backend (CHOLMOD), loaded on first use.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

namespace graphslam::solvers {

/// A sparse symmetric positive definite matrix M factorised in the order it is given in,
/// M = L L^T, by CHOLMOD's supernodal Cholesky (no fill-reducing reordering, no postorder).
/// With trailing variables placed last, the trailing block L_S of L gives the Schur
/// complement onto them: L_S L_S^T = C - Y^T Y where Y = L_A^-1 B (the submap solver's
/// elimination of a submap's interior onto its separator).
class OrderedFactor {
 public:
  virtual ~OrderedFactor() = default;

  /// Factorises M from its upper triangle (compressed columns, a column's rows in any order,
  /// the diagonal present). The first call makes the symbolic analysis; later calls must
  /// give the same pattern. False when M is not positive definite; throws graphslam::Error
  /// when CHOLMOD fails otherwise (out of memory).
  [[nodiscard]] virtual bool factorize(const Eigen::SparseMatrix<double>& upper) = 0;
  /// The last `n` rows and columns of L as a dense lower triangle. Needs factorize().
  [[nodiscard]] virtual Eigen::MatrixXd trailingBlock(int n) const = 0;
  /// L^-1 b, or L^-T b when `transposed`. Needs factorize().
  [[nodiscard]] virtual Eigen::VectorXd solveTriangular(Eigen::VectorXd b,
                                                        bool transposed) const = 0;
  /// Frees the numeric values; the symbolic analysis stays for the next factorize().
  virtual void release() = 0;
};

/// A supernodal OrderedFactor. Its calls run CHOLMOD's OpenMP loops serially when
/// serializeCholmodOpenMp(true) is in effect (process.h). Throws graphslam::Error when this
/// build has no SuiteSparse or its backend cannot be loaded.
[[nodiscard]] std::unique_ptr<OrderedFactor> makeOrderedSupernodalFactor();

/// METIS's vertex separator of a graph (through CHOLMOD's Partition module): the graph's
/// upper triangle in compressed columns (`column_starts` of n + 1 entries, then the rows of
/// each column, every row index less than its column's, no diagonal). Returns each vertex's
/// side, 0 or 1, or 2 for the separator: no edge joins side 0 to side 1. Throws
/// graphslam::Error when METIS fails or this build has no SuiteSparse.
[[nodiscard]] std::vector<int> metisVertexSeparator(const std::vector<int>& column_starts,
                                                    const std::vector<int>& rows);

}  // namespace graphslam::solvers
