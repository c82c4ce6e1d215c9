!> The run of a mechanism output (a submodule of ffrf_app_mechanism_output): the output
!> reserved, the file started, each step recorded with its progress line and checkpoint, the
!> reactions split at near-redundant rows, the run finished whatever happened.
submodule (ffrf_app_mechanism_output) ffrf_app_mechanism_output_steps
   use ffrf_core_error, only: add_context, fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR, &
      FFRF_INTERRUPTED
   use ffrf_core_posix, only: pending_signal, signal_name, file_kind, free_space
   use ffrf_core_strings, only: to_str
   use ffrf_core_paths, only: join_path
   use ffrf_core_log, only: peak_memory_mib, wall_time
   use ffrf_input_case, only: case_echo
   use ffrf_io_results, only: partial_name, commit_file, abandon_file, check_no_overwrite
   use ffrf_app_output_paths, only: check_output_paths, export_asked
   use ffrf_core_choices, only: EXPORT_XDMF
   use ffrf_io_xdmf, only: xdmf_body_t, write_xdmf_file, xdmf_name
   use ffrf_app_engine_crank_log, only: crank_progress
   use ffrf_mbs_reaction_split, only: TOLERANCE_FACTOR
   use ffrf_app_engine_auto_model, only: write_model_choice
   use ffrf_app_scene_choice, only: write_scene_choice
   use ffrf_app_restart_fingerprint, only: input_entries
   implicit none

contains

   module procedure output_reserve
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
   end procedure output_reserve

   module procedure output_release
      type(error_t), allocatable :: ignored
      if (.not. self%reserved) return
      call self%source%close(ignored)
      call self%lock%release()
      self%reserved = .false.
   end procedure output_release

   module procedure output_start
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
         if (.not. allocated(error) .and. choice%scene) call write_scene_choice(self%results, &
            choice, error)
         if (.not. allocated(error) .and. self%restarting) then
            call self%results%append_from(self%source, self%restart%num_steps, error)
            if (.not. allocated(error)) call history_from(self%source, self%restart%num_steps, &
               bodies, mech, self%history, error)
            if (.not. allocated(error)) call write_restart_origin(self%results, self%source, &
               options%restart_file, integrator%t, [self%fingerprint_input, &
               self%fingerprint_model], error)
            if (.not. allocated(error)) call self%results%restore_interval( &
               self%restart%interval, error)
            if (.not. allocated(error)) call self%source%close(error)
         end if
         if (.not. allocated(error)) call check_output_size(self, integrator, bodies, log, error)
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
         if (case%output%every_seconds > 0.0_dp) self%next_sample = next_sample_time( &
            integrator%t, case%output%every_seconds, 1.0e-6_dp * integrator%settings%h)
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
      self%torsion_before_last = mech%torsion_references()
      self%checkpoint_seconds = 0.0_dp
      self%last_cost = 0.0_dp
      self%num_checkpoints = 0
   end procedure output_start

   module procedure output_first_record
      if (.not. self%restarting) call record_step(self, mech, bodies, integrator, pressure, &
         has_pressure, .true., error)
   end procedure output_first_record

   module procedure output_before_step
      if (t_end - integrator%t <= integrator%h * (1.0_dp + 1.0e-6_dp)) then
         self%before_last = integrator
         self%balance_before_last = self%balance
         self%reference_before_last = mech%rotor_reference
         self%torsion_before_last = mech%torsion_references()
         self%rows_before_last = self%results%num_steps()
         self%interval_before_last = self%results%interval_state()
         self%have_before_last = .true.
      end if
   end procedure output_before_step

   module procedure output_after_step
      real(dp) :: wall
      logical :: sample
      sample = sample_due(self, integrator, t_end)
      call self%balance%update(mech, integrator%t, integrator%q, integrator%v, error, &
         lambda=integrator%lambda, scheme=integrator)
      if (.not. allocated(error)) call split_reactions(self, mech, bodies, integrator, log, error)
      if (.not. allocated(error)) call record_step(self, mech, bodies, integrator, pressure, &
         has_pressure, sample, error)
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
   end procedure output_after_step

   module procedure output_checkpoint
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
         self%results%num_steps(), mech%rotor_reference, mech%torsion_references(), mech, &
         bodies, self%fingerprint_input, self%fingerprint_model, error, &
         self%results%interval_state())
      if (.not. allocated(error)) call write_checkpoint_file(self%results_file, error)
      if (allocated(error)) return
      self%last_checkpoint = wall_time()
      self%steps_at_checkpoint = integrator%stats%steps
      self%num_checkpoints = self%num_checkpoints + 1
      self%last_cost = self%last_checkpoint - checkpoint_start
      self%checkpoint_seconds = self%checkpoint_seconds + self%last_cost
   end procedure output_checkpoint

   module procedure output_flush
      call self%results%flush(error)
   end procedure output_flush

   module procedure output_finish
      type(error_t), allocatable :: state_error, close_error
      type(stage_timer_t) :: timer
      character(len=:), allocatable :: status
      logical :: closed, xdmf
      !> The bodies of the XDMF export (&run export = 'xdmf') and its wall time (s)
      type(xdmf_body_t), allocatable :: exported(:)
      real(dp) :: xdmf_seconds
      if (.not. self%started) then
         if (self%reserved .and. allocated(run_error)) then
            if (run_error%code /= FFRF_INTERRUPTED) call record_failed_start(self, bodies, &
               run_error)
         end if
         call self%release()
         if (allocated(run_error)) call move_alloc(run_error, error)
         return
      end if
      self%started = .false.
      associate (case => self%case, results => self%results, results_file => self%results_file)
         ! The restart state of the results file
         if (self%have_before_last .and. integrator%t == integrator%settings%t_end) then
            call write_restart_state(results, self%before_last, self%balance_before_last, &
               self%rows_before_last, self%reference_before_last, self%torsion_before_last, &
               mech, bodies, self%fingerprint_input, self%fingerprint_model, state_error, &
               self%interval_before_last)
         else
            call write_restart_state(results, integrator, self%balance, results%num_steps(), &
               mech%rotor_reference, mech%torsion_references(), mech, bodies, &
               self%fingerprint_input, self%fingerprint_model, state_error, &
               results%interval_state())
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
         xdmf = export_asked(case, EXPORT_XDMF)
         if (.not. allocated(error) .and. (case%mechanism%mechanism%animation_frames > 0 .or. &
            xdmf) .and. .not. interrupted(run_error)) call write_animations(case, self%options, &
            bodies, self%history, log, results, xdmf, exported, xdmf_seconds, error)
         call self%times%add('output', timer%seconds())
         ! a stage of its own only when asked (the timings of a run without it are unchanged)
         if (xdmf .and. allocated(exported)) call self%times%add('xdmf export', xdmf_seconds)
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
         if (xdmf .and. allocated(exported)) then
            ! beside the results file, which it names relative to its own folder
            call write_xdmf_file(xdmf_name(results_file), results_file(index(results_file, &
               '/', back=.true.) + 1:), exported, error)
            if (allocated(error)) then
               call self%release()
               return
            end if
            call log%info('output', 'XDMF for ParaView written: ' // xdmf_name(results_file))
         end if
         call log%info('done', case%name // ': ' // to_str(self%total%seconds(), 3) // ' s, ' &
            // 'peak memory ' // to_str(peak_memory_mib(), 4) // ' MiB')
      end associate
      call self%release()
   end procedure output_finish

   !> Record the current state: into the output interval, and when it is a sample (`sample`)
   !> into the results file and the animation history.
   subroutine record_step(self, mech, bodies, integrator, pressure, has_pressure, sample, error)
      class(mechanism_output_t), intent(inout) :: self
      type(mechanism_t), intent(in) :: mech
      type(built_body_t), intent(in) :: bodies(:)
      type(galpha_integrator_t), intent(in) :: integrator
      type(pressure_model_t), intent(in) :: pressure
      logical, intent(in) :: has_pressure, sample
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
            damping_dissipation=balance%physical_dissipation, sensors=sensor_values, &
            sample=sample)
         if (allocated(error) .or. .not. sample) return
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

   !> The step just taken is a sample (&output; docs/results.md "Output rate, peaks,
   !> compression, size"): the last step (t_end), every every_steps-th step of the run
   !> (counted from its start, so a --restart keeps the rhythm), or the first step at or after
   !> the next multiple of every_seconds.
   logical function sample_due(self, integrator, t_end) result(due)
      class(mechanism_output_t), intent(inout) :: self
      type(galpha_integrator_t), intent(in) :: integrator
      real(dp), intent(in) :: t_end
      real(dp) :: tolerance
      tolerance = 1.0e-6_dp * integrator%settings%h
      due = .true.
      if (integrator%t >= t_end - tolerance) return
      associate (output => self%case%output)
         if (output%every_seconds > 0.0_dp) then
            due = integrator%t >= self%next_sample - tolerance
            if (due) self%next_sample = next_sample_time(integrator%t, output%every_seconds, &
               tolerance)
         else if (output%every_steps > 1) then
            due = mod(integrator%stats%steps, int(output%every_steps, i8)) == 0_i8
         end if
      end associate
   end function sample_due

   !> The first multiple of `period` after t (a multiple within `tolerance` of t counts as
   !> reached).
   pure real(dp) function next_sample_time(t, period, tolerance) result(next)
      real(dp), intent(in) :: t, period, tolerance
      next = (aint((t + tolerance) / period) + 1.0_dp) * period
   end function next_sample_time

   !> The predicted size of the results file (and animations) in the log, before the
   !> integration; FFRF_IO_ERROR (exit 3) when it exceeds the free space of the output folder,
   !> unless &output ignore_free_space. The prediction: the file as created (input, modes,
   !> empty series) plus the whole chunks of every series after the predicted samples, plus
   !> the restart state and run information written at the end; uncompressed (an upper bound
   !> with compression).
   subroutine check_output_size(self, integrator, bodies, log, error)
      ! sizes in bytes; `created`: the results file so far
      integer(i8) :: created, samples, steps, results_bytes, animation_bytes, free
      integer :: kind
      character(len=:), allocatable :: note
      class(mechanism_output_t), intent(inout) :: self
      type(galpha_integrator_t), intent(in) :: integrator
      type(built_body_t), intent(in) :: bodies(:)
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      associate (output => self%case%output, s => integrator%settings)
         call self%results%flush(error)
         if (.not. allocated(error)) call file_kind(self%temp_file, kind, created, error)
         if (allocated(error)) return
         steps = max(0_i8, ceiling((s%t_end - integrator%t) / s%h - 1.0e-6_dp, i8))
         samples = predicted_samples(output, integrator%t, s%t_end, s%h, &
            .not. self%restarting) + int(self%results%num_steps(), i8)
         results_bytes = created + self%results%predicted_bytes(samples) - &
            self%results%predicted_bytes(int(self%results%num_steps(), i8)) + &
            8_i8 * 16_i8 * size(integrator%q, kind=i8) + 16384_i8
         animation_bytes = predicted_animation_bytes(self%case%mechanism%mechanism% &
            animation_frames, bodies, export_asked(self%case, EXPORT_XDMF))
         ! the free space before the file was created (the prediction counts it whole)
         call free_space(self%options%output_dir, free, error)
         if (allocated(error)) return
         free = free + created
         note = ''
         if (output%compression > 0) note = ', uncompressed: compression makes it smaller'
         call log%info('output', 'predicted size: results ' // megabytes(results_bytes) // &
            ' (' // to_str(samples) // ' samples of ' // to_str(steps) // ' steps' // note // &
            '), animations ' // megabytes(animation_bytes) // '; free in the output folder ' // &
            megabytes(free))
         if (results_bytes + animation_bytes <= free .or. output%ignore_free_space) return
         self%refused = .true.
         call fatal_error(error, FFRF_IO_ERROR, 'the results (' // megabytes(results_bytes) // &
            ') and animations (' // megabytes(animation_bytes) // ') would not fit in the ' // &
            megabytes(free) // ' free in the output folder "' // self%options%output_dir // &
            '"; write fewer samples (&output every_seconds or every_steps), fewer ' // &
            'histories (&output histories), compress (&output compression), choose another ' // &
            '--output-dir, or start anyway with &output ignore_free_space = .true.')
      end associate
   end subroutine check_output_size

   module procedure predicted_samples
      integer(i8) :: steps
      steps = max(0_i8, ceiling((t_end - t) / h - 1.0e-6_dp, i8))
      if (output%every_seconds > 0.0_dp) then
         samples = min(floor(t_end / output%every_seconds + 1.0e-9_dp, i8) - &
            floor(t / output%every_seconds + 1.0e-9_dp, i8) + 1_i8, steps)
      else
         samples = min(steps / output%every_steps + 1_i8, steps)
      end if
      if (first) samples = samples + 1_i8
   end procedure predicted_samples

   !> "12.3 MB" (10^6 bytes).
   function megabytes(bytes) result(text)
      integer(i8), intent(in) :: bytes
      character(len=:), allocatable :: text
      text = to_str(real(bytes, dp) / 1.0e6_dp, 4) // ' MB'
   end function megabytes

   !> Bytes of the Gmsh animations (write_animations): per flexible body, its mesh (a line per
   !> node: tag and 3 x 25 characters) and `frames` node-data views of a line per node ('tag ux
   !> uy uz', 3 x 15 characters). With `xdmf`, also the XDMF datasets in the results file
   !> (ffrf_io_xdmf): geometry and `frames` frames of 3 doubles a node, 4-byte node numbers.
   pure integer(i8) function predicted_animation_bytes(frames, bodies, xdmf) result(bytes)
      integer, intent(in) :: frames
      type(built_body_t), intent(in) :: bodies(:)
      logical, intent(in) :: xdmf
      integer(i8) :: nodes, tets, digits
      integer :: k
      bytes = 0_i8
      do k = 1, size(bodies)
         if (bodies(k)%num_modes == 0) cycle
         nodes = size(bodies(k)%modes%mesh%xyz, 2, kind=i8)
         tets = size(bodies(k)%modes%mesh%tets, 2, kind=i8)
         digits = int(log10(real(max(nodes, 1_i8), dp)), i8) + 2_i8
         if (frames > 0) bytes = bytes + nodes * (digits + 75_i8) + tets * (size(bodies(k)% &
            modes%mesh%tets, 1, kind=i8) * digits + 8_i8 + digits) + int(frames, i8) * &
            (nodes * (digits + 45_i8) + 200_i8) + 400_i8
         if (xdmf) bytes = bytes + 24_i8 * nodes * int(max(frames, 0) + 1, i8) + 4_i8 * &
            size(bodies(k)%modes%mesh%tets, kind=i8)
      end do
   end function predicted_animation_bytes

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

end submodule ffrf_app_mechanism_output_steps
