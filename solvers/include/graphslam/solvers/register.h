// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/linear_solver.h"
#include "graphslam/solvers/options.h"

namespace graphslam::solvers {

/// Registers the solvers built on Eigen alone: "eigen-ldlt", "eigen-llt" (simplicial
/// Cholesky), "eigen-qr" (sparse QR on J), "dense-ldlt", "dense-pinv" and "pcg". Every
/// solver made from the registry takes its tuning from `options` (copied).
void registerEigenSolvers(SolverRegistry& registry, const SolverOptions& options = {});

/// Registers the SuiteSparse solvers: "cholmod" (supernodal), "cholmod-simplicial",
/// "csparse" (CXSparse Cholesky), "umfpack" (LU) and "spqr" (QR on J). Throws
/// RegistryError when graphslam was built without SuiteSparse.
void registerSuiteSparseSolvers(SolverRegistry& registry, const SolverOptions& options = {});

/// Whether this build has SuiteSparse (and with it the COLAMD and METIS orderings).
[[nodiscard]] bool haveSuiteSparse();

/// Registers "auto", the default: it predicts the factorisation's cost from the pattern
/// of H, orders by AMD or METIS and factorises with eigen-ldlt, or with supernodal
/// cholmod when the work is large (without SuiteSparse: eigen-ldlt with AMD). Each solver
/// made keeps its own cache of block orderings unless `options.ordering_cache` names one
/// to share.
void registerAutoSolver(SolverRegistry& registry, const SolverOptions& options = {});

/// The kernels block-llt (and auto, which factorises with it) uses in this process:
/// "avx2-fma" on CPUs with AVX2 and FMA, else "portable" (the x86-64 baseline the library
/// is built for). The environment variable GRAPHSLAM_SIMD=portable, read once per
/// process, selects the portable ones everywhere. The two round differently in the last
/// bits (fused multiply-adds).
[[nodiscard]] const char* blockKernelPath();

/// Registers every solver this build has, with the tuning of `options`.
void registerSolvers(SolverRegistry& registry, const SolverOptions& options = {});

}  // namespace graphslam::solvers
