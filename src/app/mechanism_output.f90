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
!>
!> This module holds the types and the interfaces; the bodies are in the submodules
!> mechanism_output_steps.f90 (reserve, start, each step, finish), mechanism_output_file.f90
!> (the file's content beside the series, the animations), mechanism_output_restart.f90
!> (checkpoints and --restart) and mechanism_output_watch.f90 (the energy watch).
module ffrf_app_mechanism_output
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t
   use ffrf_core_log, only: logger_t, stage_timer_t, stage_times_t
   use ffrf_input_case, only: case_input_t
   use ffrf_input_nml_output, only: output_input_t
   use ffrf_app_engine_results, only: engine_results_t
   use ffrf_io_hdf5, only: h5_file_t
   use ffrf_io_results, only: output_lock_t
   use ffrf_io_xdmf, only: xdmf_body_t
   use ffrf_app_run_options, only: run_options_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_sensors, only: sensor_t
   use ffrf_app_engine_pressure, only: pressure_model_t
   use ffrf_mbs_generalized_alpha, only: galpha_integrator_t
   use ffrf_mbs_energy_balance, only: energy_balance_t
   use ffrf_mbs_reaction_split, only: reaction_split_t
   use ffrf_mbs_energy_watch, only: energy_watch_t
   use ffrf_app_mechanism_builder, only: built_body_t
   use ffrf_app_engine_auto_model, only: model_choice_t
   use ffrf_model_model, only: model_t
   use ffrf_app_restart_fingerprint, only: RESTART_ENTRY_LENGTH
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
      !> The torsion springs' unwrapping references (one per spring; /checkpoint/torsion_reference)
      !> and whether the file has them (written since issue 24)
      real(dp), allocatable :: torsion_reference(:)
      logical :: has_torsion_reference = .false.
      !> The output interval being recorded (engine_results_t interval_state; empty: none)
      real(dp), allocatable :: interval(:)
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
      !> reserve succeeded (lock held); start succeeded (file open, steps recorded); the run
      !> refused to start (its results would not fit: no file at all)
      logical :: reserved = .false., started = .false., refused = .false.
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
      real(dp), allocatable :: torsion_before_last(:)
      integer :: rows_before_last = 0
      real(dp), allocatable :: interval_before_last(:)
      !> Output rate (&output): the next sample time of every_seconds (s)
      real(dp) :: next_sample = 0.0_dp
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

   interface

      ! --- ffrf_app_mechanism_output_steps (mechanism_output_steps.f90) --------------------------

      !> Before anything is computed: one run per output (ffrf_io_results lock), no overwrite when
      !> refused, and the restart state of --restart read.
      module subroutine output_reserve(self, case, options, error)
         class(mechanism_output_t), intent(inout) :: self
         type(case_input_t), intent(in) :: case
         type(run_options_t), intent(in) :: options
         type(error_t), allocatable, intent(out) :: error
      end subroutine output_reserve

      !> Release the lock and the restart source (a run that failed before or while starting).
      module subroutine output_release(self)
         class(mechanism_output_t), intent(inout) :: self
      end subroutine output_release

      !> The run is built and its integration started: apply --restart, open the results file
      !> (series, modes, redundant equations, the automatic model's choice, the earlier run's
      !> steps) and record the first state. `times` holds the stages so far.
      module subroutine output_start(self, resolved, mech, bodies, integrator, choice, log, times, &
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
      end subroutine output_start

      !> Record the first state (not when restarting: the results hold it). Separate from start so
      !> that a failure here still closes the file through finish.
      module subroutine output_first_record(self, mech, bodies, integrator, pressure, &
            has_pressure, error)
         class(mechanism_output_t), intent(inout) :: self
         type(mechanism_t), intent(in) :: mech
         type(built_body_t), intent(in) :: bodies(:)
         type(galpha_integrator_t), intent(in) :: integrator
         type(pressure_model_t), intent(in) :: pressure
         logical, intent(in) :: has_pressure
         type(error_t), allocatable, intent(out) :: error
      end subroutine output_first_record

      !> Before a step: when it is the step galpha_step shortens to end on t_end, keep the state
      !> before it (its restart state: a restart to a later t_end then takes the same steps as a
      !> run straight to it).
      module subroutine output_before_step(self, mech, integrator, t_end)
         class(mechanism_output_t), intent(inout) :: self
         type(mechanism_t), intent(in) :: mech
         type(galpha_integrator_t), intent(in) :: integrator
         !> The case's t_end (s)
         real(dp), intent(in) :: t_end
      end subroutine output_before_step

      !> After a step: energy balance, the step recorded (results file and animation history), a
      !> progress line every progress_interval simulated seconds and at t_end.
      module subroutine output_after_step(self, mech, bodies, integrator, pressure, &
            has_pressure, t_end, log, error)
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
      end subroutine output_after_step

      !> Write the restart checkpoint (write_checkpoint_file) after checkpoint_steps steps or
      !> checkpoint_seconds of wall time (at least 20 times the cost of the last checkpoint: a
      !> checkpoint copies the whole file, so checkpoints never take more than 5 % of the run).
      module subroutine output_checkpoint(self, mech, bodies, integrator, error)
         class(mechanism_output_t), intent(inout) :: self
         type(mechanism_t), intent(in) :: mech
         type(built_body_t), intent(in) :: bodies(:)
         type(galpha_integrator_t), intent(in) :: integrator
         type(error_t), allocatable, intent(out) :: error
      end subroutine output_checkpoint

      !> Flush the results file (consistent on disk under its partial name).
      module subroutine output_flush(self, error)
         class(mechanism_output_t), intent(inout) :: self
         type(error_t), allocatable, intent(out) :: error
      end subroutine output_flush

      !> End the recording, whatever happened (run_error: the failure or interruption of the
      !> run, if any; `stopped`: the status of a run ended before t_end without an error): the
      !> restart state, the integrator's counters and last converged state, the animations (not
      !> after a signal: the job must end soon; the continued run writes them), the stage times;
      !> then the file goes into place when it could be closed, the checkpoint is removed and the
      !> lock released. `error` is run_error, else the error of writing.
      module subroutine output_finish(self, mech, bodies, integrator, log, run_error, error, &
            stopped)
         class(mechanism_output_t), intent(inout) :: self
         type(mechanism_t), intent(in) :: mech
         type(built_body_t), intent(in) :: bodies(:)
         type(galpha_integrator_t), intent(in) :: integrator
         type(logger_t), intent(in) :: log
         type(error_t), allocatable, intent(inout) :: run_error
         type(error_t), allocatable, intent(out) :: error
         character(len=*), intent(in), optional :: stopped
      end subroutine output_finish

      !> Samples a run records from t to t_end at the step h with &output's rate (docs/results.md
      !> "Output rate, peaks, compression, size"): the first state when `first`, then every
      !> every_steps-th step or one per multiple of every_seconds, and the last state.
      module pure function predicted_samples(output, t, t_end, h, first) result(samples)
         type(output_input_t), intent(in) :: output
         real(dp), intent(in) :: t, t_end, h
         logical, intent(in) :: first
         integer(i8) :: samples
      end function predicted_samples

      ! --- ffrf_app_mechanism_output_file (mechanism_output_file.f90) ----------------------------

      !> Sizes and the redundant constraint equations found at the start.
      module subroutine log_mechanism(log, mech, integrator)
         type(logger_t), intent(in) :: log
         type(mechanism_t), intent(in) :: mech
         type(galpha_integrator_t), intent(in) :: integrator
      end subroutine log_mechanism

      !> "joint 'B3', equation 2 of 5" for a constraint row.
      module function row_name(mech, row) result(name)
         type(mechanism_t), intent(in) :: mech
         integer, intent(in) :: row
         character(len=:), allocatable :: name
      end function row_name

      !> The results file of a run that failed after its modes were computed and before its
      !> integration started (the starting pose not assembled, an inconsistent start): the input
      !> echo, the modes of every body and status "error: ..." (issue 24). Nothing when the
      !> failure came before every flexible body had its modes (a refused input while the bodies
      !> are built); a failure here is not reported over the run's error.
      module subroutine record_failed_start(self, bodies, run_error)
         class(mechanism_output_t), intent(inout) :: self
         type(built_body_t), intent(in) :: bodies(:)
         type(error_t), intent(in) :: run_error
      end subroutine record_failed_start

      !> Create the results file with its series and the redundant-equation flags.
      module subroutine open_results(results, results_file, case, resolved, echo, mech, bodies, &
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
      end subroutine open_results

      !> Double the history's capacity.
      module subroutine grow(history)
         type(history_t), intent(inout) :: history
      end subroutine grow

      module subroutine log_statistics(log, integrator, mech)
         type(logger_t), intent(in) :: log
         type(galpha_integrator_t), intent(in) :: integrator
         type(mechanism_t), intent(in) :: mech
      end subroutine log_statistics

      !> Integrator counters and the last converged state (also after a failure).
      module subroutine write_run_information(results, mech, integrator, error)
         type(engine_results_t), intent(inout) :: results
         type(mechanism_t), intent(in) :: mech
         type(galpha_integrator_t), intent(in) :: integrator
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_run_information

      !> For each flexible body, <results stem>_<body>_animation.msh: its elastic displacement
      !> Psi zeta (body frame) at animation_frames instants evenly spread over the last 720 deg of
      !> crank rotation (the whole run if it turned less), each the recorded step nearest in angle;
      !> without a crank, evenly in time over the whole run. With `xdmf` (&run export), the
      !> body's mesh and the same frames also go into the results file (ffrf_io_xdmf), each
      !> body described in `exported` for the XDMF file, in `xdmf_seconds` of wall time.
      module subroutine write_animations(case, options, bodies, history, log, results, xdmf, &
            exported, xdmf_seconds, error)
         type(case_input_t), intent(in) :: case
         type(run_options_t), intent(in) :: options
         type(built_body_t), intent(in) :: bodies(:)
         type(history_t), intent(in) :: history
         type(logger_t), intent(in) :: log
         type(engine_results_t), intent(inout) :: results
         logical, intent(in) :: xdmf
         type(xdmf_body_t), allocatable, intent(out) :: exported(:)
         real(dp), intent(out) :: xdmf_seconds
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_animations

      ! --- ffrf_app_mechanism_output_restart (mechanism_output_restart.f90) ----------------------

      !> `<results file>.checkpoint`: the copy of the results file at the last checkpoint.
      module pure function checkpoint_name(results_file) result(name)
         character(len=*), intent(in) :: results_file
         character(len=:), allocatable :: name
      end function checkpoint_name

      !> Remove the checkpoint of a run whose results file is in place (it holds the same state).
      module subroutine remove_checkpoint(results_file)
         character(len=*), intent(in) :: results_file
      end subroutine remove_checkpoint

      !> The restart state in the results file being written (/checkpoint): the integrator's
      !> whole state (galpha_export_state), the energy balance, the mechanism's crank-angle
      !> unwrapping reference (the pressure cycle follows the unwrapped angle), the torsion
      !> springs' unwrapping references (their angles count whole turns), the number of
      !> recorded steps that belong to it and what identifies the system (coordinates, bodies,
      !> modes) and its restart fingerprint (ffrf_app_restart_fingerprint); then the file is
      !> flushed, so that it is consistent on disk.
      module subroutine write_restart_state(results, integrator, balance, num_steps, &
            crank_reference, torsion_reference, mech, bodies, fingerprint_input, &
            fingerprint_model, error, interval)
         type(engine_results_t), intent(inout) :: results
         type(galpha_integrator_t), intent(in) :: integrator
         type(energy_balance_t), intent(in) :: balance
         !> Recorded steps (rows of the series) up to this state
         integer, intent(in) :: num_steps
         !> mechanism_t%rotor_reference at this state (rad)
         real(dp), intent(in) :: crank_reference
         !> torsion_spring_t%reference of every torsion spring at this state (rad)
         real(dp), intent(in) :: torsion_reference(:)
         type(mechanism_t), intent(in) :: mech
         type(built_body_t), intent(in) :: bodies(:)
         character(len=*), intent(in) :: fingerprint_input(:), fingerprint_model(:)
         type(error_t), allocatable, intent(out) :: error
         !> The output interval being recorded at this state (interval_state; none: absent)
         real(dp), intent(in), optional :: interval(:)
      end subroutine write_restart_state

      !> Copy the results file being written (consistent after write_restart_state) to
      !> `<results file>.checkpoint`: through a temporary name, forced to the device, renamed, so
      !> that a kill -9 at any moment leaves the previous or the new checkpoint, whole.
      module subroutine write_checkpoint_file(results_file, error)
         character(len=*), intent(in) :: results_file
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_checkpoint_file

      !> Open the results or checkpoint file of an earlier run (--restart) and read its restart
      !> state: FFRF_IO_ERROR when it cannot be read, FFRF_INPUT_ERROR when it holds none.
      module subroutine read_restart(file_name, source, restart, error)
         character(len=*), intent(in) :: file_name
         type(h5_file_t), intent(inout) :: source
         type(restart_state_t), intent(out) :: restart
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_restart

      !> The restart fingerprint's model entries of this run (ffrf_app_restart_fingerprint): the
      !> modes fingerprint of every meshed body and the integrator's step and rho_inf.
      module function model_fingerprint(mech, bodies, integrator) result(entries)
         type(mechanism_t), intent(in) :: mech
         type(built_body_t), intent(in) :: bodies(:)
         type(galpha_integrator_t), intent(in) :: integrator
         character(len=RESTART_ENTRY_LENGTH), allocatable :: entries(:)
      end function model_fingerprint

      !> FFRF_INPUT_ERROR naming the first difference when the restart file's fingerprint entries
      !> (`there`) differ from this run's (`here`).
      module subroutine check_same_model(file_name, here, there, error)
         character(len=*), intent(in) :: file_name, here(:), there(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_same_model

      !> Record in the continued file where it came from: /restart_origin/{file, time,
      !> fingerprint}, one row per restart (the source's own rows first).
      module subroutine write_restart_origin(results, source, file_name, t, fingerprint, error)
         type(engine_results_t), intent(inout) :: results
         type(h5_file_t), intent(in) :: source
         character(len=*), intent(in) :: file_name, fingerprint(:)
         real(dp), intent(in) :: t
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_restart_origin

      !> Check that the restart state belongs to this case (coordinates, bodies, modes) and
      !> restore it into the integrator, the energy balance and the mechanism's unwrapping
      !> references (crank, torsion springs); FFRF_INPUT_ERROR otherwise.
      module subroutine apply_restart(file_name, restart, mech, bodies, integrator, balance, error)
         character(len=*), intent(in) :: file_name
         type(restart_state_t), intent(in) :: restart
         type(mechanism_t), intent(inout) :: mech
         type(built_body_t), intent(in) :: bodies(:)
         type(galpha_integrator_t), intent(inout) :: integrator
         type(energy_balance_t), intent(inout) :: balance
         type(error_t), allocatable, intent(out) :: error
      end subroutine apply_restart

      !> The animation history (time, crank angle, modal coordinates) of the first num_steps
      !> steps of an earlier run's results.
      module subroutine history_from(source, num_steps, bodies, mech, history, error)
         type(h5_file_t), intent(in) :: source
         integer, intent(in) :: num_steps
         type(built_body_t), intent(in) :: bodies(:)
         type(mechanism_t), intent(in) :: mech
         type(history_t), intent(inout) :: history
         type(error_t), allocatable, intent(out) :: error
      end subroutine history_from

      ! --- ffrf_app_mechanism_output_watch (mechanism_output_watch.f90) --------------------------

      !> Start the energy watch (ffrf_mbs_energy_watch) with the run's settings (&integrator
      !> energy_watch ...), the bodies' names and T_b + U_b at the current state.
      module subroutine start_watch(self, resolved, mech, integrator, error)
         type(mechanism_output_t), intent(inout) :: self
         type(model_t), intent(in) :: resolved
         type(mechanism_t), intent(in) :: mech
         type(galpha_integrator_t), intent(in) :: integrator
         type(error_t), allocatable, intent(out) :: error
      end subroutine start_watch

      !> After the balance's update: the energy watch's check of the step; a new warning goes to
      !> the log (energy_watch = 'stop': the run ends with FFRF_NUMERIC_ERROR).
      module subroutine watch_step(self, mech, integrator, log, error)
         type(mechanism_output_t), intent(inout) :: self
         type(mechanism_t), intent(in) :: mech
         type(galpha_integrator_t), intent(in) :: integrator
         type(logger_t), intent(in) :: log
         type(error_t), allocatable, intent(out) :: error
      end subroutine watch_step

      !> The energy watch's warnings (/warnings/{text, time, body}; none: no group) and its largest
      !> spurious-energy ratio in the log; the status stays what the run reached.
      module subroutine write_warnings(results, watch, log, error)
         type(engine_results_t), intent(inout) :: results
         type(energy_watch_t), intent(in) :: watch
         type(logger_t), intent(in) :: log
         type(error_t), allocatable, intent(out) :: error
      end subroutine write_warnings
   end interface

end module ffrf_app_mechanism_output
