!> Bodies of ffrf_mbs_mechanism (a submodule, as the house style asks of long modules): building,
!> rotor state, loads and energies, the dae_system_t procedures, the consistent initial state, and
!> the private helpers they share (layout, least squares by LAPACK dgelsy, drive normals).
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_procedures
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: ip, pi
   use ffrf_core_error, only: fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_finite, only: all_finite
   use ffrf_mbs_rotation, only: euler_rotation, euler_g, euler_g_bar, skew3, &
      rotated_vector_jacobian
   use ffrf_mbs_rigid_body, only: rigid_body_t, euler_hessian, point_load_tangent
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_dae_system, only: dae_stiffness_fd, dae_damping_fd, &
      dae_constraint_stiffness_fd, dae_mass_stiffness_fd
   use ffrf_mbs_joints, only: new_joint, joint_reaction, JOINT_REVOLUTE, JOINT_PRISMATIC
   use ffrf_mbs_joint_driver, only: driver_terms, driver_hessian, driver_coordinate
   use ffrf_la_lapack, only: dgelsy
   use ffrf_mbs_mechanism_loads, only: LOAD_FORCE, LOAD_TORQUE
   use ffrf_mbs_spring_damper, only: spring_evaluate, spring_generalized_forces, spring_tangents
   implicit none

   !> Unit x axis
   real(dp), parameter :: e_x(3) = [1.0_dp, 0.0_dp, 0.0_dp]
   !> Relative rank tolerance of the least-squares solves (dgelsy rcond)
   real(dp), parameter :: rank_rcond = 1.0e-10_dp

contains

   ! ----------------------------------------------------------------------------------------------
   ! Building

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
      nj = 0
      if (allocated(self%joints)) nj = size(self%joints)
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
      character(len=:), allocatable :: where
      where = 'mechanism: spring "' // trim(spring%name) // '"'
      if (.not. (valid_body(self, spring%body_a) .and. valid_body(self, spring%body_b))) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' connects bodies ' // &
            to_str(spring%body_a) // ' and ' // to_str(spring%body_b) // &
            ', not both indices returned by add_body (1..' // to_str(num_bodies(self)) // ')')
      else if (spring%body_a == spring%body_b) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' has both ends on body "' // &
            self%bodies(spring%body_a)%name // '"; a spring connects two different bodies')
      else if (spring%marker_a < 1 .or. spring%marker_a > &
         self%bodies(spring%body_a)%body%num_markers .or. spring%marker_b < 1 .or. &
         spring%marker_b > self%bodies(spring%body_b)%body%num_markers) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': marker ' // &
            to_str(spring%marker_a) // ' or ' // to_str(spring%marker_b) // &
            ' is not a marker of its body')
      else if (.not. (spring%stiffness >= 0.0_dp .and. spring%damping >= 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': stiffness = ' // &
            to_str(spring%stiffness) // ' N/m and damping = ' // to_str(spring%damping) // &
            ' N s/m must both be >= 0')
      end if
      if (allocated(error)) return
      if (.not. allocated(self%springs)) allocate (self%springs(0))
      self%springs = [self%springs, spring]
   end procedure mechanism_add_spring

   !> Length, direction, rate and tension of spring s at (q, v).
   module procedure mechanism_spring_state
      integer :: ka, kb, na, nb
      associate (spring => self%springs(s))
         ka = self%bodies(spring%body_a)%offset
         kb = self%bodies(spring%body_b)%offset
         na = self%bodies(spring%body_a)%body%num_coordinates
         nb = self%bodies(spring%body_b)%body%num_coordinates
         state = spring_evaluate(spring, self%bodies(spring%body_a)%body, q(ka + 1:ka + na), &
            v(ka + 1:ka + na), self%bodies(spring%body_b)%body, q(kb + 1:kb + nb), &
            v(kb + 1:kb + nb))
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

   !> The rotor is body `body` (with Euler parameters); its angle is unwrapped from 0.
   module procedure mechanism_set_rotor
      if (.not. rotating_body(self, body)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: rotor body ' // to_str(body) // &
            ' must be a body with Euler parameters added by add_body')
         return
      end if
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
      if (.not. rotating_body(self, body)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: driven body ' // to_str(body) // &
            ' must be a body with Euler parameters added by add_body')
         return
      end if
      self%drive_body = body
      if (allocated(self%drive)) deallocate (self%drive)
      allocate (self%drive, source=law)
      call update_layout(self)
   end procedure mechanism_set_drive

   !> Add a driver of a revolute or prismatic joint (ffrf_mbs_joint_driver).
   module procedure mechanism_add_driver
      type(joint_driver_t) :: added
      integer :: nj
      nj = 0
      if (allocated(self%joints)) nj = size(self%joints)
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
      if (allocated(self%joints)) then
         do j = 1, size(self%joints)
            self%joints(j)%offset = row
            row = row + self%joints(j)%joint%num_equations
         end do
      end if
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

   pure integer function num_bodies(self)
      type(mechanism_t), intent(in) :: self
      num_bodies = 0
      if (allocated(self%bodies)) num_bodies = size(self%bodies)
   end function num_bodies

   pure logical function valid_body(self, b)
      type(mechanism_t), intent(in) :: self
      integer, intent(in) :: b
      valid_body = b >= 1 .and. b <= num_bodies(self)
   end function valid_body

   pure logical function rotating_body(self, b)
      type(mechanism_t), intent(in) :: self
      integer, intent(in) :: b
      rotating_body = valid_body(self, b)
      if (rotating_body) rotating_body = self%bodies(b)%body%num_coordinates >= 7
   end function rotating_body

   ! ----------------------------------------------------------------------------------------------
   ! Rotor state, loads, energies

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

   !> Generalized force of the loads (L_r^T F + L_w^T M at their markers, theory.md 3.5) and of
   !> gravity (m g at the centre of mass of rigid bodies; -dV/dq with the first moment
   !> m chi + M_PhitPsi zeta of flexible bodies, theory.md 3.6).
   module procedure mechanism_applied_force
      real(dp) :: angle, speed, value, vector(3), zero(3), A(3, 3)
      integer :: i, b, k, nb
      f = 0.0_dp
      zero = 0.0_dp
      angle = self%rotor_angle(q)
      speed = self%rotor_speed(q, v)
      if (allocated(self%loads)) then
         do i = 1, size(self%loads)
            associate (load => self%loads(i)%load)
               b = load%body
               k = self%bodies(b)%offset
               nb = self%bodies(b)%body%num_coordinates
               if (nb == 0) cycle
               value = load%magnitude(t, angle, speed)
               if (.not. ieee_is_finite(value)) then
                  call fatal_error(error, FFRF_NUMERIC_ERROR, 'load "' // trim(load%name) // &
                     '" is not finite at t = ' // to_str(t) // ' s, rotor angle ' // &
                     to_str(angle) // ' rad, speed ' // to_str(speed) // ' rad/s')
                  return
               end if
               vector = value * load%direction
               if (load%kind == LOAD_FORCE) then
                  f(k + 1:k + nb) = f(k + 1:k + nb) + self%bodies(b)%body% &
                     marker_generalized_force(q(k + 1:k + nb), load%marker, vector, zero)
               else
                  f(k + 1:k + nb) = f(k + 1:k + nb) + self%bodies(b)%body% &
                     marker_generalized_force(q(k + 1:k + nb), load%marker, zero, vector)
               end if
            end associate
         end do
      end if
      call add_spring_forces(self, q, v, t, f, error)
      if (.not. allocated(error)) call add_torsion_terms(self, q, v, t, error, f=f)
      if (.not. allocated(error)) call add_bushing_terms(self, q, v, t, error, f=f)
      if (allocated(error)) return
      if (maxval(abs(self%gravity)) <= 0.0_dp) return
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         select type (body => self%bodies(b)%body)
         class is (rigid_body_t)
            ! m g at the centre of mass chi: [m g; G_bar^T chi~ A^T m g]
            A = euler_rotation(q(k + 4:k + 7))
            vector = body%mass * self%gravity
            f(k + 1:k + 3) = f(k + 1:k + 3) + vector
            f(k + 4:k + 7) = f(k + 4:k + 7) + matmul(transpose(euler_g_bar(q(k + 4:k + 7))), &
               matmul(skew3(body%center_of_mass), matmul(transpose(A), vector)))
         class is (flexible_body_t)
            ! -dV/dq of V = -g . (m R + A (m chi + M_PhitPsi zeta)), theory.md 3.6
            nb = body%num_coordinates
            f(k + 1:k + nb) = f(k + 1:k + nb) + body%gravity_force(q(k + 1:k + nb), self%gravity)
         class default
            if (body%num_coordinates > 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: gravity is implemented ' &
                  // 'for rigid and flexible bodies; body "' // self%bodies(b)%name // &
                  '" is neither; set gravity = 0 (scene.md: gravity off)')
               return
            end if
         end select
      end do
   end procedure mechanism_applied_force

   !> Kinetic energy sum_b v_b^T M_b(q_b) v_b / 2 (J).
   module procedure mechanism_kinetic_energy
      integer :: b, k, nb
      energy = 0.0_dp
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         nb = self%bodies(b)%body%num_coordinates
         if (nb > 0) energy = energy + self%bodies(b)%body%kinetic_energy(q(k + 1:k + nb), &
            v(k + 1:k + nb))
      end do
   end procedure mechanism_kinetic_energy

   !> Strain energy of the flexible bodies, sum zeta^T K_ff zeta / 2 (J); 0 for rigid ones.
   module procedure mechanism_strain_energy
      integer :: b, k, nb
      energy = 0.0_dp
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         nb = self%bodies(b)%body%num_coordinates
         energy = energy + self%bodies(b)%body%strain_energy(q(k + 1:k + nb))
      end do
   end procedure mechanism_strain_energy

   !> Power of the applied loads and gravity, Q_applied . v (W): integrated over time it is the
   !> work that enters the energy balance kinetic + strain + dissipated = work.
   module procedure mechanism_applied_power
      real(dp) :: f(self%n)
      power = 0.0_dp
      call self%applied_force(q, v, t, f, error)
      if (allocated(error)) return
      power = dot_product(f, v)
   end procedure mechanism_applied_power

   !> Force and moment of joint j on its two bodies from the multipliers of all rows
   !> (joint_reaction: column 1 on body a at marker a, column 2 on body b at marker b).
   module procedure mechanism_reaction
      associate (jt => self%joints(j))
         call joint_reaction(jt%joint, self%bodies(jt%body_a)%body, &
            self%body_coordinates(q, jt%body_a), self%bodies(jt%body_b)%body, &
            self%body_coordinates(q, jt%body_b), &
            lambda(jt%offset + 1:jt%offset + jt%joint%num_equations), force, moment)
      end associate
   end procedure mechanism_reaction

   ! ----------------------------------------------------------------------------------------------
   ! dae_system_t

   !> n.
   module procedure mechanism_num_coordinates
      num = self%n
   end procedure mechanism_num_coordinates

   !> nc (joint rows, drive row, Euler rows).
   module procedure mechanism_num_constraints
      num = self%nc
   end procedure mechanism_num_constraints

   !> The Euler rows.
   module procedure mechanism_protected_rows
      integer :: b
      protect = .false.
      do b = 1, num_bodies(self)
         if (self%bodies(b)%euler_row > 0) protect(self%bodies(b)%euler_row) = .true.
      end do
   end procedure mechanism_protected_rows

   !> M = blockdiag(M_b(q_b)).
   module procedure mechanism_mass
      integer :: b, k, nb
      M = 0.0_dp
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         nb = self%bodies(b)%body%num_coordinates
         if (nb == 0) cycle
         M(k + 1:k + nb, k + 1:k + nb) = self%bodies(b)%body%mass_matrix(q(k + 1:k + nb))
         ! Only the bodies' blocks can hold a NaN
         if (.not. all_finite(M(k + 1:k + nb, k + 1:k + nb))) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism: mass matrix of body "' // &
               self%bodies(b)%name // '" not finite (NaN coordinates?)')
            return
         end if
      end do
   end procedure mechanism_mass

   !> f = sum_b (f_v + Q_e) + applied loads + gravity.
   module procedure mechanism_force
      integer :: b, k, nb
      call self%applied_force(q, v, t, f, error)
      if (allocated(error)) return
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         nb = self%bodies(b)%body%num_coordinates
         if (nb == 0) cycle
         associate (body => self%bodies(b)%body)
            f(k + 1:k + nb) = f(k + 1:k + nb) + body%quadratic_velocity(q(k + 1:k + nb), &
               v(k + 1:k + nb)) + body%elastic_force(q(k + 1:k + nb), v(k + 1:k + nb))
         end associate
      end do
   end procedure mechanism_force

   !> Phi: joint equations, drive row, Euler normalisations.
   module procedure mechanism_constraints
      integer :: j
      if (allocated(self%joints)) then
         do j = 1, size(self%joints)
            associate (jt => self%joints(j))
               call jt%joint%residual(self%bodies(jt%body_a)%body, &
                  self%body_coordinates(q, jt%body_a), self%bodies(jt%body_b)%body, &
                  self%body_coordinates(q, jt%body_b), &
                  phi(jt%offset + 1:jt%offset + jt%joint%num_equations))
            end associate
         end do
      end if
      call driver_rows(self, q, t, phi)
      call drive_and_euler_rows(self, q, t, phi)
      if (.not. all_finite(phi)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: constraint residuals not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_constraints

   !> Phi_q: joint blocks, drive row n^T d(A e_x)/dtheta, Euler rows 2 theta^T.
   module procedure mechanism_constraint_jacobian
      real(dp) :: phi(self%nc)
      call self%constraints_and_jacobian(q, t, phi, Phi_q, error)
      if (allocated(error)) return
      if (.not. all_finite(Phi_q)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: constraint Jacobian not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_constraint_jacobian

   !> Phi and Phi_q: one residual_jacobian call per joint, then the drive and Euler rows. Not
   !> checked for NaN here: the integrator checks the residual, which carries any NaN of Phi_q.
   module procedure mechanism_constraints_and_jacobian
      integer :: j, ka, kb, na, nb, ne
      Phi_q = 0.0_dp
      if (allocated(self%joints)) then
         do j = 1, size(self%joints)
            associate (jt => self%joints(j))
               ne = jt%joint%num_equations
               ka = self%bodies(jt%body_a)%offset
               kb = self%bodies(jt%body_b)%offset
               na = self%bodies(jt%body_a)%body%num_coordinates
               nb = self%bodies(jt%body_b)%body%num_coordinates
               ! The two bodies differ (add_joint), so their column blocks do not overlap: the
               ! joint writes its blocks in place
               call jt%joint%residual_jacobian(self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
                  self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
                  phi(jt%offset + 1:jt%offset + ne), &
                  Phi_q(jt%offset + 1:jt%offset + ne, ka + 1:ka + na), &
                  Phi_q(jt%offset + 1:jt%offset + ne, kb + 1:kb + nb))
            end associate
         end do
      end if
      call driver_rows(self, q, t, phi, Phi_q)
      call drive_and_euler_rows(self, q, t, phi, Phi_q)
      if (.not. all_finite(phi)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: constraint residuals not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_constraints_and_jacobian

   !> The drivers' rows of Phi and, if present, of Phi_q (ffrf_mbs_joint_driver), their Phi_t
   !> (phi_t), and (Phi_q v)_q v + Phi_tt + 2 Phi_qt v (accel, with v; other entries untouched).
   subroutine driver_rows(self, q, t, phi, Phi_q, v, phi_t, accel)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(in) :: t
      real(dp), intent(inout), optional :: phi(:)
      real(dp), intent(inout), optional :: Phi_q(:, :)
      real(dp), intent(in), optional :: v(:)
      real(dp), intent(inout), optional :: phi_t(:), accel(:)
      real(dp), allocatable :: ja(:), jb(:), jaf(:), jbf(:), K_aa(:, :), K_ab(:, :), K_bb(:, :)
      real(dp) :: f(3), value, value_f, value_ff
      integer :: d, ka, kb, na, nb
      if (.not. allocated(self%drivers)) return
      do d = 1, size(self%drivers)
         associate (dr => self%drivers(d), jt => self%joints(self%drivers(d)%joint))
            ka = self%bodies(jt%body_a)%offset
            kb = self%bodies(jt%body_b)%offset
            na = self%bodies(jt%body_a)%body%num_coordinates
            nb = self%bodies(jt%body_b)%body%num_coordinates
            allocate (ja(na), jb(nb), jaf(na), jbf(nb))
            f = dr%prescribed(t)
            call driver_terms(dr%kind, self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
               jt%joint%marker_a, self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
               jt%joint%marker_b, f(1), value, ja, jb, value_f, value_ff, jaf, jbf)
            if (present(phi)) phi(dr%row) = value
            if (present(Phi_q)) then
               Phi_q(dr%row, ka + 1:ka + na) = ja
               Phi_q(dr%row, kb + 1:kb + nb) = jb
            end if
            if (present(phi_t)) phi_t(dr%row) = f(2) * value_f
            ! Phi_tt + 2 Phi_qt v = f'' Phi_f + f'^2 Phi_ff + 2 f' (dPhi_q/df) v, and the
            ! convective v^T (d^2 Phi/dq^2) v from the exact second derivatives
            if (present(accel)) then
               allocate (K_aa(na, na), K_ab(na, nb), K_bb(nb, nb))
               call driver_hessian(dr%kind, self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
                  jt%joint%marker_a, self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
                  jt%joint%marker_b, f(1), 1.0_dp, K_aa, K_ab, K_bb)
               associate (va => v(ka + 1:ka + na), vb => v(kb + 1:kb + nb))
                  accel(dr%row) = f(3) * value_f + f(2)**2 * value_ff + 2.0_dp * f(2) * &
                     (dot_product(jaf, va) + dot_product(jbf, vb)) + &
                     dot_product(va, matmul(K_aa, va)) + 2.0_dp * dot_product(va, &
                     matmul(K_ab, vb)) + dot_product(vb, matmul(K_bb, vb))
               end associate
               deallocate (K_aa, K_ab, K_bb)
            end if
            deallocate (ja, jb, jaf, jbf)
         end associate
      end do
   end subroutine driver_rows

   !> Drive row n . A(theta) e_x and Euler rows |theta|^2 - 1 of Phi and, if present, their rows
   !> n^T d(A e_x)/dtheta and 2 theta^T of Phi_q (other entries untouched).
   subroutine drive_and_euler_rows(self, q, t, phi, Phi_q)
      type(mechanism_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(in) :: t
      real(dp), intent(inout) :: phi(:)
      real(dp), intent(inout), optional :: Phi_q(:, :)
      real(dp) :: f(3), normal(3)
      integer :: b, k
      if (self%drive_row > 0) then
         k = self%bodies(self%drive_body)%offset
         f = self%drive%evaluate(t)
         normal = drive_normal(f(1))
         phi(self%drive_row) = dot_product(normal, matmul(euler_rotation(q(k + 4:k + 7)), e_x))
         if (present(Phi_q)) Phi_q(self%drive_row, k + 4:k + 7) = matmul(normal, &
            rotated_vector_jacobian(q(k + 4:k + 7), e_x))
      end if
      do b = 1, num_bodies(self)
         if (self%bodies(b)%euler_row == 0) cycle
         k = self%bodies(b)%offset
         phi(self%bodies(b)%euler_row) = dot_product(q(k + 4:k + 7), q(k + 4:k + 7)) - 1.0_dp
         if (present(Phi_q)) Phi_q(self%bodies(b)%euler_row, k + 4:k + 7) = 2.0_dp * &
            q(k + 4:k + 7)
      end do
   end subroutine drive_and_euler_rows

   !> Phi_t: zero except the drive row, f' n_f . A e_x (module header).
   module procedure mechanism_constraint_rate
      real(dp) :: f(3)
      integer :: k
      phi_t = 0.0_dp
      if (self%drive_row > 0) then
         k = self%bodies(self%drive_body)%offset
         f = self%drive%evaluate(t)
         phi_t(self%drive_row) = f(2) * dot_product(drive_normal_rate(f(1)), &
            matmul(euler_rotation(q(k + 4:k + 7)), e_x))
      end if
      call driver_rows(self, q, t, phi_t=phi_t)
      if (.not. all(ieee_is_finite(phi_t))) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: drive law not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_constraint_rate

   !> g = -(Phi_q v)_q v - 2 Phi_qt v - Phi_tt (module header): analytic on the drive and Euler
   !> rows, central difference in s of Phi_q(q + s v) v on the joint rows.
   module procedure mechanism_acceleration_rhs
      real(dp) :: jac(self%nc, self%n), w_plus(self%nc), w_minus(self%nc), time_part(self%nc)
      real(dp) :: s, vmax, qscale, root3, f(3), theta(4), theta_dot(4), x_axis(3), nf(3)
      integer :: b, k, joint_rows
      g = 0.0_dp
      if (self%nc == 0) return
      joint_rows = 0
      if (allocated(self%joints)) joint_rows = sum([(self%joints(k)%joint%num_equations, &
         k = 1, size(self%joints))])
      vmax = 0.0_dp
      if (self%n > 0) vmax = maxval(abs(v))
      if (joint_rows > 0 .and. vmax > 0.0_dp) then
         root3 = epsilon(1.0_dp)**(1.0_dp / 3.0_dp)
         qscale = max(maxval(abs(q)), 1.0_dp)
         s = root3 * qscale / vmax
         call self%constraint_jacobian(q + s * v, t, jac, error)
         if (allocated(error)) return
         w_plus = matmul(jac, v)
         call self%constraint_jacobian(q - s * v, t, jac, error)
         if (allocated(error)) return
         w_minus = matmul(jac, v)
         g(:joint_rows) = -(w_plus(:joint_rows) - w_minus(:joint_rows)) / (2.0_dp * s)
      end if
      if (allocated(self%drivers)) then
         ! v^T (d^2 Phi/dq^2) v + Phi_tt + 2 Phi_qt v of the drivers' rows, exact
         time_part = 0.0_dp
         call driver_rows(self, q, t, v=v, accel=time_part)
         g = g - time_part
      end if
      if (self%drive_row > 0) then
         ! Phi = n(f(t)) . A(theta) e_x: -(n . 2 (A(theta_dot) + I) e_x) - 2 f' n_f . dA e_x
         ! - (f'' n_f - f'^2 n) . A e_x
         k = self%bodies(self%drive_body)%offset
         f = self%drive%evaluate(t)
         theta = q(k + 4:k + 7)
         theta_dot = v(k + 4:k + 7)
         x_axis = matmul(euler_rotation(theta), e_x)
         nf = drive_normal_rate(f(1))
         g(self%drive_row) = -2.0_dp * dot_product(drive_normal(f(1)), &
            matmul(euler_rotation(theta_dot), e_x) + e_x) &
            - 2.0_dp * f(2) * dot_product(nf, matmul(rotated_vector_jacobian(theta, e_x), &
            theta_dot)) - dot_product(f(3) * nf - f(2)**2 * drive_normal(f(1)), x_axis)
      end if
      do b = 1, num_bodies(self)
         if (self%bodies(b)%euler_row == 0) cycle
         k = self%bodies(b)%offset
         g(self%bodies(b)%euler_row) = -2.0_dp * dot_product(v(k + 4:k + 7), v(k + 4:k + 7))
      end do
      if (.not. all(ieee_is_finite(g))) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: acceleration right-hand side not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_acceleration_rhs

   !> After an accepted step: the state must be finite; the rotor angle becomes the new
   !> unwrapping reference.
   module procedure mechanism_accepted_step
      if (.not. (all(ieee_is_finite(q)) .and. all(ieee_is_finite(v)) .and. &
         all(ieee_is_finite(qdd)) .and. all(ieee_is_finite(lambda)))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism: state not finite at t = ' // &
            to_str(t) // ' s; reduce the time step')
         return
      end if
      self%rotor_reference = self%rotor_angle(q)
      call update_torsion_references(self, q)
   end procedure mechanism_accepted_step

   ! ----------------------------------------------------------------------------------------------
   ! Tangents of the Newton iteration (module header)

   !> K_t = -df/dq (module header: per body and load; differences if .not. analytic_tangents).
   module procedure mechanism_stiffness
      real(dp), allocatable :: K_b(:, :), C_b(:, :)
      integer :: b, k, nb
      if (.not. self%analytic_tangents) then
         call dae_stiffness_fd(self, q, v, t, K_t, error)
         return
      end if
      if (allocated(self%damping_cache)) then
         if (size(self%damping_cache, 1) /= self%n) deallocate (self%damping_cache)
      end if
      if (.not. allocated(self%damping_cache)) allocate (self%damping_cache(self%n, self%n))
      K_t = 0.0_dp
      self%damping_cache = 0.0_dp
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         nb = self%bodies(b)%body%num_coordinates
         if (nb == 0) cycle
         allocate (K_b(nb, nb), C_b(nb, nb))
         call self%bodies(b)%body%force_tangents(q(k + 1:k + nb), v(k + 1:k + nb), K_b, C_b)
         K_t(k + 1:k + nb, k + 1:k + nb) = K_b
         self%damping_cache(k + 1:k + nb, k + 1:k + nb) = C_b
         deallocate (K_b, C_b)
      end do
      call applied_tangents(self, q, v, t, K_t, self%damping_cache, error)
      if (allocated(error)) return
      self%cache_q = q
      self%cache_v = v
      self%cache_t = t
      if (.not. (all_finite(K_t) .and. all_finite(self%damping_cache))) &
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism: force tangents not finite ' &
         // 'at t = ' // to_str(t) // ' s')
   end procedure mechanism_stiffness

   !> C_t = -df/dq' (module header; reuses the stiffness call's result at the same state).
   module procedure mechanism_damping
      real(dp), allocatable :: K_t(:, :)
      logical :: cached
      if (.not. self%analytic_tangents) then
         call dae_damping_fd(self, q, v, t, C_t, error)
         return
      end if
      cached = allocated(self%damping_cache) .and. allocated(self%cache_q) .and. &
         allocated(self%cache_v)
      if (cached) cached = size(self%damping_cache, 1) == self%n .and. &
         size(self%cache_q) == size(q) .and. size(self%cache_v) == size(v)
      if (cached) cached = all(self%cache_q == q) .and. all(self%cache_v == v) .and. &
         self%cache_t == t
      if (.not. cached) then
         allocate (K_t(self%n, self%n))
         call self%stiffness(q, v, t, K_t, error)
         if (allocated(error)) return
      end if
      C_t = self%damping_cache
   end procedure mechanism_damping

   !> Subtract the derivatives of the applied loads and gravity from K_t (-df/dq) and C_t
   !> (-df/dq'): marker force at fixed magnitude, plus magnitude(t, angle, speed) through the
   !> rotor angle 2 atan2(e3, e0) and speed e_z . G(theta) theta_dot = -e_z . G(theta_dot) theta.
   subroutine applied_tangents(self, q, v, t, K_t, C_t, error)
      type(mechanism_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      real(dp), intent(inout) :: K_t(:, :), C_t(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: tangent(:, :), unit_force(:)
      real(dp) :: angle, speed, value, vector(3), zero(3), theta(4), d_angle(4), d_speed_q(4)
      real(dp) :: d_speed_v(4), g_rows(3, 4), dm_da, dm_ds, radius2
      integer :: i, b, k, nb, kc, j
      zero = 0.0_dp
      angle = self%rotor_angle(q)
      speed = self%rotor_speed(q, v)
      kc = 0
      if (self%rotor > 0) then
         kc = self%bodies(self%rotor)%offset
         theta = q(kc + 4:kc + 7)
         radius2 = max(theta(1)**2 + theta(4)**2, tiny(1.0_dp))
         d_angle = [-2.0_dp * theta(4), 0.0_dp, 0.0_dp, 2.0_dp * theta(1)] / radius2
         g_rows = euler_g(v(kc + 4:kc + 7))
         d_speed_q = -g_rows(3, :)
         g_rows = euler_g(theta)
         d_speed_v = g_rows(3, :)
      end if
      if (allocated(self%loads)) then
         do i = 1, size(self%loads)
            associate (load => self%loads(i)%load)
               b = load%body
               k = self%bodies(b)%offset
               nb = self%bodies(b)%body%num_coordinates
               if (nb == 0) cycle
               value = load%magnitude(t, angle, speed)
               allocate (tangent(nb, nb), unit_force(nb))
               vector = value * load%direction
               if (load%kind == LOAD_FORCE) then
                  call self%bodies(b)%body%marker_force_tangent(q(k + 1:k + nb), load%marker, &
                     vector, zero, tangent)
                  unit_force = self%bodies(b)%body%marker_generalized_force(q(k + 1:k + nb), &
                     load%marker, load%direction, zero)
               else
                  call self%bodies(b)%body%marker_force_tangent(q(k + 1:k + nb), load%marker, &
                     zero, vector, tangent)
                  unit_force = self%bodies(b)%body%marker_generalized_force(q(k + 1:k + nb), &
                     load%marker, zero, load%direction)
               end if
               K_t(k + 1:k + nb, k + 1:k + nb) = K_t(k + 1:k + nb, k + 1:k + nb) - tangent
               if (self%rotor > 0) then
                  call load%magnitude_rates(t, angle, speed, dm_da, dm_ds)
                  do j = 1, 4
                     K_t(k + 1:k + nb, kc + 3 + j) = K_t(k + 1:k + nb, kc + 3 + j) - &
                        unit_force * (dm_da * d_angle(j) + dm_ds * d_speed_q(j))
                     C_t(k + 1:k + nb, kc + 3 + j) = C_t(k + 1:k + nb, kc + 3 + j) - &
                        unit_force * dm_ds * d_speed_v(j)
                  end do
               end if
               deallocate (tangent, unit_force)
            end associate
         end do
      end if
      call add_spring_tangents(self, q, v, t, K_t, C_t, error)
      if (.not. allocated(error)) call add_torsion_terms(self, q, v, t, error, K_t=K_t, &
         C_t=C_t)
      if (.not. allocated(error)) call add_bushing_terms(self, q, v, t, error, K_t=K_t, &
         C_t=C_t)
      if (allocated(error)) return
      if (maxval(abs(self%gravity)) <= 0.0_dp) return
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         select type (body => self%bodies(b)%body)
         class is (rigid_body_t)
            K_t(k + 4:k + 7, k + 4:k + 7) = K_t(k + 4:k + 7, k + 4:k + 7) - &
               point_load_tangent(q(k + 4:k + 7), body%center_of_mass, &
               body%mass * self%gravity, zero)
         class is (flexible_body_t)
            ! -dQ_g/dq, theory.md 3.6 (eq. 3.6c)
            nb = body%num_coordinates
            allocate (tangent(nb, nb))
            call body%gravity_tangent(q(k + 1:k + nb), self%gravity, tangent)
            K_t(k + 1:k + nb, k + 1:k + nb) = K_t(k + 1:k + nb, k + 1:k + nb) - tangent
            deallocate (tangent)
         class default
            if (body%num_coordinates > 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: gravity is implemented ' &
                  // 'for rigid and flexible bodies; body "' // self%bodies(b)%name // &
                  '" is neither; set gravity = 0')
               return
            end if
         end select
      end do
   end subroutine applied_tangents

   !> Add the springs' generalized forces to f (ffrf_mbs_spring_damper); a spring of zero length
   !> or a non-finite tension is a numeric error.
   subroutine add_spring_forces(self, q, v, t, f, error)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      real(dp), intent(inout) :: f(:)
      type(error_t), allocatable, intent(out) :: error
      type(spring_state_t) :: state
      real(dp), allocatable :: f_a(:), f_b(:)
      integer :: s, ka, kb, na, nb
      if (.not. allocated(self%springs)) return
      do s = 1, size(self%springs)
         associate (spring => self%springs(s))
            state = self%spring_state(s, q, v)
            call check_spring_state(spring%name, state, t, error)
            if (allocated(error)) return
            ka = self%bodies(spring%body_a)%offset
            kb = self%bodies(spring%body_b)%offset
            na = self%bodies(spring%body_a)%body%num_coordinates
            nb = self%bodies(spring%body_b)%body%num_coordinates
            allocate (f_a(na), f_b(nb))
            call spring_generalized_forces(spring, state, self%bodies(spring%body_a)%body, &
               q(ka + 1:ka + na), self%bodies(spring%body_b)%body, q(kb + 1:kb + nb), f_a, f_b)
            f(ka + 1:ka + na) = f(ka + 1:ka + na) + f_a
            f(kb + 1:kb + nb) = f(kb + 1:kb + nb) + f_b
            deallocate (f_a, f_b)
         end associate
      end do
   end subroutine add_spring_forces

   !> Add the springs' exact tangents to K_t (-df/dq) and C_t (-df/dq').
   subroutine add_spring_tangents(self, q, v, t, K_t, C_t, error)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      real(dp), intent(inout) :: K_t(:, :), C_t(:, :)
      type(error_t), allocatable, intent(out) :: error
      type(spring_state_t) :: state
      real(dp), allocatable :: K(:, :), C(:, :)
      integer, allocatable :: rows(:)
      integer :: s, ka, kb, na, nb, i
      if (.not. allocated(self%springs)) return
      do s = 1, size(self%springs)
         associate (spring => self%springs(s))
            state = self%spring_state(s, q, v)
            call check_spring_state(spring%name, state, t, error)
            if (allocated(error)) return
            ka = self%bodies(spring%body_a)%offset
            kb = self%bodies(spring%body_b)%offset
            na = self%bodies(spring%body_a)%body%num_coordinates
            nb = self%bodies(spring%body_b)%body%num_coordinates
            allocate (K(na + nb, na + nb), C(na + nb, na + nb))
            call spring_tangents(spring, state, self%bodies(spring%body_a)%body, &
               q(ka + 1:ka + na), v(ka + 1:ka + na), self%bodies(spring%body_b)%body, &
               q(kb + 1:kb + nb), v(kb + 1:kb + nb), K, C)
            rows = [(ka + i, i = 1, na), (kb + i, i = 1, nb)]
            K_t(rows, rows) = K_t(rows, rows) + K
            C_t(rows, rows) = C_t(rows, rows) + C
            deallocate (K, C)
         end associate
      end do
   end subroutine add_spring_tangents

   !> A spring needs a non-zero length (its direction) and a finite tension.
   subroutine check_spring_state(name, state, t, error)
      character(len=*), intent(in) :: name
      type(spring_state_t), intent(in) :: state
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      if (.not. (state%length > 0.0_dp .and. ieee_is_finite(state%force))) &
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'spring "' // trim(name) // &
         '": length ' // to_str(state%length) // ' m, tension ' // to_str(state%force) // &
         ' N at t = ' // to_str(t) // ' s; a spring needs distinct, finite marker positions')
   end subroutine check_spring_state

   !> d(Phi_q^T lambda)/dq: joints, drive row and Euler rows (module header).
   module procedure mechanism_constraint_stiffness
      real(dp), allocatable :: K_aa(:, :), K_ab(:, :), K_bb(:, :)
      real(dp) :: f(3), X(3, 3)
      integer :: j, b, k, ka, kb, na, nb, ne, i
      if (.not. self%analytic_tangents) then
         call dae_constraint_stiffness_fd(self, q, t, lambda, K_c, error)
         return
      end if
      K_c = 0.0_dp
      if (allocated(self%joints)) then
         do j = 1, size(self%joints)
            associate (jt => self%joints(j))
               ne = jt%joint%num_equations
               ka = self%bodies(jt%body_a)%offset
               kb = self%bodies(jt%body_b)%offset
               na = self%bodies(jt%body_a)%body%num_coordinates
               nb = self%bodies(jt%body_b)%body%num_coordinates
               allocate (K_aa(na, na), K_ab(na, nb), K_bb(nb, nb))
               call jt%joint%constraint_hessian(self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
                  self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
                  lambda(jt%offset + 1:jt%offset + ne), K_aa, K_ab, K_bb)
               call add_pair_blocks(K_c, ka, na, kb, nb, K_aa, K_ab, K_bb)
               deallocate (K_aa, K_ab, K_bb)
            end associate
         end do
      end if
      if (allocated(self%drivers)) then
         do j = 1, size(self%drivers)
            associate (dr => self%drivers(j), jt => self%joints(self%drivers(j)%joint))
               ka = self%bodies(jt%body_a)%offset
               kb = self%bodies(jt%body_b)%offset
               na = self%bodies(jt%body_a)%body%num_coordinates
               nb = self%bodies(jt%body_b)%body%num_coordinates
               allocate (K_aa(na, na), K_ab(na, nb), K_bb(nb, nb))
               f = dr%prescribed(t)
               call driver_hessian(dr%kind, self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
                  jt%joint%marker_a, self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
                  jt%joint%marker_b, f(1), lambda(dr%row), K_aa, K_ab, K_bb)
               call add_pair_blocks(K_c, ka, na, kb, nb, K_aa, K_ab, K_bb)
               deallocate (K_aa, K_ab, K_bb)
            end associate
         end do
      end if
      if (self%drive_row > 0) then
         ! lambda_d n(f) . A(theta) e_x: Hessian of a term w . A b with w = lambda_d n, b = e_x
         k = self%bodies(self%drive_body)%offset
         f = self%drive%evaluate(t)
         do i = 1, 3
            X(:, i) = lambda(self%drive_row) * drive_normal(f(1)) * e_x(i)
         end do
         K_c(k + 4:k + 7, k + 4:k + 7) = K_c(k + 4:k + 7, k + 4:k + 7) + euler_hessian(X)
      end if
      do b = 1, num_bodies(self)
         if (self%bodies(b)%euler_row == 0) cycle
         k = self%bodies(b)%offset
         do i = 4, 7
            K_c(k + i, k + i) = K_c(k + i, k + i) + 2.0_dp * lambda(self%bodies(b)%euler_row)
         end do
      end do
      if (.not. all_finite(K_c)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: constraint stiffness not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_constraint_stiffness

   !> K_c += the symmetric pair blocks [K_aa K_ab; K_ab^T K_bb] of two bodies at offsets ka, kb.
   pure subroutine add_pair_blocks(K_c, ka, na, kb, nb, K_aa, K_ab, K_bb)
      real(dp), intent(inout) :: K_c(:, :)
      integer, intent(in) :: ka, na, kb, nb
      real(dp), intent(in) :: K_aa(:, :), K_ab(:, :), K_bb(:, :)
      K_c(ka + 1:ka + na, ka + 1:ka + na) = K_c(ka + 1:ka + na, ka + 1:ka + na) + K_aa
      K_c(ka + 1:ka + na, kb + 1:kb + nb) = K_c(ka + 1:ka + na, kb + 1:kb + nb) + K_ab
      K_c(kb + 1:kb + nb, ka + 1:ka + na) = K_c(kb + 1:kb + nb, ka + 1:ka + na) + &
         transpose(K_ab)
      K_c(kb + 1:kb + nb, kb + 1:kb + nb) = K_c(kb + 1:kb + nb, kb + 1:kb + nb) + K_bb
   end subroutine add_pair_blocks

   !> d(M(q) a)/dq for a fixed a: blockdiag of the bodies' mass_stiffness.
   module procedure mechanism_mass_stiffness
      real(dp), allocatable :: K_b(:, :)
      integer :: b, k, nb
      if (.not. self%analytic_tangents) then
         call dae_mass_stiffness_fd(self, q, a, K_m, error)
         return
      end if
      K_m = 0.0_dp
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         nb = self%bodies(b)%body%num_coordinates
         if (nb == 0) cycle
         allocate (K_b(nb, nb))
         call self%bodies(b)%body%mass_stiffness(q(k + 1:k + nb), a(k + 1:k + nb), K_b)
         K_m(k + 1:k + nb, k + 1:k + nb) = K_b
         deallocate (K_b)
      end do
      if (.not. all_finite(K_m)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: mass stiffness not finite')
   end procedure mechanism_mass_stiffness

   ! ----------------------------------------------------------------------------------------------
   ! Consistent initial state

   !> Solve Phi(q, t) = 0 from an approximate q by Gauss-Newton, each step the minimum-norm
   !> least-squares correction (dgelsy). With rotor_angle, the rotor's rotation about z is fixed
   !> too (equation n(angle) . A e_x = 0, as the drive) and becomes the unwrapping reference.
   !> Converged when max |Phi| <= tolerance (default 1e-12).
   module procedure mechanism_assemble
      real(dp), allocatable :: a(:, :), rhs(:, :), phi(:), jac(:, :)
      real(dp) :: tol, violation
      integer :: rows, it, k
      logical :: with_rotor
      tol = 1.0e-12_dp
      if (present(tolerance)) tol = tolerance
      with_rotor = present(rotor_angle)
      if (with_rotor .and. self%rotor == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism assembly: a rotor angle was ' // &
            'given but no rotor body is set; call set_rotor first')
         return
      end if
      rows = self%nc
      if (with_rotor) rows = rows + 1
      allocate (a(rows, self%n), rhs(max(rows, self%n), 1), phi(self%nc), jac(self%nc, self%n))
      violation = huge(1.0_dp)
      do it = 1, 50
         call self%constraints(q, t, phi, error)
         if (allocated(error)) return
         rhs = 0.0_dp
         rhs(1:self%nc, 1) = -phi
         call self%constraint_jacobian(q, t, jac, error)
         if (allocated(error)) return
         a(1:self%nc, :) = jac
         if (with_rotor) then
            k = self%bodies(self%rotor)%offset
            a(rows, :) = 0.0_dp
            a(rows, k + 4:k + 7) = matmul(drive_normal(rotor_angle), &
               rotated_vector_jacobian(q(k + 4:k + 7), e_x))
            rhs(rows, 1) = -dot_product(drive_normal(rotor_angle), &
               matmul(euler_rotation(q(k + 4:k + 7)), e_x))
         end if
         violation = maxval(abs(rhs(1:rows, 1)))
         if (present(iterations)) iterations = it - 1
         if (violation <= tol) exit
         call least_squares(a, rhs, 'assembly', error)
         if (allocated(error)) return
         q = q + rhs(1:self%n, 1)
      end do
      if (.not. (violation <= tol)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism assembly: Gauss-Newton did ' &
            // 'not reach max |Phi| <= ' // to_str(tol) // ' in 50 iterations (last ' // &
            to_str(violation) // '); start from poses closer to the assembled ones')
         return
      end if
      if (with_rotor) call self%set_rotor_reference(q, rotor_angle)
   end procedure mechanism_assemble

   !> Velocities v with Phi_q v = -Phi_t, and the rotor speed if given, in the minimum-norm
   !> least-squares sense (dgelsy); error if the residual exceeds 1e-10 of the scale.
   module procedure mechanism_initial_velocities
      real(dp), allocatable :: a(:, :), rhs(:, :), rate(:), jac(:, :)
      real(dp) :: residual, scale
      integer :: rows, k, b, row, attempt
      v = 0.0_dp
      if (present(rotor_speed) .and. self%rotor == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism initial velocities: a rotor ' // &
            'speed was given but no rotor body is set; call set_rotor first')
         return
      end if
      allocate (rate(self%nc), jac(self%nc, self%n))
      call self%constraint_jacobian(q, t, jac, error)
      if (allocated(error)) return
      call self%constraint_rate(q, t, rate, error)
      if (allocated(error)) return
      ! The bodies start undeformed and moving rigidly: every modal velocity zero (a flexible
      ! body whose interface ring rotates in its modes (issue 30) would otherwise
      ! get the minimum-norm split, a twist rate that leaves that interface at rest).
      ! Without a rigid motion that meets the constraints, the minimum-norm solution of all.
      do attempt = 1, 2
         rows = self%nc
         if (present(rotor_speed)) rows = rows + 1
         if (attempt == 1) rows = rows + count_modal()
         if (allocated(a)) deallocate (a, rhs)
         allocate (a(rows, self%n), rhs(max(rows, self%n), 1))
         a = 0.0_dp
         rhs = 0.0_dp
         a(1:self%nc, :) = jac
         rhs(1:self%nc, 1) = -rate
         row = self%nc
         if (present(rotor_speed)) then
            k = self%bodies(self%rotor)%offset
            row = row + 1
            ! omega_z = e_z^T G(theta) theta_dot: the third row of G
            a(row, k + 4:k + 7) = row3(euler_g(q(k + 4:k + 7)))
            rhs(row, 1) = rotor_speed
         end if
         if (attempt == 1) then
            do b = 1, size(self%bodies)
               do k = 8, self%bodies(b)%body%num_coordinates
                  row = row + 1
                  a(row, self%bodies(b)%offset + k) = 1.0_dp
               end do
            end do
         end if
         if (present(guess)) rhs(1:rows, 1) = rhs(1:rows, 1) - matmul(a, guess)
         call least_squares(a, rhs, 'initial velocities', error)
         if (allocated(error)) return
         v = rhs(1:self%n, 1)
         if (present(guess)) v = v + guess
         residual = maxval(abs(matmul(jac, v) + rate))
         if (count_modal() == 0 .or. residual <= 1.0e-10_dp * max(maxval(abs(rate)), 1.0_dp) * &
            max(maxval(abs(v)), 1.0_dp)) exit
      end do
      scale = max(maxval(abs(rate)), 1.0_dp) * max(maxval(abs(v)), 1.0_dp)
      if (present(rotor_speed)) then
         residual = max(residual, abs(self%rotor_speed(q, v) - rotor_speed))
      end if
      if (.not. residual <= 1.0e-10_dp * scale) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism initial velocities: the ' // &
            'velocity constraints cannot be met, residual ' // to_str(residual) // &
            ' (a rotor speed inconsistent with a drive?)')
      end if

   contains

      !> Modal coordinates of all bodies (coordinates beyond R and theta).
      integer function count_modal()
         integer :: bb
         count_modal = 0
         do bb = 1, size(self%bodies)
            count_modal = count_modal + max(self%bodies(bb)%body%num_coordinates - 7, 0)
         end do
      end function count_modal

   end procedure mechanism_initial_velocities

   !> Third row of a 3 x 4 matrix.
   pure function row3(matrix) result(row)
      real(dp), intent(in) :: matrix(3, 4)
      real(dp) :: row(4)
      row = matrix(3, :)
   end function row3

   !> rhs(1:n) <- minimum-norm least-squares solution of a x = rhs(1:m) (dgelsy; a destroyed).
   subroutine least_squares(a, rhs, what, error)
      real(dp), intent(inout) :: a(:, :)
      real(dp), intent(inout) :: rhs(:, :)
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: m, n, rank, info, lwork
      integer(ip), allocatable :: jpvt(:)
      real(dp), allocatable :: work(:)
      real(dp) :: query(1)
      integer :: i
      real(dp) :: norm
      m = int(size(a, 1), ip)
      n = int(size(a, 2), ip)
      if (m == 0 .or. n == 0) return
      ! Equilibrate the rows (metres and dimensionless axis products mix)
      do i = 1, size(a, 1)
         norm = maxval(abs(a(i, :)))
         if (norm > 0.0_dp) then
            a(i, :) = a(i, :) / norm
            rhs(i, 1) = rhs(i, 1) / norm
         end if
      end do
      allocate (jpvt(n))
      jpvt = 0
      call dgelsy(m, n, 1_ip, a, m, rhs, int(size(rhs, 1), ip), jpvt, rank_rcond, rank, query, &
         -1_ip, info)
      lwork = max(1_ip, int(query(1), ip))
      allocate (work(lwork))
      call dgelsy(m, n, 1_ip, a, m, rhs, int(size(rhs, 1), ip), jpvt, rank_rcond, rank, work, &
         lwork, info)
      if (info /= 0 .or. .not. all(ieee_is_finite(rhs))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism ' // what // ': least-squares ' &
            // 'solve failed (dgelsy info = ' // to_str(info) // ')')
      end if
   end subroutine least_squares

   !> n(f) = (-sin f, cos f, 0): normal of the driven x axis at angle f.
   pure function drive_normal(angle) result(normal)
      real(dp), intent(in) :: angle
      real(dp) :: normal(3)
      normal = [-sin(angle), cos(angle), 0.0_dp]
   end function drive_normal

   !> dn/df = (-cos f, -sin f, 0).
   pure function drive_normal_rate(angle) result(rate)
      real(dp), intent(in) :: angle
      real(dp) :: rate(3)
      rate = [-cos(angle), -sin(angle), 0.0_dp]
   end function drive_normal_rate

end submodule ffrf_mbs_mechanism_procedures
