!> PARPACK's pdsaupd/pdseupd in the sequential build (src/la/parpack_mpi.f90 is the MPI build's
!> module of the same name): one process holds every row, so they are ARPACK's dsaupd/dseupd
!> with the communicator ignored. The sequential build does not link PARPACK and its eigen loop
!> calls dsaupd itself (ffrf_modes_shift_invert_lanczos); these keep that loop's MPI branch
!> compiling. Arguments as in ffrf_la_arpack.
module ffrf_la_parpack
   use ffrf_core_kinds, only: dp, ip
   use ffrf_la_arpack, only: dsaupd, dseupd
   implicit none
   private
   public :: pdsaupd, pdseupd

contains

   !> dsaupd on the one process (comm unused).
   subroutine pdsaupd(comm, ido, bmat, n, which, nev, tol, resid, ncv, v, ldv, iparam, &
                      ipntr, workd, workl, lworkl, info)
      integer, intent(in) :: comm
      integer(ip), intent(in) :: n, nev, ncv, ldv, lworkl
      integer(ip), intent(inout) :: ido, iparam(11), ipntr(11), info
      character(len=*), intent(in) :: bmat, which
      real(dp), intent(inout) :: tol, resid(*), v(ldv, *), workd(*), workl(*)
      call dsaupd(ido, bmat, n, which, nev, tol, resid, ncv, v, ldv, iparam, ipntr, workd, &
         workl, lworkl, info)
   end subroutine pdsaupd

   !> dseupd on the one process (comm unused).
   subroutine pdseupd(comm, rvec, howmny, select, d, z, ldz, sigma, bmat, n, which, nev, tol, &
                      resid, ncv, v, ldv, iparam, ipntr, workd, workl, lworkl, info)
      integer, intent(in) :: comm
      integer(ip), intent(in) :: n, nev, ncv, ldv, ldz, lworkl
      logical, intent(in) :: rvec
      logical, intent(inout) :: select(*)
      character(len=*), intent(in) :: howmny, bmat, which
      real(dp), intent(in) :: sigma, tol
      real(dp), intent(out) :: d(*), z(ldz, *)
      real(dp), intent(inout) :: resid(*), v(ldv, *), workd(*), workl(*)
      integer(ip), intent(inout) :: iparam(11), ipntr(11), info
      call dseupd(rvec, howmny, select, d, z, ldz, sigma, bmat, n, which, nev, tol, resid, ncv, &
         v, ldv, iparam, ipntr, workd, workl, lworkl, info)
   end subroutine pdseupd

end module ffrf_la_parpack
