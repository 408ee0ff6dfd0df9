// SPDX-License-Identifier: MIT
// Shared by the project's modules (build tree only): the reference Fortran interface of the
// BLAS and LAPACK routines they call, which every BLAS / LAPACK exports (Debian's
// libblas.so.3 and liblapack.so.3; OpenBLAS with the README's set-up). Only for targets
// that link LAPACK::LAPACK and BLAS::BLAS. Their threads are the BLAS's own: OpenBLAS takes
// them from OPENBLAS_NUM_THREADS.
#pragma once

extern "C" {
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const double* alpha, const double* a, const int* lda, double* b,
            const int* ldb);
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a,
            const int* lda, double* x, const int* incx);
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a,
            const int* lda, const double* x, const int* incx, const double* beta, double* y,
            const int* incy);
}
