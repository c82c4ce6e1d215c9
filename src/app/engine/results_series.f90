!> The time series of an engine results file (a submodule of ffrf_app_engine_results): the
!> file created, series added, steps buffered and flushed, the history of an earlier run
!> appended, the status set at the end.
submodule (ffrf_app_engine_results) ffrf_app_engine_results_series
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_io_results, only: results_create
   use ffrf_io_hdf5, only: series_storage_bytes
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
      logical :: has_engine, has_energies

      self%has_crank = .true.
      if (present(has_crank)) self%has_crank = has_crank
      has_engine = self%has_crank
      if (present(engine)) has_engine = engine
      has_energies = .true.
      if (present(energies)) has_energies = energies
      self%peaks = .false.
      if (present(peaks)) self%peaks = peaks
      self%file_name = file_name
      self%num_buffered = 0
      self%num_recorded = 0
      self%num_pending = 0
      self%num_sensor_values = 0
      self%num_joint_series = 0
      self%num_modes = [integer ::]
      self%paths = [character(len=256) ::]
      self%rows = [integer ::]
      self%category = [integer ::]
      self%offset = [integer ::]
      if (allocated(self%buffer)) deallocate (self%buffer)
      if (allocated(self%peak_buffer)) deallocate (self%peak_buffer)
      if (allocated(self%last)) deallocate (self%last, self%low, self%high, self%t_low, &
         self%t_high)
      call results_create(file_name, case_name, title, echo, self%h5, error)
      if (allocated(error)) return
      self%chunk_steps = 0
      if (present(chunk_steps)) self%chunk_steps = chunk_steps
      if (present(compression)) then
         call self%h5%set_compression(compression, self%chunk_steps)
      else
         call self%h5%set_compression(0, self%chunk_steps)
      end if
      if (has_engine) then
         call self%h5%write_string('/engine/rc_set', rc_set_label, error)
         if (.not. allocated(error)) call self%h5%write_string('/engine/mpc', mpc_label, error)
         if (.not. allocated(error)) call self%h5%set_attribute('/engine', 'rc_set', &
            rc_set_label, error)
         if (.not. allocated(error)) call self%h5%set_attribute('/engine', 'mpc', mpc_label, &
            error)
      end if
      do k = 1, NUM_SCALARS
         if (.not. self%has_crank .and. (k == 2 .or. k == 3)) cycle
         if (.not. has_engine .and. k == 4) cycle
         if (.not. has_energies .and. k >= 5) cycle
         if (.not. allocated(error)) call add_series(self, trim(SCALAR_PATHS(k)), 0, &
            trim(SCALAR_UNITS(k)), 1, k - 1, error)
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
      integer :: first
      call check_not_started(self, 'add_body_series', error)
      if (allocated(error)) return
      if (num_modes < 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": body "' // body_name // '" has ' // to_str(num_modes) // ' modes; give >= 0')
         return
      end if
      first = sum(self%num_modes + 7)
      self%num_modes = [self%num_modes, num_modes]
      if (.not. wanted(write)) return
      path = '/bodies/' // body_name
      call add_series(self, trim(path) // '/position', 3, 'm', 3, first, error)
      if (.not. allocated(error)) call add_series(self, trim(path) // '/euler_parameters', 4, &
         '1', 3, first + 3, error)
      if (.not. allocated(error) .and. num_modes > 0) call add_series(self, trim(path) // &
         '/modal_coordinates', num_modes, '1', 3, first + 7, error)
   end procedure engine_results_add_body_series

   module procedure engine_results_add_joint_series
      character(len=256) :: path
      call check_not_started(self, 'add_joint_series', error)
      if (allocated(error)) return
      self%num_joint_series = self%num_joint_series + 1
      if (.not. wanted(write)) return
      path = '/joints/' // joint_name // '/reaction'
      if (present(series)) path = '/joints/' // joint_name // '/' // series
      if (present(units)) then
         call add_series(self, trim(path), REACTION_ROWS, units, 4, REACTION_ROWS * &
            (self%num_joint_series - 1), error)
      else
         call add_series(self, trim(path), REACTION_ROWS, 'N, N m', 4, REACTION_ROWS * &
            (self%num_joint_series - 1), error)
      end if
   end procedure engine_results_add_joint_series

   module procedure engine_results_add_sensor_series
      character(len=256) :: path
      path = '/sensors/' // name
      call check_not_started(self, 'add_sensor_series', error)
      if (allocated(error)) return
      self%num_sensor_values = self%num_sensor_values + rows
      if (.not. wanted(write)) return
      call add_series(self, trim(path), rows, unit, 2, self%num_sensor_values - rows, error)
      if (.not. allocated(error)) call self%h5%set_attribute(trim(path), 'type', type, error)
      if (.not. allocated(error) .and. len_trim(body) > 0) call self%h5%set_attribute( &
         trim(path), 'body', body, error)
      if (.not. allocated(error) .and. len_trim(marker) > 0) call self%h5%set_attribute( &
         trim(path), 'marker', marker, error)
      if (.not. allocated(error) .and. len_trim(joint) > 0) call self%h5%set_attribute( &
         trim(path), 'joint', joint, error)
      if (.not. allocated(error) .and. present(node)) call self%h5%set_attribute(trim(path), &
         'node', node, error)
   end procedure engine_results_add_sensor_series

   module procedure engine_results_record
      real(dp) :: d_s, d_p
      real(dp), allocatable :: values(:)

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
         size(reactions, 2) /= self%num_joint_series) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": record got ' // to_str(size(modal)) // ' body coordinates and reactions ' // &
            to_str(size(reactions, 1)) // ' x ' // to_str(size(reactions, 2)) // &
            ', expected ' // to_str(sum(self%num_modes + 7)) // ' and ' // &
            to_str(REACTION_ROWS) // ' x ' // to_str(self%num_joint_series) // &
            ' (the bodies and joints added)')
         return
      end if
      if (.not. (all(ieee_is_finite([t, crank_angle, crank_speed, pressure, energies, d_s, &
         d_p])) .and. all(ieee_is_finite(modal)) .and. all(ieee_is_finite(reactions)))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'engine results "' // self%file_name // &
            '": non-finite value at step ' // to_str(self%num_recorded + 1) // ', t = ' // &
            to_str(t) // ' s (crank speed ' // to_str(crank_speed) // ' rad/s): the ' // &
            'integration diverged; reduce the time step')
         return
      end if
      if (self%num_sensor_values > 0) then
         if (.not. present(sensors)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
               '": record got no sensor values; expected ' // to_str(self%num_sensor_values))
            return
         end if
         if (size(sensors) /= self%num_sensor_values) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
               '": record got ' // to_str(size(sensors)) // ' sensor values, expected ' // &
               to_str(self%num_sensor_values))
            return
         end if
         if (.not. all(ieee_is_finite(sensors))) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'engine results "' // self%file_name &
               // '": non-finite sensor value at step ' // to_str(self%num_recorded + 1) // &
               ', t = ' // to_str(t) // ' s: the integration diverged; reduce the time step')
            return
         end if
         values = [t, crank_angle, crank_speed, pressure, energies, d_s, d_p, sensors, modal, &
            reshape(reactions, [size(reactions)])]
      else
         values = [t, crank_angle, crank_speed, pressure, energies, d_s, d_p, modal, &
            reshape(reactions, [size(reactions)])]
      end if
      if (.not. allocated(self%buffer)) then
         allocate (self%buffer(size(values), self%steps_per_flush))
         if (self%peaks) allocate (self%peak_buffer(size(values), 4, self%steps_per_flush))
      end if
      call enter_interval(self, t, values)
      if (present(sample)) then
         if (.not. sample) return
      end if
      call take_sample(self, error)
   end procedure engine_results_record

   module procedure engine_results_flush
      integer :: k, n, first, last, column

      n = self%num_buffered
      do k = 1, size(self%paths)
         if (n == 0) exit
         first = value_index(self, k)
         last = first + max(self%rows(k), 1) - 1
         if (self%rows(k) == 0) then
            call self%h5%append(trim(self%paths(k)), self%buffer(first, 1:n), error)
         else
            call self%h5%append(trim(self%paths(k)), self%buffer(first:last, 1:n), error)
         end if
         if (allocated(error)) return
         if (.not. self%peaks .or. k == 1) cycle
         do column = 1, 4
            if (self%rows(k) == 0) then
               call self%h5%append(peak_path(self%paths(k), column), &
                  self%peak_buffer(first, column, 1:n), error)
            else
               call self%h5%append(peak_path(self%paths(k), column), &
                  self%peak_buffer(first:last, column, 1:n), error)
            end if
            if (allocated(error)) return
         end do
      end do
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
      ! the last state is always written: the end of a decimated interval becomes a sample
      if (.not. allocated(error) .and. self%num_pending > 0) call take_sample(self, error)
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

   module procedure engine_results_interval_state
      if (.not. self%peaks .or. .not. allocated(self%last)) then
         allocate (state(0))
         return
      end if
      state = [real(self%num_pending, dp), self%last_t, self%last, self%low, self%high, &
         self%t_low, self%t_high]
   end procedure engine_results_interval_state

   module procedure engine_results_restore_interval
      integer :: n
      self%num_pending = 0
      if (size(state) == 0) return
      n = (size(state) - 2) / 5
      if (.not. self%peaks .or. size(state) /= 2 + 5 * n) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": the earlier run''s output interval (' // to_str(size(state)) // ' values) ' // &
            'does not fit this run''s output; restart with the same &output')
         return
      end if
      self%num_pending = nint(state(1))
      self%last_t = state(2)
      self%last = state(3:2 + n)
      self%low = state(3 + n:2 + 2 * n)
      self%high = state(3 + 2 * n:2 + 3 * n)
      self%t_low = state(3 + 3 * n:2 + 4 * n)
      self%t_high = state(3 + 4 * n:2 + 5 * n)
   end procedure engine_results_restore_interval

   module procedure engine_results_predicted_bytes
      integer :: k, copies
      bytes = 0_i8
      do k = 1, size(self%paths)
         copies = 1
         if (self%peaks .and. k > 1) copies = 5
         bytes = bytes + copies * series_storage_bytes(self%rows(k), num_samples, &
            self%chunk_steps)
      end do
   end procedure engine_results_predicted_bytes

   module procedure engine_results_append_from
      integer :: k, column
      call check_not_started(self, 'append_from', error)
      if (allocated(error)) return
      do k = 1, size(self%paths)
         call copy_series(trim(self%paths(k)), self%rows(k) == 0)
         if (allocated(error)) return
         if (.not. self%peaks .or. k == 1) cycle
         do column = 1, 4
            call copy_series(peak_path(self%paths(k), column), self%rows(k) == 0)
            if (allocated(error)) return
         end do
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

   !> Create the series `path` (rows values per step, 0: scalar) and, with peaks, its
   !> /peaks series (not for /time/t); it takes the values category/offset of a step.
   subroutine add_series(self, path, rows, units, category, offset, error)
      type(engine_results_t), intent(inout) :: self
      character(len=*), intent(in) :: path, units
      integer, intent(in) :: rows, category, offset
      type(error_t), allocatable, intent(out) :: error
      integer :: column
      call self%h5%create_series(path, rows, units, error)
      if (allocated(error)) return
      if (self%peaks .and. size(self%paths) > 0) then
         do column = 1, 4
            if (column <= 2) then
               call self%h5%create_series(peak_path(path, column), rows, units, error)
            else
               call self%h5%create_series(peak_path(path, column), rows, 's', error)
            end if
            if (allocated(error)) return
         end do
      end if
      self%paths = [character(len=256) :: self%paths, path]
      self%rows = [self%rows, rows]
      self%category = [self%category, category]
      self%offset = [self%offset, offset]
   end subroutine add_series

   !> /peaks/<path>/{min, max, t_min, t_max} (column 1..4).
   pure function peak_path(path, column) result(peak)
      character(len=*), intent(in) :: path
      integer, intent(in) :: column
      character(len=:), allocatable :: peak
      character(len=*), parameter :: names(4) = ['min  ', 'max  ', 't_min', 't_max']
      peak = '/peaks' // trim(path) // '/' // trim(names(column))
   end function peak_path

   !> Index in a step's values of the first value of series k.
   pure integer function value_index(self, k) result(first)
      type(engine_results_t), intent(in) :: self
      integer, intent(in) :: k
      select case (self%category(k))
      case (1)
         first = 1
      case (2)
         first = 1 + NUM_SCALARS
      case (3)
         first = 1 + NUM_SCALARS + self%num_sensor_values
      case default
         first = 1 + NUM_SCALARS + self%num_sensor_values + sum(self%num_modes + 7)
      end select
      first = first + self%offset(k)
   end function value_index

   !> A step enters the output interval: its values are the last, the extremes are updated (the
   !> first step of a tie keeps its time).
   subroutine enter_interval(self, t, values)
      type(engine_results_t), intent(inout) :: self
      real(dp), intent(in) :: t, values(:)
      self%last = values
      self%last_t = t
      if (.not. self%peaks) return
      if (self%num_pending == 0) then
         self%low = values
         self%high = values
         self%t_low = spread(t, 1, size(values))
         self%t_high = self%t_low
      else
         where (values < self%low)
            self%low = values
            self%t_low = t
         end where
         where (values > self%high)
            self%high = values
            self%t_high = t
         end where
      end if
      self%num_pending = self%num_pending + 1
   end subroutine enter_interval

   !> The last step of the interval becomes a sample (with the interval's extremes); the
   !> interval ends; a full buffer is flushed.
   subroutine take_sample(self, error)
      type(engine_results_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
      integer :: n
      if (.not. allocated(self%buffer)) then
         allocate (self%buffer(size(self%last), self%steps_per_flush))
         if (self%peaks) allocate (self%peak_buffer(size(self%last), 4, self%steps_per_flush))
      end if
      n = self%num_buffered + 1
      self%buffer(:, n) = self%last
      if (self%peaks) then
         self%peak_buffer(:, 1, n) = self%low
         self%peak_buffer(:, 2, n) = self%high
         self%peak_buffer(:, 3, n) = self%t_low
         self%peak_buffer(:, 4, n) = self%t_high
      end if
      self%num_pending = 0
      self%num_buffered = n
      self%num_recorded = self%num_recorded + 1
      if (n == self%steps_per_flush) call self%flush(error)
   end subroutine take_sample

   !> The optional `write` flag of an add_* call (default .true.).
   pure logical function wanted(write)
      logical, intent(in), optional :: write
      wanted = .true.
      if (present(write)) wanted = write
   end function wanted

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
