!> The applied forces of a mechanism (ffrf_mbs_mechanism, a submodule): loads, force elements and
!> gravity, as the generalized force f or as its tangents K_t = -df/dq, C_t = -df/dq' (one
!> routine each for both, so that a force and its derivative walk the same loads and bodies).
!> The force elements (added in mechanism_build.f90): the spring-dampers' state, potential
!> energy and free lengths (ffrf_mbs_spring_damper), the torsion spring-dampers' state,
!> potential energy and unwrapping references (ffrf_mbs_torsion_spring, docs/mechanisms.md
!> "Torsion springs"), the bushings' state and potential energy (ffrf_mbs_bushing,
!> docs/mechanisms.md "Bushings").
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_applied
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar, euler_g, skew3
   use ffrf_mbs_rigid_body, only: rigid_body_t, point_load_tangent
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_torsion_spring, only: torsion_evaluate, torsion_tangents
   use ffrf_mbs_spring_damper, only: marker_pair_forces, spring_evaluate, &
      spring_generalized_forces, spring_tangents
   use ffrf_mbs_bushing, only: bushing_evaluate, bushing_generalized_force, bushing_tangents
   implicit none

contains

   !> Generalized force of the loads (L_r^T F + L_w^T M at their markers, theory.md 3.5) and of
   !> gravity (m g at the centre of mass of rigid bodies; -dV/dq with the first moment
   !> m chi + M_PhitPsi zeta of flexible bodies, theory.md 3.6).
   module procedure mechanism_applied_force
      f = 0.0_dp
      call add_applied_terms(self, q, v, t, error, f=f)
   end procedure mechanism_applied_force

   !> Loads, force elements, gravity, in this order (mechanism.f90's interface).
   module procedure add_applied_terms
      call add_load_terms(self, q, v, t, error, f, K_t, C_t)
      if (.not. allocated(error)) call add_force_element_terms(self, q, v, t, error, f, K_t, C_t)
      if (.not. allocated(error)) call add_gravity_terms(self, q, error, f, K_t)
   end procedure add_applied_terms

   !> The loads' generalized forces (f present) or tangents (K_t, C_t present): the marker force
   !> at fixed magnitude, plus magnitude(t, angle, speed) through the rotor angle
   !> 2 atan2(e3, e0) and speed e_z . G(theta) theta_dot = -e_z . G(theta_dot) theta. A load of
   !> non-finite magnitude is a numeric error.
   subroutine add_load_terms(self, q, v, t, error, f, K_t, C_t)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(inout), optional :: f(:), K_t(:, :), C_t(:, :)
      real(dp), allocatable :: tangent(:, :), unit_force(:)
      real(dp) :: angle, speed, value, force(3), moment(3), theta(4), d_angle(4), d_speed_q(4)
      real(dp) :: d_speed_v(4), g_rows(3, 4), dm_da, dm_ds, radius2
      integer :: i, k, nb, kc, j
      logical :: tangents
      if (.not. allocated(self%loads)) return
      tangents = present(K_t) .and. present(C_t)
      angle = self%rotor_angle(q)
      speed = self%rotor_speed(q, v)
      kc = 0
      if (tangents .and. self%rotor > 0) then
         kc = self%bodies(self%rotor)%offset
         theta = q(kc + 4:kc + 7)
         radius2 = max(theta(1)**2 + theta(4)**2, tiny(1.0_dp))
         d_angle = [-2.0_dp * theta(4), 0.0_dp, 0.0_dp, 2.0_dp * theta(1)] / radius2
         g_rows = euler_g(v(kc + 4:kc + 7))
         d_speed_q = -g_rows(3, :)
         g_rows = euler_g(theta)
         d_speed_v = g_rows(3, :)
      end if
      do i = 1, size(self%loads)
         associate (load => self%loads(i)%load, body => self%bodies(self%loads(i)%load%body)%body)
            call body_layout(self, load%body, k, nb)
            if (nb == 0) cycle
            value = load%magnitude(t, angle, speed)
            if (.not. ieee_is_finite(value)) then
               call fatal_error(error, FFRF_NUMERIC_ERROR, 'load "' // trim(load%name) // &
                  '" is not finite at t = ' // to_str(t) // ' s, rotor angle ' // &
                  to_str(angle) // ' rad, speed ' // to_str(speed) // ' rad/s')
               return
            end if
            call load%vectors(value, force, moment)
            if (tangents) then
               allocate (tangent(nb, nb), unit_force(nb))
               call body%marker_force_tangent(q(k + 1:k + nb), load%marker, force, moment, &
                  tangent)
               ! the generalized force of the unit magnitude, for d(magnitude)/d(angle, speed)
               call load%vectors(1.0_dp, force, moment)
               unit_force = body%marker_generalized_force(q(k + 1:k + nb), load%marker, force, &
                  moment)
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
            else if (present(f)) then
               f(k + 1:k + nb) = f(k + 1:k + nb) + body%marker_generalized_force(q(k + 1:k + nb), &
                  load%marker, force, moment)
            end if
         end associate
      end do
   end subroutine add_load_terms

   !> Gravity's generalized force (f present) or its tangent -dQ_g/dq (K_t present), for rigid
   !> and flexible bodies (theory.md 3.6); another body with coordinates is an input error
   !> while gravity is on.
   subroutine add_gravity_terms(self, q, error, f, K_t)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(inout), optional :: f(:), K_t(:, :)
      real(dp), allocatable :: tangent(:, :)
      real(dp) :: A(3, 3), vector(3)
      integer :: b, k, nb
      if (maxval(abs(self%gravity)) <= 0.0_dp) return
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         select type (body => self%bodies(b)%body)
         class is (rigid_body_t)
            if (present(K_t)) then
               K_t(k + 4:k + 7, k + 4:k + 7) = K_t(k + 4:k + 7, k + 4:k + 7) - &
                  point_load_tangent(q(k + 4:k + 7), body%center_of_mass, &
                  body%mass * self%gravity, [0.0_dp, 0.0_dp, 0.0_dp])
            else if (present(f)) then
               ! m g at the centre of mass chi: [m g; G_bar^T chi~ A^T m g]
               A = euler_rotation(q(k + 4:k + 7))
               vector = body%mass * self%gravity
               f(k + 1:k + 3) = f(k + 1:k + 3) + vector
               f(k + 4:k + 7) = f(k + 4:k + 7) + matmul(transpose(euler_g_bar(q(k + 4:k + 7))), &
                  matmul(skew3(body%center_of_mass), matmul(transpose(A), vector)))
            end if
         class is (flexible_body_t)
            nb = body%num_coordinates
            if (present(K_t)) then
               ! -dQ_g/dq, theory.md 3.6 (eq. 3.6c)
               allocate (tangent(nb, nb))
               call body%gravity_tangent(q(k + 1:k + nb), self%gravity, tangent)
               K_t(k + 1:k + nb, k + 1:k + nb) = K_t(k + 1:k + nb, k + 1:k + nb) - tangent
               deallocate (tangent)
            else if (present(f)) then
               ! -dV/dq of V = -g . (m R + A (m chi + M_PhitPsi zeta)), theory.md 3.6
               f(k + 1:k + nb) = f(k + 1:k + nb) + body%gravity_force(q(k + 1:k + nb), &
                  self%gravity)
            end if
         class default
            if (body%num_coordinates > 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism: gravity is implemented ' &
                  // 'for rigid and flexible bodies; body "' // self%bodies(b)%name // &
                  '" is neither; set gravity = 0 (scene.md: gravity off)')
               return
            end if
         end select
      end do
   end subroutine add_gravity_terms

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

   !> Springs, torsion springs and bushings, in this order (mechanism.f90's interface).
   module procedure add_force_element_terms
      call add_spring_terms(self, q, v, t, error, f, K_t, C_t)
      if (.not. allocated(error)) call add_torsion_terms(self, q, v, t, error, f, K_t, C_t)
      if (.not. allocated(error)) call add_bushing_terms(self, q, v, t, error, f, K_t, C_t)
   end procedure add_force_element_terms

   !> The springs' generalized forces (f present) or exact tangents (K_t, C_t present;
   !> ffrf_mbs_spring_damper); a spring of zero length or a non-finite tension is a numeric
   !> error.
   subroutine add_spring_terms(self, q, v, t, error, f, K_t, C_t)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(inout), optional :: f(:), K_t(:, :), C_t(:, :)
      type(spring_state_t) :: state
      real(dp), allocatable :: f_a(:), f_b(:), K(:, :), C(:, :)
      integer, allocatable :: rows(:)
      integer :: s, na
      if (.not. allocated(self%springs)) return
      do s = 1, size(self%springs)
         associate (spring => self%springs(s), body_a => &
               self%bodies(self%springs(s)%body_a)%body, &
               body_b => self%bodies(self%springs(s)%body_b)%body)
            state = self%spring_state(s, q, v)
            call check_spring_state(spring%name, state, t, error)
            if (allocated(error)) return
            call pair_rows(self, spring%body_a, spring%body_b, rows, na)
            if (present(K_t) .and. present(C_t)) then
               allocate (K(size(rows), size(rows)), C(size(rows), size(rows)))
               call spring_tangents(spring, state, body_a, q(rows(:na)), v(rows(:na)), &
                  body_b, q(rows(na + 1:)), v(rows(na + 1:)), K, C)
               call add_pair_tangents(rows, K, C, K_t, C_t)
               deallocate (K, C)
            else if (present(f)) then
               allocate (f_a(na), f_b(size(rows) - na))
               call spring_generalized_forces(spring, state, body_a, q(rows(:na)), body_b, &
                  q(rows(na + 1:)), f_a, f_b)
               f(rows) = f(rows) + [f_a, f_b]
               deallocate (f_a, f_b)
            end if
         end associate
      end do
   end subroutine add_spring_terms

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

   !> Angle, rate and torque of torsion spring s at (q, v).
   module procedure mechanism_torsion_state
      integer, allocatable :: rows(:)
      integer :: na
      associate (spring => self%torsion_springs(s))
         call pair_rows(self, spring%body_a, spring%body_b, rows, na)
         state = torsion_evaluate(spring, self%bodies(spring%body_a)%body, q(rows(:na)), &
            v(rows(:na)), self%bodies(spring%body_b)%body, q(rows(na + 1:)), v(rows(na + 1:)))
      end associate
   end procedure mechanism_torsion_state

   !> Potential energy of the torsion springs, sum k (phi - phi0)^2 / 2 (J).
   module procedure mechanism_torsion_energy
      type(torsion_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      energy = 0.0_dp
      if (.not. allocated(self%torsion_springs)) return
      zero = 0.0_dp
      do s = 1, size(self%torsion_springs)
         state = self%torsion_state(s, q, zero)
         energy = energy + 0.5_dp * self%torsion_springs(s)%stiffness * &
            (state%angle - self%torsion_springs(s)%free_angle)**2
      end do
   end procedure mechanism_torsion_energy

   !> Unwrapping references from the start, in (-pi, pi]; free angles not given from the start.
   module procedure mechanism_set_torsion_start
      type(torsion_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      if (.not. allocated(self%torsion_springs)) return
      zero = 0.0_dp
      do s = 1, size(self%torsion_springs)
         self%torsion_springs(s)%reference = 0.0_dp
         state = self%torsion_state(s, q, zero)
         self%torsion_springs(s)%reference = state%angle
         if (.not. self%torsion_springs(s)%free_angle_given) &
            self%torsion_springs(s)%free_angle = state%angle
      end do
   end procedure mechanism_set_torsion_start

   !> The torsion springs' generalized forces (f present) or exact tangents (K_t, C_t present;
   !> ffrf_mbs_torsion_spring).
   subroutine add_torsion_terms(self, q, v, t, error, f, K_t, C_t)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(inout), optional :: f(:), K_t(:, :), C_t(:, :)
      type(torsion_state_t) :: state
      real(dp), allocatable :: f_a(:), f_b(:), K(:, :), C(:, :)
      integer, allocatable :: rows(:)
      integer :: s, na
      if (.not. allocated(self%torsion_springs)) return
      do s = 1, size(self%torsion_springs)
         associate (spring => self%torsion_springs(s), body_a => &
               self%bodies(self%torsion_springs(s)%body_a)%body, &
               body_b => self%bodies(self%torsion_springs(s)%body_b)%body)
            state = self%torsion_state(s, q, v)
            if (.not. ieee_is_finite(state%torque)) then
               call fatal_error(error, FFRF_NUMERIC_ERROR, 'torsion spring "' // &
                  trim(spring%name) // '": torque ' // to_str(state%torque) // ' N m at t = ' &
                  // to_str(t) // ' s (angle ' // to_str(state%angle) // ' rad); a torsion ' &
                  // 'spring needs finite joint frames')
               return
            end if
            call pair_rows(self, spring%body_a, spring%body_b, rows, na)
            if (present(K_t) .and. present(C_t)) then
               allocate (K(size(rows), size(rows)), C(size(rows), size(rows)))
               call torsion_tangents(spring, state, body_a, q(rows(:na)), v(rows(:na)), &
                  body_b, q(rows(na + 1:)), v(rows(na + 1:)), K, C)
               call add_pair_tangents(rows, K, C, K_t, C_t)
               deallocate (K, C)
            else if (present(f)) then
               allocate (f_a(na), f_b(size(rows) - na))
               ! the moment -T z_a on marker a, +T z_a on marker b (ffrf_mbs_torsion_spring)
               call marker_pair_forces(body_a, q(rows(:na)), spring%marker_a, body_b, &
                  q(rows(na + 1:)), spring%marker_b, [0.0_dp, 0.0_dp, 0.0_dp], &
                  -state%torque * state%axis, f_a, f_b)
               f(rows) = f(rows) + [f_a, f_b]
               deallocate (f_a, f_b)
            end if
         end associate
      end do
   end subroutine add_torsion_terms

   !> The angle at an accepted step becomes each torsion spring's unwrapping reference.
   module procedure update_torsion_references
      type(torsion_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      if (.not. allocated(self%torsion_springs)) return
      zero = 0.0_dp
      do s = 1, size(self%torsion_springs)
         state = self%torsion_state(s, q, zero)
         self%torsion_springs(s)%reference = state%angle
      end do
   end procedure update_torsion_references

   !> Deflections, rates and element force of bushing s at (q, v).
   module procedure mechanism_bushing_state
      integer, allocatable :: rows(:)
      integer :: na
      associate (bushing => self%bushings(s))
         call pair_rows(self, bushing%body_a, bushing%body_b, rows, na)
         state = bushing_evaluate(bushing, self%bodies(bushing%body_a)%body, q(rows(:na)), &
            v(rows(:na)), self%bodies(bushing%body_b)%body, q(rows(na + 1:)), v(rows(na + 1:)))
      end associate
   end procedure mechanism_bushing_state

   !> Potential energy of the bushings, sum e^T K e / 2 (J).
   module procedure mechanism_bushing_energy
      type(bushing_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      energy = 0.0_dp
      if (.not. allocated(self%bushings)) return
      zero = 0.0_dp
      do s = 1, size(self%bushings)
         state = self%bushing_state(s, q, zero)
         energy = energy + 0.5_dp * sum(self%bushings(s)%stiffness * state%deflection**2)
      end do
   end procedure mechanism_bushing_energy

   !> The bushings' generalized forces (f present) or tangents (K_t, C_t present;
   !> ffrf_mbs_bushing).
   subroutine add_bushing_terms(self, q, v, t, error, f, K_t, C_t)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(inout), optional :: f(:), K_t(:, :), C_t(:, :)
      type(bushing_state_t) :: state
      real(dp), allocatable :: K(:, :), C(:, :)
      integer, allocatable :: rows(:)
      integer :: s, na
      if (.not. allocated(self%bushings)) return
      do s = 1, size(self%bushings)
         associate (bushing => self%bushings(s), body_a => &
               self%bodies(self%bushings(s)%body_a)%body, &
               body_b => self%bodies(self%bushings(s)%body_b)%body)
            state = self%bushing_state(s, q, v)
            if (.not. all(ieee_is_finite(state%force))) then
               call fatal_error(error, FFRF_NUMERIC_ERROR, 'bushing "' // trim(bushing%name) &
                  // '": force not finite at t = ' // to_str(t) // ' s; a bushing needs ' // &
                  'finite marker frames')
               return
            end if
            call pair_rows(self, bushing%body_a, bushing%body_b, rows, na)
            if (present(K_t) .and. present(C_t)) then
               allocate (K(size(rows), size(rows)), C(size(rows), size(rows)))
               call bushing_tangents(bushing, body_a, q(rows(:na)), v(rows(:na)), body_b, &
                  q(rows(na + 1:)), v(rows(na + 1:)), K, C)
               call add_pair_tangents(rows, K, C, K_t, C_t)
               deallocate (K, C)
            else if (present(f)) then
               f(rows) = f(rows) + bushing_generalized_force(bushing, body_a, q(rows(:na)), &
                  v(rows(:na)), body_b, q(rows(na + 1:)), v(rows(na + 1:)))
            end if
         end associate
      end do
   end subroutine add_bushing_terms

   !> Rows of bodies a and b in the mechanism's coordinates ([a's; b's]) and the number of a's.
   subroutine pair_rows(self, body_a, body_b, rows, na)
      type(mechanism_t), intent(in) :: self
      integer, intent(in) :: body_a, body_b
      integer, allocatable, intent(out) :: rows(:)
      integer, intent(out) :: na
      integer :: i, ka, kb, nb
      call pair_layout(self, body_a, body_b, ka, na, kb, nb)
      rows = [(ka + i, i = 1, na), (kb + i, i = 1, nb)]
   end subroutine pair_rows

   !> K_t(rows, rows) += K, C_t(rows, rows) += C.
   pure subroutine add_pair_tangents(rows, K, C, K_t, C_t)
      integer, intent(in) :: rows(:)
      real(dp), intent(in) :: K(:, :), C(:, :)
      real(dp), intent(inout) :: K_t(:, :), C_t(:, :)
      K_t(rows, rows) = K_t(rows, rows) + K
      C_t(rows, rows) = C_t(rows, rows) + C
   end subroutine add_pair_tangents

end submodule ffrf_mbs_mechanism_applied
