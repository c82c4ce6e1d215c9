!> The tangents of a mechanism's equations (ffrf_mbs_mechanism): stiffness and damping of the
!> bodies and of the applied forces (those: mechanism_applied.f90), the constraint and mass
!> stiffness, for the Newton iteration matrix.
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_tangents
   use ffrf_core_error, only: fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_finite, only: all_finite
   use ffrf_mbs_rotation, only: euler_hessian
   use ffrf_mbs_dae_system, only: dae_stiffness_fd, dae_damping_fd, dae_constraint_stiffness_fd, &
      dae_mass_stiffness_fd, dae_tangents_sparse
   use ffrf_mbs_joint_driver, only: driver_hessian
   implicit none

   !> Unit x axis
   real(dp), parameter :: e_x(3) = [1.0_dp, 0.0_dp, 0.0_dp]

contains

   !> The bodies' groups: body b's coordinates are group b when the bodies sit one after
   !> the other in q (add_body's layout), else one group (dense but correct).
   module procedure block_groups
      integer, allocatable :: starts(:), rows(:)
      integer :: b, k, nb, i
      allocate (starts(num_bodies(self) + 1))
      starts(1) = 1
      do b = 1, num_bodies(self)
         call body_layout(self, b, k, nb)
         if (nb > 0 .and. k + 1 /= starts(b)) exit
         starts(b + 1) = starts(b) + nb
      end do
      if (b <= num_bodies(self) .or. starts(size(starts)) /= self%n + 1) starts = [1, self%n + 1]
      if (constraint_rows) then
         rows = [(i, i=1, self%nc + 1)]
      else
         rows = starts
      end if
      if (.not. S%same_groups(rows, starts)) call S%init(rows, starts)
      call S%zero()
   end procedure block_groups

   !> K_t = -df/dq and C_t = -df/dq' (module header: per body and load) into K and C (set up
   !> by block_groups here).
   subroutine force_tangents(self, q, v, t, tangent, damping, error)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:), v(:), t
      type(block_sparse_t), intent(inout) :: tangent, damping
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: K_b(:, :), C_b(:, :)
      integer :: b, k, nb
      call block_groups(self, tangent, .false.)
      call block_groups(self, damping, .false.)
      do b = 1, num_bodies(self)
         call body_layout(self, b, k, nb)
         if (nb == 0) cycle
         allocate (K_b(nb, nb), C_b(nb, nb))
         call self%bodies(b)%body%force_tangents(q(k + 1:k + nb), v(k + 1:k + nb), K_b, C_b)
         call tangent%add_block(k, k, K_b)
         call damping%add_block(k, k, C_b)
         deallocate (K_b, C_b)
      end do
      ! minus the derivatives of the loads, force elements and gravity (mechanism_applied.f90)
      call add_applied_terms(self, q, v, t, error, K_t=tangent, C_t=damping)
      if (allocated(error)) return
      if (.not. (all_finite(tangent%values(:tangent%used)) .and. all_finite(damping%values(:damping%used)))) &
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism: force tangents not finite ' &
         // 'at t = ' // to_str(t) // ' s')
   end subroutine force_tangents

   !> K_t = -df/dq (module header: per body and load; differences if .not. analytic_tangents).
   module procedure mechanism_stiffness
      if (.not. self%analytic_tangents) then
         call dae_stiffness_fd(self, q, v, t, K_t, error)
         return
      end if
      call force_tangents(self, q, v, t, self%stiffness_cache, self%damping_cache, error)
      if (allocated(error)) return
      self%cache_q = q
      self%cache_v = v
      self%cache_t = t
      call self%stiffness_cache%to_dense(K_t)
   end procedure mechanism_stiffness

   !> C_t = -df/dq' (module header; reuses the stiffness call's result at the same state).
   module procedure mechanism_damping
      real(dp), allocatable :: K_t(:, :)
      logical :: cached
      if (.not. self%analytic_tangents) then
         call dae_damping_fd(self, q, v, t, C_t, error)
         return
      end if
      cached = allocated(self%cache_q) .and. allocated(self%cache_v)
      if (cached) cached = self%damping_cache%num_rows == self%n .and. &
         size(self%cache_q) == size(q) .and. size(self%cache_v) == size(v)
      if (cached) cached = all(self%cache_q == q) .and. all(self%cache_v == v) .and. &
         self%cache_t == t
      if (.not. cached) then
         allocate (K_t(self%n, self%n))
         call self%stiffness(q, v, t, K_t, error)
         if (allocated(error)) return
      end if
      call self%damping_cache%to_dense(C_t)
   end procedure mechanism_damping

   !> d(Phi_q^T lambda)/dq: joints, drive row and Euler rows (module header).
   module procedure mechanism_constraint_stiffness
      if (.not. self%analytic_tangents) then
         call dae_constraint_stiffness_fd(self, q, t, lambda, K_c, error)
         return
      end if
      call block_groups(self, self%work_blocks, .false.)
      call add_constraint_stiffness(self, q, t, lambda, self%work_blocks)
      call self%work_blocks%to_dense(K_c)
      if (.not. all_finite(K_c)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: constraint stiffness not finite at t = ' // to_str(t) // ' s')
   end procedure mechanism_constraint_stiffness

   !> K += d(Phi_q^T lambda)/dq: the joints' and drivers' pair blocks, the drive row and the
   !> Euler rows.
   subroutine add_constraint_stiffness(self, q, t, lambda, tangent)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:), t, lambda(:)
      type(block_sparse_t), intent(inout) :: tangent
      real(dp), allocatable :: K_aa(:, :), K_ab(:, :), K_bb(:, :)
      real(dp) :: f(3), X(3, 3), diagonal(1, 1)
      integer :: j, b, k, ka, kb, na, nb, ne, i
      do j = 1, num_joints(self)
         associate (jt => self%joints(j))
            ne = jt%joint%num_equations
            call pair_layout(self, jt%body_a, jt%body_b, ka, na, kb, nb)
            allocate (K_aa(na, na), K_ab(na, nb), K_bb(nb, nb))
            call jt%joint%constraint_hessian(self%bodies(jt%body_a)%body, q(ka + 1:ka + na), &
               self%bodies(jt%body_b)%body, q(kb + 1:kb + nb), &
               lambda(jt%offset + 1:jt%offset + ne), K_aa, K_ab, K_bb)
            call add_pair_blocks(tangent, ka, kb, K_aa, K_ab, K_bb)
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
               call add_pair_blocks(tangent, ka, kb, K_aa, K_ab, K_bb)
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
         call tangent%add_block(k + 3, k + 3, euler_hessian(X))
      end if
      do b = 1, num_bodies(self)
         if (self%bodies(b)%euler_row == 0) cycle
         k = self%bodies(b)%offset
         diagonal = 2.0_dp * lambda(self%bodies(b)%euler_row)
         do i = 4, 7
            call tangent%add_block(k + i - 1, k + i - 1, diagonal)
         end do
      end do
   end subroutine add_constraint_stiffness

   !> K += the symmetric pair blocks [K_aa K_ab; K_ab^T K_bb] of two bodies at offsets ka, kb.
   subroutine add_pair_blocks(tangent, ka, kb, K_aa, K_ab, K_bb)
      type(block_sparse_t), intent(inout) :: tangent
      integer, intent(in) :: ka, kb
      real(dp), intent(in) :: K_aa(:, :), K_ab(:, :), K_bb(:, :)
      call tangent%add_block(ka, ka, K_aa)
      call tangent%add_block(ka, kb, K_ab)
      call tangent%add_block(kb, ka, transpose(K_ab))
      call tangent%add_block(kb, kb, K_bb)
   end subroutine add_pair_blocks

   !> d(M(q) a)/dq for a fixed a: blockdiag of the bodies' mass_stiffness.
   module procedure mechanism_mass_stiffness
      if (.not. self%analytic_tangents) then
         call dae_mass_stiffness_fd(self, q, a, K_m, error)
         return
      end if
      call block_groups(self, self%work_blocks, .false.)
      call add_mass_stiffness(self, q, a, self%work_blocks)
      call self%work_blocks%to_dense(K_m)
      if (.not. all_finite(K_m)) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: mass stiffness not finite')
   end procedure mechanism_mass_stiffness

   !> K += blockdiag of the bodies' d(M_b a_b)/dq_b.
   subroutine add_mass_stiffness(self, q, a, tangent)
      type(mechanism_t), intent(in) :: self
      real(dp), intent(in) :: q(:), a(:)
      type(block_sparse_t), intent(inout) :: tangent
      real(dp), allocatable :: K_b(:, :)
      integer :: b, k, nb
      do b = 1, num_bodies(self)
         call body_layout(self, b, k, nb)
         if (nb == 0) cycle
         allocate (K_b(nb, nb))
         call self%bodies(b)%body%mass_stiffness(q(k + 1:k + nb), a(k + 1:k + nb), K_b)
         call tangent%add_block(k, k, K_b)
         deallocate (K_b)
      end do
   end subroutine add_mass_stiffness

   !> The sparse path's tangents: K = -df/dq + d(M a)/dq + d(Phi_q^T lambda)/dq, C = -df/dq'.
   module procedure mechanism_tangents_sparse
      if (.not. self%analytic_tangents) then
         call dae_tangents_sparse(self, q, v, a, t, lambda, K, C, error)
         return
      end if
      call force_tangents(self, q, v, t, K, C, error)
      if (allocated(error)) return
      call add_mass_stiffness(self, q, a, K)
      if (self%nc > 0) call add_constraint_stiffness(self, q, t, lambda, K)
      if (.not. all_finite(K%values(:K%used))) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'mechanism: tangent (mass and constraint stiffness) not finite at t = ' // &
         to_str(t) // ' s')
   end procedure mechanism_tangents_sparse

end submodule ffrf_mbs_mechanism_tangents
