!> The applied forces of a mechanism (ffrf_mbs_mechanism, a submodule): loads, force elements
!> (mechanism_force_elements.f90) and gravity, as the generalized force f or as its tangents
!> K_t = -df/dq, C_t = -df/dq' (one routine each for both, so that a force and its derivative
!> walk the same loads and bodies).
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_applied
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar, euler_g, skew3
   use ffrf_mbs_rigid_body, only: rigid_body_t, point_load_tangent
   use ffrf_mbs_flexible_body, only: flexible_body_t
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
      real(dp), intent(inout), optional :: f(:)
      type(block_sparse_t), intent(inout), optional :: K_t, C_t
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
               call K_t%add_block(k, k, -tangent)
               if (self%rotor > 0) then
                  call load%magnitude_rates(t, angle, speed, dm_da, dm_ds)
                  do j = 1, 4
                     call K_t%add_block(k, kc + 2 + j, reshape(-(unit_force * (dm_da * &
                        d_angle(j) + dm_ds * d_speed_q(j))), [nb, 1]))
                     call C_t%add_block(k, kc + 2 + j, reshape(-(unit_force * dm_ds * &
                        d_speed_v(j)), [nb, 1]))
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
      real(dp), intent(inout), optional :: f(:)
      type(block_sparse_t), intent(inout), optional :: K_t
      real(dp), allocatable :: tangent(:, :)
      real(dp) :: A(3, 3), vector(3)
      integer :: b, k, nb
      if (maxval(abs(self%gravity)) <= 0.0_dp) return
      do b = 1, num_bodies(self)
         k = self%bodies(b)%offset
         select type (body => self%bodies(b)%body)
         class is (rigid_body_t)
            if (present(K_t)) then
               call K_t%add_block(k + 3, k + 3, -point_load_tangent(q(k + 4:k + 7), &
                  body%center_of_mass, body%mass * self%gravity, [0.0_dp, 0.0_dp, 0.0_dp]))
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
               call K_t%add_block(k, k, -tangent)
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

end submodule ffrf_mbs_mechanism_applied
