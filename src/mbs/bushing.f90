!> A 6-dof linear bushing between two markers (&bushing; docs/mechanisms.md "Bushings",
!> docs/theory.md "3.9 Bushings"): marker a of body a and marker b of body b. In marker a's frame
!> (A_a, marker frame -> global) the deflections are
!>     d   = A_a^T (r_b - r_a)                       (relative translation, m)
!>     phi = vee(R - R^T) / 2,  R = A_a^T A_b         (axial vector of the relative rotation, rad)
!> (phi = sin(theta) u for a rotation theta about u: the rotation vector to second order; it
!> is exact to differentiate, and its rate phi' = Gamma w, Gamma = (tr(R) I - R) / 2, with the
!> relative angular velocity w = A_a^T (omega_b - omega_a)). Their rates are
!>     d'  = A_a^T (v_b - v_a - omega_a x (r_b - r_a)),   phi' = Gamma w,
!> i.e. e' = E v with e = [d; phi] and the 6 x n matrix E built from the marker velocity
!> Jacobians L_r, L_w of both bodies. The element force (marker a's axes) is
!>     f = K e + C e',   K = diag(kx, ky, kz, krx, kry, krz), C = diag(c...),
!> and the generalized force Q = -E^T f: a force -A_a f_d on marker b and +A_a f_d on marker a,
!> the moment -A_a Gamma^T f_phi on marker b and +A_a Gamma^T f_phi + (r_b - r_a) x A_a f_d on
!> marker a (action = reaction, the moment of the force pair included). Its power Q . v =
!> -f . e' = -d/dt (e^T K e / 2) - e'^T C e': conservative with potential e^T K e / 2 and the
!> damper's dissipation (counted as applied work, ffrf_mbs_energy_balance). The sensor's six
!> values are -f: F = -K d - C d', M = -K_r phi - C_r phi' (marker a's axes).
!>
!> Tangents: C_t = -dQ/dv = E^T C E (exact); K_t = -dQ/dq by central differences of Q over the
!> two bodies' coordinates at fixed v (2 (n_a + n_b) evaluations per call, step
!> eps^(1/3) max(|q_j|, 1): relative error ~1e-11, as body_t's default tangents).
module ffrf_mbs_bushing
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_body, only: body_t
   use ffrf_mbs_force_element, only: force_element_t
   use ffrf_mbs_rotation, only: skew3
   implicit none
   private
   public :: bushing_t, bushing_state_t
   public :: bushing_evaluate, bushing_generalized_force, bushing_tangents

   !> A bushing between marker_a of body_a and marker_b of body_b (mechanism indices).
   type, extends(force_element_t) :: bushing_t
      !> Name for messages and sensors
      character(len=64) :: name = 'bushing'
      !> Mechanism indices of the two bodies and their markers
      integer :: body_a = 0, marker_a = 0, body_b = 0, marker_b = 0
      !> Stiffness kx, ky, kz (N/m), krx, kry, krz (N m/rad) and damping (N s/m, N m s/rad), >= 0
      real(dp) :: stiffness(6) = 0.0_dp, damping(6) = 0.0_dp
   contains
      procedure :: bodies => bushing_bodies
      procedure :: terms => bushing_terms
   end type bushing_t

   !> Deflections, rates and element force of a bushing at a state.
   type :: bushing_state_t
      !> e = [d; phi] (m, rad), e' (m/s, rad/s), f = K e + C e' (N, N m), marker a's axes
      real(dp) :: deflection(6) = 0.0_dp, rate(6) = 0.0_dp, force(6) = 0.0_dp
   end type bushing_state_t

contains

   !> [body_a, body_b].
   pure function bushing_bodies(self) result(bodies)
      class(bushing_t), intent(in) :: self
      integer :: bodies(2)
      bodies = [self%body_a, self%body_b]
   end function bushing_bodies

   !> Generalized forces or tangents (force_element_t%terms); a non-finite force is a numeric
   !> error.
   subroutine bushing_terms(self, body_a, q_a, v_a, body_b, q_b, v_b, t, error, Q, K, C)
      class(bushing_t), intent(in) :: self
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), v_a(:), q_b(:), v_b(:), t
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(out), optional :: Q(:), K(:, :), C(:, :)
      type(bushing_state_t) :: state
      state = bushing_evaluate(self, body_a, q_a, v_a, body_b, q_b, v_b)
      if (.not. all(ieee_is_finite(state%force))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'bushing "' // trim(self%name) // &
            '": force not finite at t = ' // to_str(t) // ' s; a bushing needs finite marker ' &
            // 'frames')
      else if (present(K) .and. present(C)) then
         call bushing_tangents(self, body_a, q_a, v_a, body_b, q_b, v_b, K, C)
      else if (present(Q)) then
         Q = bushing_generalized_force(self, body_a, q_a, v_a, body_b, q_b, v_b)
      end if
   end subroutine bushing_terms

   !> Deflections, rates and force of `bushing` at the bodies' states (module header).
   pure function bushing_evaluate(bushing, body_a, q_a, v_a, body_b, q_b, v_b) result(state)
      !> The bushing
      type(bushing_t), intent(in) :: bushing
      !> Body a and its coordinates and velocities
      class(body_t), intent(in) :: body_a
      real(dp), intent(in) :: q_a(:), v_a(:)
      !> Body b and its coordinates and velocities
      class(body_t), intent(in) :: body_b
      real(dp), intent(in) :: q_b(:), v_b(:)
      type(bushing_state_t) :: state
      real(dp) :: E(6, size(q_a) + size(q_b))
      call deflection_and_jacobian(bushing, body_a, q_a, body_b, q_b, state%deflection, E)
      state%rate = matmul(E, [v_a, v_b])
      state%force = bushing%stiffness * state%deflection + bushing%damping * state%rate
   end function bushing_evaluate

   !> K = -dQ/dx (central differences) and C = -dQ/dv = E^T C E (exact), x = [q_a; q_b].
   pure subroutine bushing_tangents(bushing, body_a, q_a, v_a, body_b, q_b, v_b, K, C)
      !> The bushing
      type(bushing_t), intent(in) :: bushing
      !> Body a, its coordinates and velocities
      class(body_t), intent(in) :: body_a
      real(dp), intent(in) :: q_a(:), v_a(:)
      !> Body b, its coordinates and velocities
      class(body_t), intent(in) :: body_b
      real(dp), intent(in) :: q_b(:), v_b(:)
      !> -dQ/dx and -dQ/dv, (na + nb) x (na + nb)
      real(dp), intent(out) :: K(:, :), C(:, :)
      real(dp) :: E(6, size(q_a) + size(q_b)), e_value(6), x(size(q_a) + size(q_b))
      real(dp) :: plus(size(q_a) + size(q_b)), minus(size(q_a) + size(q_b)), step
      integer :: na, j
      na = size(q_a)
      call deflection_and_jacobian(bushing, body_a, q_a, body_b, q_b, e_value, E)
      do j = 1, size(x)
         C(:, j) = matmul(transpose(E), bushing%damping * E(:, j))
      end do
      x = [q_a, q_b]
      do j = 1, size(x)
         step = epsilon(1.0_dp)**(1.0_dp / 3.0_dp) * max(abs(x(j)), 1.0_dp)
         x(j) = x(j) + step
         plus = bushing_generalized_force(bushing, body_a, x(1:na), v_a, body_b, x(na + 1:), &
            v_b)
         x(j) = x(j) - 2.0_dp * step
         minus = bushing_generalized_force(bushing, body_a, x(1:na), v_a, body_b, x(na + 1:), &
            v_b)
         x(j) = x(j) + step
         K(:, j) = -(plus - minus) / (2.0_dp * step)
      end do
   end subroutine bushing_tangents

   !> Generalized forces Q = -E^T (K e + C E v) on body a (first size(q_a) rows) and body b.
   pure function bushing_generalized_force(bushing, body_a, q_a, v_a, body_b, q_b, v_b) result(Q)
      type(bushing_t), intent(in) :: bushing
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), v_a(:), q_b(:), v_b(:)
      real(dp) :: Q(size(q_a) + size(q_b))
      real(dp) :: E(6, size(q_a) + size(q_b)), e_value(6), f(6)
      call deflection_and_jacobian(bushing, body_a, q_a, body_b, q_b, e_value, E)
      f = bushing%stiffness * e_value + bushing%damping * matmul(E, [v_a, v_b])
      Q = -matmul(f, E)
   end function bushing_generalized_force

   !> e = [d; phi] and E with e' = E [v_a; v_b] (module header).
   pure subroutine deflection_and_jacobian(bushing, body_a, q_a, body_b, q_b, e_value, E)
      type(bushing_t), intent(in) :: bushing
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), q_b(:)
      real(dp), intent(out) :: e_value(6), E(:, :)
      real(dp) :: A_a(3, 3), A_b(3, 3), R(3, 3), gamma(3, 3), delta(3)
      integer :: na, i
      na = size(q_a)
      A_a = body_a%marker_orientation(q_a, bushing%marker_a)
      A_b = body_b%marker_orientation(q_b, bushing%marker_b)
      delta = body_b%marker_position(q_b, bushing%marker_b) - &
         body_a%marker_position(q_a, bushing%marker_a)
      R = matmul(transpose(A_a), A_b)
      e_value(1:3) = matmul(delta, A_a)
      e_value(4:6) = 0.5_dp * [R(3, 2) - R(2, 3), R(1, 3) - R(3, 1), R(2, 1) - R(1, 2)]
      gamma = -0.5_dp * R
      do i = 1, 3
         gamma(i, i) = gamma(i, i) + 0.5_dp * (R(1, 1) + R(2, 2) + R(3, 3))
      end do
      E = 0.0_dp
      if (na > 0) then
         E(1:3, 1:na) = matmul(transpose(A_a), -body_a%marker_velocity_jacobian(q_a, &
            bushing%marker_a) + matmul(skew3(delta), body_a%marker_rotation_jacobian(q_a, &
            bushing%marker_a)))
         E(4:6, 1:na) = -matmul(matmul(gamma, transpose(A_a)), &
            body_a%marker_rotation_jacobian(q_a, bushing%marker_a))
      end if
      if (size(q_b) > 0) then
         E(1:3, na + 1:) = matmul(transpose(A_a), body_b%marker_velocity_jacobian(q_b, &
            bushing%marker_b))
         E(4:6, na + 1:) = matmul(matmul(gamma, transpose(A_a)), &
            body_b%marker_rotation_jacobian(q_b, bushing%marker_b))
      end if
   end subroutine deflection_and_jacobian

end module ffrf_mbs_bushing
