!> Preparing and advancing a mechanism session (a submodule of ffrf_app_mechanism_session):
!> the modes, the mechanism and the consistent start, the steps to a host's time, the end
!> of the recorded run, the release; the modes moved between owners.
submodule (ffrf_app_mechanism_session) ffrf_app_mechanism_session_advance
   use ffrf_core_error, only: add_context, fatal_error, FFRF_INPUT_ERROR, FFRF_INTERRUPTED
   use ffrf_core_posix, only: pending_signal, signal_name, signal_test_point
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: wall_time
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t
   use ffrf_la_blas_threads, only: blas_threads, blas_library_name, begin_single_blas, &
      end_single_blas
   use ffrf_app_mechanism_builder, only: build_mechanism
   use ffrf_model_model, only: build_model
   use ffrf_app_scene_model, only: scene_record_t
   use ffrf_app_scene_prerun, only: needs_scene_prerun, scene_prerun
   use ffrf_core_parallel, only: parallel_t, current_ranks
   implicit none

contains

   !> Build the mechanism of `case` (modes of its meshed bodies, joints, loads, starting pose)
   !> and start its integration: the integrator settings of the case (h of the automatic model
   !> when it chose one), the max_steps check, galpha_init (prepare's first part).
   subroutine start_integration(self, case, mesh_dir, log, times, error, timer)
      !> The session whose resolved case, mechanism, bodies, pressure model, automatic model,
      !> integrator and sensors are made here
      class(mechanism_session_t), intent(inout) :: self
      type(case_input_t), intent(in) :: case
      !> Folder of relative mesh files
      character(len=*), intent(in) :: mesh_dir
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      type(error_t), allocatable, intent(out) :: error
      !> Started after the bodies are built (the caller's timer of the integration start)
      type(stage_timer_t), intent(inout), optional :: timer
      type(galpha_settings_t) :: settings
      type(scene_record_t) :: record
      real(dp), allocatable :: q(:), v(:)
      character(len=:), allocatable :: case_file, results_file
      case_file = case%file_name
      ! a recorded run writes the exports of &run export beside its results file
      results_file = ''
      if (allocated(self%output%results_file)) results_file = self%output%results_file
      call log_threads(log, case%mechanism%integrator%sparse_threshold)
      call build_model(case, self%resolved, error)
      if (.not. allocated(error)) then
         if (needs_scene_prerun(case, self%resolved)) then
            ! a scene without an engine: the automatic model's loads from a rigid pre-run
            call scene_prerun(case, self%resolved, mesh_dir, log, times, record, error)
            if (.not. allocated(error)) call build_mechanism(case, self%resolved, mesh_dir, &
               log, times, self%mech, self%bodies, q, v, self%pressure, self%has_pressure, &
               error, self%model, self%sensors, record, results_file)
         else
            call build_mechanism(case, self%resolved, mesh_dir, log, times, self%mech, &
               self%bodies, q, v, self%pressure, self%has_pressure, error, self%model, &
               self%sensors, results_file=results_file)
         end if
      end if
      if (allocated(error)) then
         call add_context(error, case_file)
         return
      end if
      if (present(timer)) call timer%begin()
      associate (resolved => self%resolved, model => self%model)
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
      end associate
      call self%integrator%init(self%mech, settings, q, v, error)
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

   module procedure session_prepare
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
      call start_integration(self, case, mesh_dir, log, times, error, timer)
      if (.not. allocated(error) .and. present(options)) then
         call self%output%start_recording(self%resolved, self%mech, self%bodies, &
            self%integrator, self%model, log, times, timer, error, self%sensors)
         if (.not. allocated(error)) call self%output%record_first(self%mech, self%bodies, &
            self%integrator, self%pressure, self%has_pressure, error)
      end if
      if (allocated(error)) then
         ! the file of a started recording is closed with the error (status "error: ..."); a
         ! failure after the modes leaves them in a file with that status (record_failed_start)
         call move_alloc(error, run_error)
         if (.not. allocated(self%bodies)) allocate (self%bodies(0))
         call self%output%finish(self%mech, self%bodies, self%integrator, log, run_error, error)
         return
      end if
      allocate (self%host(0))
      self%recording = present(options)
      self%prepared = .true.
   end procedure session_prepare

   module procedure session_advance
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
   end procedure session_advance

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

   module procedure session_close_output
      type(error_t), allocatable :: run_error
      if (.not. self%recording) return
      self%recording = .false.
      call self%output%finish(self%mech, self%bodies, self%integrator, self%log, run_error, &
         error, stopped='stopped: closed at t = ' // to_str(self%integrator%t, 8) // &
         ' s, before t_end = ' // to_str(self%integrator%settings%t_end, 8) // ' s')
   end procedure session_close_output

   module procedure session_finish
      type(error_t), allocatable :: ignored
      call self%close_output(ignored)
      call reset(self)
   contains
      subroutine reset(self)
         class(mechanism_session_t), intent(out) :: self
         self%prepared = .false.
      end subroutine reset
   end procedure session_finish

   module procedure move_modes
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
   end procedure move_modes

end submodule ffrf_app_mechanism_session_advance
