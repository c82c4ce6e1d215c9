!> A prepared mechanism case that a host program advances interval by interval (co-simulation):
!> prepare (modes of the flexible bodies, the mechanism, the consistent start of the
!> generalized-alpha integrator), then advance(t) as often as wanted (run_mechanism, the
!> driver's run, is prepare and one advance to t_end), reading the state in between (time,
!> crank angle and speed, body coordinates, marker positions and velocities, joint reactions)
!> and setting a force or moment at a marker for the next interval (ffrf_mbs_host_load). The
!> C API (src/capi) and the Fortran API (`use ffrf`) are thin layers over this type; nothing
!> here stops or prints errors.
!>
!> Stepping. advance(t) takes the integrator's own steps h while they end before t (within
!> 1e-6 h, the rule of galpha_step's last step) and one shortened step min(h, t - t_now) to
!> land on a t between two of them. With every t a multiple of h (e.g. 1 ms intervals of
!> h = 1e-4 s) the integrator therefore takes the very steps of an uninterrupted run: the
!> states are bitwise those of run_mechanism at the same times (the
!> last step onto t_end is shortened by galpha_step itself, as in the driver). A t beyond the
!> case's t_end, or before the current time, is an error (FFRF_INPUT_ERROR).
!>
!> Output. Prepared with run options (an output folder), the session records the run as the
!> driver does (ffrf_app_mechanism_output: results file, progress lines, checkpoints, --restart,
!> animations): run_mechanism is prepare + advance(t_end), and a host advancing in chunks gets
!> the same file. The file is flushed after every advance and put in place, complete, by the
!> advance that reaches t_end (or that fails); close_output (ffrf_case_close) ends a run
!> stopped before t_end with status "stopped: ...". Without run options nothing is written.
module ffrf_app_mechanism_session
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, add_context, fatal_error, FFRF_INPUT_ERROR, &
      FFRF_INTERRUPTED
   use ffrf_core_posix, only: pending_signal, signal_name, signal_test_point
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, stage_timer_t, wall_time
   use ffrf_app_run_options, only: run_options_t
   use ffrf_app_mechanism_output, only: mechanism_output_t
   use ffrf_input_case, only: case_input_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_mechanism_loads, only: LOAD_FORCE, LOAD_TORQUE
   use ffrf_mbs_host_load, only: host_load_t
   use ffrf_mbs_sensors, only: sensor_t, sensor_size
   use ffrf_app_engine_pressure, only: pressure_model_t
   use ffrf_mbs_generalized_alpha, only: galpha_integrator_t, galpha_settings_t
   use ffrf_la_blas_threads, only: blas_threads, blas_library_name, begin_single_blas, &
      end_single_blas
   use ffrf_app_mechanism_builder, only: built_body_t, build_mechanism
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_engine_auto_model, only: model_choice_t
   use ffrf_model_model, only: model_t, build_model
   use ffrf_core_parallel, only: parallel_t, current_ranks
   implicit none
   private
   public :: mechanism_session_t, move_modes

   !> Relative tolerance on times (of the step h): the rule of run_mechanism and galpha_step
   real(dp), parameter :: TIME_RTOL = 1.0e-6_dp

   !> The host loads at one marker: mechanism body, marker, and their indices in mech%loads.
   type :: host_marker_t
      integer :: body = 0, marker = 0, force_load = 0, torque_load = 0
   end type host_marker_t

   !> A prepared mechanism case (module header).
   type :: mechanism_session_t
      !> The mechanism (bodies, joints, loads) as built from the case
      type(mechanism_t) :: mech
      !> What the run keeps of each &body (case order): mechanism index, modes
      type(built_body_t), allocatable :: bodies(:)
      !> Cylinder pressure model (has_pressure: a &load of type pressure exists)
      type(pressure_model_t) :: pressure
      logical :: has_pressure = .false.
      !> The case resolved (ffrf_model_model)
      type(model_t) :: resolved
      !> The automatic model's choices (&model)
      type(model_choice_t) :: model
      !> The integrator and its state (t, q, v, lambda)
      type(galpha_integrator_t) :: integrator
      !> prepare succeeded
      logical :: prepared = .false.
      !> Markers with host loads
      type(host_marker_t), allocatable :: host(:)
      !> The run is recorded (prepared with run options) and its file not finished yet
      logical :: recording = .false.
      !> The recording (ffrf_app_mechanism_output)
      type(mechanism_output_t) :: output
      !> The progress log of the run (prepare's)
      type(logger_t) :: log
      !> The sensors of the case, then an engine case's crank sensors (ffrf_mbs_sensors)
      type(sensor_t), allocatable :: sensors(:)
   contains
      !> Modes, mechanism, start of the integration
      procedure :: prepare => session_prepare
      !> Integrate up to time t
      procedure :: advance => session_advance
      !> Time of the current state (s)
      procedure :: time => session_time
      !> End time of the case (s)
      procedure :: end_time => session_end_time
      !> Crank angle (rad, unwrapped) and speed (rad/s)
      procedure :: crank_angle => session_crank_angle
      procedure :: crank_speed => session_crank_speed
      !> Number of bodies of the case (&body groups; the ground is not counted)
      procedure :: num_bodies => session_num_bodies
      !> Coordinates and velocities of a body
      procedure :: body_state => session_body_state
      !> Markers of a body
      procedure :: num_markers => session_num_markers
      !> Global position, velocity and angular velocity of a marker
      procedure :: marker_motion => session_marker_motion
      !> Sensors: how many, the name and number of values of one, its values now
      procedure :: num_sensors => session_num_sensors
      procedure :: sensor_name => session_sensor_name
      procedure :: sensor_size => session_sensor_size
      procedure :: sensor_values => session_sensor_values
      !> Number of joints
      procedure :: num_joints => session_num_joints
      !> Reaction force and moment of a joint on its two bodies
      procedure :: joint_reaction => session_joint_reaction
      !> Set the host force and moment at a marker for the following intervals
      procedure :: set_marker_load => session_set_marker_load
      !> End the recording of a run stopped before t_end (nothing when not recording)
      procedure :: close_output => session_close_output
      !> Release everything
      procedure :: finish => session_finish
   end type mechanism_session_t

contains

   !> Build the mechanism of `case` (modes of its meshed bodies, joints, loads, starting pose)
   !> and start its integration: the integrator settings of the case (h of the automatic model
   !> when it chose one), the max_steps check, galpha_init (prepare's first part).
   subroutine start_integration(case, resolved, mesh_dir, log, times, mech, bodies, pressure, &
         has_pressure, model, integrator, sensors, error, timer)
      type(case_input_t), intent(in) :: case
      !> The case resolved (build_model), built here
      type(model_t), intent(out) :: resolved
      !> Folder of relative mesh files
      character(len=*), intent(in) :: mesh_dir
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      type(mechanism_t), intent(out) :: mech
      type(built_body_t), allocatable, intent(out) :: bodies(:)
      type(pressure_model_t), intent(out) :: pressure
      logical, intent(out) :: has_pressure
      type(model_choice_t), intent(out) :: model
      type(galpha_integrator_t), intent(out) :: integrator
      !> The sensors (build_mechanism)
      type(sensor_t), allocatable, intent(out) :: sensors(:)
      type(error_t), allocatable, intent(out) :: error
      !> Started after the bodies are built (the caller's timer of the integration start)
      type(stage_timer_t), intent(inout), optional :: timer
      type(galpha_settings_t) :: settings
      real(dp), allocatable :: q(:), v(:)
      character(len=:), allocatable :: case_file
      case_file = case%file_name
      call log_threads(log, case%mechanism%integrator%sparse_threshold)
      call build_model(case, resolved, error)
      if (.not. allocated(error)) call build_mechanism(case, resolved, mesh_dir, log, times, &
         mech, bodies, q, v, pressure, has_pressure, error, model, sensors)
      if (allocated(error)) then
         call add_context(error, case_file)
         return
      end if
      if (present(timer)) call timer%begin()
      settings = resolved%mechanism%integrator
      if (model%h > 0.0_dp) settings%h = model%h
      if (.not. model%active .and. .not. resolved%mechanism%h_given) call log%info( &
         'model', 'time step h = ' // to_str(settings%h, 3) // ' s (default)')
      ! The step count of the h chosen here (read_case checked the given or default h)
      if ((settings%t_end - settings%t_start) / settings%h > &
            real(resolved%mechanism%max_steps, dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, case_file // ': &integrator: ' // &
            'the automatic model''s h = ' // to_str(settings%h) // ' s makes ' // &
            to_str((settings%t_end - settings%t_start) / settings%h, 4) // ' steps, ' // &
            'more than max_steps = ' // to_str(resolved%mechanism%max_steps) // &
            '; shorten the run, give h, or raise &integrator max_steps on purpose')
         return
      end if
      call integrator%init(mech, settings, q, v, error)
      if (allocated(error)) call add_context(error, case_file // ': starting the integration')
   end subroutine start_integration

   !> The BLAS threads of each stage (issue 24): the modes (ARPACK on MUMPS factors: sparse,
   !> large) keep the threads set (--threads, OPENBLAS_NUM_THREADS, else every core); the
   !> integration runs its small dense linear algebra, and MUMPS for an iteration matrix of
   !> order >= sparse_threshold, on one thread (galpha_step).
   subroutine log_threads(log, sparse_threshold)
      type(logger_t), intent(in) :: log
      !> Order of the iteration matrix from which the sparse LU is used
      integer, intent(in) :: sparse_threshold
      character(len=:), allocatable :: library, solvers
      library = blas_library_name()
      solvers = ' (dense LU below order ' // to_str(sparse_threshold) // &
         ' of the iteration matrix, MUMPS from it)'
      select case (library)
      case ('OpenBLAS')
         call log%info('threads', 'modes: ' // to_str(blas_threads()) // ' (OpenBLAS), ' // &
            'integration: 1' // solvers)
      case ('BLIS')
         call log%info('threads', 'modes: BLIS''s own setting (BLIS_NUM_THREADS), ' // &
            'integration: 1' // solvers)
      case default
         call log%info('threads', 'not set by ffrf (the BLAS linked is neither OpenBLAS nor ' &
            // 'BLIS): its own setting in every stage; with a threaded BLAS set it to 1 ' // &
            '(e.g. OMP_NUM_THREADS=1) for small mechanisms')
      end select
   end subroutine log_threads

   !> Prepare a mechanism case read by read_case: modes, mechanism, integrator at t_start. With
   !> `options` the run is recorded in options%output_dir (module header), --restart included.
   subroutine session_prepare(self, case, mesh_dir, log, times, error, options)
      class(mechanism_session_t), intent(out) :: self
      !> The case (a mechanism case: with &joint groups)
      type(case_input_t), intent(in) :: case
      !> Folder of relative mesh files
      character(len=*), intent(in) :: mesh_dir
      !> Progress log (LOG_QUIET for silence)
      type(logger_t), intent(in) :: log
      !> Stage times, appended to
      type(stage_times_t), intent(inout) :: times
      type(error_t), allocatable, intent(out) :: error
      !> Folders, overwrite rule, restart file: record the run (absent: nothing written)
      type(run_options_t), intent(in), optional :: options
      type(stage_timer_t) :: timer
      type(error_t), allocatable :: run_error
      type(parallel_t) :: ranks
      if (.not. case%is_mechanism) then
         call fatal_error(error, FFRF_INPUT_ERROR, case%file_name // ': not a mechanism ' // &
            'case (no &joint groups): nothing to advance; compute its modes instead')
         return
      end if
      self%log = log
      if (present(options)) then
         ! one run per output, checked before anything is computed
         call self%output%reserve(case, options, error)
         if (allocated(error)) call self%output%release()
      end if
      ! MPI build: a rank 0 that cannot record the run stops every rank before the modes
      ranks = current_ranks()
      call ranks%agree(error)
      if (allocated(error)) return
      call start_integration(case, self%resolved, mesh_dir, log, times, self%mech, self%bodies, &
         self%pressure, self%has_pressure, self%model, self%integrator, self%sensors, error, &
         timer)
      if (.not. allocated(error) .and. present(options)) then
         call self%output%start_recording(self%resolved, self%mech, self%bodies, &
            self%integrator, self%model, log, times, timer, error, self%sensors)
         if (.not. allocated(error)) call self%output%record_first(self%mech, self%bodies, &
            self%integrator, self%pressure, self%has_pressure, error)
      end if
      if (allocated(error)) then
         ! the file of a started recording is closed with the error (status "error: ...")
         call move_alloc(error, run_error)
         call self%output%finish(self%mech, self%bodies, self%integrator, log, run_error, error)
         return
      end if
      allocate (self%host(0))
      self%recording = present(options)
      self%prepared = .true.
   end subroutine session_prepare

   !> Integrate from the current time up to time t (module header: steps of h, one shortened
   !> step to land between two). t = the current time does nothing.
   subroutine session_advance(self, t, error)
      class(mechanism_session_t), intent(inout) :: self
      !> Time to reach (s), at most the case's t_end
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: run_error
      real(dp) :: tolerance, t_end, wall_start
      integer :: blas_before
      if (.not. self%prepared) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: advance before prepare')
         return
      end if
      tolerance = TIME_RTOL * self%integrator%settings%h
      t_end = self%integrator%settings%t_end
      if (.not. (t <= t_end + tolerance)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: advance to t = ' // &
            to_str(t, 12) // ' s, beyond the case''s t_end = ' // to_str(t_end, 12) // &
            ' s; raise &integrator t_end')
         return
      end if
      if (t < self%integrator%t - tolerance) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: advance to t = ' // &
            to_str(t, 12) // ' s, before the current time ' // to_str(self%integrator%t, 12) &
            // ' s; time only goes forward')
         return
      end if
      wall_start = wall_time()
      ! The steps on one BLAS thread, set once for the whole advance (galpha_step's own switch
      ! then does nothing): switching OpenBLAS back to its count after every step cost 25 to
      ! 70 % per step with the default threads on a busy 2-core machine (8-link chain of
      ! benchmark_threads, 5.1 against 6.1-8.8 ms/step), once per advance nothing measurable
      blas_before = begin_single_blas()
      call step_to(self, t, t_end, tolerance, run_error)
      call end_single_blas(blas_before)
      if (.not. self%recording) then
         if (allocated(run_error)) call move_alloc(run_error, error)
         return
      end if
      self%output%integration_seconds = self%output%integration_seconds + wall_time() - &
         wall_start
      if (.not. allocated(run_error) .and. self%integrator%t < t_end - tolerance) then
         ! between two advances the file holds every step so far (under its partial name)
         call self%output%flush(run_error)
         if (.not. allocated(run_error)) return
      end if
      ! t_end reached, or the run failed: the file goes into place
      self%recording = .false.
      call self%output%finish(self%mech, self%bodies, self%integrator, self%log, run_error, &
         error)
   end subroutine session_advance

   !> The steps of advance (module header), recorded when the session records: after every
   !> step a received signal (SIGTERM, SIGINT, SIGHUP, SIGUSR1, SIGXCPU) ends the run with
   !> FFRF_INTERRUPTED, and a due restart checkpoint is written.
   subroutine step_to(self, t, t_end, tolerance, error)
      class(mechanism_session_t), intent(inout) :: self
      !> Time to reach, the case's t_end, the time tolerance (s)
      real(dp), intent(in) :: t, t_end, tolerance
      type(error_t), allocatable, intent(out) :: error
      integer :: signal
      associate (integrator => self%integrator)
         call signal_test_point('integration:before')
         do while (integrator%t < min(t, t_end) - tolerance)
            if (self%recording) call self%output%before_step(self%mech, integrator, t_end)
            if (t < t_end - tolerance .and. t - integrator%t < integrator%h * &
               (1.0_dp - TIME_RTOL)) then
               ! land on t: galpha_step shortens the step that reaches its t_end
               integrator%settings%t_end = t
               call integrator%step(self%mech, error)
               integrator%settings%t_end = t_end
            else
               call integrator%step(self%mech, error)
            end if
            if (.not. allocated(error) .and. self%recording) call self%output%after_step( &
               self%mech, self%bodies, integrator, self%pressure, self%has_pressure, t_end, &
               self%log, error)
            if (allocated(error)) return
            if (integrator%stats%steps == 10) call signal_test_point('integration:during')
            signal = pending_signal()
            if (signal /= 0) then
               if (self%recording) then
                  call fatal_error(error, FFRF_INTERRUPTED, 'interrupted by ' // &
                     signal_name(signal) // ' at t = ' // to_str(integrator%t, 8) // &
                     ' s (step ' // to_str(integrator%stats%steps) // '): results file "' // &
                     self%output%results_file // '" holds every step so far and ' // &
                     '/final_state, status "interrupted: ' // signal_name(signal) // &
                     '"; continue with --restart ' // self%output%results_file)
               else
                  call fatal_error(error, FFRF_INTERRUPTED, 'mechanism: interrupted by ' // &
                     signal_name(signal) // ' at t = ' // to_str(integrator%t, 8) // ' s')
               end if
               return
            end if
            if (self%recording .and. integrator%t < t_end - tolerance) then
               call self%output%checkpoint(self%mech, self%bodies, integrator, error)
               if (allocated(error)) return
            end if
         end do
         call signal_test_point('integration:after')
      end associate
   end subroutine step_to

   !> End the recording of a run stopped before t_end: its file goes into place with every
   !> recorded step, /final_state and status "stopped: ..." (nothing when not recording).
   subroutine session_close_output(self, error)
      class(mechanism_session_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: run_error
      if (.not. self%recording) return
      self%recording = .false.
      call self%output%finish(self%mech, self%bodies, self%integrator, self%log, run_error, &
         error, stopped='stopped: closed at t = ' // to_str(self%integrator%t, 8) // &
         ' s, before t_end = ' // to_str(self%integrator%settings%t_end, 8) // ' s')
   end subroutine session_close_output

   !> Time of the current state (s).
   pure real(dp) function session_time(self)
      class(mechanism_session_t), intent(in) :: self
      session_time = self%integrator%t
   end function session_time

   !> End time of the case (s).
   pure real(dp) function session_end_time(self)
      class(mechanism_session_t), intent(in) :: self
      session_end_time = self%integrator%settings%t_end
   end function session_end_time

   !> Crank angle of the current state (rad, unwrapped over the revolutions; 0 without crank).
   pure real(dp) function session_crank_angle(self)
      class(mechanism_session_t), intent(in) :: self
      session_crank_angle = 0.0_dp
      if (self%prepared) session_crank_angle = self%mech%rotor_angle(self%integrator%q)
   end function session_crank_angle

   !> Crank speed of the current state (rad/s; 0 without crank).
   pure real(dp) function session_crank_speed(self)
      class(mechanism_session_t), intent(in) :: self
      session_crank_speed = 0.0_dp
      if (self%prepared) session_crank_speed = self%mech%rotor_speed(self%integrator%q, &
         self%integrator%v)
   end function session_crank_speed

   !> Number of bodies of the case (&body groups in input order; the ground is not counted).
   pure integer function session_num_bodies(self)
      class(mechanism_session_t), intent(in) :: self
      session_num_bodies = 0
      if (allocated(self%bodies)) session_num_bodies = size(self%bodies)
   end function session_num_bodies

   !> Check a body number (1..num_bodies) and give its mechanism index.
   subroutine body_of(self, body, index, error)
      class(mechanism_session_t), intent(in) :: self
      integer, intent(in) :: body
      integer, intent(out) :: index
      type(error_t), allocatable, intent(out) :: error
      index = 0
      if (.not. self%prepared) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: not prepared')
      else if (body < 1 .or. body > self%num_bodies()) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: body ' // to_str(body) // &
            ' does not exist; the case has ' // to_str(self%num_bodies()) // ' bodies')
      else
         index = self%bodies(body)%index
      end if
   end subroutine body_of

   !> Coordinates q and velocities v of body `body` (1..num_bodies): rigid [R; theta] (7),
   !> flexible [R; theta; zeta] (7 + modes); theory.md 3.1.
   subroutine session_body_state(self, body, q, v, error)
      class(mechanism_session_t), intent(in) :: self
      !> Body number, 1..num_bodies (case order)
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: q(:), v(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: b
      call body_of(self, body, b, error)
      if (allocated(error)) return
      q = self%mech%body_coordinates(self%integrator%q, b)
      v = self%mech%body_coordinates(self%integrator%v, b)
   end subroutine session_body_state

   !> Number of markers of body `body` (0 for a bad body number).
   integer function session_num_markers(self, body)
      class(mechanism_session_t), intent(in) :: self
      !> Body number, 1..num_bodies
      integer, intent(in) :: body
      type(error_t), allocatable :: error
      integer :: b
      session_num_markers = 0
      call body_of(self, body, b, error)
      if (.not. allocated(error)) session_num_markers = self%mech%bodies(b)%body%num_markers
   end function session_num_markers

   !> Check a marker of a body; b is the mechanism index.
   subroutine marker_of(self, body, marker, b, error)
      class(mechanism_session_t), intent(in) :: self
      integer, intent(in) :: body, marker
      integer, intent(out) :: b
      type(error_t), allocatable, intent(out) :: error
      call body_of(self, body, b, error)
      if (allocated(error)) return
      if (marker < 1 .or. marker > self%mech%bodies(b)%body%num_markers) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: body "' // &
            self%mech%bodies(b)%name // '" has no marker ' // to_str(marker) // ' (it has ' // &
            to_str(self%mech%bodies(b)%body%num_markers) // ')')
      end if
   end subroutine marker_of

   !> Global position (m), velocity (m/s) and angular velocity (rad/s) of a marker: r_k(q),
   !> L_r v and L_w v (theory.md 3.5). A flexible body's markers are its interfaces' virtual
   !> nodes in input order; a rigid body's are made from its &marker points per joint end and
   !> load (ffrf_app_mechanism_builder).
   subroutine session_marker_motion(self, body, marker, position, velocity, &
         angular_velocity, error)
      class(mechanism_session_t), intent(in) :: self
      !> Body number, 1..num_bodies; marker number, 1..num_markers(body)
      integer, intent(in) :: body, marker
      real(dp), intent(out) :: position(3), velocity(3), angular_velocity(3)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: qb(:), vb(:)
      integer :: b
      position = 0.0_dp
      velocity = 0.0_dp
      angular_velocity = 0.0_dp
      call marker_of(self, body, marker, b, error)
      if (allocated(error)) return
      qb = self%mech%body_coordinates(self%integrator%q, b)
      vb = self%mech%body_coordinates(self%integrator%v, b)
      associate (x => self%mech%bodies(b)%body)
         position = x%marker_position(qb, marker)
         velocity = matmul(x%marker_velocity_jacobian(qb, marker), vb)
         angular_velocity = matmul(x%marker_rotation_jacobian(qb, marker), vb)
      end associate
   end subroutine session_marker_motion

   !> Number of sensors (&sensor groups in input order, then an engine case's crank_angle and
   !> crank_speed).
   pure integer function session_num_sensors(self)
      class(mechanism_session_t), intent(in) :: self
      session_num_sensors = 0
      if (allocated(self%sensors)) session_num_sensors = size(self%sensors)
   end function session_num_sensors

   !> Check a sensor number.
   subroutine sensor_of(self, sensor, error)
      class(mechanism_session_t), intent(in) :: self
      integer, intent(in) :: sensor
      type(error_t), allocatable, intent(out) :: error
      if (.not. self%prepared) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: not prepared')
      else if (sensor < 1 .or. sensor > self%num_sensors()) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: sensor ' // to_str(sensor) // &
            ' does not exist; the case has ' // to_str(self%num_sensors()) // ' sensors')
      end if
   end subroutine sensor_of

   !> Name of sensor `sensor` (1..num_sensors).
   subroutine session_sensor_name(self, sensor, name, error)
      class(mechanism_session_t), intent(in) :: self
      integer, intent(in) :: sensor
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
      name = ''
      call sensor_of(self, sensor, error)
      if (.not. allocated(error)) name = trim(self%sensors(sensor)%name)
   end subroutine session_sensor_name

   !> Number of values of sensor `sensor` (1..num_sensors).
   subroutine session_sensor_size(self, sensor, size_, error)
      class(mechanism_session_t), intent(in) :: self
      integer, intent(in) :: sensor
      integer, intent(out) :: size_
      type(error_t), allocatable, intent(out) :: error
      size_ = 0
      call sensor_of(self, sensor, error)
      if (.not. allocated(error)) size_ = sensor_size(self%sensors(sensor)%kind)
   end subroutine session_sensor_size

   !> Values of sensor `sensor` at the current state (the integrator's multipliers for a
   !> reaction; docs/sensors.md).
   subroutine session_sensor_values(self, sensor, values, error)
      class(mechanism_session_t), intent(in) :: self
      integer, intent(in) :: sensor
      real(dp), allocatable, intent(out) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      allocate (values(0))
      call sensor_of(self, sensor, error)
      if (allocated(error)) return
      call self%sensors(sensor)%evaluate(self%mech, self%integrator%q, self%integrator%v, &
         self%integrator%qdd, self%integrator%lambda, values, error)
   end subroutine session_sensor_values

   !> Number of joints (&joint groups in input order).
   pure integer function session_num_joints(self)
      class(mechanism_session_t), intent(in) :: self
      session_num_joints = 0
      if (allocated(self%mech%joints)) session_num_joints = size(self%mech%joints)
   end function session_num_joints

   !> Reaction of joint `joint` (1..num_joints) from the current multipliers: force (N) and
   !> moment (N m), global, column 1 on body 1 of the joint, column 2 on body 2.
   subroutine session_joint_reaction(self, joint, force, moment, error)
      class(mechanism_session_t), intent(in) :: self
      integer, intent(in) :: joint
      real(dp), intent(out) :: force(3, 2), moment(3, 2)
      type(error_t), allocatable, intent(out) :: error
      force = 0.0_dp
      moment = 0.0_dp
      if (.not. self%prepared) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: not prepared')
         return
      end if
      if (joint < 1 .or. joint > self%num_joints()) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: joint ' // to_str(joint) // &
            ' does not exist; the case has ' // to_str(self%num_joints()) // ' joints')
         return
      end if
      call self%mech%reaction(joint, self%integrator%q, self%integrator%lambda, force, moment)
   end subroutine session_joint_reaction

   !> Apply the global force F (N) and moment M (N m) at a marker from now on (until set
   !> again): the host's load of the next interval (ffrf_mbs_host_load). The first call for a
   !> marker adds its two loads to the mechanism.
   subroutine session_set_marker_load(self, body, marker, force, moment, error)
      class(mechanism_session_t), intent(inout) :: self
      !> Body number, 1..num_bodies; marker number, 1..num_markers(body)
      integer, intent(in) :: body, marker
      real(dp), intent(in) :: force(3), moment(3)
      type(error_t), allocatable, intent(out) :: error
      type(host_load_t) :: load
      type(host_marker_t), allocatable :: grown(:)
      integer :: b, k
      call marker_of(self, body, marker, b, error)
      if (allocated(error)) return
      if (.not. all(abs(force) <= huge(1.0_dp) .and. abs(moment) <= huge(1.0_dp))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: host load at marker ' // &
            to_str(marker) // ' of body "' // self%mech%bodies(b)%name // '" is not finite')
         return
      end if
      k = findloc(self%host%body == b .and. self%host%marker == marker, .true., dim=1)
      if (k == 0) then
         load%body = b
         load%marker = marker
         load%name = 'host'
         load%kind = LOAD_FORCE
         call self%mech%add_load(load, error)
         if (allocated(error)) return
         load%kind = LOAD_TORQUE
         call self%mech%add_load(load, error)
         if (allocated(error)) return
         allocate (grown(size(self%host) + 1))
         grown(:size(self%host)) = self%host
         k = size(grown)
         grown(k) = host_marker_t(b, marker, size(self%mech%loads) - 1, size(self%mech%loads))
         call move_alloc(grown, self%host)
      end if
      call set_vector(self%host(k)%force_load, force)
      call set_vector(self%host(k)%torque_load, moment)

   contains

      subroutine set_vector(index, vector)
         integer, intent(in) :: index
         real(dp), intent(in) :: vector(3)
         select type (x => self%mech%loads(index)%load)
         type is (host_load_t)
            call x%set_vector(vector)
         end select
      end subroutine set_vector

   end subroutine session_set_marker_load

   !> Move the modal results of a body from `from` to `to` (arrays moved, not copied; `from`
   !> keeps its scalars).
   subroutine move_modes(from, to)
      type(body_modes_t), intent(inout) :: from
      type(body_modes_t), intent(out) :: to
      if (allocated(from%name)) call move_alloc(from%name, to%name)
      call move_alloc(from%mesh%xyz, to%mesh%xyz)
      call move_alloc(from%mesh%tets, to%mesh%tets)
      to%mesh%num_nodes = from%mesh%num_nodes
      to%mesh%nodes_per_tet = from%mesh%nodes_per_tet
      if (allocated(from%interfaces)) call move_alloc(from%interfaces, to%interfaces)
      to%mass = from%mass
      to%center_of_mass = from%center_of_mass
      to%inertia = from%inertia
      if (allocated(from%frequency_hz)) call move_alloc(from%frequency_hz, to%frequency_hz)
      if (allocated(from%shape)) call move_alloc(from%shape, to%shape)
      if (allocated(from%virtual_node_shape)) call move_alloc(from%virtual_node_shape, &
         to%virtual_node_shape)
      if (allocated(from%residual)) call move_alloc(from%residual, to%residual)
   end subroutine move_modes

   !> Release the mechanism, bodies and integrator (the session can be prepared again); a run
   !> still recorded is ended first (close_output).
   subroutine session_finish(self)
      class(mechanism_session_t), intent(inout) :: self
      type(error_t), allocatable :: ignored
      call self%close_output(ignored)
      call reset(self)
   contains
      subroutine reset(self)
         class(mechanism_session_t), intent(out) :: self
         self%prepared = .false.
      end subroutine reset
   end subroutine session_finish

end module ffrf_app_mechanism_session
