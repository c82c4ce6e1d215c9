!> Building a mechanism (ffrf_mbs_mechanism): bodies, joints, loads, springs, torsion springs,
!> bushings, drivers, the rotor and the driving constraint, and the coordinate layout they share.
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_build
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: pi
   use ffrf_core_error, only: fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_rotation, only: euler_g
   use ffrf_mbs_joints, only: new_joint, JOINT_REVOLUTE, JOINT_PRISMATIC
   use ffrf_mbs_joint_driver, only: driver_coordinate
   use ffrf_mbs_mechanism_loads, only: LOAD_FORCE, LOAD_TORQUE
   use ffrf_mbs_spring_damper, only: spring_evaluate
   implicit none

contains

   !> Add a copy of `body`; `index` is its mechanism index for joints, loads, rotor and drive.
   module procedure mechanism_add_body
      type(mechanism_body_t), allocatable :: grown(:)
      integer :: i, nb
      index = 0
      if (body%num_coordinates < 0 .or. (body%num_coordinates > 0 .and. &
         body%num_coordinates < 7)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: body "' // name // '" has ' // &
            to_str(body%num_coordinates) // ' coordinates; expected 0 (ground) or at least 7 ' &
            // '([R; theta; zeta]); initialise the body first')
         return
      end if
      nb = 0
      if (allocated(self%bodies)) nb = size(self%bodies)
      allocate (grown(nb + 1))
      do i = 1, nb
         call move_alloc(self%bodies(i)%body, grown(i)%body)
         call move_alloc(self%bodies(i)%name, grown(i)%name)
      end do
      allocate (grown(nb + 1)%body, source=body)
      grown(nb + 1)%name = name
      call move_alloc(grown, self%bodies)
      index = nb + 1
      call update_layout(self)
   end procedure mechanism_add_body

   !> Add a joint of `kind` (JOINT_* of ffrf_mbs_joints: new_joint) between marker_a of body a
   !> and marker_b of body b (mechanism indices).
   module procedure mechanism_add_joint
      type(mechanism_joint_t), allocatable :: grown(:)
      class(joint_t), allocatable :: joint
      integer :: i, nj
      if (.not. (valid_body(self, body_a) .and. valid_body(self, body_b)) .or. &
         body_a == body_b) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: joint "' // name // &
            '" connects bodies ' // to_str(body_a) // ' and ' // to_str(body_b) // &
            '; they must be two different indices returned by add_body (1..' // &
            to_str(num_bodies(self)) // ')')
         return
      end if
      call new_joint(kind, joint, error)
      if (.not. allocated(error)) call joint%connect(self%bodies(body_a)%body, marker_a, &
         self%bodies(body_b)%body, marker_b, error)
      if (allocated(error)) then
         call add_context(error, 'mechanism: joint "' // name // '"')
         return
      end if
      nj = num_joints(self)
      allocate (grown(nj + 1))
      do i = 1, nj
         call move_alloc(self%joints(i)%joint, grown(i)%joint)
         call move_alloc(self%joints(i)%name, grown(i)%name)
         grown(i)%body_a = self%joints(i)%body_a
         grown(i)%body_b = self%joints(i)%body_b
      end do
      call move_alloc(joint, grown(nj + 1)%joint)
      grown(nj + 1)%name = name
      grown(nj + 1)%body_a = body_a
      grown(nj + 1)%body_b = body_b
      call move_alloc(grown, self%joints)
      call update_layout(self)
   end procedure mechanism_add_joint

   !> Add a copy of an applied load; its direction is normalised here.
   module procedure mechanism_add_load
      type(mechanism_load_t), allocatable :: grown(:)
      integer :: i, nl
      if (.not. valid_body(self, load%body)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: load "' // trim(load%name) // &
            '" is on body ' // to_str(load%body) // ', not an index returned by add_body (1..' &
            // to_str(num_bodies(self)) // ')')
         return
      end if
      if (load%marker < 1 .or. load%marker > self%bodies(load%body)%body%num_markers) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: load "' // trim(load%name) // &
            '" at marker ' // to_str(load%marker) // '; body "' // &
            self%bodies(load%body)%name // '" has ' // &
            to_str(self%bodies(load%body)%body%num_markers) // ' markers')
         return
      end if
      if (.not. (norm2(load%direction) > 0.0_dp .and. all(ieee_is_finite(load%direction)))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: load "' // trim(load%name) // &
            '" has a zero or non-finite direction; give a non-zero global vector')
         return
      end if
      if (load%kind /= LOAD_FORCE .and. load%kind /= LOAD_TORQUE) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: load "' // trim(load%name) // &
            '" has kind ' // to_str(load%kind) // '; use LOAD_FORCE (1) or LOAD_TORQUE (2)')
         return
      end if
      nl = 0
      if (allocated(self%loads)) nl = size(self%loads)
      allocate (grown(nl + 1))
      do i = 1, nl
         call move_alloc(self%loads(i)%load, grown(i)%load)
      end do
      allocate (grown(nl + 1)%load, source=load)
      grown(nl + 1)%load%direction = load%direction / norm2(load%direction)
      call move_alloc(grown, self%loads)
   end procedure mechanism_add_load

   !> Add a copy of a spring-damper (refusals: mechanism.f90's interface).
   module procedure mechanism_add_spring
      call check_pair_ends(self, 'spring', spring%name, spring%body_a, spring%marker_a, &
         spring%body_b, spring%marker_b, spring%stiffness >= 0.0_dp .and. &
         spring%damping >= 0.0_dp, 'stiffness = ' // to_str(spring%stiffness) // &
         ' N/m and damping = ' // to_str(spring%damping) // ' N s/m must both be >= 0', error)
      if (allocated(error)) return
      if (.not. allocated(self%springs)) allocate (self%springs(0))
      self%springs = [self%springs, spring]
   end procedure mechanism_add_spring

   !> Length, direction, rate and tension of spring s at (q, v).
   module procedure mechanism_spring_state
      integer, allocatable :: rows(:)
      integer :: na
      associate (spring => self%springs(s))
         call pair_rows(self, spring%body_a, spring%body_b, rows, na)
         state = spring_evaluate(spring, self%bodies(spring%body_a)%body, q(rows(:na)), &
            v(rows(:na)), self%bodies(spring%body_b)%body, q(rows(na + 1:)), v(rows(na + 1:)))
      end associate
   end procedure mechanism_spring_state

   !> Potential energy of the springs, sum k (l - L0)^2 / 2 (J).
   module procedure mechanism_spring_energy
      type(spring_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      energy = 0.0_dp
      if (.not. allocated(self%springs)) return
      zero = 0.0_dp
      do s = 1, size(self%springs)
         state = self%spring_state(s, q, zero)
         energy = energy + 0.5_dp * self%springs(s)%stiffness * &
            (state%length - self%springs(s)%free_length)**2
      end do
   end procedure mechanism_spring_energy

   !> Free lengths not given become the lengths at q (mechanism.f90's interface).
   module procedure mechanism_set_spring_free_lengths
      type(spring_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      if (.not. allocated(self%springs)) return
      zero = 0.0_dp
      do s = 1, size(self%springs)
         if (self%springs(s)%free_length >= 0.0_dp) cycle
         state = self%spring_state(s, q, zero)
         if (.not. (state%length > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'spring "' // &
               trim(self%springs(s)%name) // '": its markers coincide at the start (length 0);' &
               // ' give free_length')
            return
         end if
         self%springs(s)%free_length = state%length
      end do
   end procedure mechanism_set_spring_free_lengths

   !> Add a copy of a torsion spring about a revolute or cylindrical joint.
   module procedure mechanism_add_torsion_spring
      type(torsion_spring_t) :: added
      integer :: nj
      character(len=:), allocatable :: where
      where = 'mechanism: torsion spring "' // trim(spring%name) // '"'
      nj = num_joints(self)
      if (spring%joint < 1 .or. spring%joint > nj) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': the mechanism has no joint ' // &
            to_str(spring%joint) // ' (' // to_str(nj) // ' joints)')
         return
      end if
      associate (jt => self%joints(spring%joint))
         select case (jt%joint%kind_name())
         case ('revolute', 'cylindrical')
         case default
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': joint "' // jt%name // &
               '" is ' // jt%joint%kind_name() // '; a torsion spring needs a revolute or ' // &
               'cylindrical joint')
            return
         end select
         if (.not. (spring%stiffness >= 0.0_dp .and. spring%damping >= 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': stiffness = ' // &
               to_str(spring%stiffness) // ' N m/rad and damping = ' // &
               to_str(spring%damping) // ' N m s/rad; both must be >= 0')
            return
         end if
         added = spring
         added%body_a = jt%body_a
         added%body_b = jt%body_b
         added%marker_a = jt%joint%marker_a
         added%marker_b = jt%joint%marker_b
      end associate
      if (.not. allocated(self%torsion_springs)) allocate (self%torsion_springs(0))
      self%torsion_springs = [self%torsion_springs, added]
   end procedure mechanism_add_torsion_spring

   !> Add a copy of a bushing between two markers of two bodies.
   module procedure mechanism_add_bushing
      call check_pair_ends(self, 'bushing', bushing%name, bushing%body_a, bushing%marker_a, &
         bushing%body_b, bushing%marker_b, all(bushing%stiffness >= 0.0_dp) .and. &
         all(bushing%damping >= 0.0_dp), 'a negative stiffness or damping entry; all six ' // &
         'of each must be >= 0', error)
      if (allocated(error)) return
      if (.not. allocated(self%bushings)) allocate (self%bushings(0))
      self%bushings = [self%bushings, bushing]
   end procedure mechanism_add_bushing

   !> The rotor is body `body` (with Euler parameters); its angle is unwrapped from 0.
   module procedure mechanism_set_rotor
      call check_rotating_body(self, body, 'rotor', error)
      if (allocated(error)) return
      self%rotor = body
      self%rotor_reference = 0.0_dp
   end procedure mechanism_set_rotor

   !> Unwrap the rotor angle of q against `angle` (rad) and keep the result as the reference.
   module procedure mechanism_set_rotor_reference
      self%rotor_reference = angle
      self%rotor_reference = self%rotor_angle(q)
   end procedure mechanism_set_rotor_reference

   !> Prescribe the rotation about z of body `body` as law%evaluate(t) (one rheonomic row).
   module procedure mechanism_set_drive
      call check_rotating_body(self, body, 'driven', error)
      if (allocated(error)) return
      self%drive_body = body
      if (allocated(self%drive)) deallocate (self%drive)
      allocate (self%drive, source=law)
      call update_layout(self)
   end procedure mechanism_set_drive

   !> Add a driver of a revolute or prismatic joint (ffrf_mbs_joint_driver).
   module procedure mechanism_add_driver
      type(joint_driver_t) :: added
      integer :: nj
      nj = num_joints(self)
      if (driver%joint < 1 .or. driver%joint > nj) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'driver "' // trim(driver%name) // &
            '": the mechanism has no joint ' // to_str(driver%joint) // ' (' // to_str(nj) // &
            ' joints)')
         return
      end if
      added = driver
      select case (self%joints(driver%joint)%joint%kind_name())
      case ('revolute')
         added%kind = JOINT_REVOLUTE
      case ('prismatic')
         added%kind = JOINT_PRISMATIC
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'driver "' // trim(driver%name) // &
            '": joint "' // self%joints(driver%joint)%name // '" is ' // &
            self%joints(driver%joint)%joint%kind_name() // '; a driver needs a revolute or ' // &
            'prismatic joint')
         return
      end select
      if (.not. allocated(self%drivers)) allocate (self%drivers(0))
      self%drivers = [self%drivers, added]
      call update_layout(self)
   end procedure mechanism_add_driver

   !> [coordinate, rate, tau = -lambda] of driver d (ffrf_mbs_joint_driver).
   module procedure mechanism_driver_state
      associate (dr => self%drivers(d), jt => self%joints(self%drivers(d)%joint))
         call driver_coordinate(dr%kind, self%bodies(jt%body_a)%body, &
            self%body_coordinates(q, jt%body_a), self%body_coordinates(v, jt%body_a), &
            jt%joint%marker_a, self%bodies(jt%body_b)%body, self%body_coordinates(q, jt%body_b), &
            self%body_coordinates(v, jt%body_b), jt%joint%marker_b, values(1), values(2))
         values(3) = -lambda(dr%row)
      end associate
   end procedure mechanism_driver_state

   !> Offsets of coordinates and rows after a change.
   subroutine update_layout(self)
      type(mechanism_t), intent(inout) :: self
      integer :: b, j, row
      self%n = 0
      do b = 1, num_bodies(self)
         self%bodies(b)%offset = self%n
         self%n = self%n + self%bodies(b)%body%num_coordinates
      end do
      row = 0
      do j = 1, num_joints(self)
         self%joints(j)%offset = row
         row = row + self%joints(j)%joint%num_equations
      end do
      if (allocated(self%drivers)) then
         do j = 1, size(self%drivers)
            row = row + 1
            self%drivers(j)%row = row
         end do
      end if
      self%drive_row = 0
      if (self%drive_body > 0) then
         row = row + 1
         self%drive_row = row
      end if
      do b = 1, num_bodies(self)
         self%bodies(b)%euler_row = 0
         if (self%bodies(b)%body%num_coordinates >= 7) then
            row = row + 1
            self%bodies(b)%euler_row = row
         end if
      end do
      self%nc = row
   end subroutine update_layout

   module procedure check_pair_ends
      character(len=:), allocatable :: where
      where = 'mechanism: ' // what // ' "' // trim(name) // '"'
      if (.not. (valid_body(self, body_a) .and. valid_body(self, body_b))) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' connects bodies ' // &
            to_str(body_a) // ' and ' // to_str(body_b) // &
            ', not both indices returned by add_body (1..' // to_str(num_bodies(self)) // ')')
      else if (body_a == body_b) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' has both ends on body "' // &
            self%bodies(body_a)%name // '"; a ' // what // ' connects two different bodies')
      else if (marker_a < 1 .or. marker_a > self%bodies(body_a)%body%num_markers .or. &
         marker_b < 1 .or. marker_b > self%bodies(body_b)%body%num_markers) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': marker ' // to_str(marker_a) // &
            ' or ' // to_str(marker_b) // ' is not a marker of its body')
      else if (.not. coefficients_ok) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': ' // refusal)
      end if
   end procedure check_pair_ends

   module procedure pair_rows
      integer :: i, ka, kb, nb
      call pair_layout(self, body_a, body_b, ka, na, kb, nb)
      rows = [(ka + i, i = 1, na), (kb + i, i = 1, nb)]
   end procedure pair_rows

   module procedure body_layout
      k = self%bodies(b)%offset
      nb = self%bodies(b)%body%num_coordinates
   end procedure body_layout

   module procedure pair_layout
      call body_layout(self, body_a, ka, na)
      call body_layout(self, body_b, kb, nb)
   end procedure pair_layout

   module procedure valid_body
      valid_body = b >= 1 .and. b <= num_bodies(self)
   end procedure valid_body

   module procedure num_joints
      num_joints = 0
      if (allocated(self%joints)) num_joints = size(self%joints)
   end procedure num_joints

   !> Refuses body b as the `role` body (rotor, driven) unless add_body gave it Euler parameters.
   subroutine check_rotating_body(self, b, role, error)
      type(mechanism_t), intent(in) :: self
      integer, intent(in) :: b
      character(len=*), intent(in) :: role
      type(error_t), allocatable, intent(out) :: error
      logical :: rotating
      rotating = valid_body(self, b)
      if (rotating) rotating = self%bodies(b)%body%num_coordinates >= 7
      if (.not. rotating) call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: ' // role // &
         ' body ' // to_str(b) // ' must be a body with Euler parameters added by add_body')
   end subroutine check_rotating_body

   !> q(offset + 1 : offset + num_coordinates) of body b (empty for the ground).
   module procedure mechanism_body_coordinates
      qb = q(self%bodies(b)%offset + 1:self%bodies(b)%offset + size(qb))
   end procedure mechanism_body_coordinates

   !> Unwrapped rotor angle phi_ref + wrap(2 atan2(e3, e0) - phi_ref) (module header); 0 without
   !> a rotor.
   module procedure mechanism_rotor_angle
      real(dp) :: theta(4), raw
      angle = 0.0_dp
      if (self%rotor == 0) return
      theta = q(self%bodies(self%rotor)%offset + 4:self%bodies(self%rotor)%offset + 7)
      raw = 2.0_dp * atan2(theta(4), theta(1))
      angle = self%rotor_reference + modulo(raw - self%rotor_reference + pi, 2.0_dp * pi) - pi
   end procedure mechanism_rotor_angle

   !> Rotor speed e_z . G(theta) theta_dot (rad/s); 0 without a rotor.
   module procedure mechanism_rotor_speed
      real(dp) :: omega(3)
      integer :: k
      speed = 0.0_dp
      if (self%rotor == 0) return
      k = self%bodies(self%rotor)%offset
      omega = matmul(euler_g(q(k + 4:k + 7)), v(k + 4:k + 7))
      speed = omega(3)
   end procedure mechanism_rotor_speed

end submodule ffrf_mbs_mechanism_build
