!> The tangents of a mechanism's equations (ffrf_mbs_mechanism): stiffness and damping of the
!> applied forces and springs, the constraint and mass stiffness, for the Newton iteration matrix.
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_tangents
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_finite, only: all_finite
   use ffrf_mbs_rotation, only: euler_g
   use ffrf_mbs_rigid_body, only: rigid_body_t, euler_hessian, point_load_tangent
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_dae_system, only: dae_stiffness_fd, dae_damping_fd, dae_constraint_stiffness_fd, &
      dae_mass_stiffness_fd
   use ffrf_mbs_joint_driver, only: driver_hessian
   use ffrf_mbs_mechanism_loads, only: LOAD_FORCE
   use ffrf_mbs_spring_damper, only: spring_tangents
   implicit none

   !> Unit x axis
   real(dp), parameter :: e_x(3) = [1.0_dp, 0.0_dp, 0.0_dp]

contains

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

end submodule ffrf_mbs_mechanism_tangents
