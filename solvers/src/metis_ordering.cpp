// SPDX-License-Identifier: MIT
// METIS nested dissection of a block graph, through CHOLMOD (part of the SuiteSparse backend,
// loaded on first use).
#include <cholmod.h>

#include <string>
#include <vector>

#include "graphslam/support/error.h"
#include "suitesparse_backend.h"

namespace graphslam::solvers::suitesparse {

/// METIS nested dissection (through CHOLMOD) on a symmetric block graph.
std::vector<int> metisBlocks(const detail::BlockGraph& g) {
  cholmod_common cc;
  cholmod_start(&cc);
  cc.print = 0;
  cc.error_handler = nullptr;
  cholmod_sparse a{};
  a.nrow = a.ncol = static_cast<size_t>(g.num_blocks);
  a.nzmax = g.idx.size();
  a.p = const_cast<int*>(g.ptr.data());
  a.i = const_cast<int*>(g.idx.data());
  a.stype = 1;  // symmetric: METIS takes the graph of A itself (upper part read)
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_PATTERN;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  std::vector<int> perm(static_cast<std::size_t>(g.num_blocks));
  const int ok = cholmod_metis(&a, nullptr, 0, 0, perm.data(), &cc);
  const int status = cc.status;
  cholmod_finish(&cc);
  if (!ok || status < CHOLMOD_OK) {
    throw Error("METIS ordering failed (CHOLMOD status " + std::to_string(status) + ")");
  }
  return perm;
}

}  // namespace graphslam::solvers::suitesparse
