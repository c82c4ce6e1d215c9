!> Explicit interfaces to PARPACK's symmetric drivers pdsaupd and pdseupd (ARPACK-NG 3.8,
!> PARPACK/SRC/MPI/pdsaupd.f and pdseupd.f; Debian's libparpack2-dev), MPI build only
!> (src/la/parpack_serial.f90 is the sequential build's module of the same name). The arguments
!> are those of dsaupd/dseupd (ffrf_la_arpack) with the Fortran communicator first; n is the
!> number of rows this rank holds (resid, v, workd, z are row-distributed: each rank its own
!> contiguous block of rows), nev, ncv, iparam and workl are the same on every rank. PARPACK
!> forms the inner products and norms with MPI_Allreduce on comm.
module ffrf_la_parpack
   use ffrf_core_kinds, only: dp, ip
   implicit none
   private
   public :: pdsaupd, pdseupd

   interface
      !> One step of the implicitly restarted Lanczos iteration on the ranks of comm (dsaupd).
      subroutine pdsaupd(comm, ido, bmat, n, which, nev, tol, resid, ncv, v, ldv, iparam, &
                         ipntr, workd, workl, lworkl, info)
         import :: dp, ip
         implicit none
         integer, intent(in) :: comm
         integer(ip), intent(in) :: n, nev, ncv, ldv, lworkl
         integer(ip), intent(inout) :: ido, iparam(11), ipntr(11), info
         character(len=1), intent(in) :: bmat
         character(len=2), intent(in) :: which
         real(dp), intent(inout) :: tol, resid(n), v(ldv, ncv), workd(3*n), workl(lworkl)
      end subroutine pdsaupd

      !> Ritz values d(nev) and this rank's rows of the Ritz vectors z(ldz, nev) (dseupd).
      subroutine pdseupd(comm, rvec, howmny, select, d, z, ldz, sigma, bmat, n, which, nev, &
                         tol, resid, ncv, v, ldv, iparam, ipntr, workd, workl, lworkl, info)
         import :: dp, ip
         implicit none
         integer, intent(in) :: comm
         integer(ip), intent(in) :: n, nev, ncv, ldv, ldz, lworkl
         logical, intent(in) :: rvec
         logical, intent(inout) :: select(ncv)
         character(len=1), intent(in) :: howmny, bmat
         character(len=2), intent(in) :: which
         real(dp), intent(in) :: sigma, tol
         real(dp), intent(out) :: d(nev), z(ldz, nev)
         real(dp), intent(inout) :: resid(n), v(ldv, ncv), workd(2*n), workl(lworkl)
         integer(ip), intent(inout) :: iparam(11), ipntr(11), info
      end subroutine pdseupd
   end interface

end module ffrf_la_parpack
