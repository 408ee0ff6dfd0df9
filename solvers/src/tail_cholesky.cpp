// SPDX-License-Identifier: MIT
// When tail-llt (tail_cholesky.h) pays: the work a dense tail saves against its price.
#include "tail_cholesky.h"

namespace graphslam::solvers::detail {

bool blasTailPays(double tail_rows, double panel_columns, double pair_flops) {
#ifdef GRAPHSLAM_HAVE_LAPACK
  // dsyrk makes tail_rows^2 * panel_columns / 2 multiply-adds where a sparse loop makes
  // pair_flops / 2, each several times slower than BLAS's; the dense tail stays below
  // 128 MiB, W (tail_rows x panel_columns) below 64 MiB.
  return tail_rows >= kBlasTailMinRows && tail_rows <= 4096.0 &&
         tail_rows * panel_columns <= 8.0 * 1024 * 1024 &&
         tail_rows * tail_rows * panel_columns <= 4.0 * pair_flops;
#else
  static_cast<void>(tail_rows);
  static_cast<void>(panel_columns);
  static_cast<void>(pair_flops);
  return false;
#endif
}

}  // namespace graphslam::solvers::detail
