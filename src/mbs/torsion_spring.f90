!> A rotational spring-damper about a revolute (or cylindrical) joint (&torsion_spring;
!> docs/mechanisms.md "Torsion springs", docs/theory.md "3.8 Torsion springs"): between marker a of
!> body a and marker b of body b, the joint's two markers. With the marker axes x_a, y_a, z_a
!> (A_a e_j) and x_b (A_b e_x), the joint angle is the angle of x_b about z_a,
!>     phi = phi_ref + wrap(atan2(y_a . x_b, x_a . x_b) - phi_ref),   wrap into [-pi, pi),
!> unwrapped against phi_ref, the angle at the last accepted step (set_reference; as the rotor
!> angle of ffrf_mbs_mechanism: counts turns while the joint turns less than pi per step). The
!> rate is w = z_a . (L_w,b v_b - L_w,a v_a), the torque about z_a
!>     T = -k (phi - phi0) - c w,
!> applied as the moment +T z_a on marker b and -T z_a on marker a (action = reaction). The
!> generalized force (the mechanism applies the pair with ffrf_mbs_spring_damper's
!> marker_pair_forces) is Q = T g with g = S_w^T z_a, S_w = [-L_w,a, L_w,b], and its power
!> Q . v = T w: on the joint (z_b = z_a, x_b normal to z_a) w = phi', so the power is
!> -d/dt [k (phi - phi0)^2 / 2] - c w^2 (potential energy and dissipation; the mechanism counts
!> the torque's work as applied work, ffrf_mbs_energy_balance).
!>
!> Newton tangents (exact for this Q; theory.md 3.8), x = [q_a; q_b], Z = dz_a/dx
!> = [J_z,a, 0] (J_j,a = d(A_a e_j)/dq_a, body_t%marker_axis_jacobian), B = d(S_w^T m)/dx at a
!> fixed moment m = z_a, blockdiag(-T_a(z_a), T_b(z_a)) with T_k(M) = d(L_w,k^T M)/dq_k
!> (body_t%marker_force_tangent):
!>     dphi/dx = (c ds - s dc) / (c^2 + s^2),  c = x_a . x_b, s = y_a . x_b,
!>               ds = x_b^T [J_y,a, 0] + y_a^T [0, J_x,b], dc = x_b^T [J_x,a, 0] + x_a^T [0, J_x,b]
!>     dw/dx   = (S_w v)^T Z + v^T B,    dw/dv = g^T
!>     K = -dQ/dx = g (k dphi/dx + c dw/dx) - T (B + S_w^T Z)
!>     C = -dQ/dv = c g g^T
!> The ground has no coordinates: its blocks are empty.
module ffrf_mbs_torsion_spring
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_body, only: body_t
   use ffrf_mbs_force_element, only: force_element_t, marker_pair_forces
   implicit none
   private
   public :: torsion_spring_t, torsion_state_t
   public :: torsion_evaluate, torsion_tangents

   !> A torsion spring-damper about joint `joint` (mechanism indices).
   type, extends(force_element_t) :: torsion_spring_t
      !> Name for messages and sensors
      character(len=64) :: name = 'torsion_spring'
      !> Mechanism joint number; its bodies and markers (set by mechanism%add_torsion_spring)
      integer :: joint = 0, body_a = 0, marker_a = 0, body_b = 0, marker_b = 0
      !> Stiffness k (N m/rad) and damping c (N m s/rad), both >= 0
      real(dp) :: stiffness = 0.0_dp, damping = 0.0_dp
      !> Free angle phi0 (rad); used only when free_angle_given, else set from the start
      real(dp) :: free_angle = 0.0_dp
      logical :: free_angle_given = .false.
      !> Unwrapping reference phi_ref: the angle at the last accepted step (rad)
      real(dp) :: reference = 0.0_dp
   contains
      procedure :: bodies => torsion_bodies
      procedure :: terms => torsion_terms
   end type torsion_spring_t

   !> Angle, rate and torque of a torsion spring at a state, with what the tangents reuse.
   type :: torsion_state_t
      !> Unwrapped angle phi (rad), rate w (rad/s), torque T = -k (phi - phi0) - c w (N m)
      real(dp) :: angle = 0.0_dp, rate = 0.0_dp, torque = 0.0_dp
      !> The joint axis z_a, global
      real(dp) :: axis(3) = 0.0_dp
   end type torsion_state_t

contains

   !> [body_a, body_b] (the joint's).
   pure function torsion_bodies(self) result(bodies)
      class(torsion_spring_t), intent(in) :: self
      integer :: bodies(2)
      bodies = [self%body_a, self%body_b]
   end function torsion_bodies

   !> Generalized forces (the moment -T z_a on marker a, +T z_a on marker b) or exact tangents
   !> (force_element_t%terms); a non-finite torque is a numeric error.
   subroutine torsion_terms(self, body_a, q_a, v_a, body_b, q_b, v_b, t, error, Q, K, C)
      class(torsion_spring_t), intent(in) :: self
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), v_a(:), q_b(:), v_b(:), t
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(out), optional :: Q(:), K(:, :), C(:, :)
      type(torsion_state_t) :: state
      state = torsion_evaluate(self, body_a, q_a, v_a, body_b, q_b, v_b)
      if (.not. ieee_is_finite(state%torque)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'torsion spring "' // trim(self%name) // &
            '": torque ' // to_str(state%torque) // ' N m at t = ' // to_str(t) // &
            ' s (angle ' // to_str(state%angle) // ' rad); a torsion spring needs finite ' // &
            'joint frames')
      else if (present(K) .and. present(C)) then
         call torsion_tangents(self, state, body_a, q_a, v_a, body_b, q_b, v_b, K, C)
      else if (present(Q)) then
         call marker_pair_forces(body_a, q_a, self%marker_a, body_b, q_b, self%marker_b, &
            [0.0_dp, 0.0_dp, 0.0_dp], -state%torque * state%axis, Q(:size(q_a)), &
            Q(size(q_a) + 1:))
      end if
   end subroutine torsion_terms

   !> Angle, rate and torque of `spring` at the bodies' states (q_a, v_a; q_b, v_b: the bodies'
   !> own coordinates, empty for the ground).
   pure function torsion_evaluate(spring, body_a, q_a, v_a, body_b, q_b, v_b) result(state)
      !> The torsion spring
      type(torsion_spring_t), intent(in) :: spring
      !> Body a and its coordinates and velocities
      class(body_t), intent(in) :: body_a
      real(dp), intent(in) :: q_a(:), v_a(:)
      !> Body b and its coordinates and velocities
      class(body_t), intent(in) :: body_b
      real(dp), intent(in) :: q_b(:), v_b(:)
      type(torsion_state_t) :: state
      real(dp) :: frame_a(3, 3), frame_b(3, 3), x_b(3), raw, w(3)
      frame_a = body_a%marker_orientation(q_a, spring%marker_a)
      frame_b = body_b%marker_orientation(q_b, spring%marker_b)
      x_b = frame_b(:, 1)
      raw = atan2(dot_product(frame_a(:, 2), x_b), dot_product(frame_a(:, 1), x_b))
      state%angle = spring%reference + modulo(raw - spring%reference + pi, 2.0_dp * pi) - pi
      state%axis = frame_a(:, 3)
      w = 0.0_dp
      if (size(q_b) > 0) w = matmul(body_b%marker_rotation_jacobian(q_b, spring%marker_b), v_b)
      if (size(q_a) > 0) w = w - matmul(body_a%marker_rotation_jacobian(q_a, spring%marker_a), &
         v_a)
      state%rate = dot_product(state%axis, w)
      state%torque = -spring%stiffness * (state%angle - spring%free_angle) - &
         spring%damping * state%rate
   end function torsion_evaluate

   !> K = -dQ/dx and C = -dQ/dv over x = [q_a; q_b] (module header), exact.
   pure subroutine torsion_tangents(spring, state, body_a, q_a, v_a, body_b, q_b, v_b, K, C)
      !> The torsion spring
      type(torsion_spring_t), intent(in) :: spring
      !> Its state (torsion_evaluate)
      type(torsion_state_t), intent(in) :: state
      !> Body a, its coordinates and velocities
      class(body_t), intent(in) :: body_a
      real(dp), intent(in) :: q_a(:), v_a(:)
      !> Body b, its coordinates and velocities
      class(body_t), intent(in) :: body_b
      real(dp), intent(in) :: q_b(:), v_b(:)
      !> -dQ/dx and -dQ/dv, (na + nb) x (na + nb)
      real(dp), intent(out) :: K(:, :), C(:, :)
      real(dp) :: S(3, size(q_a) + size(q_b)), Z(3, size(q_a) + size(q_b))
      real(dp) :: B(size(q_a) + size(q_b), size(q_a) + size(q_b))
      real(dp) :: g(size(q_a) + size(q_b)), v(size(q_a) + size(q_b))
      real(dp) :: d_angle(size(q_a) + size(q_b)), d_rate(size(q_a) + size(q_b))
      real(dp) :: ds(size(q_a) + size(q_b)), dc(size(q_a) + size(q_b))
      real(dp) :: frame_a(3, 3), frame_b(3, 3), x_b(3), cosine, sine, zero(3)
      integer :: na, n
      na = size(q_a)
      n = na + size(q_b)
      v = [v_a, v_b]
      zero = 0.0_dp
      ! S, Z, ds and dc are set column by column below (a's columns, then b's); B block by block
      B = 0.0_dp
      frame_a = body_a%marker_orientation(q_a, spring%marker_a)
      frame_b = body_b%marker_orientation(q_b, spring%marker_b)
      x_b = frame_b(:, 1)
      cosine = dot_product(frame_a(:, 1), x_b)
      sine = dot_product(frame_a(:, 2), x_b)
      if (na > 0) then
         S(:, 1:na) = -body_a%marker_rotation_jacobian(q_a, spring%marker_a)
         Z(:, 1:na) = body_a%marker_axis_jacobian(q_a, spring%marker_a, &
            [0.0_dp, 0.0_dp, 1.0_dp])
         ds(1:na) = matmul(x_b, body_a%marker_axis_jacobian(q_a, spring%marker_a, &
            [0.0_dp, 1.0_dp, 0.0_dp]))
         dc(1:na) = matmul(x_b, body_a%marker_axis_jacobian(q_a, spring%marker_a, &
            [1.0_dp, 0.0_dp, 0.0_dp]))
         call body_a%marker_force_tangent(q_a, spring%marker_a, zero, state%axis, B(1:na, 1:na))
         B(1:na, 1:na) = -B(1:na, 1:na)
      end if
      if (n > na) then
         S(:, na + 1:) = body_b%marker_rotation_jacobian(q_b, spring%marker_b)
         Z(:, na + 1:) = 0.0_dp
         ds(na + 1:) = matmul(frame_a(:, 2), body_b%marker_axis_jacobian(q_b, spring%marker_b, &
            [1.0_dp, 0.0_dp, 0.0_dp]))
         dc(na + 1:) = matmul(frame_a(:, 1), body_b%marker_axis_jacobian(q_b, spring%marker_b, &
            [1.0_dp, 0.0_dp, 0.0_dp]))
         call body_b%marker_force_tangent(q_b, spring%marker_b, zero, state%axis, &
            B(na + 1:, na + 1:))
      end if
      g = matmul(state%axis, S)
      d_angle = (cosine * ds - sine * dc) / (cosine**2 + sine**2)
      d_rate = matmul(matmul(S, v), Z) + matmul(v, B)
      K = spread(g, 2, n) * spread(spring%stiffness * d_angle + spring%damping * d_rate, 1, n) &
         - state%torque * (B + matmul(transpose(S), Z))
      C = spring%damping * spread(g, 2, n) * spread(g, 1, n)
   end subroutine torsion_tangents

end module ffrf_mbs_torsion_spring
