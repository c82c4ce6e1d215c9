!> Kind parameters used everywhere in ffrf: `dp` for reals, `ip` for indices and sizes handed to
!> MUMPS, ARPACK, METIS and LAPACK (all 32-bit in Debian's builds), `i8` for counts past 2**31.
module ffrf_core_kinds
   use, intrinsic :: iso_fortran_env, only: real64, int32, int64
   implicit none
   private
   public :: dp, ip, i8, pi

   integer, parameter :: dp = real64
   integer, parameter :: ip = int32
   integer, parameter :: i8 = int64
   real(dp), parameter :: pi = 3.14159265358979323846264338327950288_dp
end module ffrf_core_kinds
