!> The results file of an engine run (HDF5): the time histories, written progressively so that a
!> run killed at any point leaves a readable file with status 'running' and every step up to the
!> last flush (issue 3, part 5). Schema (read by postprocess/ffrf_results.py, `read_engine`):
!> root attributes status, case_name, title, ffrf_version; /input/namelist; /build/versions;
!> /engine with attributes rc_set and mpc (also as the string datasets /engine/rc_set and
!> /engine/mpc: a group needs a dataset to exist); growing series (one entry per step)
!> /time/{t [s], crank_angle [rad, unwrapped], crank_speed [rad/s], pressure [Pa]} (the crank
!> series only when the run has a crank: create's has_crank),
!> /sensors/<name> (one per sensor, sum of their values per step; attributes units, type, body,
!> marker, joint; docs/sensors.md),
!> /energy/{kinetic, strain, external_work, numerical_dissipation, scheme_dissipation,
!> damping_dissipation} [J] (ffrf_mbs_energy_balance: D = W - dT - dU - D_p, D_s from the
!> integrator's identity, D_p the energy taken by the modal damping),
!> /bodies/<body>/{position (3 rows) [m], euler_parameters (4 rows) [1]} (the body frame),
!> /bodies/<body>/modal_coordinates (num_modes rows, flexible bodies only) [1],
!> /joints/<joint>/reaction (12 rows: force and moment on each of the two bodies) [N, N m];
!> at the end /timings/stage, /timings/seconds [s], /timings/peak_memory_mib [MiB] (when given)
!> and status 'complete' or the error message. `write_modes` stores, per flexible body, what the
!> modal coordinates need to be read back in physical terms: /bodies/<body>/modes/{frequency [Hz],
!> virtual_node_shape (6 n_if rows, m)} (attributes basis, num_static_modes) and
!> /bodies/<body>/interfaces/{order, <name>/virtual_node [m]}; the virtual-node motion in the
!> body frame is virtual_node_shape zeta(t).
!> `write_real`/`write_int` store run information (redundant joint equations, integrator
!> counters) anywhere in the file.
!> Steps are buffered in memory and appended + flushed every `steps_per_flush` steps (100 by
!> default) and by `finish`: HDF5 is touched once per chunk, not once per step.
module ffrf_app_engine_results
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_io_hdf5, only: h5_file_t
   use ffrf_io_results, only: results_create
   implicit none
   private
   public :: engine_results_t

   !> Number of scalar series: 4 /time series and 6 /energy series.
   integer, parameter :: NUM_SCALARS = 10
   !> Paths of the scalar series, in the order of the buffer columns.
   character(len=*), parameter :: SCALAR_PATHS(NUM_SCALARS) = [character(len=35) :: &
      '/time/t', '/time/crank_angle', '/time/crank_speed', '/time/pressure', &
      '/energy/kinetic', '/energy/strain', '/energy/external_work', &
      '/energy/numerical_dissipation', '/energy/scheme_dissipation', &
      '/energy/damping_dissipation']
   !> Units of the scalar series.
   character(len=*), parameter :: SCALAR_UNITS(NUM_SCALARS) = [character(len=5) :: &
      's', 'rad', 'rad/s', 'Pa', 'J', 'J', 'J', 'J', 'J', 'J']
   !> Rows of a joint reaction: force and moment on both bodies.
   integer, parameter :: REACTION_ROWS = 12

   !> Writer of an engine results file. Use: `create`, then `add_body_series` /
   !> `add_joint_series` for each body and joint, then `record` once per step, then `finish`.
   type :: engine_results_t
      private
      !> The open file
      type(h5_file_t) :: h5
      !> File name, for messages
      character(len=:), allocatable :: file_name
      !> Steps buffered before appending and flushing
      integer :: steps_per_flush = 100
      !> Steps in the buffer
      integer :: num_buffered = 0
      !> Steps recorded so far (buffered or written)
      integer :: num_recorded = 0
      !> Paths of the body groups and joint series
      character(len=256), allocatable :: body_paths(:), joint_paths(:)
      !> Modes per body
      integer, allocatable :: num_modes(:)
      !> The run has a crank: /time/crank_angle and /time/crank_speed are written (create)
      logical :: has_crank = .true.
      !> Sensor series /sensors/<name> and their numbers of values
      character(len=256), allocatable :: sensor_paths(:)
      integer, allocatable :: sensor_rows(:)
      !> Buffered sensor values (sum(sensor_rows), steps_per_flush)
      real(dp), allocatable :: sensor_buffer(:, :)
      !> Buffered scalars (steps_per_flush, NUM_SCALARS)
      real(dp), allocatable :: scalars(:, :)
      !> Buffered coordinates [R; theta; zeta] of all bodies, stacked
      !> (sum(7 + num_modes), steps_per_flush)
      real(dp), allocatable :: modal(:, :)
      !> Buffered reactions (REACTION_ROWS, steps_per_flush, num_joints)
      real(dp), allocatable :: reactions(:, :, :)
   contains
      procedure :: create => engine_results_create
      procedure :: set_steps_per_flush => engine_results_set_steps_per_flush
      procedure :: add_body_series => engine_results_add_body_series
      procedure :: add_joint_series => engine_results_add_joint_series
      procedure :: add_sensor_series => engine_results_add_sensor_series
      procedure :: record => engine_results_record
      procedure :: flush => engine_results_flush
      procedure :: finish => engine_results_finish
      procedure :: num_steps => engine_results_num_steps
      procedure :: write_real => engine_results_write_real
      procedure :: write_matrix => engine_results_write_matrix
      procedure :: write_int => engine_results_write_int
      procedure :: write_strings => engine_results_write_strings
      procedure :: write_modes => engine_results_write_modes
      procedure :: write_long => engine_results_write_long
      procedure :: append_from => engine_results_append_from
   end type engine_results_t

contains

   !> Create the file (truncated if it exists) with status 'running', the input echo, the
   !> /engine attributes and the empty /time and /energy series.
   subroutine engine_results_create(self, file_name, case_name, title, rc_set_label, mpc_label, &
         echo, error, has_crank)
      class(engine_results_t), intent(inout) :: self
      !> Results file
      character(len=*), intent(in) :: file_name
      !> Case name and title
      character(len=*), intent(in) :: case_name, title
      !> Label of the RC set ('RC set 1', 'rigid crank') and the MPC kind ('RBE3', 'rigid')
      character(len=*), intent(in) :: rc_set_label, mpc_label
      !> Resolved input as namelist text
      character(len=*), intent(in) :: echo
      type(error_t), allocatable, intent(out) :: error
      !> .false.: a run without a crank, no /time/crank_angle nor /time/crank_speed (default .true.)
      logical, intent(in), optional :: has_crank
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
   end subroutine engine_results_create

   !> Set how many steps are buffered between two flushes (before the first `record`).
   subroutine engine_results_set_steps_per_flush(self, steps, error)
      class(engine_results_t), intent(inout) :: self
      !> Steps per flush, >= 1
      integer, intent(in) :: steps
      type(error_t), allocatable, intent(out) :: error
      if (steps < 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '": steps per flush ' // to_str(steps) // ' must be at least 1')
         return
      end if
      call check_not_started(self, 'set_steps_per_flush', error)
      if (.not. allocated(error)) self%steps_per_flush = steps
   end subroutine engine_results_set_steps_per_flush

   !> Add the series /bodies/<body_name>/{position, euler_parameters, modal_coordinates} (3, 4
   !> and num_modes rows; no modal series for num_modes = 0), before the first `record`.
   !> `record` takes the bodies' coordinates [R; theta; zeta] stacked in the order of these calls.
   subroutine engine_results_add_body_series(self, body_name, num_modes, error)
      class(engine_results_t), intent(inout) :: self
      !> Body name
      character(len=*), intent(in) :: body_name
      !> Number of modal coordinates (>= 0)
      integer, intent(in) :: num_modes
      type(error_t), allocatable, intent(out) :: error
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
   end subroutine engine_results_add_body_series

   !> Add the series /joints/<joint_name>/reaction (12 rows), before the first `record`.
   !> `record` takes the joints' reactions as columns in the order of these calls. `series`
   !> and `units` name another 12-row series of the joint (default 'reaction', 'N, N m'), e.g.
   !> its per-step flags /joints/<joint>/reaction_min_norm.
   subroutine engine_results_add_joint_series(self, joint_name, error, series, units)
      class(engine_results_t), intent(inout) :: self
      !> Joint name
      character(len=*), intent(in) :: joint_name
      type(error_t), allocatable, intent(out) :: error
      !> Series name under /joints/<joint_name> and its units
      character(len=*), intent(in), optional :: series, units
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
   end subroutine engine_results_add_joint_series

   !> A sensor series /sensors/<name>: `rows` values per step (a (num_steps x rows) dataset in
   !> h5py) with the attributes units, type and, when given, body, marker, joint and node.
   subroutine engine_results_add_sensor_series(self, name, rows, unit, type, body, marker, &
         joint, error, node)
      class(engine_results_t), intent(inout) :: self
      !> Sensor name, unit of its values, its type word, what it measures ('' when not)
      character(len=*), intent(in) :: name
      integer, intent(in) :: rows
      character(len=*), intent(in) :: unit, type, body, marker, joint
      type(error_t), allocatable, intent(out) :: error
      !> Mesh node (Gmsh tag) of a node sensor
      integer, intent(in), optional :: node
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
   end subroutine engine_results_add_sensor_series

   !> Record one step. It is buffered; every `steps_per_flush` steps the buffer is appended to
   !> the series and the file flushed. A non-finite value is an error (nothing is recorded).
   subroutine engine_results_record(self, t, crank_angle, crank_speed, pressure, energies, &
         modal, reactions, error, scheme_dissipation, damping_dissipation, sensors)
      class(engine_results_t), intent(inout) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      !> Crank angle (rad, unwrapped: continuous over revolutions)
      real(dp), intent(in) :: crank_angle
      !> Crank speed (rad/s)
      real(dp), intent(in) :: crank_speed
      !> Cylinder pressure (Pa)
      real(dp), intent(in) :: pressure
      !> Kinetic energy, strain energy, external work, numerical dissipation (J)
      real(dp), intent(in) :: energies(4)
      !> Coordinates [R (3); theta (4); zeta (num_modes)] of the bodies, stacked in the order of
      !> `add_body_series`
      real(dp), intent(in) :: modal(:)
      !> Joint reactions (12, num_joints), columns in the order of `add_joint_series`
      real(dp), intent(in) :: reactions(:, :)
      type(error_t), allocatable, intent(out) :: error
      !> Numerical dissipation of the scheme D_s (J); 0 when absent
      real(dp), intent(in), optional :: scheme_dissipation
      !> Energy taken by the modal damping D_p (J); 0 when absent
      real(dp), intent(in), optional :: damping_dissipation
      !> Values of the sensors added, concatenated in the order of add_sensor_series
      real(dp), intent(in), optional :: sensors(:)
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
   end subroutine engine_results_record

   !> Append the buffered steps to the series and flush the file to disk.
   subroutine engine_results_flush(self, error)
      class(engine_results_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
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
   end subroutine engine_results_flush

   !> Flush the buffer, write the stage timings, set the status ('complete' or the error
   !> message) and close, whatever fails. If a write fails, the status becomes that failure's
   !> message; `closed` tells whether the file was closed cleanly (then it is readable).
   subroutine engine_results_finish(self, status, stage_names, stage_seconds, error, &
         stage_peak_mib, closed)
      class(engine_results_t), intent(inout) :: self
      !> 'complete' or the error message of the run
      character(len=*), intent(in) :: status
      !> Stage names (may be empty)
      character(len=*), intent(in) :: stage_names(:)
      !> Wall time of each stage (s)
      real(dp), intent(in) :: stage_seconds(:)
      type(error_t), allocatable, intent(out) :: error
      !> Peak resident memory of the process at the end of each stage (MiB, VmHWM)
      real(dp), intent(in), optional :: stage_peak_mib(:)
      !> True when the file was closed without error
      logical, intent(out), optional :: closed
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
   end subroutine engine_results_finish

   !> Steps recorded so far (written or buffered).
   pure integer function engine_results_num_steps(self) result(num_steps)
      class(engine_results_t), intent(in) :: self
      num_steps = self%num_recorded
   end function engine_results_num_steps

   !> Write run information, e.g. /integrator/newton_iterations, with its unit.
   subroutine engine_results_write_real(self, path, values, unit, error)
      class(engine_results_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      real(dp), intent(in) :: values(:)
      !> Unit, '1' when dimensionless
      character(len=*), intent(in) :: unit
      type(error_t), allocatable, intent(out) :: error
      call self%h5%write_real(path, values, unit, error)
   end subroutine engine_results_write_real

   !> Write a real matrix, e.g. /bodies/<body>/modes/shape.
   subroutine engine_results_write_matrix(self, path, values, unit, error)
      class(engine_results_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      real(dp), intent(in) :: values(:, :)
      !> Unit, '1' when dimensionless
      character(len=*), intent(in) :: unit
      type(error_t), allocatable, intent(out) :: error
      call self%h5%write_real(path, values, unit, error)
   end subroutine engine_results_write_matrix

   !> Write integer run information, e.g. /joints/<joint>/redundant_equations.
   subroutine engine_results_write_int(self, path, values, error)
      class(engine_results_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      integer, intent(in) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      call self%h5%write_int(path, values, error)
   end subroutine engine_results_write_int

   !> Write a list of strings, e.g. /model_selection/<body>/meshes_tried.
   subroutine engine_results_write_strings(self, path, values, error)
      class(engine_results_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      character(len=*), intent(in) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      call self%h5%write_string_list(path, values, error)
   end subroutine engine_results_write_strings

   !> The modal data of flexible body `body_name` (module header): frequencies, virtual-node rows
   !> of the modes, the basis, and the interfaces' names and virtual-node positions.
   subroutine engine_results_write_modes(self, body_name, frequency_hz, virtual_node_shape, &
         interface_names, virtual_xyz, basis, num_static, error)
      class(engine_results_t), intent(inout) :: self
      !> Body name
      character(len=*), intent(in) :: body_name
      !> Frequencies of the modes (Hz), (m)
      real(dp), intent(in) :: frequency_hz(:)
      !> Virtual-node rows [u; theta] per interface, (6 n_if, m), m kg^-1/2 and rad kg^-1/2
      real(dp), intent(in) :: virtual_node_shape(:, :)
      !> Interface names, in the order of the virtual-node rows
      character(len=*), intent(in) :: interface_names(:)
      !> Virtual-node positions in the body frame, (3, n_if), m
      real(dp), intent(in) :: virtual_xyz(:, :)
      !> 'rc_normal' or 'craig_bampton'
      character(len=*), intent(in) :: basis
      !> Static constraint modes in the basis (0 for rc_normal)
      integer, intent(in) :: num_static
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: root
      integer :: k
      if (size(virtual_node_shape, 1) /= 6 * size(interface_names) .or. &
         size(virtual_node_shape, 2) /= size(frequency_hz) .or. &
         size(virtual_xyz, 2) /= size(interface_names)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'engine results "' // self%file_name // &
            '", body "' // body_name // '": ' // to_str(size(frequency_hz)) // ' modes, ' // &
            to_str(size(interface_names)) // ' interfaces, virtual-node rows ' // &
            to_str(size(virtual_node_shape, 1)) // ' x ' // to_str(size(virtual_node_shape, 2)) &
            // '; need 6 rows per interface and one column per mode')
         return
      end if
      root = '/bodies/' // body_name
      call self%h5%write_real(root // '/modes/frequency', frequency_hz, 'Hz', error)
      if (.not. allocated(error)) call self%h5%write_real(root // '/modes/virtual_node_shape', &
         virtual_node_shape, 'm kg^-1/2 (u), rad kg^-1/2 (theta)', error)
      if (.not. allocated(error)) call self%h5%set_attribute(root // '/modes', 'basis', basis, &
         error)
      if (.not. allocated(error)) call self%h5%set_attribute(root // '/modes', &
         'num_static_modes', num_static, error)
      if (.not. allocated(error) .and. size(interface_names) > 0) call &
         self%h5%write_string_list(root // '/interfaces/order', interface_names, error)
      do k = 1, size(interface_names)
         if (allocated(error)) exit
         call self%h5%write_real(root // '/interfaces/' // trim(interface_names(k)) // &
            '/virtual_node', virtual_xyz(:, k), 'm', error)
      end do
      if (allocated(error)) call add_context(error, 'engine results "' // self%file_name // '"')
   end subroutine engine_results_write_modes

   !> Write 64-bit integer run information (the restart state).
   subroutine engine_results_write_long(self, path, values, error)
      class(engine_results_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      integer(i8), intent(in) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      call self%h5%write_int(path, values, error)
   end subroutine engine_results_write_long

   !> Append the first `num_steps` steps of every series of `source` (the results file of an
   !> earlier run of the same case, open for reading) to this file, before any `record`: a
   !> restarted run holds the whole history. The series of `source` must have the rows of the
   !> bodies and joints added here.
   subroutine engine_results_append_from(self, source, num_steps, error)
      class(engine_results_t), intent(inout) :: self
      !> Earlier results file
      type(h5_file_t), intent(in) :: source
      !> Steps to copy
      integer, intent(in) :: num_steps
      type(error_t), allocatable, intent(out) :: error
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

   end subroutine engine_results_append_from

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

end module ffrf_app_engine_results
