// SPDX-License-Identifier: MIT
// The BLAS and LAPACK routines the project's modules call (dense fronts of the incremental
// factor, the dense tail of tail-llt), through the reference Fortran interface every BLAS /
// LAPACK exports (Debian's libblas.so.3 and liblapack.so.3; OpenBLAS with the README's
// set-up). The libraries are loaded on the first call, not when a program starts: a
// program that never factorises a large dense block never loads them (OpenBLAS starts its
// threads when it loads). Their threads are the BLAS's own: OpenBLAS takes them from
// OPENBLAS_NUM_THREADS (solvers::setBlasThreads).
#pragma once

namespace graphslam::support::blas {

/// The Fortran entry points, resolved from the build's BLAS and LAPACK.
struct Functions {
  void (*dsyrk)(const char* uplo, const char* trans, const int* n, const int* k,
                const double* alpha, const double* a, const int* lda, const double* beta,
                double* c, const int* ldc) = nullptr;
  void (*dpotrf)(const char* uplo, const int* n, double* a, const int* lda, int* info) = nullptr;
  void (*dtrsm)(const char* side, const char* uplo, const char* transa, const char* diag,
                const int* m, const int* n, const double* alpha, const double* a, const int* lda,
                double* b, const int* ldb) = nullptr;
  void (*dtrsv)(const char* uplo, const char* trans, const char* diag, const int* n,
                const double* a, const int* lda, double* x, const int* incx) = nullptr;
  void (*dgemv)(const char* trans, const int* m, const int* n, const double* alpha,
                const double* a, const int* lda, const double* x, const int* incx,
                const double* beta, double* y, const int* incy) = nullptr;
};

/// Whether this build knows a BLAS and LAPACK to load (CMake found them).
[[nodiscard]] bool configured();

/// The routines, loading the libraries on the first call (thread-safe). Throws
/// graphslam::Error naming the library and the loader's reason when one cannot be loaded or
/// lacks a routine (callers check configured() first).
[[nodiscard]] const Functions& functions();

/// Whether the libraries are loaded in this process already.
[[nodiscard]] bool loaded();

inline void dsyrk(const char* uplo, const char* trans, const int* n, const int* k,
                  const double* alpha, const double* a, const int* lda, const double* beta,
                  double* c, const int* ldc) {
  functions().dsyrk(uplo, trans, n, k, alpha, a, lda, beta, c, ldc);
}
inline void dpotrf(const char* uplo, const int* n, double* a, const int* lda, int* info) {
  functions().dpotrf(uplo, n, a, lda, info);
}
inline void dtrsm(const char* side, const char* uplo, const char* transa, const char* diag,
                  const int* m, const int* n, const double* alpha, const double* a, const int* lda,
                  double* b, const int* ldb) {
  functions().dtrsm(side, uplo, transa, diag, m, n, alpha, a, lda, b, ldb);
}
inline void dtrsv(const char* uplo, const char* trans, const char* diag, const int* n,
                  const double* a, const int* lda, double* x, const int* incx) {
  functions().dtrsv(uplo, trans, diag, n, a, lda, x, incx);
}
inline void dgemv(const char* trans, const int* m, const int* n, const double* alpha,
                  const double* a, const int* lda, const double* x, const int* incx,
                  const double* beta, double* y, const int* incy) {
  functions().dgemv(trans, m, n, alpha, a, lda, x, incx, beta, y, incy);
}

}  // namespace graphslam::support::blas
