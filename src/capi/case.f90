!> The case object of the public APIs: a typed Fortran `ffrf_case_t` (exported by `use ffrf`)
!> that the C API (ffrf_capi, include/ffrf.h) wraps one to one. It holds a case read from its
!> namelist file, the modes of its bodies once computed and, for a mechanism case, its
!> mechanism session (ffrf_sim_mechanism_session). Every procedure reports through
!> `type(error_t), allocatable, intent(out) :: error` (code FFRF_BAD_CALL for a call out of
!> order or a bad index, else the library's codes); nothing here stops, prints or installs
!> signal handlers, and there is no state outside the object.
!>
!> Indices here are 1-based (bodies in &body order, markers, joints in &joint order, modes);
!> the C API shifts them to 0-based.
!>
!> Call order: open -> run (modal case: modes; mechanism case: modes and motion to t_end), or
!> for a mechanism case advance(t) repeatedly (the first call prepares: modes, mechanism,
!> consistent start). Body data after the modes; mechanism state after the first advance (or
!> after run without an output folder).
module ffrf_capi_case
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_core_paths, only: folder_of
   use ffrf_io_case, only: case_input_t, read_case
   use ffrf_modes_modal_analysis, only: body_modes_t, compute_body_modes
   use ffrf_modes_modal_case, only: run_options_t, run_modal
   use ffrf_sim_mechanism_case, only: run_mechanism
   use ffrf_sim_mechanism_session, only: mechanism_session_t, move_modes
   implicit none
   private
   public :: ffrf_case_t, FFRF_BAD_CALL

   !> Status of a call out of order, a bad index or argument, a buffer too small (the C API's
   !> FFRF_BAD_CALL); the other codes are those of ffrf_core_error
   integer, parameter :: FFRF_BAD_CALL = 1

   !> A case (module header).
   type :: ffrf_case_t
      !> The case as read (open)
      type(case_input_t), private :: case
      !> Folders (output_dir = '' with write_output false: nothing written)
      type(run_options_t), private :: options
      logical, private :: write_output = .false.
      !> Silent logger (LOG_QUIET)
      type(logger_t), private :: log
      !> open succeeded / run done / modes available
      logical, private :: opened = .false., ran = .false., have_modes = .false.
      !> The modes of every body (case order; rigid bodies: empty)
      type(body_modes_t), allocatable, private :: modes(:)
      !> The mechanism session (advance, state queries)
      type(mechanism_session_t), private :: session
      !> Time, crank angle, crank speed after a run that wrote results (no session state)
      real(dp), private :: final_state(3) = 0.0_dp
      logical, private :: have_final = .false.
   contains
      !> Read and check a case file
      procedure :: open => case_open
      !> Modes (and motion to t_end for a mechanism case)
      procedure :: run => case_run
      !> Whether the case is a mechanism case
      procedure :: is_mechanism => case_is_mechanism
      !> Number of bodies, a body's name
      procedure :: body_count => case_body_count
      procedure :: body_name => case_body_name
      !> Body data after the modes
      procedure :: frequencies => case_frequencies
      procedure :: body_sizes => case_body_sizes
      procedure :: nodes => case_nodes
      procedure :: mode_shapes => case_mode_shapes
      procedure :: virtual_node_shapes => case_virtual_node_shapes
      procedure :: mass_properties => case_mass_properties
      !> Mechanism: advance, state, host loads
      procedure :: advance => case_advance
      procedure :: crank_state => case_crank_state
      procedure :: time => case_time
      procedure :: body_state => case_body_state
      procedure :: marker_count => case_marker_count
      procedure :: marker_state => case_marker_state
      procedure :: joint_count => case_joint_count
      procedure :: joint_name => case_joint_name
      procedure :: joint_reaction => case_joint_reaction
      procedure :: set_marker_load => case_set_marker_load
      !> Release everything
      procedure :: close => case_close
   end type ffrf_case_t

contains

   !> Read and check the namelist case `case_file`. mesh_dir: folder of relative mesh files
   !> (absent or '': the case file's folder); output_dir: folder of the results (absent:
   !> nothing is written).
   subroutine case_open(self, case_file, error, mesh_dir, output_dir)
      class(ffrf_case_t), intent(out) :: self
      character(len=*), intent(in) :: case_file
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: mesh_dir, output_dir
      self%log%level = LOG_QUIET
      self%options%log_level = LOG_QUIET
      self%options%mesh_dir = ''
      if (present(mesh_dir)) self%options%mesh_dir = mesh_dir
      self%options%output_dir = ''
      self%write_output = present(output_dir)
      if (present(output_dir)) self%options%output_dir = output_dir
      self%options%restart_file = ''
      call read_case(case_file, self%case, error)
      if (allocated(error)) return
      self%opened = .true.
   end subroutine case_open

   !> Raise FFRF_BAD_CALL with `message`.
   subroutine bad_call(error, message)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: message
      call fatal_error(error, FFRF_BAD_CALL, message)
   end subroutine bad_call

   !> FFRF_BAD_CALL unless the case is open.
   subroutine check_open(self, what, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      if (.not. self%opened) call bad_call(error, what // ': the case is not open ' // &
         '(ffrf_case_open failed or was not called)')
   end subroutine check_open

   !> The folder of relative mesh files.
   function mesh_folder(self) result(folder)
      class(ffrf_case_t), intent(in) :: self
      character(len=:), allocatable :: folder
      folder = self%options%mesh_dir
      if (len(folder) == 0) folder = folder_of(self%case%file_name)
   end function mesh_folder

   !> Modal case: the modes of every body (results written as the driver writes them when an
   !> output folder was given). Mechanism case: the modes, then the motion to t_end (with an
   !> output folder: run_mechanism, the driver's run; else the session, state kept).
   subroutine case_run(self, error)
      class(ffrf_case_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
      type(stage_times_t) :: times
      integer :: k
      call check_open(self, 'run', error)
      if (allocated(error)) return
      if (self%ran) then
         call bad_call(error, 'run: the case has already run')
         return
      end if
      if (self%case%is_mechanism .and. self%session%prepared) then
         if (self%write_output) then
            call bad_call(error, 'run: the mechanism was advanced already; with an output ' &
               // 'folder run writes the whole run from t_start: open the case again')
            return
         end if
      end if
      self%ran = .true.
      if (.not. self%case%is_mechanism) then
         if (self%write_output) then
            call run_modal(self%case, self%options, self%log, error, self%modes)
         else
            allocate (self%modes(size(self%case%bodies)))
            do k = 1, size(self%case%bodies)
               if (self%case%motions(k)%type == 'rigid') cycle
               call compute_body_modes(self%case%bodies(k), self%case%interfaces, &
                  self%case%modes, mesh_folder(self), self%log, times, self%modes(k), error)
               if (allocated(error)) then
                  call add_context(error, self%case%file_name)
                  exit
               end if
            end do
         end if
         self%have_modes = .not. allocated(error)
         return
      end if
      if (self%write_output) then
         call run_mechanism(self%case, self%options, self%log, error, self%modes, &
            self%final_state)
         self%have_final = .true.
         self%have_modes = allocated(self%modes)
         return
      end if
      call self%advance(session_end_time(self), error)
   end subroutine case_run

   !> The case's t_end (mechanism), without preparing.
   real(dp) function session_end_time(self)
      class(ffrf_case_t), intent(in) :: self
      session_end_time = self%case%mechanism%integrator%t_end
   end function session_end_time

   !> Whether the case is a mechanism case (has &joint groups).
   logical function case_is_mechanism(self)
      class(ffrf_case_t), intent(in) :: self
      case_is_mechanism = self%opened .and. self%case%is_mechanism
   end function case_is_mechanism

   !> Number of bodies (&body groups).
   subroutine case_body_count(self, n, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(out) :: n
      type(error_t), allocatable, intent(out) :: error
      n = 0
      call check_open(self, 'body_count', error)
      if (.not. allocated(error)) n = size(self%case%bodies)
   end subroutine case_body_count

   !> FFRF_BAD_CALL unless 1 <= body <= number of bodies.
   subroutine check_body(self, what, body, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      call check_open(self, what, error)
      if (allocated(error)) return
      if (body < 1 .or. body > size(self%case%bodies)) call bad_call(error, what // ': body ' // &
         to_str(body - 1) // ' does not exist; the case has ' // &
         to_str(size(self%case%bodies)) // ' bodies, 0..' // &
         to_str(size(self%case%bodies) - 1))
   end subroutine check_body

   !> FFRF_BAD_CALL unless the body exists and the modes have been computed.
   subroutine check_modes(self, what, body, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      call check_body(self, what, body, error)
      if (allocated(error)) return
      if (.not. self%have_modes) call bad_call(error, what // ': no modes yet; call ' // &
         'ffrf_case_run first (mechanism case: or ffrf_mechanism_advance)')
   end subroutine check_modes

   !> Name of body `body`.
   subroutine case_body_name(self, body, name, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
      name = ''
      call check_body(self, 'body_name', body, error)
      if (.not. allocated(error)) name = trim(self%case%bodies(body)%name)
   end subroutine case_body_name

   !> Natural frequencies (Hz) of the body's modes (none for a rigid body).
   subroutine case_frequencies(self, body, hz, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: hz(:)
      type(error_t), allocatable, intent(out) :: error
      allocate (hz(0))
      call check_modes(self, 'body_frequencies', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%frequency_hz)) hz = self%modes(body)%frequency_hz
   end subroutine case_frequencies

   !> Mesh nodes, modes and interfaces of a body (0 for a rigid body without a mesh).
   subroutine case_body_sizes(self, body, num_nodes, num_modes, num_interfaces, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      integer, intent(out) :: num_nodes, num_modes, num_interfaces
      type(error_t), allocatable, intent(out) :: error
      num_nodes = 0
      num_modes = 0
      num_interfaces = 0
      call check_modes(self, 'body_sizes', body, error)
      if (allocated(error)) return
      associate (m => self%modes(body))
         if (allocated(m%mesh%xyz)) num_nodes = size(m%mesh%xyz, 2)
         if (allocated(m%frequency_hz)) num_modes = size(m%frequency_hz)
         if (allocated(m%interfaces)) num_interfaces = size(m%interfaces)
      end associate
   end subroutine case_body_sizes

   !> Node coordinates (m), 3 x num_nodes.
   subroutine case_nodes(self, body, xyz, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: xyz(:, :)
      type(error_t), allocatable, intent(out) :: error
      allocate (xyz(3, 0))
      call check_modes(self, 'body_nodes', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%mesh%xyz)) xyz = self%modes(body)%mesh%xyz
   end subroutine case_nodes

   !> Mass-normalised mode shapes, (3 num_nodes, num_modes).
   subroutine case_mode_shapes(self, body, shape, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: shape(:, :)
      type(error_t), allocatable, intent(out) :: error
      allocate (shape(0, 0))
      call check_modes(self, 'body_mode_shapes', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%shape)) shape = self%modes(body)%shape
   end subroutine case_mode_shapes

   !> Virtual-node rows of the modes, (6 num_interfaces, num_modes).
   subroutine case_virtual_node_shapes(self, body, rows, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: rows(:, :)
      type(error_t), allocatable, intent(out) :: error
      allocate (rows(0, 0))
      call check_modes(self, 'body_virtual_node_shapes', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%virtual_node_shape)) rows = &
         self%modes(body)%virtual_node_shape
   end subroutine case_virtual_node_shapes

   !> Mass (kg), centre of mass (m) and inertia about it (kg m^2) of a meshed body.
   subroutine case_mass_properties(self, body, mass, center, inertia, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), intent(out) :: mass, center(3), inertia(3, 3)
      type(error_t), allocatable, intent(out) :: error
      mass = 0.0_dp
      center = 0.0_dp
      inertia = 0.0_dp
      call check_modes(self, 'body_mass_properties', body, error)
      if (allocated(error)) return
      if (.not. allocated(self%modes(body)%mesh%xyz)) then
         call bad_call(error, 'body_mass_properties: body "' // &
            trim(self%case%bodies(body)%name) // '" has no mesh; its mass is the &body input')
         return
      end if
      mass = self%modes(body)%mass
      center = self%modes(body)%center_of_mass
      inertia = self%modes(body)%inertia
   end subroutine case_mass_properties

   !> FFRF_BAD_CALL unless the case is a mechanism case with a prepared session.
   subroutine check_session(self, what, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      call check_open(self, what, error)
      if (allocated(error)) return
      if (.not. self%case%is_mechanism) then
         call bad_call(error, what // ': "' // self%case%file_name // '" is a modal case ' // &
            '(no &joint groups); only a mechanism case moves')
      else if (.not. self%session%prepared) then
         if (self%have_final) then
            call bad_call(error, what // ': not available after ffrf_case_run with an ' // &
               'output folder (the run is over); open the case without one to query the state')
         else
            call bad_call(error, what // ': the mechanism is not prepared yet; call ' // &
               'ffrf_mechanism_advance first (advance to t_start only prepares)')
         end if
      end if
   end subroutine check_session

   !> Mechanism case: prepare on the first call (modes, mechanism, consistent start), then
   !> integrate up to time t (ffrf_sim_mechanism_session).
   subroutine case_advance(self, t, error)
      class(ffrf_case_t), intent(inout) :: self
      !> Time to reach (s), t_start <= t <= t_end
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      type(stage_times_t) :: times
      integer :: k
      call check_open(self, 'mechanism_advance', error)
      if (allocated(error)) return
      if (.not. self%case%is_mechanism) then
         call bad_call(error, 'mechanism_advance: "' // self%case%file_name // '" is a ' // &
            'modal case (no &joint groups); only a mechanism case moves')
         return
      end if
      if (self%have_final) then
         call bad_call(error, 'mechanism_advance: the case has run to t_end with an output ' &
            // 'folder; open it again to advance it')
         return
      end if
      if (.not. self%session%prepared) then
         ! a time beyond t_end is refused before the modes are computed (session_advance
         ! checks it again with the h of the automatic model)
         associate (settings => self%case%mechanism%integrator)
            if (.not. (t <= settings%t_end + 1.0e-6_dp * settings%h)) then
               call fatal_error(error, FFRF_INPUT_ERROR, self%case%file_name // &
                  ': mechanism: advance to t = ' // to_str(t, 12) // ' s, beyond the ' // &
                  'case''s t_end = ' // to_str(settings%t_end, 12) // ' s; raise ' // &
                  '&integrator t_end')
               return
            end if
         end associate
         call self%session%prepare(self%case, mesh_folder(self), self%log, times, error)
         if (allocated(error)) return
         allocate (self%modes(size(self%session%bodies)))
         do k = 1, size(self%session%bodies)
            call move_modes(self%session%bodies(k)%modes, self%modes(k))
         end do
         self%have_modes = .true.
      end if
      call self%session%advance(t, error)
      if (allocated(error)) call add_context(error, self%case%file_name)
   end subroutine case_advance

   !> Crank angle (rad, unwrapped) and speed (rad/s) of the current state.
   subroutine case_crank_state(self, angle, speed, error)
      class(ffrf_case_t), intent(in) :: self
      real(dp), intent(out) :: angle, speed
      type(error_t), allocatable, intent(out) :: error
      angle = 0.0_dp
      speed = 0.0_dp
      if (self%have_final) then
         angle = self%final_state(2)
         speed = self%final_state(3)
         return
      end if
      call check_session(self, 'crank_state', error)
      if (allocated(error)) return
      angle = self%session%crank_angle()
      speed = self%session%crank_speed()
   end subroutine case_crank_state

   !> Time of the current state and the case's t_end (s).
   subroutine case_time(self, t, t_end, error)
      class(ffrf_case_t), intent(in) :: self
      real(dp), intent(out) :: t, t_end
      type(error_t), allocatable, intent(out) :: error
      t = 0.0_dp
      t_end = 0.0_dp
      if (self%have_final) then
         t = self%final_state(1)
         t_end = session_end_time(self)
         return
      end if
      call check_session(self, 'mechanism_time', error)
      if (allocated(error)) return
      t = self%session%time()
      t_end = self%session%end_time()
   end subroutine case_time

   !> Coordinates and velocities of a body (ffrf_sim_mechanism_session body_state).
   subroutine case_body_state(self, body, q, v, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: q(:), v(:)
      type(error_t), allocatable, intent(out) :: error
      allocate (q(0), v(0))
      call check_session(self, 'body_state', error)
      if (.not. allocated(error)) call check_body(self, 'body_state', body, error)
      if (.not. allocated(error)) call self%session%body_state(body, q, v, error)
   end subroutine case_body_state

   !> Number of markers of a body.
   subroutine case_marker_count(self, body, n, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      integer, intent(out) :: n
      type(error_t), allocatable, intent(out) :: error
      n = 0
      call check_session(self, 'marker_count', error)
      if (.not. allocated(error)) call check_body(self, 'marker_count', body, error)
      if (.not. allocated(error)) n = self%session%num_markers(body)
   end subroutine case_marker_count

   !> FFRF_BAD_CALL unless the marker exists on the body.
   subroutine check_marker(self, what, body, marker, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: body, marker
      type(error_t), allocatable, intent(out) :: error
      integer :: n
      call check_session(self, what, error)
      if (.not. allocated(error)) call check_body(self, what, body, error)
      if (allocated(error)) return
      n = self%session%num_markers(body)
      if (marker < 1 .or. marker > n) call bad_call(error, what // ': marker ' // &
         to_str(marker - 1) // ' does not exist; body "' // trim(self%case%bodies(body)%name) &
         // '" has ' // to_str(n) // ' markers, 0..' // to_str(n - 1))
   end subroutine check_marker

   !> Global position (m), velocity (m/s) and angular velocity (rad/s) of a marker.
   subroutine case_marker_state(self, body, marker, position, velocity, angular_velocity, &
         error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body, marker
      real(dp), intent(out) :: position(3), velocity(3), angular_velocity(3)
      type(error_t), allocatable, intent(out) :: error
      position = 0.0_dp
      velocity = 0.0_dp
      angular_velocity = 0.0_dp
      call check_marker(self, 'marker_state', body, marker, error)
      if (.not. allocated(error)) call self%session%marker_motion(body, marker, position, &
         velocity, angular_velocity, error)
   end subroutine case_marker_state

   !> Number of joints.
   subroutine case_joint_count(self, n, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(out) :: n
      type(error_t), allocatable, intent(out) :: error
      n = 0
      call check_session(self, 'joint_count', error)
      if (.not. allocated(error)) n = self%session%num_joints()
   end subroutine case_joint_count

   !> FFRF_BAD_CALL unless the joint exists.
   subroutine check_joint(self, what, joint, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: joint
      type(error_t), allocatable, intent(out) :: error
      call check_session(self, what, error)
      if (allocated(error)) return
      if (joint < 1 .or. joint > self%session%num_joints()) call bad_call(error, what // &
         ': joint ' // to_str(joint - 1) // ' does not exist; the case has ' // &
         to_str(self%session%num_joints()) // ' joints')
   end subroutine check_joint

   !> Name of joint `joint`.
   subroutine case_joint_name(self, joint, name, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: joint
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
      name = ''
      call check_joint(self, 'joint_name', joint, error)
      if (.not. allocated(error)) name = self%session%mech%joints(joint)%name
   end subroutine case_joint_name

   !> Reaction force (N) and moment (N m) of a joint, global; column 1 on its body 1.
   subroutine case_joint_reaction(self, joint, force, moment, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: joint
      real(dp), intent(out) :: force(3, 2), moment(3, 2)
      type(error_t), allocatable, intent(out) :: error
      force = 0.0_dp
      moment = 0.0_dp
      call check_joint(self, 'joint_reaction', joint, error)
      if (.not. allocated(error)) call self%session%joint_reaction(joint, force, moment, error)
   end subroutine case_joint_reaction

   !> Apply a global force (N) and moment (N m) at a marker from now on, until set again.
   subroutine case_set_marker_load(self, body, marker, force, moment, error)
      class(ffrf_case_t), intent(inout) :: self
      integer, intent(in) :: body, marker
      real(dp), intent(in) :: force(3), moment(3)
      type(error_t), allocatable, intent(out) :: error
      call check_marker(self, 'marker_set_load', body, marker, error)
      if (.not. allocated(error)) call self%session%set_marker_load(body, marker, force, &
         moment, error)
   end subroutine case_set_marker_load

   !> Release everything (the object can be opened again).
   subroutine case_close(self)
      class(ffrf_case_t), intent(out) :: self
      self%opened = .false.
   end subroutine case_close

end module ffrf_capi_case
