!> Explicit interfaces to the ARPACK-NG 3.8 symmetric drivers dsaupd (implicitly restarted
!> Lanczos, reverse communication) and dseupd (Ritz values and vectors), as in SRC/dsaupd.f and
!> SRC/dseupd.f: 32-bit integers, Fortran calling convention (theory.md 5.1). Only this module
!> declares them; callers write the reverse-communication loop.
module ffrf_la_arpack
   use ffrf_core_kinds, only: dp, ip
   implicit none
   private
   public :: dsaupd, dseupd

   interface
      !> One step of the implicitly restarted Lanczos iteration for A x = lambda B x.
      !> ido: reverse-communication flag (0 first call; -1/1: y = OP x, 2: y = B x, 99: done);
      !> bmat 'I' or 'G'; which 'LM', 'SA', ...; nev wanted values; tol relative accuracy
      !> (<= 0: machine eps); resid start vector (info = 1) / residual; ncv Lanczos vectors;
      !> v (ldv, ncv) basis; iparam(11): 1 shift strategy, 3 max iterations (out: taken),
      !> 5 (out) converged, 7 mode, 9-11 (out) OP/B/reorthogonalisation counts; ipntr(11)
      !> pointers into workd; workd(3n); workl(lworkl), lworkl >= ncv**2 + 8 ncv; info: in 0
      !> (random start) or 1 (resid given), out 0, 1 (max iterations), 3 (no shifts), < 0.
      subroutine dsaupd(ido, bmat, n, which, nev, tol, resid, ncv, v, ldv, iparam, ipntr, &
                        workd, workl, lworkl, info)
         import :: dp, ip
         implicit none
         integer(ip), intent(in) :: n, nev, ncv, ldv, lworkl
         integer(ip), intent(inout) :: ido
         character(len=1), intent(in) :: bmat
         character(len=2), intent(in) :: which
         real(dp), intent(inout) :: tol
         real(dp), intent(inout) :: resid(n)
         real(dp), intent(inout) :: v(ldv, ncv)
         integer(ip), intent(inout) :: iparam(11)
         integer(ip), intent(inout) :: ipntr(11)
         real(dp), intent(inout) :: workd(3*n)
         real(dp), intent(inout) :: workl(lworkl)
         integer(ip), intent(inout) :: info
      end subroutine dsaupd

      !> Ritz values d(nev) and, with rvec, Ritz vectors z(ldz, nev) from the dsaupd state.
      !> howmny 'A' (all nev); select(ncv) workspace; sigma the shift (modes 3-5); the other
      !> arguments exactly as left by dsaupd. info: 0, or < 0 (-14: no converged value,
      !> -17: count of converged values differs from dsaupd's).
      subroutine dseupd(rvec, howmny, select, d, z, ldz, sigma, bmat, n, which, nev, tol, &
                        resid, ncv, v, ldv, iparam, ipntr, workd, workl, lworkl, info)
         import :: dp, ip
         implicit none
         integer(ip), intent(in) :: n, nev, ncv, ldv, ldz, lworkl
         logical, intent(in) :: rvec
         character(len=1), intent(in) :: howmny
         logical, intent(inout) :: select(ncv)
         real(dp), intent(out) :: d(nev)
         real(dp), intent(out) :: z(ldz, nev)
         real(dp), intent(in) :: sigma
         character(len=1), intent(in) :: bmat
         character(len=2), intent(in) :: which
         real(dp), intent(in) :: tol
         real(dp), intent(inout) :: resid(n)
         real(dp), intent(inout) :: v(ldv, ncv)
         integer(ip), intent(inout) :: iparam(11)
         integer(ip), intent(inout) :: ipntr(11)
         real(dp), intent(inout) :: workd(2*n)
         real(dp), intent(inout) :: workl(lworkl)
         integer(ip), intent(inout) :: info
      end subroutine dseupd
   end interface

end module ffrf_la_arpack
