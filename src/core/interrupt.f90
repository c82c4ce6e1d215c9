!> Safe points where a long computation gives way to a run that is being ended: a signal the
!> driver's handlers recorded (SIGTERM, SIGINT, SIGHUP, SIGUSR1, SIGXCPU; ffrf_core_posix)
!> becomes an FFRF_INTERRUPTED error at the next `check`, on every rank together.
module ffrf_core_interrupt
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INTERRUPTED
   use ffrf_core_parallel, only: parallel_t
   use ffrf_core_posix, only: pending_signal, signal_name
   implicit none
   private
   public :: interrupt_t

   !> Whether to stop at the checks, and the ranks that stop together.
   type :: interrupt_t
      !> .false.: `check` never stops (the computation runs to its end)
      logical :: enabled = .false.
      !> The ranks calling `check` at the same points (MPI build; default one process)
      type(parallel_t) :: ranks
   contains
      procedure :: check => interrupt_check
   end type interrupt_t

contains

   !> When enabled and a signal is pending on any rank: error FFRF_INTERRUPTED, "interrupted by
   !> SIGTERM " // where. Collective: every rank of `ranks` calls it at the same point.
   subroutine interrupt_check(self, where, error)
      class(interrupt_t), intent(in) :: self
      !> Where the computation stopped, e.g. "in the eigen loop after 12 solves"
      character(len=*), intent(in) :: where
      type(error_t), allocatable, intent(out) :: error
      integer :: signal
      if (.not. self%enabled) return
      signal = self%ranks%max_int(pending_signal())
      if (signal /= 0) call fatal_error(error, FFRF_INTERRUPTED, 'interrupted by ' // &
         signal_name(signal) // ' ' // where)
   end subroutine interrupt_check

end module ffrf_core_interrupt
