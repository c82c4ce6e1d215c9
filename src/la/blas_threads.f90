!> Threads of the BLAS (OpenBLAS; src/la/blas_threads.c): set from the command line (--threads)
!> or by a library caller before the first solve.
module ffrf_la_blas_threads
   use, intrinsic :: iso_c_binding, only: c_int, c_long_long
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: set_blas_threads, blas_threads, reserve_blas_buffers, fit_blas_address_limit
   public :: begin_single_blas, end_single_blas, blas_library_name

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
      integer(c_int) function c_blas_kind() bind(c, name='ffrf_blas_kind')
         import :: c_int
         implicit none
      end function c_blas_kind
      integer(c_int) function c_blas_single_begin() bind(c, name='ffrf_blas_single_begin')
         import :: c_int
         implicit none
      end function c_blas_single_begin
      subroutine c_blas_single_end(before) bind(c, name='ffrf_blas_single_end')
         import :: c_int
         implicit none
         integer(c_int), value :: before
      end subroutine c_blas_single_end
      integer(c_int) function c_blas_fit_address_limit() &
         bind(c, name='ffrf_blas_fit_address_limit')
         import :: c_int
         implicit none
      end function c_blas_fit_address_limit
      integer(c_int) function c_blas_reserve_buffers(count, bytes) &
         bind(c, name='ffrf_blas_reserve_buffers')
         import :: c_int, c_long_long
         implicit none
         integer(c_int), intent(out) :: count
         integer(c_long_long), intent(out) :: bytes
      end function c_blas_reserve_buffers
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
      if (used == -2) then
         used = blas_threads()
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'BLAS threads: ' // to_str(n) // &
            ' asked, but the address-space limit (ulimit -v) leaves no room for the work ' // &
            'buffers of ' // to_str(n - used) // ' more (128 MiB each; OpenBLAS would wait ' // &
            'for them forever); use fewer threads or raise the limit')
         return
      end if
      if (used < 0) call fatal_error(error, FFRF_INPUT_ERROR, 'BLAS threads: the BLAS linked ' &
         // 'is not OpenBLAS, whose threads ffrf sets; set its own variable (e.g. ' // &
         'OMP_NUM_THREADS) instead')
   end subroutine set_blas_threads

   !> The threads the BLAS uses, -1 when unknown (not OpenBLAS).
   integer function blas_threads()
      blas_threads = int(c_blas_threads())
   end function blas_threads

   !> Put the BLAS on one thread for small dense work (the integrator's steps: threaded LAPACK
   !> on a 100 x 100 matrix stalls on a busy machine; issue 24, blas_threads.c). Returns the
   !> count to give to end_single_blas (0: nothing changed, e.g. one thread already or a BLAS
   !> whose threads ffrf cannot set).
   integer function begin_single_blas() result(before)
      before = int(c_blas_single_begin())
   end function begin_single_blas

   !> Give the BLAS back the thread count that begin_single_blas returned.
   subroutine end_single_blas(before)
      !> The result of begin_single_blas
      integer, intent(in) :: before
      call c_blas_single_end(int(before, c_int))
   end subroutine end_single_blas

   !> The BLAS whose threads ffrf sets: 'OpenBLAS', 'BLIS', or '' (another BLAS, left alone).
   function blas_library_name() result(name)
      character(len=:), allocatable :: name
      select case (c_blas_kind())
      case (1)
         name = 'OpenBLAS'
      case (2)
         name = 'BLIS'
      case default
         name = ''
      end select
   end function blas_library_name

   !> Take the work buffer of OpenBLAS's calling thread (and one more when it fits) now, while
   !> the process is small: OpenBLAS 0.3.21 retries a failed buffer mapping forever, deaf to
   !> signals, so a run under an address-space limit (ulimit -v) must never map one later
   !> (blas_threads.c; issue 23). After the BLAS threads are set. FFRF_NUMERIC_ERROR (exit 4)
   !> when there is no room.
   subroutine reserve_blas_buffers(error)
      type(error_t), allocatable, intent(out) :: error
      integer(c_int) :: status, count
      integer(c_long_long) :: bytes
      status = c_blas_reserve_buffers(count, bytes)
      if (status /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, 'out of memory at the ' // &
         'start: the address-space limit (ulimit -v) leaves no room for the work buffer of ' // &
         'the BLAS (OpenBLAS, ' // to_str(int(bytes / 1048576)) // ' MiB); raise the limit')
   end subroutine reserve_blas_buffers

   !> A program's first call (the driver's): under an address-space limit (ulimit -v) with more
   !> than one BLAS thread, the program is executed again with OPENBLAS_NUM_THREADS=1 (OpenBLAS's
   !> workers, started at load, could otherwise spin forever on buffers that do not fit;
   !> blas_threads.c). Returns when nothing had to be done (or the exec failed: run on).
   subroutine fit_blas_address_limit()
      integer(c_int) :: status
      status = c_blas_fit_address_limit()
   end subroutine fit_blas_address_limit

end module ffrf_la_blas_threads
