!> Error objects: the library never stops and never prints an error. A routine that can fail has
!> `type(error_t), allocatable, intent(out) :: error` as its last argument; not allocated means
!> success. Callers add where it happened with `add_context` and pass it up to the driver.
module ffrf_core_error
   implicit none
   private
   public :: error_t, fatal_error, add_context, check_solution
   public :: FFRF_INPUT_ERROR, FFRF_IO_ERROR, FFRF_NUMERIC_ERROR, FFRF_INTERRUPTED

   !> Bad user input: namelist, mesh content, inconsistent model description. The three codes
   !> double as the exit status of the ffrf driver.
   integer, parameter :: FFRF_INPUT_ERROR = 2
   !> A file could not be opened, read or written
   integer, parameter :: FFRF_IO_ERROR = 3
   !> A numerical method failed (singular matrix, no convergence, NaN)
   integer, parameter :: FFRF_NUMERIC_ERROR = 4
   !> The run was stopped by a signal (SIGTERM, SIGINT, SIGHUP, SIGUSR1, SIGXCPU) after a clean
   !> end of its current step: results and restart state written, a job script may requeue it
   integer, parameter :: FFRF_INTERRUPTED = 5

   !> What went wrong, where, and how to fix it.
   type :: error_t
      !> One of FFRF_INPUT_ERROR, FFRF_IO_ERROR, FFRF_NUMERIC_ERROR, FFRF_INTERRUPTED
      integer :: code = FFRF_INPUT_ERROR
      !> One line: what, where, the offending value, the fix
      character(len=:), allocatable :: message
   end type error_t

contains

   !> Create an error with `code` and `message`.
   subroutine fatal_error(error, code, message)
      !> Error to create
      type(error_t), allocatable, intent(out) :: error
      !> FFRF_INPUT_ERROR, FFRF_IO_ERROR or FFRF_NUMERIC_ERROR
      integer, intent(in) :: code
      !> What, where, value, fix
      character(len=*), intent(in) :: message
      allocate (error)
      error%code = code
      error%message = message
   end subroutine fatal_error

   !> Prefix `where` to the message of an existing error ("body crank: ...").
   subroutine add_context(error, where)
      !> Error to extend (must be allocated)
      type(error_t), intent(inout) :: error
      !> Where the failing call was made
      character(len=*), intent(in) :: where
      if (.not. allocated(error%message)) error%message = ''
      error%message = where // ': ' // error%message
   end subroutine add_context

   !> After a linear solve: `where` prefixed to its error, else FFRF_NUMERIC_ERROR `message` when
   !> the solution is not finite (`finite`: all(ieee_is_finite(x)) of the caller's x).
   subroutine check_solution(error, where, finite, message)
      !> The solve's error (not allocated: it succeeded)
      type(error_t), allocatable, intent(inout) :: error
      !> Where the solve was made
      character(len=*), intent(in) :: where
      !> Every entry of the solution is finite
      logical, intent(in) :: finite
      !> What the NaN or Inf means and how to fix it
      character(len=*), intent(in) :: message
      if (allocated(error)) then
         call add_context(error, where)
      else if (.not. finite) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, message)
      end if
   end subroutine check_solution

end module ffrf_core_error
