!> A linear spring-damper between two markers (&spring; docs/mechanisms.md "Springs"): marker a
!> of body a and marker b of body b (rigid markers, ground markers, a flexible body's virtual
!> nodes). With d = r_b - r_a (global marker positions r_k(q)), the length l = |d|, the unit
!> direction n = d / l and the rate l' = n . (L_r,b v_b - L_r,a v_a) (L_r the marker velocity
!> Jacobians of body_t), the tension is
!>     f = k (l - L0) + c l'
!> and the forces are +f n on marker a and -f n on marker b (a stretched spring pulls the markers
!> together). The generalized force is Q = -S^T n f with S = [-L_r,a, L_r,b], so its power is
!> Q . v = -f l' = -d/dt [k (l - L0)^2 / 2] - c l'^2: the spring's work is minus its potential
!> energy and the damper's dissipation (ffrf_mbs_energy_balance counts it as applied work).
!>
!> Newton tangents (exact; theory.md 3.5), x = [q_a; q_b], D = dd/dx = [-P_a, P_b] with P the
!> exact position Jacobians, N = dn/dx = (I - n n^T) D / l, T_k(F) = d(L_r,k^T F)/dq_k at fixed F
!> (body_t%marker_force_tangent):
!>     df/dx  = k n^T D + c (w^T N + v^T blockdiag(-T_a(n), T_b(n))),  w = S v
!>     df/dv  = c n^T S
!>     K = -dQ/dx = blockdiag(-T_a(f n), T_b(f n)) + f S^T N + S^T n df/dx
!>     C = -dQ/dv = c S^T n n^T S
!> The ground has no coordinates: its blocks are empty.
module ffrf_mbs_spring_damper
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_body, only: body_t
   use ffrf_mbs_force_element, only: force_element_t, marker_pair_forces
   implicit none
   private
   public :: spring_damper_t, spring_state_t

   !> A spring-damper between marker_a of body_a and marker_b of body_b (mechanism indices).
   type, extends(force_element_t) :: spring_damper_t
      !> Name for messages and sensors
      character(len=64) :: name = 'spring'
      !> Mechanism indices of the two bodies and their markers
      integer :: body_a = 0, marker_a = 0, body_b = 0, marker_b = 0
      !> Stiffness k (N/m) and damping c (N s/m), both >= 0
      real(dp) :: stiffness = 0.0_dp, damping = 0.0_dp
      !> Free length L0 (m); negative: not given, set from the starting pose (set_free_length)
      real(dp) :: free_length = -1.0_dp
   contains
      procedure :: bodies => spring_bodies
      procedure :: terms => spring_terms
   end type spring_damper_t

   !> Length, rate and tension of a spring at a state, with what the tangents reuse.
   type :: spring_state_t
      !> Length l (m), rate l' (m/s), tension f = k (l - L0) + c l' (N)
      real(dp) :: length = 0.0_dp, rate = 0.0_dp, force = 0.0_dp
      !> Unit direction n = (r_b - r_a) / l
      real(dp) :: direction(3) = 0.0_dp
      !> Relative marker velocity w = L_r,b v_b - L_r,a v_a (m/s)
      real(dp) :: relative_velocity(3) = 0.0_dp
   end type spring_state_t

   public :: spring_evaluate, spring_generalized_forces, spring_tangents

contains

   !> [body_a, body_b].
   pure function spring_bodies(self) result(bodies)
      class(spring_damper_t), intent(in) :: self
      integer :: bodies(2)
      bodies = [self%body_a, self%body_b]
   end function spring_bodies

   !> Generalized forces or tangents (force_element_t%terms); a zero length or a non-finite
   !> tension is a numeric error.
   subroutine spring_terms(self, body_a, q_a, v_a, body_b, q_b, v_b, t, error, Q, K, C)
      class(spring_damper_t), intent(in) :: self
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), v_a(:), q_b(:), v_b(:), t
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(out), optional :: Q(:), K(:, :), C(:, :)
      type(spring_state_t) :: state
      state = spring_evaluate(self, body_a, q_a, v_a, body_b, q_b, v_b)
      if (.not. (state%length > 0.0_dp .and. ieee_is_finite(state%force))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'spring "' // trim(self%name) // &
            '": length ' // to_str(state%length) // ' m, tension ' // to_str(state%force) // &
            ' N at t = ' // to_str(t) // ' s; a spring needs distinct, finite marker positions')
      else if (present(K) .and. present(C)) then
         call spring_tangents(self, state, body_a, q_a, v_a, body_b, q_b, v_b, K, C)
      else if (present(Q)) then
         call spring_generalized_forces(self, state, body_a, q_a, body_b, q_b, Q(:size(q_a)), &
            Q(size(q_a) + 1:))
      end if
   end subroutine spring_terms

   !> Length, direction, rate and tension of `spring` at the bodies' states (q_a, v_a; q_b, v_b:
   !> the bodies' own coordinates, empty for the ground). A zero length leaves direction 0.
   pure function spring_evaluate(spring, body_a, q_a, v_a, body_b, q_b, v_b) result(state)
      !> The spring
      type(spring_damper_t), intent(in) :: spring
      !> Body a and its coordinates and velocities
      class(body_t), intent(in) :: body_a
      real(dp), intent(in) :: q_a(:), v_a(:)
      !> Body b and its coordinates and velocities
      class(body_t), intent(in) :: body_b
      real(dp), intent(in) :: q_b(:), v_b(:)
      type(spring_state_t) :: state
      real(dp) :: d(3)
      d = body_b%marker_position(q_b, spring%marker_b) - &
         body_a%marker_position(q_a, spring%marker_a)
      state%length = norm2(d)
      state%relative_velocity = marker_velocity(body_b, q_b, v_b, spring%marker_b) - &
         marker_velocity(body_a, q_a, v_a, spring%marker_a)
      if (state%length > 0.0_dp) state%direction = d / state%length
      state%rate = dot_product(state%direction, state%relative_velocity)
      state%force = spring%stiffness * (state%length - spring%free_length) + &
         spring%damping * state%rate
   end function spring_evaluate

   !> Generalized forces of the spring on body a (L_r,a^T f n) and body b (-L_r,b^T f n).
   pure subroutine spring_generalized_forces(spring, state, body_a, q_a, body_b, q_b, f_a, f_b)
      !> The spring
      type(spring_damper_t), intent(in) :: spring
      !> Its state (spring_evaluate)
      type(spring_state_t), intent(in) :: state
      !> Body a and its coordinates
      class(body_t), intent(in) :: body_a
      real(dp), intent(in) :: q_a(:)
      !> Body b and its coordinates
      class(body_t), intent(in) :: body_b
      real(dp), intent(in) :: q_b(:)
      !> Generalized forces (size of q_a and q_b)
      real(dp), intent(out) :: f_a(:), f_b(:)
      real(dp) :: zero(3)
      zero = 0.0_dp
      call marker_pair_forces(body_a, q_a, spring%marker_a, body_b, q_b, spring%marker_b, &
         state%force * state%direction, zero, f_a, f_b)
   end subroutine spring_generalized_forces

   !> K = -dQ/dx and C = -dQ/dv over x = [q_a; q_b] (module header), exact.
   pure subroutine spring_tangents(spring, state, body_a, q_a, v_a, body_b, q_b, v_b, K, C)
      !> The spring
      type(spring_damper_t), intent(in) :: spring
      !> Its state (spring_evaluate; length > 0)
      type(spring_state_t), intent(in) :: state
      !> Body a, its coordinates and velocities
      class(body_t), intent(in) :: body_a
      real(dp), intent(in) :: q_a(:), v_a(:)
      !> Body b, its coordinates and velocities
      class(body_t), intent(in) :: body_b
      real(dp), intent(in) :: q_b(:), v_b(:)
      !> -dQ/dx and -dQ/dv, (na + nb) x (na + nb)
      real(dp), intent(out) :: K(:, :), C(:, :)
      real(dp) :: S(3, size(q_a) + size(q_b)), D(3, size(q_a) + size(q_b))
      real(dp) :: N(3, size(q_a) + size(q_b)), df_dx(size(q_a) + size(q_b))
      real(dp) :: projector(3, 3), Sn(size(q_a) + size(q_b)), v(size(q_a) + size(q_b))
      real(dp) :: T_force(size(q_a) + size(q_b), size(q_a) + size(q_b))
      real(dp) :: T_unit(size(q_a) + size(q_b), size(q_a) + size(q_b))
      integer :: na, i
      na = size(q_a)
      v = [v_a, v_b]
      S = 0.0_dp
      D = 0.0_dp
      if (na > 0) then
         S(:, 1:na) = -body_a%marker_velocity_jacobian(q_a, spring%marker_a)
         D(:, 1:na) = -body_a%marker_position_jacobian(q_a, spring%marker_a)
      end if
      if (size(q_b) > 0) then
         S(:, na + 1:) = body_b%marker_velocity_jacobian(q_b, spring%marker_b)
         D(:, na + 1:) = body_b%marker_position_jacobian(q_b, spring%marker_b)
      end if
      projector = -spread(state%direction, 2, 3) * spread(state%direction, 1, 3)
      do i = 1, 3
         projector(i, i) = projector(i, i) + 1.0_dp
      end do
      N = matmul(projector, D) / state%length
      call force_tangent_blocks(state%force * state%direction, T_force)
      call force_tangent_blocks(state%direction, T_unit)
      df_dx = spring%stiffness * matmul(state%direction, D) + spring%damping * &
         (matmul(state%relative_velocity, N) + matmul(v, T_unit))
      Sn = matmul(state%direction, S)
      K = T_force + state%force * matmul(transpose(S), N) + &
         spread(Sn, 2, size(v)) * spread(df_dx, 1, size(v))
      C = spring%damping * spread(Sn, 2, size(v)) * spread(Sn, 1, size(v))
   contains
      !> blockdiag(-T_a(F), T_b(F)): d(S^T F)/dx at fixed F.
      pure subroutine force_tangent_blocks(force, T)
         real(dp), intent(in) :: force(3)
         real(dp), intent(out) :: T(:, :)
         real(dp) :: zero(3)
         zero = 0.0_dp
         T = 0.0_dp
         if (na > 0) then
            call body_a%marker_force_tangent(q_a, spring%marker_a, force, zero, T(1:na, 1:na))
            T(1:na, 1:na) = -T(1:na, 1:na)
         end if
         if (size(q_b) > 0) call body_b%marker_force_tangent(q_b, spring%marker_b, force, &
            zero, T(na + 1:, na + 1:))
      end subroutine force_tangent_blocks
   end subroutine spring_tangents

   !> L_r v of marker k (0 for a body without coordinates).
   pure function marker_velocity(body, q, v, k) result(velocity)
      class(body_t), intent(in) :: body
      real(dp), intent(in) :: q(:), v(:)
      integer, intent(in) :: k
      real(dp) :: velocity(3)
      velocity = 0.0_dp
      if (size(q) > 0) velocity = matmul(body%marker_velocity_jacobian(q, k), v)
   end function marker_velocity

end module ffrf_mbs_spring_damper
