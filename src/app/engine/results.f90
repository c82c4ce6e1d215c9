!> The results file of an engine run (HDF5): the time histories, written progressively so that a
!> run killed at any point leaves a readable file with status 'running' and every step up to the
!> last flush (issue 3, part 5). Schema (read by postprocess/ffrf_results, `read_engine`):
!> root attributes status, schema_version, case_name, title, ffrf_version; /input/namelist;
!> /build/versions; /engine with attributes rc_set and mpc (also as the string datasets
!> /engine/rc_set and /engine/mpc: a group needs a dataset to exist; an engine only: create's
!> engine); growing series (one entry per sample: every step, or as &output asks)
!> /time/{t [s], crank_angle [rad, unwrapped], crank_speed [rad/s], pressure [Pa]} (the crank
!> series only when the run has a crank: create's has_crank; pressure only for an engine),
!> /peaks/<series>/{min, max, t_min, t_max} (create's peaks: the extremes over each output
!> interval; docs/results.md "Output rate, peaks, compression, size"),
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
!> Samples are buffered in memory and appended + flushed every `steps_per_flush` samples (100
!> by default) and by `finish`: HDF5 is touched once per chunk, not once per step.
!>
!> This module holds the type and the interfaces; the bodies are in the submodules
!> results_series.f90 (the time series) and results_data.f90 (datasets written once).
module ffrf_app_engine_results
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t
   use ffrf_io_hdf5, only: h5_file_t
   implicit none
   private
   public :: engine_results_t

   !> Number of scalar series: 4 /time series and 6 /energy series.
   integer, parameter :: NUM_SCALARS = 10
   !> Rows of a joint reaction: force and moment on both bodies.
   integer, parameter :: REACTION_ROWS = 12

   !> Writer of an engine results file. Use: `create`, then `add_body_series` /
   !> `add_joint_series` for each body and joint, then `record` once per step, then `finish`.
   !> A step's values (`record`'s arguments) are kept as one vector: the NUM_SCALARS scalars
   !> [t, crank angle, crank speed, pressure, 6 energies], the sensors' values, the bodies'
   !> coordinates, the joints' series (12 each), in this order; each series written is a slice
   !> of it (paths, rows, category, offset).
   type :: engine_results_t
      private
      !> The open file
      type(h5_file_t) :: h5
      !> File name, for messages
      character(len=:), allocatable :: file_name
      !> Samples buffered before appending and flushing
      integer :: steps_per_flush = 100
      !> Samples in the buffer
      integer :: num_buffered = 0
      !> Samples recorded so far (buffered or written): the rows of the series
      integer :: num_recorded = 0
      !> Modes per body, in the order of add_body_series
      integer, allocatable :: num_modes(:)
      !> Sensor values and joint series per step (every one added, written or not)
      integer :: num_sensor_values = 0, num_joint_series = 0
      !> The run has a crank: /time/crank_angle and /time/crank_speed are written (create)
      logical :: has_crank = .true.
      !> Min and max over each output interval under /peaks (create's peaks)
      logical :: peaks = .false.
      !> Steps per chunk at most (create's chunk_steps; 0: no cap)
      integer :: chunk_steps = 0
      !> The series written: path, values per step (0: a scalar series), category of the step's
      !> values (1 scalars, 2 sensors, 3 bodies, 4 joints) and first value in the category - 1
      character(len=256), allocatable :: paths(:)
      integer, allocatable :: rows(:), category(:), offset(:)
      !> Buffered samples (values of a step, steps_per_flush) and their peaks
      !> (values of a step, 4: min, max, time of min, time of max, steps_per_flush)
      real(dp), allocatable :: buffer(:, :), peak_buffer(:, :, :)
      !> The output interval being recorded: steps in it, the last step's values and their
      !> time, the extremes and their times
      integer :: num_pending = 0
      real(dp) :: last_t = 0.0_dp
      real(dp), allocatable :: last(:), low(:), high(:), t_low(:), t_high(:)
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
      procedure :: interval_state => engine_results_interval_state
      procedure :: restore_interval => engine_results_restore_interval
      procedure :: predicted_bytes => engine_results_predicted_bytes
   end type engine_results_t

   interface

      ! --- ffrf_app_engine_results_series (results_series.f90) -----------------------------------

      !> Create the file (truncated if it exists) with status 'running', the input echo, the
      !> /engine attributes and the empty /time and /energy series.
      module subroutine engine_results_create(self, file_name, case_name, title, rc_set_label, &
            mpc_label, echo, error, has_crank, engine, energies, peaks, compression, &
            chunk_steps)
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
         !> .false.: a run without a crank, no /time/crank_angle nor /time/crank_speed (default
         !> .true.)
         logical, intent(in), optional :: has_crank
         !> .false.: no /engine group nor /time/pressure (default: has_crank)
         logical, intent(in), optional :: engine
         !> .false.: no /energy series (default .true.)
         logical, intent(in), optional :: energies
         !> .true.: every series but /time/t gets /peaks/<its path>/{min, max, t_min, t_max}, its
         !> extremes over each output interval (default .false.)
         logical, intent(in), optional :: peaks
         !> Deflate level of the series (0, default: none; ffrf_io_hdf5 set_compression)
         integer, intent(in), optional :: compression
         !> Steps per chunk at most (default 0: no cap; set_compression's max_chunk_steps)
         integer, intent(in), optional :: chunk_steps
      end subroutine engine_results_create

      !> Set how many steps are buffered between two flushes (before the first `record`).
      module subroutine engine_results_set_steps_per_flush(self, steps, error)
         class(engine_results_t), intent(inout) :: self
         !> Steps per flush, >= 1
         integer, intent(in) :: steps
         type(error_t), allocatable, intent(out) :: error
      end subroutine engine_results_set_steps_per_flush

      !> Add the series /bodies/<body_name>/{position, euler_parameters, modal_coordinates} (3, 4
      !> and num_modes rows; no modal series for num_modes = 0), before the first `record`.
      !> `record` takes the bodies' coordinates [R; theta; zeta] stacked in the order of these
      !> calls.
      module subroutine engine_results_add_body_series(self, body_name, num_modes, error, write)
         class(engine_results_t), intent(inout) :: self
         !> Body name
         character(len=*), intent(in) :: body_name
         !> Number of modal coordinates (>= 0)
         integer, intent(in) :: num_modes
         type(error_t), allocatable, intent(out) :: error
         !> .false.: the body's coordinates are taken by `record` but not written
         logical, intent(in), optional :: write
      end subroutine engine_results_add_body_series

      !> Add the series /joints/<joint_name>/reaction (12 rows), before the first `record`.
      !> `record` takes the joints' reactions as columns in the order of these calls. `series`
      !> and `units` name another 12-row series of the joint (default 'reaction', 'N, N m'), e.g.
      !> its per-step flags /joints/<joint>/reaction_min_norm.
      module subroutine engine_results_add_joint_series(self, joint_name, error, series, units, &
            write)
         class(engine_results_t), intent(inout) :: self
         !> Joint name
         character(len=*), intent(in) :: joint_name
         type(error_t), allocatable, intent(out) :: error
         !> Series name under /joints/<joint_name> and its units
         character(len=*), intent(in), optional :: series, units
         !> .false.: taken by `record` but not written
         logical, intent(in), optional :: write
      end subroutine engine_results_add_joint_series

      !> A sensor series /sensors/<name>: `rows` values per step (a (num_steps x rows) dataset in
      !> h5py) with the attributes units, type and, when given, body, marker, joint and node.
      module subroutine engine_results_add_sensor_series(self, name, rows, unit, type, body, &
            marker, joint, error, node, write)
         class(engine_results_t), intent(inout) :: self
         !> Sensor name, unit of its values, its type word, what it measures ('' when not)
         character(len=*), intent(in) :: name
         integer, intent(in) :: rows
         character(len=*), intent(in) :: unit, type, body, marker, joint
         type(error_t), allocatable, intent(out) :: error
         !> Mesh node (Gmsh tag) of a node sensor
         integer, intent(in), optional :: node
         !> .false.: taken by `record` but not written
         logical, intent(in), optional :: write
      end subroutine engine_results_add_sensor_series

      !> Record one step. It enters the output interval (its extremes); when it is a sample, the
      !> step and the interval's extremes are buffered and the interval ends. Every
      !> `steps_per_flush` samples the buffer is appended to the series and the file flushed. A
      !> non-finite value is an error (nothing is recorded).
      module subroutine engine_results_record(self, t, crank_angle, crank_speed, pressure, &
            energies, modal, reactions, error, scheme_dissipation, damping_dissipation, sensors, &
            sample)
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
         !> .false.: the step only enters the output interval (default .true.: written)
         logical, intent(in), optional :: sample
      end subroutine engine_results_record

      !> Append the buffered steps to the series and flush the file to disk.
      module subroutine engine_results_flush(self, error)
         class(engine_results_t), intent(inout) :: self
         type(error_t), allocatable, intent(out) :: error
      end subroutine engine_results_flush

      !> Flush the buffer, write the stage timings, set the status ('complete' or the error
      !> message) and close, whatever fails. If a write fails, the status becomes that failure's
      !> message; `closed` tells whether the file was closed cleanly (then it is readable).
      module subroutine engine_results_finish(self, status, stage_names, stage_seconds, error, &
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
      end subroutine engine_results_finish

      !> Samples recorded so far (written or buffered): the rows of the series.
      module pure integer function engine_results_num_steps(self) result(num_steps)
         class(engine_results_t), intent(in) :: self
      end function engine_results_num_steps

      !> The output interval being recorded, for the restart state: [steps in it, time of its
      !> last step, that step's values, the extremes, their times]; empty without peaks.
      module pure function engine_results_interval_state(self) result(state)
         class(engine_results_t), intent(in) :: self
         real(dp), allocatable :: state(:)
      end function engine_results_interval_state

      !> Continue the output interval of `state` (interval_state of an earlier run; empty: a
      !> new interval), after append_from.
      module subroutine engine_results_restore_interval(self, state, error)
         class(engine_results_t), intent(inout) :: self
         real(dp), intent(in) :: state(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine engine_results_restore_interval

      !> Bytes the series (and their peaks) will take after `num_samples` samples, uncompressed
      !> (ffrf_io_hdf5 series_storage_bytes).
      module pure integer(i8) function engine_results_predicted_bytes(self, num_samples) &
            result(bytes)
         class(engine_results_t), intent(in) :: self
         integer(i8), intent(in) :: num_samples
      end function engine_results_predicted_bytes

      !> Append the first `num_steps` steps of every series of `source` (the results file of an
      !> earlier run of the same case, open for reading) to this file, before any `record`: a
      !> restarted run holds the whole history. The series of `source` must have the rows of the
      !> bodies and joints added here.
      module subroutine engine_results_append_from(self, source, num_steps, error)
         class(engine_results_t), intent(inout) :: self
         !> Earlier results file
         type(h5_file_t), intent(in) :: source
         !> Steps to copy
         integer, intent(in) :: num_steps
         type(error_t), allocatable, intent(out) :: error
      end subroutine engine_results_append_from

      ! --- ffrf_app_engine_results_data (results_data.f90) ---------------------------------------

      !> Write run information, e.g. /integrator/newton_iterations, with its unit.
      module subroutine engine_results_write_real(self, path, values, unit, error)
         class(engine_results_t), intent(inout) :: self
         character(len=*), intent(in) :: path
         real(dp), intent(in) :: values(:)
         !> Unit, '1' when dimensionless
         character(len=*), intent(in) :: unit
         type(error_t), allocatable, intent(out) :: error
      end subroutine engine_results_write_real

      !> Write a real matrix, e.g. /bodies/<body>/modes/shape.
      module subroutine engine_results_write_matrix(self, path, values, unit, error)
         class(engine_results_t), intent(inout) :: self
         character(len=*), intent(in) :: path
         real(dp), intent(in) :: values(:, :)
         !> Unit, '1' when dimensionless
         character(len=*), intent(in) :: unit
         type(error_t), allocatable, intent(out) :: error
      end subroutine engine_results_write_matrix

      !> Write integer run information, e.g. /joints/<joint>/redundant_equations.
      module subroutine engine_results_write_int(self, path, values, error)
         class(engine_results_t), intent(inout) :: self
         character(len=*), intent(in) :: path
         integer, intent(in) :: values(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine engine_results_write_int

      !> Write a list of strings, e.g. /model_selection/<body>/meshes_tried.
      module subroutine engine_results_write_strings(self, path, values, error)
         class(engine_results_t), intent(inout) :: self
         character(len=*), intent(in) :: path
         character(len=*), intent(in) :: values(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine engine_results_write_strings

      !> The modal data of flexible body `body_name` (module header): frequencies, virtual-node rows
      !> of the modes, the basis, and the interfaces' names and virtual-node positions.
      module subroutine engine_results_write_modes(self, body_name, frequency_hz, &
            virtual_node_shape, interface_names, virtual_xyz, basis, num_static, error)
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
      end subroutine engine_results_write_modes

      !> Write 64-bit integer run information (the restart state).
      module subroutine engine_results_write_long(self, path, values, error)
         class(engine_results_t), intent(inout) :: self
         character(len=*), intent(in) :: path
         integer(i8), intent(in) :: values(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine engine_results_write_long
   end interface

end module ffrf_app_engine_results
