!> The results of a mechanism run, recorded step by step (ffrf_app_mechanism_session calls it
!> from prepare and advance when the run has an output folder): the results file
!> (ffrf_app_engine_results) with the time histories, the energy balance, the redundant
!> constraint equations, the automatic model's choice, the integrator's counters, the final
!> state, restart checkpoints, --restart, and a Gmsh animation of each flexible body's elastic
!> deformation over the last 720 deg of the crank. The driver's run (run_mechanism) and the C
!> and Fortran API's advance with an output folder both go through it, so a run advanced in
!> chunks writes the file of a run made in one go (apart from the timings).
!>
!> The file is written under a partial name (ffrf_io_results partial_name), flushed after every
!> advance, and put in place (complete, status "complete") when the run reaches t_end; a run
!> that fails, is interrupted or is closed before t_end still gets its file with every recorded
!> step, /final_state and status = what happened.
!>
!> Energy balance per step (issue 3, part 5; ffrf_mbs_energy_balance): kinetic energy T, strain
!> energy U of the modal coordinates, work of the applied loads W (trapezoidal rule on their
!> power), and the numerical dissipation D = W - (T + U - T_0 - U_0) - D_damping (D_damping: the
!> energy taken by modal damping). For the exact solution D = 0; generalized-alpha with
!> rho_inf < 1 removes energy from the high frequencies, so D grows slowly (and the trapezoidal
!> quadrature adds O(h^2)); the integrator passed to the balance gives also the scheme's own
!> dissipation D_s (/energy/scheme_dissipation, docs/theory.md 4.4).
module ffrf_app_mechanism_output
   use ffrf_core_kinds, only: dp, i8, pi
   use ffrf_core_error, only: error_t, add_context, fatal_error, FFRF_INPUT_ERROR, &
      FFRF_IO_ERROR, FFRF_INTERRUPTED
   use ffrf_core_posix, only: pending_signal, signal_name, copy_file, rename_file, remove_file, &
      check_input_file
   use ffrf_core_strings, only: to_str
   use ffrf_core_paths, only: join_path, insert_suffix
   use ffrf_core_log, only: logger_t, stage_timer_t, stage_times_t, peak_memory_mib, wall_time
   use ffrf_input_case, only: case_input_t, case_echo
   use ffrf_app_engine_results, only: engine_results_t
   use ffrf_io_hdf5, only: h5_file_t, H5_READ_ONLY
   use ffrf_io_results, only: output_lock_t, partial_name, commit_file, abandon_file, &
      check_no_overwrite
   use ffrf_io_gmsh_writer, only: write_displacement_frames_msh
   use ffrf_app_run_options, only: run_options_t
   use ffrf_app_output_paths, only: check_output_paths
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_modes_fingerprint, only: modes_fingerprint_t
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_io_modes_file, only: fingerprint_dataset, NUM_FINGERPRINT_DATASETS
   use ffrf_modes_input, only: basis_name
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_sensors, only: sensor_t, sensor_size, sensor_unit, sensor_word
   use ffrf_app_engine_crank_log, only: crank_progress, crank_summary
   use ffrf_mbs_joints, only: JOINT_REVOLUTE
   use ffrf_app_engine_pressure, only: pressure_model_t
   use ffrf_mbs_generalized_alpha, only: galpha_integrator_t
   use ffrf_mbs_energy_balance, only: energy_balance_t
   use ffrf_mbs_reaction_split, only: reaction_split_t, TOLERANCE_FACTOR
   use ffrf_mbs_energy_watch, only: energy_watch_t
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_app_mechanism_builder, only: built_body_t
   use ffrf_app_engine_auto_model, only: model_choice_t, write_model_choice
   use ffrf_model_model, only: model_t
   use ffrf_app_restart_fingerprint, only: RESTART_ENTRY_LENGTH, input_entries, model_entries, &
      first_difference, entries_hash
   implicit none
   private
   public :: mechanism_output_t

   !> Rows of a joint reaction record: force and moment on body 1, then on body 2
   integer, parameter :: REACTION_ROWS = 12

   !> The restart state read from an earlier run's results (--restart).
   type :: restart_state_t
      !> Integrator state (galpha_export_state)
      real(dp), allocatable :: reals(:)
      integer(i8), allocatable :: ints(:)
      !> Energy balance accumulators, crank-angle unwrapping reference (1)
      real(dp), allocatable :: balance(:), crank_reference(:)
      !> Recorded steps that belong to the state, coordinates of the system
      integer :: num_steps = 0, num_coordinates = 0
      !> Names and modes of the bodies of the results
      character(len=:), allocatable :: bodies(:)
      integer(i8), allocatable :: body_modes(:)
      !> Its restart fingerprint (ffrf_app_restart_fingerprint)
      character(len=:), allocatable :: fingerprint_input(:), fingerprint_model(:)
   end type restart_state_t

   !> Crank angle and modal coordinates of every step, kept for the animation.
   type :: history_t
      integer :: num_steps = 0
      real(dp), allocatable :: t(:), angle(:)
      !> Modal coordinates of all flexible bodies, stacked (sum of modes, steps)
      real(dp), allocatable :: zeta(:, :)
   end type history_t

   !> The results of a run being recorded (module header).
   type :: mechanism_output_t
      !> reserve succeeded (lock held); start succeeded (file open, steps recorded)
      logical :: reserved = .false., started = .false.
      !> Folders, overwrite rule, restart file
      type(run_options_t) :: options
      !> The case (names, labels, animation, progress interval)
      type(case_input_t), allocatable :: case
      !> Final and partial names of the results file
      character(len=:), allocatable :: results_file, temp_file
      type(output_lock_t) :: lock
      !> --restart: the earlier run's results and its restart state
      logical :: restarting = .false.
      type(h5_file_t) :: source
      type(restart_state_t) :: restart
      !> This run's restart fingerprint: input entries (reserve), model entries (start)
      character(len=RESTART_ENTRY_LENGTH), allocatable :: fingerprint_input(:), &
         fingerprint_model(:)
      type(engine_results_t) :: results
      type(energy_balance_t) :: balance
      !> The energy watch (issue 30; ffrf_mbs_energy_watch): warnings in the log and /warnings
      type(energy_watch_t) :: watch
      type(history_t) :: history
      !> Stage times of the run and its total time
      type(stage_times_t) :: times
      type(stage_timer_t) :: total
      !> Wall time of the integration (s), over every advance
      real(dp) :: integration_seconds = 0.0_dp
      !> Progress, checkpoints
      real(dp) :: start = 0.0_dp, next_progress = 0.0_dp, last_checkpoint = 0.0_dp
      real(dp) :: checkpoint_seconds = 0.0_dp, last_cost = 0.0_dp
      integer :: num_checkpoints = 0
      integer(i8) :: steps_at_checkpoint = 0_i8
      !> The state before the step that ends on t_end (its restart state)
      logical :: have_before_last = .false.
      type(galpha_integrator_t) :: before_last
      type(energy_balance_t) :: balance_before_last
      real(dp) :: reference_before_last = 0.0_dp
      integer :: rows_before_last = 0
      !> Joint reactions of a step and their min-norm flags, interleaved (REACTION_ROWS,
      !> 2 joints): column 2j-1 the reaction of joint j, 2j its /reaction_min_norm flags
      real(dp), allocatable :: reactions(:, :)
      !> Reported multipliers of near-redundant rows (issue 30), their tracker, and the reported
      !> multipliers of the current state (nc)
      type(reaction_split_t) :: split
      real(dp), allocatable :: reported(:)
      !> The sensors of the run (/sensors/<name>, every recorded step; ffrf_mbs_sensors)
      type(sensor_t), allocatable :: sensors(:)
   contains
      !> Before the run is built: lock the output, check overwrite, read --restart
      procedure :: reserve => output_reserve
      !> After the start of the integration: restart, results file, first step
      procedure :: start_recording => output_start
      !> Record the first state (after start_recording)
      procedure :: record_first => output_first_record
      !> Before a step (keeps the state before the one that ends on t_end)
      procedure :: before_step => output_before_step
      !> After a step: energy balance, record, progress line
      procedure :: after_step => output_after_step
      !> Write the restart checkpoint when it is due
      procedure :: checkpoint => output_checkpoint
      !> Flush the file (after an advance)
      procedure :: flush => output_flush
      !> Counters, final state, animations; the file in place; the lock released
      procedure :: finish => output_finish
      !> Release the lock and the restart source of a run that did not start
      procedure :: release => output_release
   end type mechanism_output_t

contains

   !> Before anything is computed: one run per output (ffrf_io_results lock), no overwrite when
   !> refused, and the restart state of --restart read.
   subroutine output_reserve(self, case, options, error)
      class(mechanism_output_t), intent(inout) :: self
      type(case_input_t), intent(in) :: case
      type(run_options_t), intent(in) :: options
      type(error_t), allocatable, intent(out) :: error
      call self%total%begin()
      self%options = options
      self%case = case
      self%results_file = join_path(options%output_dir, trim(case%run%output))
      ! no output on an input or on another output (exit 2), before anything is written
      call check_output_paths(case, options, error)
      if (allocated(error)) return
      call self%lock%acquire(self%results_file, error)
      if (allocated(error)) return
      self%reserved = .true.
      if (.not. options%overwrite) then
         call check_no_overwrite(self%results_file, error)
         if (allocated(error)) return
      end if
      self%restarting = .false.
      if (allocated(options%restart_file)) self%restarting = len(options%restart_file) > 0
      self%fingerprint_input = input_entries(case_echo(case))
      if (.not. self%restarting) return
      call read_restart(options%restart_file, self%source, self%restart, error)
      if (.not. allocated(error)) call check_same_model(options%restart_file, &
         self%fingerprint_input, self%restart%fingerprint_input, error)
   end subroutine output_reserve

   !> Release the lock and the restart source (a run that failed before or while starting).
   subroutine output_release(self)
      class(mechanism_output_t), intent(inout) :: self
      type(error_t), allocatable :: ignored
      if (.not. self%reserved) return
      call self%source%close(ignored)
      call self%lock%release()
      self%reserved = .false.
   end subroutine output_release

   !> The run is built and its integration started: apply --restart, open the results file
   !> (series, modes, redundant equations, the automatic model's choice, the earlier run's
   !> steps) and record the first state. `times` holds the stages so far.
   subroutine output_start(self, resolved, mech, bodies, integrator, choice, log, times, &
         timer, error, sensors)
      class(mechanism_output_t), intent(inout) :: self
      type(model_t), intent(in) :: resolved
      type(mechanism_t), intent(inout) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(inout) :: integrator
      type(model_choice_t), intent(in) :: choice
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(in) :: times
      !> Started at the start of the integration
      type(stage_timer_t), intent(in) :: timer
      type(error_t), allocatable, intent(out) :: error
      !> Sensors recorded every step (none when absent)
      type(sensor_t), intent(in), optional :: sensors(:)
      type(error_t), allocatable :: close_error
      character(len=:), allocatable :: echo
      self%times = times
      if (present(sensors)) then
         self%sensors = sensors
      else
         allocate (self%sensors(0))
      end if
      associate (case => self%case, options => self%options)
         self%fingerprint_model = model_fingerprint(mech, bodies, integrator)
         if (self%restarting) then
            call check_same_model(options%restart_file, self%fingerprint_model, &
               self%restart%fingerprint_model, error)
            if (.not. allocated(error)) call apply_restart(options%restart_file, self%restart, &
               mech, bodies, integrator, self%balance, error)
            if (allocated(error)) return
            ! a restart continues to a later end; say so with the option, the file and t_end
            if (integrator%t > integrator%settings%t_end + 1.0e-6_dp * integrator%settings%h) then
               call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // &
                  options%restart_file // '": its restart state is at t = ' // &
                  to_str(integrator%t, 12) // ' s, later than this case''s &integrator ' // &
                  't_end = ' // to_str(integrator%settings%t_end, 12) // ' s; a restart ' // &
                  'continues a run: give a t_end after ' // to_str(integrator%t, 12) // ' s')
               return
            end if
            call log%info('restart', options%restart_file // ': continuing from t = ' // &
               to_str(integrator%t, 8) // ' s, step ' // to_str(integrator%stats%steps) // &
               ', to t_end = ' // to_str(integrator%settings%t_end, 8) // ' s')
         end if
         call self%times%add('start of the integration', timer%seconds())
         call log_mechanism(log, mech, integrator)

         echo = case_echo(case)
         self%temp_file = partial_name(self%results_file)
         call open_results(self%results, self%temp_file, case, resolved, echo, mech, bodies, &
            integrator, self%sensors, error)
         if (.not. allocated(error)) call write_model_choice(self%results, case, choice, error)
         if (.not. allocated(error) .and. self%restarting) then
            call self%results%append_from(self%source, self%restart%num_steps, error)
            if (.not. allocated(error)) call history_from(self%source, self%restart%num_steps, &
               bodies, mech, self%history, error)
            if (.not. allocated(error)) call write_restart_origin(self%results, self%source, &
               options%restart_file, integrator%t, [self%fingerprint_input, &
               self%fingerprint_model], error)
            if (.not. allocated(error)) call self%source%close(error)
         end if
         if (allocated(error)) then
            call self%results%finish('error: ' // error%message, [character(len=1) ::], &
               [real(dp) ::], close_error)
            call abandon_file(self%temp_file)
            call add_context(error, 'results file "' // self%results_file // '"')
            return
         end if
         call log%info('output', 'results (written when complete, checkpoints in ' // &
            checkpoint_name(self%results_file) // '): ' // self%results_file)

         self%start = wall_time()
         if (.not. allocated(self%history%t)) allocate (self%history%t(1024), &
            self%history%angle(1024), self%history%zeta(sum(bodies%num_modes), 1024))
         allocate (self%reactions(REACTION_ROWS, 2 * size(mech%joints)))
         call split_reactions(self, mech, bodies, integrator, log, error)
         if (allocated(error)) return
         self%next_progress = integrator%t + case%mechanism%mechanism%progress_interval
         self%started = .true.
         if (.not. self%restarting) then
            call self%balance%init(mech, integrator%t, integrator%q, integrator%v, error, &
               lambda=integrator%lambda, scheme=integrator)
            if (allocated(error)) return
         end if
         call start_watch(self, resolved, mech, integrator, error)
         if (allocated(error)) return
      end associate
      self%last_checkpoint = wall_time()
      self%steps_at_checkpoint = integrator%stats%steps
      self%have_before_last = .false.
      self%rows_before_last = 0
      self%reference_before_last = 0.0_dp
      self%checkpoint_seconds = 0.0_dp
      self%last_cost = 0.0_dp
      self%num_checkpoints = 0
   end subroutine output_start

   !> Record the first state (not when restarting: the results hold it). Separate from start so
   !> that a failure here still closes the file through finish.
   subroutine output_first_record(self, mech, bodies, integrator, pressure, has_pressure, error)
      class(mechanism_output_t), intent(inout) :: self
      type(mechanism_t), intent(in) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(in) :: integrator
      type(pressure_model_t), intent(in) :: pressure
      logical, intent(in) :: has_pressure
      type(error_t), allocatable, intent(out) :: error
      if (.not. self%restarting) call record_step(self, mech, bodies, integrator, pressure, &
         has_pressure, error)
   end subroutine output_first_record

   !> Before a step: when it is the step galpha_step shortens to end on t_end, keep the state
   !> before it (its restart state: a restart to a later t_end then takes the same steps as a
   !> run straight to it).
   subroutine output_before_step(self, mech, integrator, t_end)
      class(mechanism_output_t), intent(inout) :: self
      type(mechanism_t), intent(in) :: mech
      type(galpha_integrator_t), intent(in) :: integrator
      !> The case's t_end (s)
      real(dp), intent(in) :: t_end
      if (t_end - integrator%t <= integrator%h * (1.0_dp + 1.0e-6_dp)) then
         self%before_last = integrator
         self%balance_before_last = self%balance
         self%reference_before_last = mech%rotor_reference
         self%rows_before_last = self%results%num_steps()
         self%have_before_last = .true.
      end if
   end subroutine output_before_step

   !> After a step: energy balance, the step recorded (results file and animation history), a
   !> progress line every progress_interval simulated seconds and at t_end.
   subroutine output_after_step(self, mech, bodies, integrator, pressure, has_pressure, t_end, &
         log, error)
      class(mechanism_output_t), intent(inout) :: self
      type(mechanism_t), intent(inout) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(in) :: integrator
      type(pressure_model_t), intent(in) :: pressure
      logical, intent(in) :: has_pressure
      !> The case's t_end (s)
      real(dp), intent(in) :: t_end
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: wall
      call self%balance%update(mech, integrator%t, integrator%q, integrator%v, error, &
         lambda=integrator%lambda, scheme=integrator)
      if (.not. allocated(error)) call split_reactions(self, mech, bodies, integrator, log, error)
      if (.not. allocated(error)) call record_step(self, mech, bodies, integrator, pressure, &
         has_pressure, error)
      if (.not. allocated(error)) call watch_step(self, mech, integrator, log, error)
      if (allocated(error)) return
      associate (h => integrator%settings%h, interval => &
            self%case%mechanism%mechanism%progress_interval)
         if (integrator%t >= self%next_progress - 1.0e-3_dp * h .or. &
            integrator%t >= t_end - 1.0e-6_dp * h) then
            wall = wall_time() - self%start
            call log%info('run', 't = ' // to_str(integrator%t, 5) // ' s, ' // &
               to_str(integrator%stats%steps) // ' steps (' // &
               to_str(integrator%stats%rejected_steps) // ' rejected), ' // &
               to_str(integrator%stats%newton_iterations) // ' Newton iterations' // &
               crank_progress(mech, integrator%q, integrator%v) // ', wall ' // &
               to_str(wall, 4) // ' s (' // to_str(integrator%t / max(wall, 1.0e-9_dp), 3) // &
               ' x real time)')
            do while (self%next_progress <= integrator%t + 1.0e-3_dp * h)
               self%next_progress = self%next_progress + interval
            end do
         end if
      end associate
   end subroutine output_after_step

   !> Write the restart checkpoint (write_checkpoint_file) after checkpoint_steps steps or
   !> checkpoint_seconds of wall time (at least 20 times the cost of the last checkpoint: a
   !> checkpoint copies the whole file, so checkpoints never take more than 5 % of the run).
   subroutine output_checkpoint(self, mech, bodies, integrator, error)
      class(mechanism_output_t), intent(inout) :: self
      type(mechanism_t), intent(in) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(in) :: integrator
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: checkpoint_start
      logical :: due
      associate (s => integrator%settings)
         due = .false.
         if (s%checkpoint_steps > 0) due = integrator%stats%steps - self%steps_at_checkpoint &
            >= s%checkpoint_steps
         if (s%checkpoint_seconds > 0.0_dp) due = due .or. wall_time() - &
            self%last_checkpoint >= max(s%checkpoint_seconds, 20.0_dp * self%last_cost)
      end associate
      if (.not. due) return
      checkpoint_start = wall_time()
      call write_restart_state(self%results, integrator, self%balance, &
         self%results%num_steps(), mech%rotor_reference, mech, bodies, self%fingerprint_input, &
         self%fingerprint_model, error)
      if (.not. allocated(error)) call write_checkpoint_file(self%results_file, error)
      if (allocated(error)) return
      self%last_checkpoint = wall_time()
      self%steps_at_checkpoint = integrator%stats%steps
      self%num_checkpoints = self%num_checkpoints + 1
      self%last_cost = self%last_checkpoint - checkpoint_start
      self%checkpoint_seconds = self%checkpoint_seconds + self%last_cost
   end subroutine output_checkpoint

   !> Flush the results file (consistent on disk under its partial name).
   subroutine output_flush(self, error)
      class(mechanism_output_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
      call self%results%flush(error)
   end subroutine output_flush

   !> End the recording, whatever happened (run_error: the failure or interruption of the
   !> run, if any; `stopped`: the status of a run ended before t_end without an error): the
   !> restart state, the integrator's counters and last converged state, the animations (not
   !> after a signal: the job must end soon; the continued run writes them), the stage times;
   !> then the file goes into place when it could be closed, the checkpoint is removed and the
   !> lock released. `error` is run_error, else the error of writing.
   subroutine output_finish(self, mech, bodies, integrator, log, run_error, error, stopped)
      class(mechanism_output_t), intent(inout) :: self
      type(mechanism_t), intent(in) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(in) :: integrator
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(inout) :: run_error
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: stopped
      type(error_t), allocatable :: state_error, close_error
      type(stage_timer_t) :: timer
      character(len=:), allocatable :: status
      logical :: closed
      if (.not. self%started) then
         call self%release()
         if (allocated(run_error)) call move_alloc(run_error, error)
         return
      end if
      self%started = .false.
      associate (case => self%case, results => self%results, results_file => self%results_file)
         ! The restart state of the results file
         if (self%have_before_last .and. integrator%t == integrator%settings%t_end) then
            call write_restart_state(results, self%before_last, self%balance_before_last, &
               self%rows_before_last, self%reference_before_last, mech, bodies, &
               self%fingerprint_input, self%fingerprint_model, state_error)
         else
            call write_restart_state(results, integrator, self%balance, results%num_steps(), &
               mech%rotor_reference, mech, bodies, self%fingerprint_input, &
               self%fingerprint_model, state_error)
         end if
         if (self%num_checkpoints > 0) call log%info('run', to_str(self%num_checkpoints) // &
            ' restart checkpoint(s) written to ' // checkpoint_name(results_file) // ' in ' // &
            to_str(self%checkpoint_seconds, 3) // ' s (' // to_str(100.0_dp * &
            self%checkpoint_seconds / max(self%integration_seconds, 1.0e-9_dp), 2) // &
            ' % of the integration)')
         call self%times%add('integration', self%integration_seconds)
         call log_statistics(log, integrator, mech)

         if (.not. allocated(run_error) .and. allocated(state_error)) &
            call move_alloc(state_error, run_error)
         call timer%begin()
         call write_run_information(results, mech, integrator, error)
         if (.not. allocated(error)) call write_warnings(results, self%watch, log, error)
         if (.not. allocated(error) .and. case%mechanism%mechanism%animation_frames > 0 .and. &
            .not. interrupted(run_error)) call write_animations(case, self%options, bodies, &
            self%history, log, error)
         call self%times%add('output', timer%seconds())
         call self%times%add('total', self%total%seconds())
         ! A failed, interrupted or stopped run: its file goes into place when it could be closed
         if (allocated(run_error) .or. allocated(error) .or. present(stopped)) then
            if (allocated(run_error)) then
               if (run_error%code /= FFRF_INTERRUPTED) then
                  if (run_error%code == FFRF_IO_ERROR) call add_context(run_error, &
                     'results file "' // results_file // '"')
                  call add_context(run_error, case%file_name)
                  status = 'error: ' // run_error%message
               else
                  status = 'interrupted: ' // signal_name(pending_signal())
               end if
               if (allocated(error)) status = 'error: ' // error%message
               call move_alloc(run_error, error)
            else if (allocated(error)) then
               status = 'error: ' // error%message
            else
               status = stopped
            end if
            call results%finish(status, self%times%names, self%times%seconds, close_error, &
               self%times%peak_mib, closed)
            if (closed) then
               call commit_file(self%temp_file, results_file, close_error)
            else
               call abandon_file(self%temp_file)
            end if
            if (.not. allocated(close_error)) call remove_checkpoint(results_file)
            call self%release()
            return
         end if
         call results%finish('complete', self%times%names, self%times%seconds, error, &
            self%times%peak_mib)
         if (.not. allocated(error)) call commit_file(self%temp_file, results_file, error)
         if (allocated(error)) then
            call abandon_file(self%temp_file)
            call add_context(error, 'results file "' // results_file // '"')
            call self%release()
            return
         end if
         call remove_checkpoint(results_file)
         call log%info('output', 'results written: ' // results_file)
         call log%info('done', case%name // ': ' // to_str(self%total%seconds(), 3) // ' s, ' &
            // 'peak memory ' // to_str(peak_memory_mib(), 4) // ' MiB')
      end associate
      call self%release()
   end subroutine output_finish

   !> Record the current state (results file and animation history).
   subroutine record_step(self, mech, bodies, integrator, pressure, has_pressure, error)
      class(mechanism_output_t), intent(inout) :: self
      type(mechanism_t), intent(in) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(in) :: integrator
      type(pressure_model_t), intent(in) :: pressure
      logical, intent(in) :: has_pressure
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: angle, speed, p, force(3, 2), moment(3, 2)
      real(dp), allocatable :: coordinates(:), sensor_values(:), values(:)
      integer :: j, k, first, n
      angle = mech%rotor_angle(integrator%q)
      speed = mech%rotor_speed(integrator%q, integrator%v)
      p = 0.0_dp
      if (has_pressure) p = pressure%pressure(angle)
      do j = 1, size(mech%joints)
         call mech%reaction(j, integrator%q, self%reported, force, moment)
         self%reactions(:, 2 * j - 1) = [force(:, 1), moment(:, 1), force(:, 2), moment(:, 2)]
         self%reactions(:, 2 * j) = min_norm_flags(mech, j, integrator%q, self%split%min_norm)
      end do
      coordinates = [real(dp) ::]
      do k = 1, size(bodies)
         associate (b => mech%bodies(bodies(k)%index))
            coordinates = [coordinates, integrator%q(b%offset + 1:b%offset + 7 + &
               bodies(k)%num_modes)]
         end associate
      end do
      sensor_values = [real(dp) ::]
      do k = 1, size(self%sensors)
         call self%sensors(k)%evaluate(mech, integrator%q, integrator%v, integrator%qdd, &
            self%reported, values, error)
         if (allocated(error)) return
         sensor_values = [sensor_values, values]
      end do
      associate (balance => self%balance, history => self%history)
         call self%results%record(integrator%t, angle, speed, p, [balance%kinetic, &
            balance%strain, balance%work, balance%numerical_dissipation], coordinates, &
            self%reactions, error, scheme_dissipation=balance%scheme_dissipation, &
            damping_dissipation=balance%physical_dissipation, sensors=sensor_values)
         if (allocated(error)) return
         ! Animation history
         n = history%num_steps + 1
         if (n > size(history%t)) call grow(history)
         history%t(n) = integrator%t
         history%angle(n) = angle
         first = 0
         do k = 1, size(bodies)
            if (bodies(k)%num_modes == 0) cycle
            associate (b => mech%bodies(bodies(k)%index))
               history%zeta(first + 1:first + bodies(k)%num_modes, n) = &
                  integrator%q(b%offset + 8:b%offset + 7 + bodies(k)%num_modes)
            end associate
            first = first + bodies(k)%num_modes
         end do
         history%num_steps = n
      end associate
   end subroutine record_step

   !> True when `error` is the end of a run by a signal.
   pure logical function interrupted(error)
      type(error_t), allocatable, intent(in) :: error
      interrupted = .false.
      if (allocated(error)) interrupted = error%code == FFRF_INTERRUPTED
   end function interrupted

   !> The reported multipliers of the current state (self%reported, issue 30): the integrator's,
   !> except on near-redundant rows of the kept constraint Jacobian, whose split is the
   !> minimum-norm one (ffrf_mbs_reaction_split). Logs each row the first time it is so.
   subroutine split_reactions(self, mech, bodies, integrator, log, error)
      class(mechanism_output_t), intent(inout) :: self
      type(mechanism_t), intent(inout) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(in) :: integrator
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: Phi_q(:, :)
      logical, allocatable :: before(:), modal(:)
      logical :: newly
      integer :: k
      if (.not. allocated(self%reported)) then
         allocate (self%reported(size(integrator%lambda)))
         self%split%sigma_rtol = min(0.5_dp, TOLERANCE_FACTOR * &
            self%case%mechanism%model%force_tolerance)
      end if
      if (.not. self%split%near .and. mod(integrator%stats%steps, &
         int(self%split%check_interval, i8)) /= 0_i8 .and. allocated(self%split%min_norm)) then
         self%reported = integrator%lambda
         return
      end if
      allocate (Phi_q(size(integrator%lambda), size(integrator%q)))
      call mech%constraint_jacobian(integrator%q, integrator%t, Phi_q, error)
      if (allocated(error)) return
      before = [logical ::]
      if (allocated(self%split%ever)) before = self%split%ever
      allocate (modal(size(integrator%q)))
      modal = .false.
      do k = 1, size(bodies)
         associate (b => mech%bodies(bodies(k)%index))
            modal(b%offset + 8:b%offset + 7 + bodies(k)%num_modes) = .true.
         end associate
      end do
      call self%split%update(integrator%t, Phi_q, integrator%active, integrator%lambda, modal, &
         self%reported, newly, error)
      if (allocated(error)) then
         call add_context(error, 't = ' // to_str(integrator%t) // ' s')
         return
      end if
      if (.not. newly) return
      if (size(before) == 0) before = [(.false., k=1, size(self%split%ever))]
      call log%note('mechanism', 'near-redundant constraint equations at t = ' // &
         to_str(integrator%t) // ' s (a self-stress of the rigid mechanism that the modes ' // &
         'resolve with participation ' // to_str(self%split%sigma_ratio, 3) // ', at most ' // &
         to_str(self%split%sigma_rtol, 3) // ' = 10 x &model force_tolerance): their ' // &
         'reactions are reported by the minimum-norm rule while they stay so (/joints/' // &
         '<joint>/reaction_min_norm flags each step''s components):')
      do k = 1, size(self%split%ever)
         if (self%split%ever(k) .and. .not. before(k)) call log%note('mechanism', '  ' // &
            row_name(mech, k))
      end do
   end subroutine split_reactions

   !> 1 for each of the 12 reaction components of joint j that a min-norm row of the joint
   !> contributes to (its reaction for a unit multiplier exceeds 1e-9 of that reaction's
   !> largest component), 0 elsewhere.
   function min_norm_flags(mech, j, q, min_norm) result(flags)
      type(mechanism_t), intent(in) :: mech
      integer, intent(in) :: j
      real(dp), intent(in) :: q(:)
      logical, allocatable, intent(in) :: min_norm(:)
      real(dp) :: flags(REACTION_ROWS)
      real(dp) :: force(3, 2), moment(3, 2), unit(REACTION_ROWS)
      real(dp), allocatable :: lambda(:)
      integer :: k, row
      flags = 0.0_dp
      if (.not. allocated(min_norm)) return
      associate (joint => mech%joints(j))
         do k = 1, joint%joint%num_equations
            row = joint%offset + k
            if (.not. min_norm(row)) cycle
            allocate (lambda(size(min_norm)))
            lambda = 0.0_dp
            lambda(row) = 1.0_dp
            call mech%reaction(j, q, lambda, force, moment)
            deallocate (lambda)
            unit = abs([force(:, 1), moment(:, 1), force(:, 2), moment(:, 2)])
            where (unit > 1.0e-9_dp * maxval(unit)) flags = 1.0_dp
         end do
      end associate
   end function min_norm_flags

   !> Sizes and the redundant constraint equations found at the start.
   subroutine log_mechanism(log, mech, integrator)
      type(logger_t), intent(in) :: log
      type(mechanism_t), intent(in) :: mech
      type(galpha_integrator_t), intent(in) :: integrator
      integer :: k
      call log%info('mechanism', to_str(size(mech%bodies) - 1) // ' moving bodies, ' // &
         to_str(size(mech%joints)) // ' joints, ' // to_str(size(mech%loads)) // ' loads; ' // &
         to_str(mech%num_coordinates()) // ' coordinates, ' // to_str(mech%num_constraints()) // &
         ' constraint equations')
      if (size(integrator%dropped) == 0) then
         call log%info('mechanism', 'no redundant constraint equations')
         return
      end if
      call log%note('mechanism', to_str(size(integrator%dropped)) // ' redundant constraint ' // &
         'equation(s) found by rank-revealing QR and dropped (their reactions are reported ' // &
         'as zero: the split of a redundant reaction is not unique for rigid bodies):')
      do k = 1, size(integrator%dropped)
         call log%note('mechanism', '  ' // row_name(mech, integrator%dropped(k)))
      end do
   end subroutine log_mechanism

   !> "joint 'B3', equation 2 of 5" for a constraint row.
   function row_name(mech, row) result(name)
      type(mechanism_t), intent(in) :: mech
      integer, intent(in) :: row
      character(len=:), allocatable :: name
      integer :: j, b
      do j = 1, size(mech%joints)
         associate (joint => mech%joints(j))
            if (row > joint%offset .and. row <= joint%offset + joint%joint%num_equations) then
               name = 'joint ''' // joint%name // ''' (' // joint%joint%kind_name() // &
                  '), equation ' // to_str(row - joint%offset) // ' of ' // &
                  to_str(joint%joint%num_equations)
               return
            end if
         end associate
      end do
      do b = 1, size(mech%bodies)
         if (mech%bodies(b)%euler_row == row) then
            name = 'Euler-parameter normalisation of ''' // mech%bodies(b)%name // ''''
            return
         end if
      end do
      name = 'driving constraint (row ' // to_str(row) // ')'
   end function row_name

   !> Create the results file with its series and the redundant-equation flags.
   subroutine open_results(results, results_file, case, resolved, echo, mech, bodies, &
         integrator, sensors, error)
      type(engine_results_t), intent(inout) :: results
      character(len=*), intent(in) :: results_file, echo
      type(case_input_t), intent(in) :: case
      !> The case resolved (the crank's MPC label)
      type(model_t), intent(in) :: resolved
      type(mechanism_t), intent(in) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(in) :: integrator
      type(sensor_t), intent(in) :: sensors(:)
      type(error_t), allocatable, intent(out) :: error
      integer, allocatable :: flags(:)
      integer :: k, j
      call results%create(results_file, case%name, trim(case%run%title), &
         trim(case%mechanism%mechanism%label), resolved%crank_mpc(), echo, error, &
         has_crank=mech%rotor > 0)
      call add_sensor_series(results, mech, sensors, error)
      do k = 1, size(bodies)
         if (allocated(error)) exit
         call results%add_body_series(mech%bodies(bodies(k)%index)%name, bodies(k)%num_modes, &
            error)
         if (allocated(error) .or. bodies(k)%num_modes == 0) cycle
         call write_body_modes(results, mech%bodies(bodies(k)%index)%name, bodies(k)%modes, error)
      end do
      do j = 1, size(mech%joints)
         if (allocated(error)) exit
         call results%add_joint_series(mech%joints(j)%name, error)
         if (.not. allocated(error)) call results%add_joint_series(mech%joints(j)%name, error, &
            series='reaction_min_norm', units='1')
         if (allocated(error)) exit
         associate (joint => mech%joints(j))
            flags = [(merge(1, 0, any(integrator%dropped == joint%offset + k)), &
               k=1, joint%joint%num_equations)]
            call results%write_int('/joints/' // joint%name // '/redundant_equations', flags, &
               error)
         end associate
      end do
      if (allocated(error)) call add_context(error, 'results file "' // results_file // '"')
   end subroutine open_results

   !> A series /sensors/<name> per sensor, with its type and what it measures as attributes.
   subroutine add_sensor_series(results, mech, sensors, error)
      type(engine_results_t), intent(inout) :: results
      type(mechanism_t), intent(in) :: mech
      type(sensor_t), intent(in) :: sensors(:)
      type(error_t), allocatable, intent(inout) :: error
      character(len=:), allocatable :: body, marker, joint
      integer :: k, joint_kind
      do k = 1, size(sensors)
         if (allocated(error)) return
         associate (x => sensors(k))
            body = ''
            marker = ''
            joint = ''
            joint_kind = 0
            if (x%body > 0) body = mech%bodies(x%body)%name
            if (x%marker > 0) marker = trim(x%marker_name)
            if (x%joint > 0) then
               joint = mech%joints(x%joint)%name
               if (mech%joints(x%joint)%joint%kind_name() == 'revolute') &
                  joint_kind = JOINT_REVOLUTE
            end if
            if (x%node > 0) then
               call results%add_sensor_series(trim(x%name), sensor_size(x%kind), &
                  sensor_unit(x%kind, joint_kind), sensor_word(x%kind), body, marker, joint, &
                  error, node=x%node)
            else
               call results%add_sensor_series(trim(x%name), sensor_size(x%kind), &
                  sensor_unit(x%kind, joint_kind), sensor_word(x%kind), body, marker, joint, &
                  error)
            end if
         end associate
      end do
   end subroutine add_sensor_series

   !> The modal data of a flexible body for reading its modal coordinates back (frequencies,
   !> virtual-node rows, basis, interfaces), engine_results_write_modes.
   subroutine write_body_modes(results, name, modes, error)
      type(engine_results_t), intent(inout) :: results
      character(len=*), intent(in) :: name
      type(body_modes_t), intent(in) :: modes
      type(error_t), allocatable, intent(out) :: error
      character(len=64), allocatable :: names(:)
      real(dp), allocatable :: xyz(:, :)
      integer :: i
      allocate (names(size(modes%interfaces)), xyz(3, size(modes%interfaces)))
      do i = 1, size(modes%interfaces)
         names(i) = modes%interfaces(i)%name
         xyz(:, i) = modes%interfaces(i)%virtual_xyz
      end do
      call results%write_modes(name, modes%frequency_hz, modes%virtual_node_shape, names, xyz, &
         basis_name(modes%basis), int(modes%num_static), error)
      if (.not. allocated(error)) call write_reusable_modes(results, name, modes, error)
   end subroutine write_body_modes

   !> The mode shapes and their fingerprint (ffrf_io_modes_file), so that a later run can take
   !> this body's modes from the file (&body modes_file) instead of computing them.
   subroutine write_reusable_modes(results, name, modes, error)
      type(engine_results_t), intent(inout) :: results
      character(len=*), intent(in) :: name
      type(body_modes_t), intent(in) :: modes
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: dataset
      character(len=:), allocatable :: values(:)
      integer :: k
      if (.not. modes%fingerprint%is_set()) return
      call results%write_matrix('/bodies/' // name // '/modes/shape', modes%shape, 'm kg^-1/2', &
         error)
      do k = 1, NUM_FINGERPRINT_DATASETS
         if (allocated(error)) return
         call fingerprint_dataset(modes%fingerprint, k, dataset, values)
         call results%write_strings('/bodies/' // name // '/modes/fingerprint/' // dataset, &
            values, error)
      end do
   end subroutine write_reusable_modes

   !> Double the history's capacity.
   subroutine grow(history)
      type(history_t), intent(inout) :: history
      real(dp), allocatable :: t(:), angle(:), zeta(:, :)
      integer :: n
      n = size(history%t)
      allocate (t(2 * n), angle(2 * n), zeta(size(history%zeta, 1), 2 * n))
      t(:n) = history%t
      angle(:n) = history%angle
      zeta(:, :n) = history%zeta
      call move_alloc(t, history%t)
      call move_alloc(angle, history%angle)
      call move_alloc(zeta, history%zeta)
   end subroutine grow

   subroutine log_statistics(log, integrator, mech)
      type(logger_t), intent(in) :: log
      type(galpha_integrator_t), intent(in) :: integrator
      type(mechanism_t), intent(in) :: mech
      character(len=:), allocatable :: summary
      associate (s => integrator%stats)
         call log%info('run', to_str(s%steps) // ' steps, ' // to_str(s%rejected_steps) // &
            ' rejected, ' // to_str(s%newton_iterations) // ' Newton iterations, ' // &
            to_str(s%factorizations) // ' Jacobian factorisations (' // to_str(s%tangents) // &
            ' with new tangents), smallest step ' // &
            to_str(s%h_min, 3) // ' s, ' // to_str(s%wall_seconds, 4) // ' s (' // &
            to_str(1.0e3_dp * s%wall_seconds / real(max(s%steps, 1_i8), dp), 3) // &
            ' ms/step), largest constraint violation ' // to_str(s%max_constraint_violation, 3))
         call log%info('run', 'integration time: residuals ' // to_str(s%residual_seconds, 3) &
            // ' s (' // to_str(s%residual_evaluations) // '), tangents ' // &
            to_str(s%tangent_seconds, 3) // ' s, factorisations ' // &
            to_str(s%factor_seconds, 3) // ' s, solves ' // to_str(s%solve_seconds, 3) // &
            ' s, other (predictor, output hook) ' // to_str(s%wall_seconds - &
            s%residual_seconds - s%tangent_seconds - s%factor_seconds - s%solve_seconds, 3) // &
            ' s')
         if (s%sparse_factorizations > 0) then
            call log%info('run', 'iteration matrix: order ' // to_str(s%matrix_order) // &
               ', sparse LU (MUMPS, ' // to_str(s%sparse_analyses) // ' analyses, ' // &
               to_str(s%sparse_factorizations) // ' factorisations, ' // &
               to_str(s%sparse_entries) // ' entries, ' // to_str(s%sparse_factor_entries) // &
               ' in the factors, ' // to_str(s%sparse_mumps_seconds, 3) // ' s in MUMPS)')
         else
            call log%info('run', 'iteration matrix: order ' // to_str(s%matrix_order) // &
               ', dense LU (LAPACK)')
         end if
         ! the engine's summary (ffrf_app_engine_crank_log); a mechanism without a crank has none
         summary = crank_summary(mech, integrator%q, integrator%v)
         if (len(summary) > 0) call log%info('run', summary)
      end associate
   end subroutine log_statistics

   !> Integrator counters and the last converged state (also after a failure).
   subroutine write_run_information(results, mech, integrator, error)
      type(engine_results_t), intent(inout) :: results
      type(mechanism_t), intent(in) :: mech
      type(galpha_integrator_t), intent(in) :: integrator
      type(error_t), allocatable, intent(out) :: error
      associate (s => integrator%stats)
         call results%write_real('/integrator/counters', real([s%steps, s%rejected_steps, &
            s%newton_iterations, s%factorizations, s%residual_evaluations], dp), '1', error)
         if (.not. allocated(error)) call results%write_real('/integrator/wall_seconds', &
            [s%wall_seconds], 's', error)
         if (.not. allocated(error)) call results%write_real( &
            '/integrator/max_constraint_violation', [s%max_constraint_violation], 'm', error)
         if (.not. allocated(error)) call results%write_int('/integrator/dropped_rows', &
            integrator%dropped, error)
      end associate
      if (.not. allocated(error)) call results%write_real('/final_state/t', [integrator%t], 's', &
         error)
      if (.not. allocated(error)) call results%write_real('/final_state/q', integrator%q, '1', &
         error)
      if (.not. allocated(error)) call results%write_real('/final_state/v', integrator%v, '1', &
         error)
      if (.not. allocated(error)) call results%write_real('/final_state/lambda', &
         integrator%lambda, '1', error)
      if (.not. allocated(error) .and. mech%rotor > 0) call results%write_real( &
         '/final_state/crank_angle', [mech%rotor_angle(integrator%q)], 'rad', error)
   end subroutine write_run_information

   !> For each flexible body, <results stem>_<body>_animation.msh: its elastic displacement
   !> Psi zeta (body frame) at animation_frames instants evenly spread over the last 720 deg of
   !> crank rotation (the whole run if it turned less), each the recorded step nearest in angle;
   !> without a crank, evenly in time over the whole run.
   subroutine write_animations(case, options, bodies, history, log, error)
      type(case_input_t), intent(in) :: case
      type(run_options_t), intent(in) :: options
      type(built_body_t), intent(in) :: bodies(:)
      type(history_t), intent(in) :: history
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      integer :: frames, f, k, first, n, s
      integer, allocatable :: steps(:)
      real(dp) :: angle_end, angle_start, target
      real(dp), allocatable :: fields(:, :), x(:)
      character(len=:), allocatable :: file_name, span
      n = history%num_steps
      if (n < 2 .or. .not. any(bodies%num_modes > 0)) return
      frames = case%mechanism%mechanism%animation_frames
      if (history%angle(n) /= history%angle(1)) then
         ! an engine: the last 720 deg of its crank
         x = history%angle(:n)
         angle_end = x(n)
         angle_start = max(x(1), angle_end - 4.0_dp * pi)
         span = 'the last cycle'
      else
         ! a mechanism without a crank (no angle): evenly in time over the whole run
         x = history%t(:n)
         angle_end = x(n)
         angle_start = x(1)
         span = 'the run'
      end if
      allocate (steps(frames))
      s = 1
      do f = 1, frames
         target = angle_start + (angle_end - angle_start) * real(f - 1, dp) / real(max(frames - &
            1, 1), dp)
         do while (s < n)
            if (abs(x(s + 1) - target) > abs(x(s) - target)) exit
            s = s + 1
         end do
         steps(f) = s
      end do
      first = 0
      do k = 1, size(bodies)
         if (bodies(k)%num_modes == 0) cycle
         associate (modes => bodies(k)%modes, m => bodies(k)%num_modes)
            fields = matmul(modes%shape, history%zeta(first + 1:first + m, steps))
            file_name = insert_suffix(join_path(options%output_dir, trim(case%run%output)), &
               '_' // modes%name // '_animation')
            file_name = file_name(:index(file_name, '.', back=.true.)) // 'msh'
            call write_displacement_frames_msh(file_name, modes%mesh%xyz, modes%mesh%tets, &
               fields, history%t(steps), error)
            if (allocated(error)) return
            call log%info('output', modes%name // ': elastic deformation over ' // span // &
               ' for gmsh: ' // file_name)
            first = first + m
         end associate
      end do
   end subroutine write_animations

   ! ------------------------------------------------------------------ restart

   !> `<results file>.checkpoint`: the copy of the results file at the last checkpoint.
   pure function checkpoint_name(results_file) result(name)
      character(len=*), intent(in) :: results_file
      character(len=:), allocatable :: name
      name = results_file // '.checkpoint'
   end function checkpoint_name

   !> Remove the checkpoint of a run whose results file is in place (it holds the same state).
   subroutine remove_checkpoint(results_file)
      character(len=*), intent(in) :: results_file
      type(error_t), allocatable :: ignored
      call remove_file(checkpoint_name(results_file), ignored)
   end subroutine remove_checkpoint

   !> The restart state in the results file being written (/checkpoint): the integrator's
   !> whole state (galpha_export_state), the energy balance, the mechanism's crank-angle
   !> unwrapping reference (the pressure cycle follows the unwrapped angle), the number of
   !> recorded steps that belong to it and what identifies the system (coordinates, bodies,
   !> modes) and its restart fingerprint (ffrf_app_restart_fingerprint); then the file is
   !> flushed, so that it is consistent on disk.
   subroutine write_restart_state(results, integrator, balance, num_steps, crank_reference, &
         mech, bodies, fingerprint_input, fingerprint_model, error)
      type(engine_results_t), intent(inout) :: results
      type(galpha_integrator_t), intent(in) :: integrator
      type(energy_balance_t), intent(in) :: balance
      !> Recorded steps (rows of the series) up to this state
      integer, intent(in) :: num_steps
      !> mechanism_t%rotor_reference at this state (rad)
      real(dp), intent(in) :: crank_reference
      type(mechanism_t), intent(in) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      character(len=*), intent(in) :: fingerprint_input(:), fingerprint_model(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: reals(:)
      integer(i8), allocatable :: ints(:)
      character(len=64), allocatable :: names(:)
      integer :: k
      call results%flush(error)
      if (allocated(error)) return
      call integrator%export_state(reals, ints)
      allocate (names(size(bodies)))
      do k = 1, size(bodies)
         names(k) = mech%bodies(bodies(k)%index)%name
      end do
      call results%write_real('/checkpoint/integrator_reals', reals, '1', error)
      if (.not. allocated(error)) call results%write_long('/checkpoint/integrator_ints', ints, &
         error)
      if (.not. allocated(error)) call results%write_real('/checkpoint/energy_balance', &
         balance%export_state(), '1', error)
      ! the crank angle's unwrapping reference: an engine (a mechanism with a crank) only
      if (.not. allocated(error) .and. mech%rotor > 0) call results%write_real( &
         '/checkpoint/crank_reference', [crank_reference], 'rad', error)
      if (.not. allocated(error)) call results%write_long('/checkpoint/num_steps', &
         [int(num_steps, i8)], error)
      if (.not. allocated(error)) call results%write_long('/checkpoint/num_coordinates', &
         [int(mech%num_coordinates(), i8)], error)
      if (.not. allocated(error)) call results%write_strings('/checkpoint/bodies', names, error)
      if (.not. allocated(error)) call results%write_long('/checkpoint/body_modes', &
         int(bodies%num_modes, i8), error)
      if (.not. allocated(error)) call results%write_strings('/checkpoint/fingerprint_input', &
         fingerprint_input, error)
      if (.not. allocated(error)) call results%write_strings('/checkpoint/fingerprint_model', &
         fingerprint_model, error)
      if (.not. allocated(error)) call results%flush(error)
   end subroutine write_restart_state

   !> Copy the results file being written (consistent after write_restart_state) to
   !> `<results file>.checkpoint`: through a temporary name, forced to the device, renamed, so
   !> that a kill -9 at any moment leaves the previous or the new checkpoint, whole.
   subroutine write_checkpoint_file(results_file, error)
      character(len=*), intent(in) :: results_file
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: ignored
      character(len=:), allocatable :: checkpoint
      checkpoint = checkpoint_name(results_file)
      call copy_file(partial_name(results_file), partial_name(checkpoint), error)
      if (.not. allocated(error)) call rename_file(partial_name(checkpoint), checkpoint, error)
      if (allocated(error)) then
         call remove_file(partial_name(checkpoint), ignored)
         call add_context(error, 'checkpoint "' // checkpoint // '"')
      end if
   end subroutine write_checkpoint_file

   !> Open the results or checkpoint file of an earlier run (--restart) and read its restart
   !> state: FFRF_IO_ERROR when it cannot be read, FFRF_INPUT_ERROR when it holds none.
   subroutine read_restart(file_name, source, restart, error)
      character(len=*), intent(in) :: file_name
      type(h5_file_t), intent(inout) :: source
      type(restart_state_t), intent(out) :: restart
      type(error_t), allocatable, intent(out) :: error
      integer(i8), allocatable :: counts(:)
      ! a regular file: HDF5 would block on a FIFO (exit 3 naming the option otherwise)
      call check_input_file(file_name, '--restart file', huge(1_i8), error)
      if (allocated(error)) return
      call source%open(file_name, H5_READ_ONLY, error)
      if (allocated(error)) then
         call add_context(error, '--restart')
         return
      end if
      if (.not. source%exists('/checkpoint/integrator_ints')) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // '": no ' // &
            'restart state (/checkpoint) in it; give the results file (.h5) or the ' // &
            '.checkpoint file of an earlier run of this mechanism case')
         return
      end if
      call source%read_real('/checkpoint/integrator_reals', restart%reals, error)
      if (.not. allocated(error)) call source%read_int('/checkpoint/integrator_ints', &
         restart%ints, error)
      if (.not. allocated(error)) call source%read_real('/checkpoint/energy_balance', &
         restart%balance, error)
      if (.not. allocated(error)) then
         if (source%exists('/checkpoint/crank_reference')) then
            call source%read_real('/checkpoint/crank_reference', restart%crank_reference, error)
         else
            ! a run without a crank writes none: the unwrapping reference stays 0
            restart%crank_reference = [0.0_dp]
         end if
      end if
      if (.not. allocated(error)) call source%read_int('/checkpoint/num_steps', counts, error)
      if (.not. allocated(error)) restart%num_steps = int(counts(1))
      if (.not. allocated(error)) call source%read_int('/checkpoint/num_coordinates', counts, &
         error)
      if (.not. allocated(error)) restart%num_coordinates = int(counts(1))
      if (.not. allocated(error)) call source%read_string_list('/checkpoint/bodies', &
         restart%bodies, error)
      if (.not. allocated(error)) call source%read_int('/checkpoint/body_modes', &
         restart%body_modes, error)
      if (allocated(error)) then
         error%code = FFRF_INPUT_ERROR
         call add_context(error, '--restart "' // file_name // '": unreadable restart state')
         return
      end if
      if (.not. source%exists('/checkpoint/fingerprint_model')) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // '": its ' // &
            'restart state has no restart fingerprint (/checkpoint/fingerprint_input, ' // &
            '/checkpoint/fingerprint_model: written by ffrf since issue 23), so ffrf cannot ' // &
            'check that it is a run of this model; run the case from t = 0')
         return
      end if
      call source%read_string_list('/checkpoint/fingerprint_input', restart%fingerprint_input, &
         error)
      if (.not. allocated(error)) call source%read_string_list('/checkpoint/fingerprint_model', &
         restart%fingerprint_model, error)
      if (allocated(error)) then
         error%code = FFRF_INPUT_ERROR
         call add_context(error, '--restart "' // file_name // '": unreadable restart state')
      end if
   end subroutine read_restart

   !> The restart fingerprint's model entries of this run (ffrf_app_restart_fingerprint): the
   !> modes fingerprint of every meshed body and the integrator's step and rho_inf.
   function model_fingerprint(mech, bodies, integrator) result(entries)
      type(mechanism_t), intent(in) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(in) :: integrator
      character(len=RESTART_ENTRY_LENGTH), allocatable :: entries(:)
      character(len=64), allocatable :: names(:)
      type(modes_fingerprint_t), allocatable :: fingerprints(:)
      type(mesh_t), allocatable :: meshes(:)
      integer :: k
      allocate (names(size(bodies)), fingerprints(size(bodies)), meshes(size(bodies)))
      do k = 1, size(bodies)
         names(k) = mech%bodies(bodies(k)%index)%name
         if (.not. bodies(k)%meshed) cycle
         fingerprints(k) = bodies(k)%modes%fingerprint
         meshes(k) = bodies(k)%modes%mesh
      end do
      entries = model_entries(names, fingerprints, bodies%meshed, meshes, integrator%settings%h, &
         integrator%settings%rho_inf)
   end function model_fingerprint

   !> FFRF_INPUT_ERROR naming the first difference when the restart file's fingerprint entries
   !> (`there`) differ from this run's (`here`).
   subroutine check_same_model(file_name, here, there, error)
      character(len=*), intent(in) :: file_name, here(:), there(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: difference
      difference = first_difference(here, there)
      if (len(difference) == 0) return
      call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // '": not a run ' // &
         'of this model: ' // difference // '; continue only a run of the same model (what ' // &
         'may change, e.g. t_end and the outputs: docs/restart.md)')
   end subroutine check_same_model

   !> Record in the continued file where it came from: /restart_origin/{file, time,
   !> fingerprint}, one row per restart (the source's own rows first).
   subroutine write_restart_origin(results, source, file_name, t, fingerprint, error)
      type(engine_results_t), intent(inout) :: results
      type(h5_file_t), intent(in) :: source
      character(len=*), intent(in) :: file_name, fingerprint(:)
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: files(:), hashes(:)
      real(dp), allocatable :: times(:)
      character(len=max(len(file_name), 16)), allocatable :: all_files(:)
      character(len=16), allocatable :: all_hashes(:)
      allocate (all_files(0), all_hashes(0), times(0))
      if (source%exists('/restart_origin/file')) then
         call source%read_string_list('/restart_origin/file', files, error)
         if (.not. allocated(error)) call source%read_string_list('/restart_origin/fingerprint', &
            hashes, error)
         if (.not. allocated(error)) call source%read_real('/restart_origin/time', times, error)
         if (allocated(error)) return
         all_files = [character(len=len(all_files)) :: files]
         all_hashes = [character(len=16) :: hashes]
      end if
      all_files = [character(len=len(all_files)) :: all_files, file_name]
      all_hashes = [character(len=16) :: all_hashes, entries_hash(fingerprint)]
      times = [times, t]
      call results%write_strings('/restart_origin/file', all_files, error)
      if (.not. allocated(error)) call results%write_strings('/restart_origin/fingerprint', &
         all_hashes, error)
      if (.not. allocated(error)) call results%write_real('/restart_origin/time', times, 's', &
         error)
   end subroutine write_restart_origin

   !> Check that the restart state belongs to this case (coordinates, bodies, modes) and
   !> restore it into the integrator and the energy balance; FFRF_INPUT_ERROR otherwise.
   subroutine apply_restart(file_name, restart, mech, bodies, integrator, balance, error)
      character(len=*), intent(in) :: file_name
      type(restart_state_t), intent(in) :: restart
      type(mechanism_t), intent(inout) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(inout) :: integrator
      type(energy_balance_t), intent(inout) :: balance
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: here, there
      logical :: ok
      integer :: k
      here = ''
      do k = 1, size(bodies)
         here = here // ' ' // mech%bodies(bodies(k)%index)%name // '(' // &
            to_str(bodies(k)%num_modes) // ' modes)'
      end do
      there = ''
      do k = 1, size(restart%bodies)
         there = there // ' ' // trim(restart%bodies(k))
         if (k <= size(restart%body_modes)) there = there // '(' // &
            to_str(int(restart%body_modes(k))) // ' modes)'
      end do
      if (restart%num_coordinates /= mech%num_coordinates() .or. here /= there) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // '": its ' // &
            'run had ' // to_str(restart%num_coordinates) // ' coordinates and bodies' // &
            there // '; this case has ' // to_str(mech%num_coordinates()) // &
            ' coordinates and bodies' // here // '; restart only from a run of the same ' // &
            'case (t_end may differ)')
         return
      end if
      call integrator%import_state(restart%reals, restart%ints, error)
      if (allocated(error)) then
         call add_context(error, '--restart "' // file_name // '"')
         return
      end if
      call balance%import_state(restart%balance, ok)
      if (.not. ok .or. size(restart%crank_reference) /= 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, '--restart "' // file_name // &
            '": its energy balance or crank reference state has the wrong size')
         return
      end if
      mech%rotor_reference = restart%crank_reference(1)
   end subroutine apply_restart

   !> The animation history (time, crank angle, modal coordinates) of the first num_steps
   !> steps of an earlier run's results.
   subroutine history_from(source, num_steps, bodies, mech, history, error)
      type(h5_file_t), intent(in) :: source
      integer, intent(in) :: num_steps
      type(built_body_t), intent(in) :: bodies(:)
      type(mechanism_t), intent(in) :: mech
      type(history_t), intent(inout) :: history
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: t(:), angle(:), zeta(:, :)
      integer :: k, first, capacity
      capacity = max(1024, 2 * num_steps)
      allocate (history%t(capacity), history%angle(capacity), &
         history%zeta(sum(bodies%num_modes), capacity))
      call source%read_real('/time/t', t, error)
      if (allocated(error)) return
      if (mech%rotor > 0) then
         call source%read_real('/time/crank_angle', angle, error)
         if (allocated(error)) return
      else
         ! a run without a crank records no angle (write_animations then spreads over time)
         allocate (angle(size(t)), source=0.0_dp)
      end if
      history%t(:num_steps) = t(:num_steps)
      history%angle(:num_steps) = angle(:num_steps)
      first = 0
      do k = 1, size(bodies)
         if (bodies(k)%num_modes == 0) cycle
         call source%read_real('/bodies/' // mech%bodies(bodies(k)%index)%name // &
            '/modal_coordinates', zeta, error)
         if (allocated(error)) return
         history%zeta(first + 1:first + bodies(k)%num_modes, :num_steps) = zeta(:, :num_steps)
         first = first + bodies(k)%num_modes
      end do
      history%num_steps = num_steps
   end subroutine history_from

   !> Start the energy watch (ffrf_mbs_energy_watch) with the run's settings (&integrator
   !> energy_watch ...), the bodies' names and T_b + U_b at the current state.
   subroutine start_watch(self, resolved, mech, integrator, error)
      type(mechanism_output_t), intent(inout) :: self
      type(model_t), intent(in) :: resolved
      type(mechanism_t), intent(in) :: mech
      type(galpha_integrator_t), intent(in) :: integrator
      type(error_t), allocatable, intent(out) :: error
      character(len=64), allocatable :: names(:)
      logical, allocatable :: flexible(:)
      real(dp), allocatable :: kinetic(:), strain(:)
      integer :: b, n
      n = size(mech%bodies)
      allocate (names(n), flexible(n))
      do b = 1, n
         names(b) = mech%bodies(b)%name
         select type (body => mech%bodies(b)%body)
         class is (flexible_body_t)
            flexible(b) = .true.
         class default
            flexible(b) = .false.
         end select
      end do
      call body_energies(mech, integrator%q, integrator%v, kinetic, strain)
      call self%watch%init(resolved%mechanism%energy_watch, integrator%t, names, flexible, &
         kinetic + strain, error)
   end subroutine start_watch

   !> T_b and U_b of every body of the mechanism at (q, v) (J).
   subroutine body_energies(mech, q, v, kinetic, strain)
      type(mechanism_t), intent(in) :: mech
      real(dp), intent(in) :: q(:), v(:)
      real(dp), allocatable, intent(out) :: kinetic(:), strain(:)
      integer :: b, k, nb
      allocate (kinetic(size(mech%bodies)), strain(size(mech%bodies)))
      kinetic = 0.0_dp
      strain = 0.0_dp
      do b = 1, size(mech%bodies)
         k = mech%bodies(b)%offset
         nb = mech%bodies(b)%body%num_coordinates
         if (nb == 0) cycle
         kinetic(b) = mech%bodies(b)%body%kinetic_energy(q(k + 1:k + nb), v(k + 1:k + nb))
         strain(b) = mech%bodies(b)%body%strain_energy(q(k + 1:k + nb))
      end do
   end subroutine body_energies

   !> After the balance's update: the energy watch's check of the step; a new warning goes to
   !> the log (energy_watch = 'stop': the run ends with FFRF_NUMERIC_ERROR).
   subroutine watch_step(self, mech, integrator, log, error)
      type(mechanism_output_t), intent(inout) :: self
      type(mechanism_t), intent(in) :: mech
      type(galpha_integrator_t), intent(in) :: integrator
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: kinetic(:), strain(:)
      character(len=:), allocatable :: text, body
      real(dp) :: t
      logical :: new_warning
      call body_energies(mech, integrator%q, integrator%v, kinetic, strain)
      associate (b => self%balance)
         call self%watch%check(b%t, b%kinetic, b%strain, b%work, b%physical_dissipation, &
            b%numerical_dissipation, b%scheme_dissipation, b%has_scheme, kinetic, strain, &
            new_warning, error)
      end associate
      if (new_warning .and. .not. allocated(error)) then
         call self%watch%warning(self%watch%count(), text, t, body)
         call log%note('energy', 'warning: ' // text)
      end if
   end subroutine watch_step

   !> The energy watch's warnings (/warnings/{text, time, body}; none: no group) and its largest
   !> spurious-energy ratio in the log; the status stays what the run reached.
   subroutine write_warnings(results, watch, log, error)
      type(engine_results_t), intent(inout) :: results
      type(energy_watch_t), intent(in) :: watch
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: text, body
      character(len=1024), allocatable :: texts(:)
      character(len=64), allocatable :: bodies(:)
      real(dp), allocatable :: times(:)
      integer :: k, n
      if (.not. allocated(watch%names)) return
      n = watch%count()
      call log%info('energy', 'watch: largest spurious energy -D_s = ' // &
         to_str(watch%worst_ratio, 3) // ' of the energy scale (t = ' // &
         to_str(watch%worst_time, 6) // ' s; tolerance ' // &
         to_str(watch%settings%tolerance, 3) // '), ' // to_str(n) // ' warning(s)')
      if (n == 0) return
      allocate (texts(n), bodies(n), times(n))
      do k = 1, n
         call watch%warning(k, text, times(k), body)
         texts(k) = text
         bodies(k) = body
      end do
      call results%write_strings('/warnings/text', texts, error)
      if (.not. allocated(error)) call results%write_real('/warnings/time', times, 's', error)
      if (.not. allocated(error)) call results%write_strings('/warnings/body', bodies, error)
   end subroutine write_warnings

end module ffrf_app_mechanism_output
