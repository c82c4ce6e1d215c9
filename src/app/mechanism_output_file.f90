!> The results file's content beside the time series (a submodule of
!> ffrf_app_mechanism_output): the opened file with its series, the bodies' modes, the run
!> information and statistics, the log of the mechanism, the Gmsh animations.
submodule (ffrf_app_mechanism_output) ffrf_app_mechanism_output_file
   use ffrf_core_kinds, only: pi, i8
   use ffrf_core_error, only: add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_paths, only: join_path, insert_suffix
   use ffrf_input_case, only: case_echo
   use ffrf_input_nml_output, only: output_input_t
   use ffrf_io_results, only: partial_name, commit_file, abandon_file
   use ffrf_io_gmsh_writer, only: write_displacement_frames_msh
   use ffrf_io_xdmf, only: xdmf_body_t
   use ffrf_io_modes_file, only: fingerprint_dataset, NUM_FINGERPRINT_DATASETS
   use ffrf_modes_input, only: basis_name
   use ffrf_mbs_sensors, only: sensor_size, sensor_unit, sensor_word
   use ffrf_app_engine_crank_log, only: crank_summary
   use ffrf_mbs_joints, only: JOINT_REVOLUTE
   implicit none

contains

   module procedure log_mechanism
      integer :: k, num_loads
      ! a mechanism without &load has no loads array (the size of an unallocated array is
      ! undefined: it printed "1 loads" for input/spring_pendulum.nml)
      num_loads = 0
      if (allocated(mech%loads)) num_loads = size(mech%loads)
      call log%info('mechanism', to_str(size(mech%bodies) - 1) // ' moving bodies, ' // &
         to_str(size(mech%joints)) // ' joints, ' // to_str(num_loads) // ' loads; ' // &
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
   end procedure log_mechanism

   module procedure row_name
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
   end procedure row_name

   module procedure open_results
      !> Samples per flush and per chunk of a compressed file
      integer, parameter :: COMPRESSED_FLUSH = 256
      integer, allocatable :: flags(:)
      integer :: k, j, chunk_steps
      logical :: decimated
      associate (output => case%output, s => integrator%settings)
         ! an engine's histories only with a crank; the peaks only at a reduced rate, whose
         ! chunks hold at most the run's samples (a chunk is allocated whole)
         decimated = output%every_steps > 1 .or. output%every_seconds > 0.0_dp
         chunk_steps = 0
         if (decimated) chunk_steps = int(min(predicted_samples(output, 0.0_dp, s%t_end, s%h, &
            .true.), 8192_i8))
         ! compressed: a chunk per flush (of COMPRESSED_FLUSH samples), so that each chunk is
         ! deflated once, not again at every flush that adds to it
         if (output%compression > 0) chunk_steps = min(merge(chunk_steps, COMPRESSED_FLUSH, &
            chunk_steps > 0), COMPRESSED_FLUSH)
         call results%create(results_file, case%name, trim(case%run%title), &
            trim(case%mechanism%mechanism%label), resolved%crank_mpc(), echo, error, &
            has_crank=mech%rotor > 0, energies=chosen(output, 'energies', ''), &
            peaks=output%peaks .and. decimated, compression=output%compression, &
            chunk_steps=chunk_steps)
         if (.not. allocated(error) .and. output%compression > 0) &
            call results%set_steps_per_flush(COMPRESSED_FLUSH, error)
      end associate
      call add_sensor_series(results, mech, sensors, case, error)
      do k = 1, size(bodies)
         if (allocated(error)) exit
         call results%add_body_series(mech%bodies(bodies(k)%index)%name, bodies(k)%num_modes, &
            error, write=chosen(case%output, 'bodies', mech%bodies(bodies(k)%index)%name))
         if (allocated(error) .or. bodies(k)%num_modes == 0) cycle
         call write_body_modes(results, mech%bodies(bodies(k)%index)%name, bodies(k)%modes, error)
      end do
      do j = 1, size(mech%joints)
         if (allocated(error)) exit
         call results%add_joint_series(mech%joints(j)%name, error, write=chosen(case%output, &
            'joints', mech%joints(j)%name))
         if (.not. allocated(error)) call results%add_joint_series(mech%joints(j)%name, error, &
            series='reaction_min_norm', units='1', write=chosen(case%output, 'joints', &
            mech%joints(j)%name))
         if (allocated(error)) exit
         associate (joint => mech%joints(j))
            flags = [(merge(1, 0, any(integrator%dropped == joint%offset + k)), &
               k=1, joint%joint%num_equations)]
            call results%write_int('/joints/' // joint%name // '/redundant_equations', flags, &
               error)
         end associate
      end do
      if (allocated(error)) call add_context(error, 'results file "' // results_file // '"')
   end procedure open_results

   !> A series /sensors/<name> per sensor, with its type and what it measures as attributes.
   subroutine add_sensor_series(results, mech, sensors, case, error)
      type(engine_results_t), intent(inout) :: results
      type(mechanism_t), intent(in) :: mech
      type(sensor_t), intent(in) :: sensors(:)
      type(case_input_t), intent(in) :: case
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
                  error, node=x%node, write=chosen(case%output, 'sensors', trim(x%name)))
            else
               call results%add_sensor_series(trim(x%name), sensor_size(x%kind), &
                  sensor_unit(x%kind, joint_kind), sensor_word(x%kind), body, marker, joint, &
                  error, write=chosen(case%output, 'sensors', trim(x%name)))
            end if
         end associate
      end do
   end subroutine add_sensor_series

   !> A history is written (&output histories): every one by default ('' entries) or with
   !> 'all', those of its kind ('bodies', 'joints', 'energies', 'sensors'), the one named.
   pure logical function chosen(output, kind, name)
      type(output_input_t), intent(in) :: output
      character(len=*), intent(in) :: kind, name
      chosen = all(output%histories == '')
      if (chosen) return
      chosen = any(output%histories == 'all' .or. output%histories == kind)
      if (len(name) > 0) chosen = chosen .or. any(output%histories == name)
   end function chosen

   !> The modal data of a flexible body for reading its modal coordinates back (frequencies,
   !> virtual-node rows, basis, interfaces), engine_results_write_modes.
   module procedure record_failed_start
      type(engine_results_t) :: results
      type(error_t), allocatable :: error
      character(len=:), allocatable :: temp_file, status
      logical :: closed
      integer :: k
      ! after the modes stage only: every flexible body's modes computed (a refusal while the
      ! bodies are built, e.g. a modes_file that does not fit, leaves no file)
      if (.not. (all(bodies%made) .and. any(bodies%num_modes > 0)) .or. self%refused) return
      temp_file = partial_name(self%results_file)
      call results%create(temp_file, self%case%name, trim(self%case%run%title), &
         trim(self%case%mechanism%mechanism%label), '', case_echo(self%case), error, &
         has_crank=.false., engine=.true.)
      if (allocated(error)) then
         call abandon_file(temp_file)
         return
      end if
      do k = 1, size(bodies)
         if (allocated(error)) exit
         if (bodies(k)%num_modes > 0) call write_body_modes(results, bodies(k)%modes%name, &
            bodies(k)%modes, error)
      end do
      status = 'error: ' // run_error%message
      if (allocated(error)) status = 'error: ' // error%message
      ! no stage times yet (they start with the recording)
      call results%finish(status, [character(len=80) ::], [real(dp) ::], error, closed=closed)
      if (closed) then
         call commit_file(temp_file, self%results_file, error)
      else
         call abandon_file(temp_file)
      end if
   end procedure record_failed_start

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

   module procedure grow
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
   end procedure grow

   module procedure log_statistics
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
   end procedure log_statistics

   module procedure write_run_information
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
   end procedure write_run_information

   module procedure write_animations
      integer :: frames, f, k, first, n, s
      integer, allocatable :: steps(:)
      real(dp) :: angle_end, angle_start, target
      real(dp), allocatable :: fields(:, :), x(:)
      character(len=:), allocatable :: file_name, span
      type(xdmf_body_t), allocatable :: grown(:)
      type(stage_timer_t) :: timer
      allocate (exported(0))
      xdmf_seconds = 0.0_dp
      n = history%num_steps
      if (.not. any(bodies%num_modes > 0)) return
      frames = case%mechanism%mechanism%animation_frames
      if (n < 2) frames = 0
      if (frames == 0 .and. .not. xdmf) return
      allocate (steps(frames))
      if (frames > 0) then
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
         s = 1
         do f = 1, frames
            target = angle_start + (angle_end - angle_start) * real(f - 1, dp) / &
               real(max(frames - 1, 1), dp)
            do while (s < n)
               if (abs(x(s + 1) - target) > abs(x(s) - target)) exit
               s = s + 1
            end do
            steps(f) = s
         end do
      end if
      first = 0
      do k = 1, size(bodies)
         if (bodies(k)%num_modes == 0) cycle
         associate (modes => bodies(k)%modes, m => bodies(k)%num_modes)
            fields = matmul(modes%shape, history%zeta(first + 1:first + m, steps))
            if (frames > 0) then
               file_name = insert_suffix(join_path(options%output_dir, &
                  trim(case%run%output)), '_' // modes%name // '_animation')
               file_name = file_name(:index(file_name, '.', back=.true.)) // 'msh'
               call write_displacement_frames_msh(file_name, modes%mesh%xyz, modes%mesh%tets, &
                  fields, history%t(steps), error)
               if (allocated(error)) return
               call log%info('output', modes%name // ': elastic deformation over ' // span // &
                  ' for gmsh: ' // file_name)
            end if
            if (xdmf) then
               ! the same frames into the results file (/xdmf/<body>), grown by hand
               call timer%begin()
               allocate (grown(size(exported) + 1))
               grown(:size(exported)) = exported
               call results%write_xdmf_body(modes%name, modes%mesh%xyz, modes%mesh%tets, &
                  fields, history%t(steps), grown(size(grown)), error)
               call move_alloc(grown, exported)
               xdmf_seconds = xdmf_seconds + timer%seconds()
               if (allocated(error)) return
            end if
            first = first + m
         end associate
      end do
   end procedure write_animations

end submodule ffrf_app_mechanism_output_file
