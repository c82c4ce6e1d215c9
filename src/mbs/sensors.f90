!> Sensors: named measurements of a mechanism's state, evaluated at a state (q, v, q'', lambda)
!> and written once per recorded step (docs/sensors.md). One table lists the kinds: the words a
!> user writes (&sensor type), the kind each maps to, the number of values and their unit.
!>
!> | word             | values                                                    | unit     |
!> |------------------|-----------------------------------------------------------|----------|
!> | position         | r_k(q), global position of the marker                     | m        |
!> | velocity         | L_r v (theory.md 3.5)                                     | m/s      |
!> | acceleration     | L_r q'' + (d L_r / dt) v                                  | m/s^2    |
!> | orientation      | the marker frame, global: its x, y, z axes (9, by column) | 1        |
!> | angular_velocity | L_w v, global                                             | rad/s    |
!> | joint_coordinate | revolute: angle of marker b's x axis about marker a's z   | rad or m |
!> |                  | axis, in (-pi, pi]; prismatic: (r_b - r_a) . z_a; other   |          |
!> |                  | kinds: |r_b - r_a|                                         |          |
!> | reaction         | force and moment on body a, then on body b (12, global)   | N, N m   |
!> | energy           | kinetic v^T M v / 2 and strain energy of a body (2)       | J        |
!> | node_displacement| elastic displacement Psi_n zeta of a mesh node, body frame | m        |
!> | node_position    | R + A(theta) (x_n + Psi_n zeta), global                   | m        |
!> | spring           | length l, rate l' and tension k (l - L0) + c l' of a      | m, m/s, N|
!> |                  | &spring (ffrf_mbs_spring_damper)                          |          |
!> | driver           | of the driver of a joint (ffrf_mbs_joint_driver): angle or | rad, rad/s,|
!> |                  | travel, its rate, driving torque or force tau = -lambda    | N m; m,  |
!> |                  | on body b about or along the axis                          | m/s, N   |
!> | torsion_spring   | angle phi (unwrapped), rate phi' and torque                | rad,     |
!> |                  | -k (phi - phi0) - c phi' on body b about the joint axis of | rad/s,   |
!> |                  | a &torsion_spring (ffrf_mbs_torsion_spring)                | N m      |
!> | bushing          | deflections d, phi (6), then F = -K d - C d' and           | m, rad,  |
!> |                  | M = -K_r phi - C_r phi' (6), marker 1's axes (&bushing,     | N, N m   |
!> |                  | ffrf_mbs_bushing)                                          |          |
!>
!> A marker is any marker of a body: a rigid body's or the ground's &marker point, a flexible
!> body's interface virtual node or mesh point (a node, or a physical surface's RBE3 point:
!> flexible_body_t add_point) (its elastic motion included: r_k, L_r and L_w are the body's
!> own marker functions). (d L_r / dt) v is the central difference of L_r(q + s v) v in
!> s (s = eps**(1/3) relative): exact but for round-off on rigid bodies (L_r is quadratic in
!> the Euler parameters), O(s^2) on flexible ones. A mesh node's rows Psi_n of the mode shapes
!> (3 x num_modes) and its position x_n in the body frame are given by the application that
!> builds the sensor (node_shape, node_xyz; a rigid body has no rows). Two further kinds are not
!> user words: the
!> rotor angle and speed of the mechanism (ffrf_mbs_mechanism set_rotor), which applications
!> attach under their own names.
module ffrf_mbs_sensors
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_choices, only: choice_kind_of, choice_name, choice_words, sensor_choices, &
      rotor_sensor_choices, SENSOR_POSITION, SENSOR_VELOCITY, SENSOR_ACCELERATION, &
      SENSOR_ORIENTATION, SENSOR_ANGULAR_VELOCITY, SENSOR_JOINT_COORDINATE, SENSOR_REACTION, &
      SENSOR_ENERGY, SENSOR_NODE_DISPLACEMENT, SENSOR_NODE_POSITION, SENSOR_SPRING, &
      SENSOR_DRIVER, SENSOR_TORSION_SPRING, SENSOR_BUSHING, SENSOR_ROTOR_ANGLE, SENSOR_ROTOR_SPEED
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_joints, only: JOINT_REVOLUTE, JOINT_PRISMATIC
   use ffrf_mbs_rotation, only: euler_rotation
   use ffrf_mbs_spring_damper, only: spring_state_t
   use ffrf_mbs_torsion_spring, only: torsion_state_t
   use ffrf_mbs_bushing, only: bushing_state_t
   implicit none
   private
   public :: sensor_t, sensor_kind_of, sensor_word, sensor_size, sensor_unit, sensor_choices
   public :: sensor_needs, NEEDS_MARKER, NEEDS_JOINT, NEEDS_BODY, NEEDS_NODE, NEEDS_SPRING
   public :: SENSOR_SPRING, SENSOR_DRIVER, SENSOR_TORSION_SPRING, &
      SENSOR_BUSHING
   public :: SENSOR_POSITION, SENSOR_VELOCITY, SENSOR_ACCELERATION, SENSOR_ORIENTATION, &
      SENSOR_ANGULAR_VELOCITY, SENSOR_JOINT_COORDINATE, SENSOR_REACTION, SENSOR_ENERGY, &
      SENSOR_NODE_DISPLACEMENT, SENSOR_NODE_POSITION, SENSOR_ROTOR_ANGLE, SENSOR_ROTOR_SPEED

   !> What each kind is measured on (sensor_needs): a marker, a joint, a body (energy), a mesh
   !> node of a body, a spring (&spring, &torsion_spring, &bushing); the rotor kinds on none
   integer, parameter :: NEEDS_MARKER = 1, NEEDS_JOINT = 2, NEEDS_BODY = 3, NEEDS_NODE = 4, &
      NEEDS_SPRING = 5
   integer, parameter :: MEASURED_ON(16) = [NEEDS_MARKER, NEEDS_MARKER, NEEDS_MARKER, &
      NEEDS_MARKER, NEEDS_MARKER, NEEDS_JOINT, NEEDS_JOINT, NEEDS_BODY, NEEDS_NODE, NEEDS_NODE, &
      NEEDS_SPRING, NEEDS_JOINT, NEEDS_SPRING, NEEDS_SPRING, 0, 0]
   !> Number of values and unit of each kind, in the order of the kinds (module header)
   integer, parameter :: SIZES(16) = [3, 3, 3, 9, 3, 1, 12, 2, 3, 3, 3, 3, 3, 12, 1, 1]
   character(len=*), parameter :: UNITS(16) = [character(len=15) :: 'm', 'm/s', 'm/s^2', '1', &
      'rad/s', 'rad', 'N, N m', 'J', 'm', 'm', 'm, m/s, N', 'rad, rad/s, N m', &
      'rad, rad/s, N m', 'm, rad, N, N m', 'rad', 'rad/s']

   !> A sensor, resolved to mechanism indices.
   type :: sensor_t
      !> Name (the results group /sensors/<name>)
      character(len=64) :: name = ''
      !> SENSOR_*
      integer :: kind = 0
      !> Mechanism index of the body (marker and energy kinds)
      integer :: body = 0
      !> Marker of the body (marker kinds) and its name, for the output
      integer :: marker = 0
      character(len=64) :: marker_name = ''
      !> Mechanism joint number (joint kinds)
      integer :: joint = 0
      !> Mechanism spring number (spring kind: order of add_spring; torsion_spring kind: order
      !> of add_torsion_spring)
      integer :: spring = 0
      !> Node kinds: the mesh node (for the output), its position in the body frame (m) and its
      !> rows of the mode shapes (3, num_modes; 0 columns for a rigid body)
      integer :: node = 0
      real(dp) :: node_xyz(3) = 0.0_dp
      real(dp), allocatable :: node_shape(:, :)
   contains
      !> Its values at a state (sensor_size(kind) of them)
      procedure :: evaluate => sensor_evaluate
   end type sensor_t

contains

   !> The kind of a &sensor type word (a user word, any case; 0 if none).
   pure integer function sensor_kind_of(word) result(kind)
      character(len=*), intent(in) :: word
      kind = choice_kind_of(sensor_choices, word)
   end function sensor_kind_of

   !> The word of a kind (the rotor kinds included).
   pure function sensor_word(kind) result(word)
      integer, intent(in) :: kind
      character(len=:), allocatable :: word
      word = choice_name([sensor_choices, rotor_sensor_choices], kind)
   end function sensor_word

   !> Number of values of a kind.
   pure integer function sensor_size(kind)
      integer, intent(in) :: kind
      sensor_size = 0
      if (kind >= 1 .and. kind <= size(SIZES)) sensor_size = SIZES(kind)
   end function sensor_size

   !> Unit of a kind; joint_coordinate: 'rad' for a revolute joint, else 'm'.
   pure function sensor_unit(kind, joint_kind) result(unit)
      integer, intent(in) :: kind
      !> JOINT_* of the sensor's joint (joint kinds; else ignored)
      integer, intent(in) :: joint_kind
      character(len=:), allocatable :: unit
      unit = '1'
      if (kind >= 1 .and. kind <= size(UNITS)) unit = trim(UNITS(kind))
      if (kind == SENSOR_JOINT_COORDINATE .and. joint_kind /= JOINT_REVOLUTE) unit = 'm'
      if (kind == SENSOR_DRIVER .and. joint_kind /= JOINT_REVOLUTE) unit = 'm, m/s, N'
   end function sensor_unit

   !> .true. when kind is measured on `what`: NEEDS_MARKER (a marker of a body), NEEDS_JOINT,
   !> NEEDS_SPRING (a &spring, &torsion_spring or &bushing), NEEDS_NODE (a mesh node of a body)
   !> or NEEDS_BODY (a body without a marker: energy and the node kinds).
   pure logical function sensor_needs(kind, what)
      integer, intent(in) :: kind, what
      sensor_needs = .false.
      if (kind < 1 .or. kind > size(MEASURED_ON)) return
      sensor_needs = MEASURED_ON(kind) == what .or. &
         (what == NEEDS_BODY .and. MEASURED_ON(kind) == NEEDS_NODE)
   end function sensor_needs

   !> The sensor's values at the state (q, v, q'', lambda) of `mech` (module header).
   subroutine sensor_evaluate(self, mech, q, v, qdd, lambda, values, error)
      class(sensor_t), intent(in) :: self
      type(mechanism_t), intent(in) :: mech
      !> Coordinates, velocities, accelerations (n), multipliers (nc)
      real(dp), intent(in) :: q(:), v(:), qdd(:), lambda(:)
      !> sensor_size(kind) values
      real(dp), allocatable, intent(out) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: qb(:), vb(:), ab(:)
      real(dp) :: force(3, 2), moment(3, 2), frame_a(3, 3), frame_b(3, 3), s, u(3)
      type(spring_state_t) :: state
      type(torsion_state_t) :: torsion
      type(bushing_state_t) :: bushing
      integer :: a, b, m
      allocate (values(sensor_size(self%kind)), source=0.0_dp)
      if (sensor_needs(self%kind, NEEDS_MARKER) .or. sensor_needs(self%kind, NEEDS_BODY)) then
         if (self%body < 1 .or. self%body > size(mech%bodies)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'sensor "' // trim(self%name) // &
               '": the mechanism has no body ' // to_str(self%body))
            return
         end if
         qb = mech%body_coordinates(q, self%body)
         vb = mech%body_coordinates(v, self%body)
         ab = mech%body_coordinates(qdd, self%body)
      end if
      if (sensor_needs(self%kind, NEEDS_MARKER)) then
         if (self%marker < 1 .or. self%marker > mech%bodies(self%body)%body%num_markers) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'sensor "' // trim(self%name) // &
               '": body "' // mech%bodies(self%body)%name // '" has no marker ' // &
               to_str(self%marker))
            return
         end if
      end if
      if (sensor_needs(self%kind, NEEDS_JOINT)) then
         if (self%joint < 1 .or. self%joint > size(mech%joints)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'sensor "' // trim(self%name) // &
               '": the mechanism has no joint ' // to_str(self%joint))
            return
         end if
      end if
      if (sensor_needs(self%kind, NEEDS_SPRING)) then
         m = 0
         if (self%kind == SENSOR_SPRING .and. allocated(mech%springs)) m = size(mech%springs)
         if (self%kind == SENSOR_TORSION_SPRING .and. allocated(mech%torsion_springs)) &
            m = size(mech%torsion_springs)
         if (self%kind == SENSOR_BUSHING .and. allocated(mech%bushings)) m = size(mech%bushings)
         if (self%spring < 1 .or. self%spring > m) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'sensor "' // trim(self%name) // &
               '": the mechanism has no spring ' // to_str(self%spring))
            return
         end if
      end if
      select case (self%kind)
      case (SENSOR_SPRING)
         state = mech%spring_state(self%spring, q, v)
         values = [state%length, state%rate, state%force]
      case (SENSOR_TORSION_SPRING)
         torsion = mech%torsion_state(self%spring, q, v)
         values = [torsion%angle, torsion%rate, torsion%torque]
      case (SENSOR_BUSHING)
         bushing = mech%bushing_state(self%spring, q, v)
         values = [bushing%deflection, -bushing%force]
      case (SENSOR_POSITION)
         values = mech%bodies(self%body)%body%marker_position(qb, self%marker)
      case (SENSOR_VELOCITY)
         values = matmul(mech%bodies(self%body)%body%marker_velocity_jacobian(qb, &
            self%marker), vb)
      case (SENSOR_ACCELERATION)
         associate (x => mech%bodies(self%body)%body)
            values = matmul(x%marker_velocity_jacobian(qb, self%marker), ab)
            if (size(vb) > 0) then
               if (maxval(abs(vb)) > 0.0_dp) then
                  s = epsilon(1.0_dp)**(1.0_dp / 3.0_dp) * max(1.0_dp, maxval(abs(qb))) / &
                     maxval(abs(vb))
                  values = values + (matmul(x%marker_velocity_jacobian(qb + s * vb, &
                     self%marker), vb) - matmul(x%marker_velocity_jacobian(qb - s * vb, &
                     self%marker), vb)) / (2.0_dp * s)
               end if
            end if
         end associate
      case (SENSOR_ORIENTATION)
         frame_a = mech%bodies(self%body)%body%marker_orientation(qb, self%marker)
         values = reshape(frame_a, [9])
      case (SENSOR_ANGULAR_VELOCITY)
         values = matmul(mech%bodies(self%body)%body%marker_rotation_jacobian(qb, &
            self%marker), vb)
      case (SENSOR_JOINT_COORDINATE)
         associate (jt => mech%joints(self%joint))
            a = jt%body_a
            b = jt%body_b
            associate (body_a => mech%bodies(a)%body, body_b => mech%bodies(b)%body, &
                  qa => mech%body_coordinates(q, a), qbb => mech%body_coordinates(q, b))
               frame_a = body_a%marker_orientation(qa, jt%joint%marker_a)
               frame_b = body_b%marker_orientation(qbb, jt%joint%marker_b)
               select case (jt%joint%kind_name())
               case ('revolute')
                  ! x axis of b in the frame of a: its angle about z_a
                  values(1) = atan2(dot_product(frame_a(:, 2), frame_b(:, 1)), &
                     dot_product(frame_a(:, 1), frame_b(:, 1)))
               case ('prismatic')
                  values(1) = dot_product(body_b%marker_position(qbb, jt%joint%marker_b) - &
                     body_a%marker_position(qa, jt%joint%marker_a), frame_a(:, 3))
               case default
                  values(1) = norm2(body_b%marker_position(qbb, jt%joint%marker_b) - &
                     body_a%marker_position(qa, jt%joint%marker_a))
               end select
            end associate
         end associate
      case (SENSOR_DRIVER)
         m = 0
         if (allocated(mech%drivers)) m = findloc(mech%drivers%joint, self%joint, dim=1)
         if (m == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'sensor "' // trim(self%name) // &
               '": joint "' // mech%joints(self%joint)%name // '" has no driver; add &driver ' &
               // 'joint = ''' // mech%joints(self%joint)%name // ''' or use joint_coordinate')
            return
         end if
         values = mech%driver_state(m, q, v, lambda)
      case (SENSOR_REACTION)
         call mech%reaction(self%joint, q, lambda, force, moment)
         values = [force(:, 1), moment(:, 1), force(:, 2), moment(:, 2)]
      case (SENSOR_ENERGY)
         values = [mech%bodies(self%body)%body%kinetic_energy(qb, vb), &
            mech%bodies(self%body)%body%strain_energy(qb)]
      case (SENSOR_NODE_DISPLACEMENT, SENSOR_NODE_POSITION)
         u = 0.0_dp
         m = 0
         if (allocated(self%node_shape)) m = size(self%node_shape, 2)
         if (m > 0) then
            if (size(qb) < 7 + m) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'sensor "' // trim(self%name) // &
                  '": body "' // mech%bodies(self%body)%name // '" has ' // &
                  to_str(max(size(qb) - 7, 0)) // ' modal coordinates, the node rows ' // &
                  to_str(m))
               return
            end if
            u = matmul(self%node_shape, qb(8:7 + m))
         end if
         if (self%kind == SENSOR_NODE_DISPLACEMENT) then
            values = u
         else if (size(qb) >= 7) then
            values = qb(1:3) + matmul(euler_rotation(qb(4:7)), self%node_xyz + u)
         else
            values = self%node_xyz
         end if
      case (SENSOR_ROTOR_ANGLE)
         values(1) = mech%rotor_angle(q)
      case (SENSOR_ROTOR_SPEED)
         values(1) = mech%rotor_speed(q, v)
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'sensor "' // trim(self%name) // &
            '": unknown kind ' // to_str(self%kind) // '; the types are ' // &
            choice_words(sensor_choices))
      end select
   end subroutine sensor_evaluate

end module ffrf_mbs_sensors
