!> The tangents of a mechanism's equations (ffrf_mbs_mechanism): stiffness and damping of the
!> bodies and of the applied forces (those: mechanism_applied.f90), the constraint and mass
!> stiffness, for the Newton iteration matrix.
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_tangents
   use ffrf_core_error, only: fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_finite, only: all_finite
   use ffrf_mbs_rotation, only: euler_hessian
   use ffrf_mbs_dae_system, only: dae_stiffness_fd, dae_damping_fd, dae_constraint_stiffness_fd, &
      dae_mass_stiffness_fd
   use ffrf_mbs_joint_driver, only: driver_hessian
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
         call body_layout(self, b, k, nb)
         if (nb == 0) cycle
         allocate (K_b(nb, nb), C_b(nb, nb))
         call self%bodies(b)%body%force_tangents(q(k + 1:k + nb), v(k + 1:k + nb), K_b, C_b)
         K_t(k + 1:k + nb, k + 1:k + nb) = K_b
         self%damping_cache(k + 1:k + nb, k + 1:k + nb) = C_b
         deallocate (K_b, C_b)
      end do
      ! minus the derivatives of the loads, force elements and gravity (mechanism_applied.f90)
      call add_applied_terms(self, q, v, t, error, K_t=K_t, C_t=self%damping_cache)
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
      do j = 1, num_joints(self)
         associate (jt => self%joints(j))
            ne = jt%joint%num_equations
            call pair_layout(self, jt%body_a, jt%body_b, ka, na, kb, nb)
            allocate (K_aa(na, na), K_ab(na, nb), K_bb(nb, nb))
            call jt%joint%constraint_hessian(self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
               self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
               lambda(jt%offset + 1:jt%offset + ne), K_aa, K_ab, K_bb)
            call add_pair_blocks(K_c, ka, na, kb, nb, K_aa, K_ab, K_bb)
            deallocate (K_aa, K_ab, K_bb)
         end associate
      end do
      if (allocated(self%drivers)) then
         do j = 1, size(self%drivers)
            associate (dr => self%drivers(j), jt => self%joints(self%drivers(j)%joint))
               call pair_layout(self, jt%body_a, jt%body_b, ka, na, kb, nb)
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
         call body_layout(self, b, k, nb)
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
