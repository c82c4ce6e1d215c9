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
!>
!> This module holds the type and the interfaces; the bodies are in the submodules
!> mechanism_session_advance.f90 (prepare, advance, close) and mechanism_session_state.f90 (the
!> state queries and the host's loads).
module ffrf_app_mechanism_session
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_core_log, only: logger_t, stage_times_t, stage_timer_t
   use ffrf_app_run_options, only: run_options_t
   use ffrf_app_mechanism_output, only: mechanism_output_t
   use ffrf_input_case, only: case_input_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_sensors, only: sensor_t, sensor_size
   use ffrf_app_engine_pressure, only: pressure_model_t
   use ffrf_mbs_generalized_alpha, only: galpha_integrator_t
   use ffrf_app_mechanism_builder, only: built_body_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_engine_auto_model, only: model_choice_t
   use ffrf_model_model, only: model_t
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

   interface

      ! --- ffrf_app_mechanism_session_advance (mechanism_session_advance.f90) --------------------

      !> Prepare a mechanism case read by read_case: modes, mechanism, integrator at t_start. With
      !> `options` the run is recorded in options%output_dir (module header), --restart included.
      module subroutine session_prepare(self, case, mesh_dir, log, times, error, options)
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
      end subroutine session_prepare

      !> Integrate from the current time up to time t (module header: steps of h, one shortened
      !> step to land between two). t = the current time does nothing.
      module subroutine session_advance(self, t, error)
         class(mechanism_session_t), intent(inout) :: self
         !> Time to reach (s), at most the case's t_end
         real(dp), intent(in) :: t
         type(error_t), allocatable, intent(out) :: error
      end subroutine session_advance

      !> End the recording of a run stopped before t_end: its file goes into place with every
      !> recorded step, /final_state and status "stopped: ..." (nothing when not recording).
      module subroutine session_close_output(self, error)
         class(mechanism_session_t), intent(inout) :: self
         type(error_t), allocatable, intent(out) :: error
      end subroutine session_close_output

      !> Release the mechanism, bodies and integrator (the session can be prepared again); a run
      !> still recorded is ended first (close_output).
      module subroutine session_finish(self)
         class(mechanism_session_t), intent(inout) :: self
      end subroutine session_finish

      !> Move the modal results of a body from `from` to `to` (arrays moved, not copied; `from`
      !> keeps its scalars).
      module subroutine move_modes(from, to)
         type(body_modes_t), intent(inout) :: from
         type(body_modes_t), intent(out) :: to
      end subroutine move_modes

      ! --- ffrf_app_mechanism_session_state (mechanism_session_state.f90) ------------------------

      !> Time of the current state (s).
      module pure real(dp) function session_time(self)
         class(mechanism_session_t), intent(in) :: self
      end function session_time

      !> End time of the case (s).
      module pure real(dp) function session_end_time(self)
         class(mechanism_session_t), intent(in) :: self
      end function session_end_time

      !> Crank angle of the current state (rad, unwrapped over the revolutions; 0 without crank).
      module pure real(dp) function session_crank_angle(self)
         class(mechanism_session_t), intent(in) :: self
      end function session_crank_angle

      !> Crank speed of the current state (rad/s; 0 without crank).
      module pure real(dp) function session_crank_speed(self)
         class(mechanism_session_t), intent(in) :: self
      end function session_crank_speed

      !> Number of bodies of the case (&body groups in input order; the ground is not counted).
      module pure integer function session_num_bodies(self)
         class(mechanism_session_t), intent(in) :: self
      end function session_num_bodies

      !> Coordinates q and velocities v of body `body` (1..num_bodies): rigid [R; theta] (7),
      !> flexible [R; theta; zeta] (7 + modes); theory.md 3.1.
      module subroutine session_body_state(self, body, q, v, error)
         class(mechanism_session_t), intent(in) :: self
         !> Body number, 1..num_bodies (case order)
         integer, intent(in) :: body
         real(dp), allocatable, intent(out) :: q(:), v(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine session_body_state

      !> Number of markers of body `body` (0 for a bad body number).
      module integer function session_num_markers(self, body)
         class(mechanism_session_t), intent(in) :: self
         !> Body number, 1..num_bodies
         integer, intent(in) :: body
      end function session_num_markers

      !> Global position (m), velocity (m/s) and angular velocity (rad/s) of a marker: r_k(q),
      !> L_r v and L_w v (theory.md 3.5). A flexible body's markers are its interfaces' virtual
      !> nodes in input order; a rigid body's are made from its &marker points per joint end and
      !> load (ffrf_app_mechanism_builder).
      module subroutine session_marker_motion(self, body, marker, position, velocity, &
            angular_velocity, error)
         class(mechanism_session_t), intent(in) :: self
         !> Body number, 1..num_bodies; marker number, 1..num_markers(body)
         integer, intent(in) :: body, marker
         real(dp), intent(out) :: position(3), velocity(3), angular_velocity(3)
         type(error_t), allocatable, intent(out) :: error
      end subroutine session_marker_motion

      !> Number of sensors (&sensor groups in input order, then an engine case's crank_angle and
      !> crank_speed).
      module pure integer function session_num_sensors(self)
         class(mechanism_session_t), intent(in) :: self
      end function session_num_sensors

      !> Name of sensor `sensor` (1..num_sensors).
      module subroutine session_sensor_name(self, sensor, name, error)
         class(mechanism_session_t), intent(in) :: self
         integer, intent(in) :: sensor
         character(len=:), allocatable, intent(out) :: name
         type(error_t), allocatable, intent(out) :: error
      end subroutine session_sensor_name

      !> Number of values of sensor `sensor` (1..num_sensors).
      module subroutine session_sensor_size(self, sensor, size_, error)
         class(mechanism_session_t), intent(in) :: self
         integer, intent(in) :: sensor
         integer, intent(out) :: size_
         type(error_t), allocatable, intent(out) :: error
      end subroutine session_sensor_size

      !> Values of sensor `sensor` at the current state (the integrator's multipliers for a
      !> reaction; docs/sensors.md).
      module subroutine session_sensor_values(self, sensor, values, error)
         class(mechanism_session_t), intent(in) :: self
         integer, intent(in) :: sensor
         real(dp), allocatable, intent(out) :: values(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine session_sensor_values

      !> Number of joints (&joint groups in input order).
      module pure integer function session_num_joints(self)
         class(mechanism_session_t), intent(in) :: self
      end function session_num_joints

      !> Reaction of joint `joint` (1..num_joints) from the current multipliers: force (N) and
      !> moment (N m), global, column 1 on body 1 of the joint, column 2 on body 2.
      module subroutine session_joint_reaction(self, joint, force, moment, error)
         class(mechanism_session_t), intent(in) :: self
         integer, intent(in) :: joint
         real(dp), intent(out) :: force(3, 2), moment(3, 2)
         type(error_t), allocatable, intent(out) :: error
      end subroutine session_joint_reaction

      !> Apply the global force F (N) and moment M (N m) at a marker from now on (until set
      !> again): the host's load of the next interval (ffrf_mbs_host_load). The first call for a
      !> marker adds its two loads to the mechanism.
      module subroutine session_set_marker_load(self, body, marker, force, moment, error)
         class(mechanism_session_t), intent(inout) :: self
         !> Body number, 1..num_bodies; marker number, 1..num_markers(body)
         integer, intent(in) :: body, marker
         real(dp), intent(in) :: force(3), moment(3)
         type(error_t), allocatable, intent(out) :: error
      end subroutine session_set_marker_load
   end interface

end module ffrf_app_mechanism_session
