!> Explicit interfaces to the LAPACK/BLAS routines ffrf calls (reference LAPACK signatures, 32-bit
!> integers as in Debian's OpenBLAS). Only this module declares them.
module ffrf_la_lapack
   use ffrf_core_kinds, only: dp, ip
   implicit none
   private
   public :: dgesvd, dsyev, dsygv, dposv, dgesv, dgemm, dgelsy, dgeev, dpotrf, dtrsm

   interface
      !> Minimum-norm least squares by complete orthogonal factorisation, A P = Q [R11 R12; 0 R22].
      subroutine dgelsy(m, n, nrhs, a, lda, b, ldb, jpvt, rcond, rank, work, lwork, info)
         import :: dp, ip
         implicit none
         integer(ip), intent(in) :: m, n, nrhs, lda, ldb, lwork
         real(dp), intent(inout) :: a(lda, *), b(ldb, *)
         integer(ip), intent(inout) :: jpvt(*)
         real(dp), intent(in) :: rcond
         integer(ip), intent(out) :: rank
         real(dp), intent(out) :: work(*)
         integer(ip), intent(out) :: info
      end subroutine dgelsy

      !> Singular value decomposition A = U S V^T.
      subroutine dgesvd(jobu, jobvt, m, n, a, lda, s, u, ldu, vt, ldvt, work, lwork, info)
         import :: dp, ip
         implicit none
         character, intent(in) :: jobu, jobvt
         integer(ip), intent(in) :: m, n, lda, ldu, ldvt, lwork
         real(dp), intent(inout) :: a(lda, *)
         real(dp), intent(out) :: s(*), u(ldu, *), vt(ldvt, *), work(*)
         integer(ip), intent(out) :: info
      end subroutine dgesvd

      !> Eigen decomposition of a symmetric matrix.
      subroutine dsyev(jobz, uplo, n, a, lda, w, work, lwork, info)
         import :: dp, ip
         implicit none
         character, intent(in) :: jobz, uplo
         integer(ip), intent(in) :: n, lda, lwork
         real(dp), intent(inout) :: a(lda, *)
         real(dp), intent(out) :: w(*), work(*)
         integer(ip), intent(out) :: info
      end subroutine dsyev

      !> Generalized symmetric-definite eigenproblem A x = lambda B x.
      subroutine dsygv(itype, jobz, uplo, n, a, lda, b, ldb, w, work, lwork, info)
         import :: dp, ip
         implicit none
         integer(ip), intent(in) :: itype, n, lda, ldb, lwork
         character, intent(in) :: jobz, uplo
         real(dp), intent(inout) :: a(lda, *), b(ldb, *)
         real(dp), intent(out) :: w(*), work(*)
         integer(ip), intent(out) :: info
      end subroutine dsygv

      !> Solve A X = B, A symmetric positive definite (Cholesky).
      subroutine dposv(uplo, n, nrhs, a, lda, b, ldb, info)
         import :: dp, ip
         implicit none
         character, intent(in) :: uplo
         integer(ip), intent(in) :: n, nrhs, lda, ldb
         real(dp), intent(inout) :: a(lda, *), b(ldb, *)
         integer(ip), intent(out) :: info
      end subroutine dposv

      !> Eigenvalues (and optionally eigenvectors) of a general matrix.
      subroutine dgeev(jobvl, jobvr, n, a, lda, wr, wi, vl, ldvl, vr, ldvr, work, lwork, info)
         import :: dp, ip
         implicit none
         character, intent(in) :: jobvl, jobvr
         integer(ip), intent(in) :: n, lda, ldvl, ldvr, lwork
         real(dp), intent(inout) :: a(lda, *)
         real(dp), intent(out) :: wr(*), wi(*), vl(ldvl, *), vr(ldvr, *), work(*)
         integer(ip), intent(out) :: info
      end subroutine dgeev

      !> Solve A X = B, A general (LU with partial pivoting).
      subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
         import :: dp, ip
         implicit none
         integer(ip), intent(in) :: n, nrhs, lda, ldb
         real(dp), intent(inout) :: a(lda, *), b(ldb, *)
         integer(ip), intent(out) :: ipiv(*), info
      end subroutine dgesv

      !> C = alpha op(A) op(B) + beta C.
      subroutine dgemm(transa, transb, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc)
         import :: dp, ip
         implicit none
         character, intent(in) :: transa, transb
         integer(ip), intent(in) :: m, n, k, lda, ldb, ldc
         real(dp), intent(in) :: alpha, beta, a(lda, *), b(ldb, *)
         real(dp), intent(inout) :: c(ldc, *)
      end subroutine dgemm
      !> Cholesky factorisation A = U^T U (uplo = 'U') of a symmetric positive definite matrix.
      subroutine dpotrf(uplo, n, a, lda, info)
         import :: dp, ip
         implicit none
         character, intent(in) :: uplo
         integer(ip), intent(in) :: n, lda
         real(dp), intent(inout) :: a(lda, *)
         integer(ip), intent(out) :: info
      end subroutine dpotrf

      !> B = alpha op(A)^-1 B (side = 'L') or alpha B op(A)^-1 (side = 'R'), A triangular.
      subroutine dtrsm(side, uplo, transa, diag, m, n, alpha, a, lda, b, ldb)
         import :: dp, ip
         implicit none
         character, intent(in) :: side, uplo, transa, diag
         integer(ip), intent(in) :: m, n, lda, ldb
         real(dp), intent(in) :: alpha, a(lda, *)
         real(dp), intent(inout) :: b(ldb, *)
      end subroutine dtrsm
   end interface

end module ffrf_la_lapack
