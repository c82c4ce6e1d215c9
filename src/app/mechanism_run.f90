!> A mechanism case from its namelist file to its results: read and echo the input, then the
!> mechanism session (ffrf_app_mechanism_session) prepared with the run options and advanced to
!> t_end: it computes the modes of the flexible bodies, builds the mechanism, integrates it
!> with generalized-alpha and records the run (ffrf_app_mechanism_output: the results file
!> written progressively, checkpoints, --restart, animations). The C and Fortran API's advance
!> with an output folder takes the same path. Nothing here stops or prints errors; a failed
!> integration still closes the results file with every recorded step, the last converged
!> state and status = the error message.
module ffrf_app_mechanism_run
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_core_paths, only: folder_of
   use ffrf_core_log, only: logger_t, stage_times_t
   use ffrf_input_case, only: case_input_t, read_case, case_echo
   use ffrf_app_run_options, only: run_options_t, set_log_level
   use ffrf_input_nml_run, only: log_level_code
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_mechanism_session, only: mechanism_session_t, move_modes
   use ffrf_core_parallel, only: use_ranks
   implicit none
   private
   public :: run_mechanism_case, run_mechanism

contains

   !> Run the mechanism case `case_file` ('-': standard input): read_case, then run_mechanism.
   subroutine run_mechanism_case(case_file, options, log, error)
      !> Namelist case file
      character(len=*), intent(in) :: case_file
      !> Folders, log level, overwrite rule, restart file
      type(run_options_t), intent(in) :: options
      !> Logger (its level is set from the case unless the options fix it)
      type(logger_t), intent(inout) :: log
      type(error_t), allocatable, intent(out) :: error
      type(case_input_t) :: case
      call read_case(case_file, case, error)
      if (.not. allocated(error)) call run_mechanism(case, options, log, error)
   end subroutine run_mechanism_case

   !> Run a mechanism case read by read_case; progress goes to `log`'s unit.
   subroutine run_mechanism(case, options, log, error, modes, final_state)
      !> The case, read and checked (a case with &joint groups)
      type(case_input_t), intent(in) :: case
      !> Folders and log level
      type(run_options_t), intent(in) :: options
      !> Logger (its level is set from the case unless the options fix it)
      type(logger_t), intent(inout) :: log
      type(error_t), allocatable, intent(out) :: error
      !> The modes of every body (case order; rigid bodies: none), when built (C API)
      type(body_modes_t), allocatable, intent(out), optional :: modes(:)
      !> Time (s), crank angle (rad) and speed (rad/s) of the last state (0 when none)
      real(dp), intent(out), optional :: final_state(3)
      type(mechanism_session_t) :: session
      type(stage_times_t) :: times
      type(run_options_t) :: run_options
      character(len=:), allocatable :: echo
      integer :: k

      call set_log_level(log, options, log_level_code(case%run%log_level))
      run_options = options
      if (len(run_options%mesh_dir) == 0) run_options%mesh_dir = folder_of(case%file_name)
      echo = case_echo(case)
      call log%info('input', case%file_name // ': ' // trim(case%run%title))
      call log%info('input', 'resolved input:' // new_line('a') // echo(:len(echo) - 1))
      ! prepare records the run (lock, restart, results file, first state); the advance to t_end
      ! puts the file in place, also when the run fails
      ! MPI build: every rank computes the modes together and integrates the (small) mechanism
      ! itself; rank 0 alone records the run (the others write nothing)
      call use_ranks(options%parallel)
      if (options%parallel%is_root()) then
         call session%prepare(case, run_options%mesh_dir, log, times, error, &
            options=run_options)
      else
         call session%prepare(case, run_options%mesh_dir, log, times, error)
      end if
      if (.not. allocated(error)) call session%advance(session%end_time(), error)
      if (present(modes) .and. allocated(session%bodies)) then
         allocate (modes(size(session%bodies)))
         do k = 1, size(session%bodies)
            call move_modes(session%bodies(k)%modes, modes(k))
         end do
      end if
      if (present(final_state)) then
         final_state = 0.0_dp
         if (allocated(session%integrator%q)) final_state = [session%integrator%t, &
            session%mech%rotor_angle(session%integrator%q), &
            session%mech%rotor_speed(session%integrator%q, session%integrator%v)]
      end if
   end subroutine run_mechanism

end module ffrf_app_mechanism_run
