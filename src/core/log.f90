!> Leveled progress log and stage timers. One logger writes to a unit the caller picks; every
!> stage reports its size and wall time: `[modes] crank, RC set 2: 20 modes ... 2.93 s`.
module ffrf_core_log
   use, intrinsic :: iso_fortran_env, only: output_unit
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_memory, only: read_proc_field
   implicit none
   private
   public :: logger_t, stage_timer_t, stage_times_t, wall_time, peak_memory_mib
   public :: LOG_QUIET, LOG_INFO, LOG_DEBUG

   integer, parameter :: LOG_QUIET = 0  !< nothing
   integer, parameter :: LOG_INFO = 1   !< stages, sizes, timings, notes
   integer, parameter :: LOG_DEBUG = 2  !< per-iteration detail

   !> Progress log: lines go to `unit` when their level is at most `level`.
   type :: logger_t
      !> Fortran unit written to
      integer :: unit = output_unit
      !> LOG_QUIET, LOG_INFO or LOG_DEBUG
      integer :: level = LOG_INFO
   contains
      procedure :: info => logger_info
      procedure :: debug => logger_debug
      procedure :: note => logger_note
   end type logger_t

   !> Wall-clock timer of one stage.
   type :: stage_timer_t
      !> Start, seconds since an arbitrary origin
      real(dp) :: start = 0.0_dp
   contains
      procedure :: begin => stage_timer_begin
      procedure :: seconds => stage_timer_seconds
   end type stage_timer_t

   !> Wall time and peak memory of each stage of a run, in order, for the results file.
   type :: stage_times_t
      !> Stage names ("crank: assembly")
      character(len=80), allocatable :: names(:)
      !> Wall time of each stage (s)
      real(dp), allocatable :: seconds(:)
      !> Peak resident memory of the process at the end of each stage (MiB)
      real(dp), allocatable :: peak_mib(:)
      !> Peak resident memory of every MPI rank at the end of the run (MiB; MPI runs only)
      real(dp), allocatable :: rank_peak_mib(:)
   contains
      procedure :: add => stage_times_add
   end type stage_times_t

contains

   !> Append a stage.
   subroutine stage_times_add(self, name, seconds)
      class(stage_times_t), intent(inout) :: self
      !> Stage name
      character(len=*), intent(in) :: name
      !> Wall time (s)
      real(dp), intent(in) :: seconds
      character(len=80), allocatable :: names(:)
      real(dp), allocatable :: seconds_new(:), peak_new(:)
      integer :: n
      n = 0
      if (allocated(self%names)) n = size(self%names)
      ! Grown by hand: gfortran 12's -fcheck=bounds rejects [names, name] for character arrays.
      allocate (names(n + 1), seconds_new(n + 1), peak_new(n + 1))
      if (n > 0) then
         names(:n) = self%names
         seconds_new(:n) = self%seconds
         peak_new(:n) = self%peak_mib
      end if
      names(n + 1) = name
      seconds_new(n + 1) = seconds
      peak_new(n + 1) = peak_memory_mib()
      call move_alloc(names, self%names)
      call move_alloc(seconds_new, self%seconds)
      call move_alloc(peak_new, self%peak_mib)
   end subroutine stage_times_add

   !> An information line, "[stage] text".
   subroutine logger_info(self, stage, text)
      class(logger_t), intent(in) :: self
      !> Stage tag, e.g. "mesh"
      character(len=*), intent(in) :: stage
      !> Message
      character(len=*), intent(in) :: text
      if (self%level >= LOG_INFO) then
         write (self%unit, '(a)') '[' // stage // '] ' // text
         flush (self%unit)
      end if
   end subroutine logger_info

   !> A detail line, shown at LOG_DEBUG only.
   subroutine logger_debug(self, stage, text)
      class(logger_t), intent(in) :: self
      !> Stage tag
      character(len=*), intent(in) :: stage
      !> Message
      character(len=*), intent(in) :: text
      if (self%level >= LOG_DEBUG) write (self%unit, '(a)') '[' // stage // '] ' // text
   end subroutine logger_debug

   !> A note the user should read (hyperstatic RC set, fallback taken), "[stage] note: text".
   subroutine logger_note(self, stage, text)
      class(logger_t), intent(in) :: self
      !> Stage tag
      character(len=*), intent(in) :: stage
      !> Message
      character(len=*), intent(in) :: text
      call self%info(stage, 'note: ' // text)
   end subroutine logger_note

   !> Wall-clock seconds since an arbitrary origin.
   function wall_time() result(seconds)
      real(dp) :: seconds
      integer(i8) :: count, rate
      call system_clock(count, rate)
      seconds = real(count, dp) / real(rate, dp)
   end function wall_time

   subroutine stage_timer_begin(self)
      class(stage_timer_t), intent(inout) :: self
      self%start = wall_time()
   end subroutine stage_timer_begin

   !> Seconds since `begin`.
   function stage_timer_seconds(self) result(seconds)
      class(stage_timer_t), intent(in) :: self
      real(dp) :: seconds
      seconds = wall_time() - self%start
   end function stage_timer_seconds

   !> Peak resident memory of this process in MiB (VmHWM of /proc/self/status; 0 if unknown).
   function peak_memory_mib() result(mib)
      real(dp) :: mib
      integer(i8) :: kib
      logical :: found
      mib = 0.0_dp
      call read_proc_field('/proc/self/status', 'VmHWM:', kib, found)
      if (found) mib = real(kib, dp) / 1024.0_dp
   end function peak_memory_mib

end module ffrf_core_log
