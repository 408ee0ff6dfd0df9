// SPDX-License-Identifier: MIT
// METIS nested dissection of a block graph and METIS's vertex separator of a graph, through
// CHOLMOD (part of the SuiteSparse backend, loaded on first use).
#include <cholmod.h>

#include <string>
#include <vector>

#include "graphslam/support/error.h"
#include "suitesparse_backend.h"

namespace graphslam::solvers::suitesparse {

namespace {

/// A symmetric pattern given by its upper triangle's compressed columns, as CHOLMOD's
/// matrix (no copy: CHOLMOD only reads it).
cholmod_sparse upperPattern(const std::vector<int>& column_starts, const std::vector<int>& rows) {
  cholmod_sparse a{};
  a.nrow = a.ncol = column_starts.empty() ? 0 : column_starts.size() - 1;
  a.nzmax = rows.size();
  a.p = const_cast<int*>(column_starts.data());
  a.i = const_cast<int*>(rows.data());
  a.stype = 1;  // symmetric: METIS takes the graph of A itself (upper part read)
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_PATTERN;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  return a;
}

}  // namespace

/// METIS nested dissection (through CHOLMOD) on a symmetric block graph.
std::vector<int> metisBlocks(const detail::BlockGraph& g) {
  cholmod_common cc;
  cholmod_start(&cc);
  cc.print = 0;
  cc.error_handler = nullptr;
  cholmod_sparse a = upperPattern(g.ptr, g.idx);
  std::vector<int> perm(static_cast<std::size_t>(g.num_blocks));
  const int ok = cholmod_metis(&a, nullptr, 0, 0, perm.data(), &cc);
  const int status = cc.status;
  cholmod_finish(&cc);
  if (!ok || status < CHOLMOD_OK) {
    throw Error("METIS ordering failed (CHOLMOD status " + std::to_string(status) + ")");
  }
  return perm;
}

std::vector<int> metisSeparator(const std::vector<int>& column_starts,
                                const std::vector<int>& rows) {
  cholmod_common cc;
  cholmod_start(&cc);
  cc.print = 0;
  cc.error_handler = nullptr;
  cholmod_sparse a = upperPattern(column_starts, rows);
  std::vector<int> side(a.nrow, 0);
  const SuiteSparse_long separator =
      a.nrow == 0 ? 0 : cholmod_bisect(&a, nullptr, 0, /*compress=*/1, side.data(), &cc);
  const int status = cc.status;
  cholmod_finish(&cc);
  if (separator < 0 || status < CHOLMOD_OK) {
    throw Error("METIS's vertex separator of " + std::to_string(a.nrow) +
                " vertices failed (CHOLMOD status " + std::to_string(status) + ")");
  }
  return side;
}

}  // namespace graphslam::solvers::suitesparse
