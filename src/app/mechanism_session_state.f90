!> The state of a mechanism session between two advances (a submodule of
!> ffrf_app_mechanism_session): time and crank, body coordinates, markers, sensors, joint
!> reactions, and the host's loads at markers for the next interval.
submodule (ffrf_app_mechanism_session) ffrf_app_mechanism_session_state
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_mechanism_loads, only: LOAD_FORCE, LOAD_TORQUE
   use ffrf_mbs_host_load, only: host_load_t
   implicit none

contains

   module procedure session_time
      session_time = self%integrator%t
   end procedure session_time

   module procedure session_end_time
      session_end_time = self%integrator%settings%t_end
   end procedure session_end_time

   module procedure session_crank_angle
      session_crank_angle = 0.0_dp
      if (self%prepared) session_crank_angle = self%mech%rotor_angle(self%integrator%q)
   end procedure session_crank_angle

   module procedure session_crank_speed
      session_crank_speed = 0.0_dp
      if (self%prepared) session_crank_speed = self%mech%rotor_speed(self%integrator%q, &
         self%integrator%v)
   end procedure session_crank_speed

   module procedure session_num_bodies
      session_num_bodies = 0
      if (allocated(self%bodies)) session_num_bodies = size(self%bodies)
   end procedure session_num_bodies

   !> Check a body number (1..num_bodies) and give its mechanism index.
   subroutine body_of(self, body, index, error)
      class(mechanism_session_t), intent(in) :: self
      integer, intent(in) :: body
      integer, intent(out) :: index
      type(error_t), allocatable, intent(out) :: error
      index = 0
      call check_item(self, 'body', 'bodies', body, self%num_bodies(), error)
      if (.not. allocated(error)) index = self%bodies(body)%index
   end subroutine body_of

   module procedure session_body_state
      integer :: b
      call body_of(self, body, b, error)
      if (allocated(error)) return
      q = self%mech%body_coordinates(self%integrator%q, b)
      v = self%mech%body_coordinates(self%integrator%v, b)
   end procedure session_body_state

   module procedure session_num_markers
      type(error_t), allocatable :: error
      integer :: b
      session_num_markers = 0
      call body_of(self, body, b, error)
      if (.not. allocated(error)) session_num_markers = self%mech%bodies(b)%body%num_markers
   end procedure session_num_markers

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

   module procedure session_marker_motion
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
   end procedure session_marker_motion

   module procedure session_num_sensors
      session_num_sensors = 0
      if (allocated(self%sensors)) session_num_sensors = size(self%sensors)
   end procedure session_num_sensors

   !> Check a sensor number.
   subroutine sensor_of(self, sensor, error)
      class(mechanism_session_t), intent(in) :: self
      integer, intent(in) :: sensor
      type(error_t), allocatable, intent(out) :: error
      call check_item(self, 'sensor', 'sensors', sensor, self%num_sensors(), error)
   end subroutine sensor_of

   module procedure session_sensor_name
      name = ''
      call sensor_of(self, sensor, error)
      if (.not. allocated(error)) name = trim(self%sensors(sensor)%name)
   end procedure session_sensor_name

   module procedure session_sensor_size
      size_ = 0
      call sensor_of(self, sensor, error)
      if (.not. allocated(error)) size_ = sensor_size(self%sensors(sensor)%kind)
   end procedure session_sensor_size

   module procedure session_sensor_values
      allocate (values(0))
      call sensor_of(self, sensor, error)
      if (allocated(error)) return
      call self%sensors(sensor)%evaluate(self%mech, self%integrator%q, self%integrator%v, &
         self%integrator%qdd, self%integrator%lambda, values, error)
   end procedure session_sensor_values

   module procedure session_num_joints
      session_num_joints = 0
      if (allocated(self%mech%joints)) session_num_joints = size(self%mech%joints)
   end procedure session_num_joints

   module procedure session_joint_reaction
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
   end procedure session_joint_reaction

   module procedure session_set_marker_load
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

   end procedure session_set_marker_load

   !> FFRF_INPUT_ERROR unless the session is prepared and 1 <= index <= count: "mechanism: <word>
   !> <index> does not exist; the case has <count> <plural>".
   subroutine check_item(self, word, plural, index, count, error)
      class(mechanism_session_t), intent(in) :: self
      character(len=*), intent(in) :: word, plural
      integer, intent(in) :: index, count
      type(error_t), allocatable, intent(out) :: error
      if (.not. self%prepared) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: not prepared')
      else if (index < 1 .or. index > count) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: ' // word // ' ' // &
            to_str(index) // ' does not exist; the case has ' // to_str(count) // ' ' // plural)
      end if
   end subroutine check_item

end submodule ffrf_app_mechanism_session_state
