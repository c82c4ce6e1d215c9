!> Threads of the BLAS (OpenBLAS; src/la/blas_threads.c): set from the command line (--threads)
!> or by a library caller before the first solve.
module ffrf_la_blas_threads
   use, intrinsic :: iso_c_binding, only: c_int
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: set_blas_threads, blas_threads

   interface
      integer(c_int) function c_blas_set_threads(n) bind(c, name='ffrf_blas_set_threads')
         import :: c_int
         implicit none
         integer(c_int), value :: n
      end function c_blas_set_threads
      integer(c_int) function c_blas_threads() bind(c, name='ffrf_blas_threads')
         import :: c_int
         implicit none
      end function c_blas_threads
   end interface

contains

   !> Let the BLAS use `n` threads (n >= 1); `used`: the threads it then uses (OpenBLAS may cap
   !> n at the most it was built for). An error when n < 1 or the BLAS is not OpenBLAS.
   subroutine set_blas_threads(n, used, error)
      integer, intent(in) :: n
      integer, intent(out) :: used
      type(error_t), allocatable, intent(out) :: error
      used = blas_threads()
      if (n < 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'BLAS threads: ' // to_str(n) // &
            ' asked; give 1 or more')
         return
      end if
      used = int(c_blas_set_threads(int(n, c_int)))
      if (used < 0) call fatal_error(error, FFRF_INPUT_ERROR, 'BLAS threads: the BLAS linked ' &
         // 'is not OpenBLAS, whose threads ffrf sets; set its own variable (e.g. ' // &
         'OMP_NUM_THREADS) instead')
   end subroutine set_blas_threads

   !> The threads the BLAS uses, -1 when unknown (not OpenBLAS).
   integer function blas_threads()
      blas_threads = int(c_blas_threads())
   end function blas_threads

end module ffrf_la_blas_threads
