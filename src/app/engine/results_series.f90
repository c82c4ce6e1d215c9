!> The time series of an engine results file (a submodule of ffrf_app_engine_results): the
!> file created, series added, steps buffered and flushed, the history of an earlier run
!> appended, the status set at the end.
submodule (ffrf_app_engine_results) ffrf_app_engine_results_series
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_io_results, only: results_create
   implicit none

   !> Paths of the scalar series, in the order of the buffer columns.
   character(len=*), parameter :: SCALAR_PATHS(NUM_SCALARS) = [character(len=35) :: &
      '/time/t', '/time/crank_angle', '/time/crank_speed', '/time/pressure', &
      '/energy/kinetic', '/energy/strain', '/energy/external_work', &
      '/energy/numerical_dissipation', '/energy/scheme_dissipation', &
      '/energy/damping_dissipation']
   !> Units of the scalar series.
   character(len=*), parameter :: SCALAR_UNITS(NUM_SCALARS) = [character(len=5) :: &
      's', 'rad', 'rad/s', 'Pa', 'J', 'J', 'J', 'J', 'J', 'J']

contains

   module procedure engine_results_create
      integer :: k

      self%has_crank = .true.
      if (present(has_crank)) self%has_crank = has_crank
      self%sensor_paths = [character(len=256) ::]
      self%sensor_rows = [integer ::]
      if (allocated(self%sensor_buffer)) deallocate (self%sensor_buffer)
      self%file_name = file_name
      self%num_buffered = 0
      self%num_recorded = 0
      self%body_paths = [character(len=256) ::]
      self%joint_paths = [character(len=256) ::]
      self%num_modes = [integer ::]
      if (allocated(self%scalars)) deallocate (self%scalars, self%modal, self%reactions)
      call results_create(file_name, case_name, title, echo, self%h5, error)
      if (.not. allocated(error)) call self%h5%write_string('/engine/rc_set', rc_set_label, error)
      if (.not. allocated(error)) call self%h5%write_string('/engine/mpc', mpc_label, error)
      if (.not. allocated(error)) call self%h5%set_attribute('/engine', 'rc_set', rc_set_label, &
         error)
      if (.not. allocated(error)) call self%h5%set_attribute('/engine', 'mpc', mpc_label, error)
      do k = 1, NUM_SCALARS
         if (.not. self%has_crank .and. (k == 2 .or. k == 3)) cycle
         if (.not. allocated(error)) call self%h5%create_series(trim(SCALAR_PATHS(k)), 0, &
            trim(SCALAR_UNITS(k)), error)
      end do
      if (.not. allocated(error)) call self%h5%flush(error)
      if (allocated(error)) call add_context(error, 'engine results file "' // file_name // '"')
   end procedure engine_results_create

   module procedure engine_results_set_steps_per_flush
      if (steps < 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": steps per flush ' // to_str(steps) // ' must be at least 1')
         return
      end if
      call check_not_started(self, 'set_steps_per_flush', error)
      if (.not. allocated(error)) self%steps_per_flush = steps
   end procedure engine_results_set_steps_per_flush

   module procedure engine_results_add_body_series
      character(len=256) :: path
      call check_not_started(self, 'add_body_series', error)
      if (allocated(error)) return
      if (num_modes < 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": body "' // body_name // '" has ' // to_str(num_modes) // ' modes; give >= 0')
         return
      end if
      path = '/bodies/' // body_name
      call self%h5%create_series(trim(path) // '/position', 3, 'm', error)
      if (.not. allocated(error)) call self%h5%create_series(trim(path) // &
         '/euler_parameters', 4, '1', error)
      if (.not. allocated(error) .and. num_modes > 0) call self%h5%create_series(trim(path) &
         // '/modal_coordinates', num_modes, '1', error)
      if (allocated(error)) return
      self%body_paths = [character(len=256) :: self%body_paths, path]
      self%num_modes = [self%num_modes, num_modes]
   end procedure engine_results_add_body_series

   module procedure engine_results_add_joint_series
      character(len=256) :: path
      call check_not_started(self, 'add_joint_series', error)
      if (allocated(error)) return
      path = '/joints/' // joint_name // '/reaction'
      if (present(series)) path = '/joints/' // joint_name // '/' // series
      if (present(units)) then
         call self%h5%create_series(trim(path), REACTION_ROWS, units, error)
      else
         call self%h5%create_series(trim(path), REACTION_ROWS, 'N, N m', error)
      end if
      if (allocated(error)) return
      self%joint_paths = [character(len=256) :: self%joint_paths, path]
   end procedure engine_results_add_joint_series

   module procedure engine_results_add_sensor_series
      character(len=256) :: path
      call check_not_started(self, 'add_sensor_series', error)
      if (allocated(error)) return
      path = '/sensors/' // name
      call self%h5%create_series(trim(path), rows, unit, error)
      if (.not. allocated(error)) call self%h5%set_attribute(trim(path), 'type', type, error)
      if (.not. allocated(error) .and. len_trim(body) > 0) call self%h5%set_attribute( &
         trim(path), 'body', body, error)
      if (.not. allocated(error) .and. len_trim(marker) > 0) call self%h5%set_attribute( &
         trim(path), 'marker', marker, error)
      if (.not. allocated(error) .and. len_trim(joint) > 0) call self%h5%set_attribute( &
         trim(path), 'joint', joint, error)
      if (.not. allocated(error) .and. present(node)) call self%h5%set_attribute(trim(path), &
         'node', node, error)
      if (allocated(error)) return
      self%sensor_paths = [character(len=256) :: self%sensor_paths, path]
      self%sensor_rows = [self%sensor_rows, rows]
   end procedure engine_results_add_sensor_series

   module procedure engine_results_record
      real(dp) :: d_s, d_p
      integer :: n

      d_s = 0.0_dp
      if (present(scheme_dissipation)) d_s = scheme_dissipation
      d_p = 0.0_dp
      if (present(damping_dissipation)) d_p = damping_dissipation
      if (.not. self%h5%is_open()) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results: record called on a file ' // &
            'that is not open; call create first')
         return
      end if
      if (size(modal) /= sum(self%num_modes + 7) .or. size(reactions, 1) /= REACTION_ROWS .or. &
         size(reactions, 2) /= size(self%joint_paths)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": record got ' // to_str(size(modal)) // ' body coordinates and reactions ' // &
            to_str(size(reactions, 1)) // ' x ' // to_str(size(reactions, 2)) // &
            ', expected ' // to_str(sum(self%num_modes + 7)) // ' and ' // &
            to_str(REACTION_ROWS) // ' x ' // to_str(size(self%joint_paths)) // &
            ' (the bodies and joints added)')
         return
      end if
      if (.not. (all(ieee_is_finite([t, crank_angle, crank_speed, pressure, energies, d_s, &
         d_p])) &
         .and. &
         all(ieee_is_finite(modal)) .and. all(ieee_is_finite(reactions)))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'engine results "' // self%file_name // &
            '": non-finite value at step ' // to_str(self%num_recorded + 1) // ', t = ' // &
            to_str(t) // ' s (crank speed ' // to_str(crank_speed) // ' rad/s): the ' // &
            'integration diverged; reduce the time step')
         return
      end if
      if (sum(self%sensor_rows) > 0) then
         if (.not. present(sensors)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
               '": record got no sensor values; expected ' // to_str(sum(self%sensor_rows)))
            return
         end if
         if (size(sensors) /= sum(self%sensor_rows)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
               '": record got ' // to_str(size(sensors)) // ' sensor values, expected ' // &
               to_str(sum(self%sensor_rows)))
            return
         end if
         if (.not. all(ieee_is_finite(sensors))) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'engine results "' // self%file_name &
               // '": non-finite sensor value at step ' // to_str(self%num_recorded + 1) // &
               ', t = ' // to_str(t) // ' s: the integration diverged; reduce the time step')
            return
         end if
         if (.not. allocated(self%sensor_buffer)) allocate (self%sensor_buffer( &
            sum(self%sensor_rows), self%steps_per_flush))
         self%sensor_buffer(:, self%num_buffered + 1) = sensors
      end if
      if (.not. allocated(self%scalars)) then
         allocate (self%scalars(self%steps_per_flush, NUM_SCALARS))
         allocate (self%modal(sum(self%num_modes + 7), self%steps_per_flush))
         allocate (self%reactions(REACTION_ROWS, self%steps_per_flush, size(self%joint_paths)))
      end if
      n = self%num_buffered + 1
      self%scalars(n, :) = [t, crank_angle, crank_speed, pressure, energies, d_s, d_p]
      self%modal(:, n) = modal
      self%reactions(:, n, :) = reactions
      self%num_buffered = n
      self%num_recorded = self%num_recorded + 1
      if (n == self%steps_per_flush) call self%flush(error)
   end procedure engine_results_record

   module procedure engine_results_flush
      real(dp), allocatable :: block(:, :)
      integer :: k, n, first

      n = self%num_buffered
      if (n > 0) then
         do k = 1, NUM_SCALARS
            if (.not. self%has_crank .and. (k == 2 .or. k == 3)) cycle
            call self%h5%append(trim(SCALAR_PATHS(k)), self%scalars(1:n, k), error)
            if (allocated(error)) return
         end do
         first = 1
         do k = 1, size(self%sensor_paths)
            block = self%sensor_buffer(first:first + self%sensor_rows(k) - 1, 1:n)
            call self%h5%append(trim(self%sensor_paths(k)), block, error)
            if (allocated(error)) return
            first = first + self%sensor_rows(k)
         end do
         first = 1
         do k = 1, size(self%body_paths)
            block = self%modal(first:first + 2, 1:n)
            call self%h5%append(trim(self%body_paths(k)) // '/position', block, error)
            if (allocated(error)) return
            block = self%modal(first + 3:first + 6, 1:n)
            call self%h5%append(trim(self%body_paths(k)) // '/euler_parameters', block, error)
            if (allocated(error)) return
            if (self%num_modes(k) > 0) then
               block = self%modal(first + 7:first + 6 + self%num_modes(k), 1:n)
               call self%h5%append(trim(self%body_paths(k)) // '/modal_coordinates', block, &
                  error)
               if (allocated(error)) return
            end if
            first = first + 7 + self%num_modes(k)
         end do
         do k = 1, size(self%joint_paths)
            call self%h5%append(trim(self%joint_paths(k)), self%reactions(:, 1:n, k), error)
            if (allocated(error)) return
         end do
      end if
      self%num_buffered = 0
      call self%h5%flush(error)
   end procedure engine_results_flush

   module procedure engine_results_finish
      type(error_t), allocatable :: ignored, close_error

      if (size(stage_names) /= size(stage_seconds)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": ' // to_str(size(stage_names)) // ' stage names but ' // &
            to_str(size(stage_seconds)) // ' stage times')
      end if
      if (present(stage_peak_mib) .and. .not. allocated(error)) then
         if (size(stage_peak_mib) /= size(stage_names)) call fatal_error(error, &
            FFRF_INPUT_ERROR, 'engine results "' // self%file_name // '": ' // &
            to_str(size(stage_names)) // ' stage names but ' // to_str(size(stage_peak_mib)) &
            // ' peak memory values')
      end if
      if (.not. allocated(error)) call self%flush(error)
      if (.not. allocated(error) .and. size(stage_names) > 0) then
         call self%h5%write_string_list('/timings/stage', stage_names, error)
         if (.not. allocated(error)) call self%h5%write_real('/timings/seconds', stage_seconds, &
            's', error)
         if (.not. allocated(error) .and. present(stage_peak_mib)) call self%h5%write_real( &
            '/timings/peak_memory_mib', stage_peak_mib, 'MiB', error)
      end if
      if (.not. allocated(error)) call self%h5%set_status(status, error)
      if (allocated(error)) call self%h5%set_status('error: ' // error%message, ignored)
      call self%h5%close(close_error)
      if (present(closed)) closed = .not. allocated(close_error)
      if (.not. allocated(error) .and. allocated(close_error)) call move_alloc(close_error, error)
   end procedure engine_results_finish

   module procedure engine_results_num_steps
      num_steps = self%num_recorded
   end procedure engine_results_num_steps

   module procedure engine_results_append_from
      integer :: k
      call check_not_started(self, 'append_from', error)
      if (allocated(error)) return
      do k = 1, NUM_SCALARS
         if (.not. self%has_crank .and. (k == 2 .or. k == 3)) cycle
         call copy_series(trim(SCALAR_PATHS(k)), .true.)
         if (allocated(error)) return
      end do
      do k = 1, size(self%sensor_paths)
         call copy_series(trim(self%sensor_paths(k)), .false.)
         if (allocated(error)) return
      end do
      do k = 1, size(self%body_paths)
         call copy_series(trim(self%body_paths(k)) // '/position', .false.)
         if (.not. allocated(error)) call copy_series(trim(self%body_paths(k)) // &
            '/euler_parameters', .false.)
         if (.not. allocated(error) .and. self%num_modes(k) > 0) call copy_series( &
            trim(self%body_paths(k)) // '/modal_coordinates', .false.)
         if (allocated(error)) return
      end do
      do k = 1, size(self%joint_paths)
         call copy_series(trim(self%joint_paths(k)), .false.)
         if (allocated(error)) return
      end do
      self%num_recorded = num_steps
      call self%h5%flush(error)

   contains

      subroutine copy_series(path, scalar)
         character(len=*), intent(in) :: path
         logical, intent(in) :: scalar
         real(dp), allocatable :: x(:), xx(:, :)
         if (scalar) then
            call source%read_real(path, x, error)
            if (.not. allocated(error)) then
               if (size(x) < num_steps) call short(size(x))
            end if
            if (.not. allocated(error) .and. num_steps > 0) call self%h5%append(path, &
               x(1:num_steps), error)
         else
            call source%read_real(path, xx, error)
            if (.not. allocated(error)) then
               if (size(xx, 2) < num_steps) call short(size(xx, 2))
            end if
            if (.not. allocated(error) .and. num_steps > 0) call self%h5%append(path, &
               xx(:, 1:num_steps), error)
         end if
      end subroutine copy_series

      subroutine short(length)
         integer, intent(in) :: length
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": the earlier run''s series hold ' // to_str(length) // ' steps, fewer than ' // &
            'the ' // to_str(num_steps) // ' of its restart state')
      end subroutine short

   end procedure engine_results_append_from

   !> Error unless the file is open and no step has been recorded.
   subroutine check_not_started(self, what, error)
      type(engine_results_t), intent(in) :: self
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      if (.not. self%h5%is_open()) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results: ' // what // ' called on ' // &
            'a file that is not open; call create first')
      else if (self%num_recorded > 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": ' // what // ' called after ' // to_str(self%num_recorded) // ' steps were ' // &
            'recorded; add every body and joint before the first record')
      end if
   end subroutine check_not_started

end submodule ffrf_app_engine_results_series
