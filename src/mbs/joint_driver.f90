!> Drivers of joints: the relative angle of a revolute joint or the travel of a prismatic joint
!> prescribed over time, one rheonomic constraint row each (Nikravesh, Computer-Aided Analysis of
!> Mechanical Systems, 1988, ch. 7: driving constraints; docs/theory.md "3.7 Drivers of joints").
!> The mechanism (ffrf_mbs_mechanism) places the rows after the joints' and asks this module for
!> their terms; the prescribed coordinate is
!>     f(t) = offset + g(t)          (quantity = coordinate)
!>     f(t) = offset + int_0^t g     (quantity = rate: g prescribes the speed)
!> with g a time function (ffrf_mbs_time_function).
!>
!> Notation as ffrf_mbs_joints: r_a, r_b the joint's marker positions, x_a, y_a, z_a and x_b the
!> marker axes (global), z_a the joint axis.
!>
!> Revolute: the angle theta of x_b about z_a, measured from x_a (the joint_coordinate sensor).
!>     Phi = n(f) . x_b,  n(f) = cos f y_a - sin f x_a            (= sin(theta - f) on the joint)
!>     dPhi/dq_a = x_b^T (cos f Y_a - sin f X_a),  dPhi/dq_b = n^T X_b
!> with X = dx/dq the exact marker axis Jacobians (body_t marker_axis_jacobian);
!>     Phi_f = dPhi/df = n_f . x_b, n_f = -(cos f x_a + sin f y_a);  Phi_ff = -Phi.
!> Prismatic: the travel s = (r_b - r_a) . z_a.
!>     Phi = (r_b - r_a) . z_a - f,  dPhi/dq_a = -z_a^T P_a + d^T Z_a,  dPhi/dq_b = z_a^T P_b,
!>     Phi_f = -1, Phi_ff = 0 (P = dr/dq, Z = dz/dq exact, d = r_b - r_a).
!> Rheonomic terms (f' = df/dt): Phi_t = f' Phi_f, Phi_tt = f'' Phi_f + f'^2 Phi_ff,
!> Phi_qt = f' d(Phi_q)/df (analytic: the Jacobian with n_f in place of n; 0 for a prismatic).
!>
!> Driving torque or force. The constraint force -Phi_q^T lambda does on the joint coordinate the
!> generalized force -lambda dPhi/dtheta = -lambda cos(theta - f) (revolute) or -lambda
!> (prismatic); on the constraint (theta = f) the driver applies the torque (force)
!>     tau = -lambda
!> to body b about (along) z_a, and -tau to body a. Its power is lambda Phi_t = tau f' on the
!> constraint, the driver's term in the energy balance (ffrf_mbs_energy_balance).
!>
!> Second derivatives (driver_hessian): lambda d^2 Phi/dq^2 from the bodies' marker_hessian and
!> the products of the exact marker Jacobians (exact for rigid bodies and the ground; for a
!> flexible body as exact as its marker_hessian), the Newton tangent of the row, and with
!> lambda = 1 the convective term (Phi_q v)_q v = v^T (d^2 Phi/dq^2) v of the acceleration
!> right-hand side.
module ffrf_mbs_joint_driver
   use ffrf_core_kinds, only: dp
   use ffrf_mbs_body, only: body_t
   use ffrf_mbs_joints, only: JOINT_REVOLUTE, JOINT_PRISMATIC
   use ffrf_mbs_time_function, only: time_function_t
   implicit none
   private
   public :: joint_driver_t, driver_terms, driver_hessian, driver_coordinate

   !> A driver of one joint (module header).
   type :: joint_driver_t
      !> Name for messages and output
      character(len=64) :: name = 'driver'
      !> Mechanism joint number (order of add_joint)
      integer :: joint = 0
      !> JOINT_REVOLUTE or JOINT_PRISMATIC (set by mechanism_t%add_driver)
      integer :: kind = 0
      !> The time function g
      type(time_function_t) :: law
      !> .true.: g prescribes the rate (f = offset + int_0^t g); .false.: the coordinate
      logical :: rate = .false.
      !> Coordinate at t = 0 added to g or its integral (rad or m)
      real(dp) :: offset = 0.0_dp
      !> Its constraint row (set by the mechanism's layout)
      integer :: row = 0
   contains
      !> [f, f', f''] at t
      procedure :: prescribed => driver_prescribed
   end type joint_driver_t

contains

   !> [f, f', f''] at t (module header).
   pure function driver_prescribed(self, t) result(f)
      class(joint_driver_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      real(dp) :: f(3)
      real(dp) :: g(3)
      g = self%law%evaluate(t)
      if (self%rate) then
         f = [self%offset + self%law%integral(t), g(1), g(2)]
      else
         f = [self%offset + g(1), g(2), g(3)]
      end if
   end function driver_prescribed

   !> Phi, dPhi/dq_a, dPhi/dq_b at the prescribed value f and their derivatives in f (module
   !> header): phi_f = dPhi/df, phi_ff = d^2 Phi/df^2, jac_a_f, jac_b_f = d(Phi_q)/df.
   pure subroutine driver_terms(kind, body_a, q_a, marker_a, body_b, q_b, marker_b, f, phi, &
         jac_a, jac_b, phi_f, phi_ff, jac_a_f, jac_b_f)
      !> JOINT_REVOLUTE or JOINT_PRISMATIC
      integer, intent(in) :: kind
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), q_b(:)
      integer, intent(in) :: marker_a, marker_b
      !> Prescribed angle (rad) or travel (m)
      real(dp), intent(in) :: f
      real(dp), intent(out) :: phi, phi_f, phi_ff
      !> Rows dPhi/dq (body_a%num_coordinates, body_b%num_coordinates) and their f-derivatives
      real(dp), intent(out) :: jac_a(:), jac_b(:), jac_a_f(:), jac_b_f(:)
      real(dp) :: frame_a(3, 3), frame_b(3, 3), n(3), n_f(3), d(3)
      real(dp) :: x_jac_a(3, size(q_a)), y_jac_a(3, size(q_a)), x_jac_b(3, size(q_b))
      frame_a = body_a%marker_orientation(q_a, marker_a)
      frame_b = body_b%marker_orientation(q_b, marker_b)
      jac_a_f = 0.0_dp
      jac_b_f = 0.0_dp
      if (kind == JOINT_REVOLUTE) then
         n = cos(f) * frame_a(:, 2) - sin(f) * frame_a(:, 1)
         n_f = -(cos(f) * frame_a(:, 1) + sin(f) * frame_a(:, 2))
         phi = dot_product(n, frame_b(:, 1))
         phi_f = dot_product(n_f, frame_b(:, 1))
         phi_ff = -phi
         if (size(q_a) > 0) then
            x_jac_a = body_a%marker_axis_jacobian(q_a, marker_a, [1.0_dp, 0.0_dp, 0.0_dp])
            y_jac_a = body_a%marker_axis_jacobian(q_a, marker_a, [0.0_dp, 1.0_dp, 0.0_dp])
            jac_a = matmul(frame_b(:, 1), cos(f) * y_jac_a - sin(f) * x_jac_a)
            jac_a_f = -matmul(frame_b(:, 1), sin(f) * y_jac_a + cos(f) * x_jac_a)
         end if
         if (size(q_b) > 0) then
            x_jac_b = body_b%marker_axis_jacobian(q_b, marker_b, [1.0_dp, 0.0_dp, 0.0_dp])
            jac_b = matmul(n, x_jac_b)
            jac_b_f = matmul(n_f, x_jac_b)
         end if
      else
         d = body_b%marker_position(q_b, marker_b) - body_a%marker_position(q_a, marker_a)
         phi = dot_product(d, frame_a(:, 3)) - f
         phi_f = -1.0_dp
         phi_ff = 0.0_dp
         if (size(q_a) > 0) jac_a = -matmul(frame_a(:, 3), &
            body_a%marker_position_jacobian(q_a, marker_a)) + matmul(d, &
            body_a%marker_axis_jacobian(q_a, marker_a, [0.0_dp, 0.0_dp, 1.0_dp]))
         if (size(q_b) > 0) jac_b = matmul(frame_a(:, 3), &
            body_b%marker_position_jacobian(q_b, marker_b))
      end if
   end subroutine driver_terms

   !> The joint coordinate (theta in (-pi, pi], or the travel s) and its rate at (q, v).
   pure subroutine driver_coordinate(kind, body_a, q_a, v_a, marker_a, body_b, q_b, v_b, &
         marker_b, coordinate, rate)
      integer, intent(in) :: kind
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), v_a(:), q_b(:), v_b(:)
      integer, intent(in) :: marker_a, marker_b
      real(dp), intent(out) :: coordinate, rate
      real(dp) :: frame_a(3, 3), frame_b(3, 3), phi, phi_f, phi_ff
      real(dp) :: jac_a(size(q_a)), jac_b(size(q_b)), jac_a_f(size(q_a)), jac_b_f(size(q_b))
      frame_a = body_a%marker_orientation(q_a, marker_a)
      frame_b = body_b%marker_orientation(q_b, marker_b)
      if (kind == JOINT_REVOLUTE) then
         coordinate = atan2(dot_product(frame_a(:, 2), frame_b(:, 1)), &
            dot_product(frame_a(:, 1), frame_b(:, 1)))
      else
         coordinate = dot_product(body_b%marker_position(q_b, marker_b) - &
            body_a%marker_position(q_a, marker_a), frame_a(:, 3))
      end if
      ! At f = coordinate, dPhi/dq is d(coordinate)/dq (revolute: cos(theta - f) = 1)
      call driver_terms(kind, body_a, q_a, marker_a, body_b, q_b, marker_b, coordinate, phi, &
         jac_a, jac_b, phi_f, phi_ff, jac_a_f, jac_b_f)
      rate = dot_product(jac_a, v_a) + dot_product(jac_b, v_b)
   end subroutine driver_coordinate

   !> lambda d^2 Phi/dq^2 as blocks (a, a), (a, b), (b, b) (module header), from the bodies'
   !> marker_hessian and products of the exact marker Jacobians, as ffrf_mbs_joints forms its
   !> perpendicular (revolute) and lateral (prismatic) equations.
   pure subroutine driver_hessian(kind, body_a, q_a, marker_a, body_b, q_b, marker_b, f, lambda, &
         K_aa, K_ab, K_bb)
      integer, intent(in) :: kind
      class(body_t), intent(in) :: body_a, body_b
      real(dp), intent(in) :: q_a(:), q_b(:)
      integer, intent(in) :: marker_a, marker_b
      real(dp), intent(in) :: f, lambda
      real(dp), intent(out) :: K_aa(:, :), K_ab(:, :), K_bb(:, :)
      real(dp) :: r_a(3), r_b(3), frame_a(3, 3), frame_b(3, 3), d(3)
      real(dp) :: pos_a(3, size(q_a)), pos_b(3, size(q_b))
      real(dp) :: axis_a(3, size(q_a), 3), axis_b(3, size(q_b), 3)
      real(dp) :: wr_a(3), wr_b(3), wx_a(3, 3), wx_b(3, 3)
      logical :: need_a(3), need_b(3)
      need_a = [kind == JOINT_REVOLUTE, kind == JOINT_REVOLUTE, kind == JOINT_PRISMATIC]
      need_b = [kind == JOINT_REVOLUTE, .false., .false.]
      axis_a = 0.0_dp
      axis_b = 0.0_dp
      call body_a%marker_kinematics(q_a, marker_a, need_a, r_a, frame_a, pos_a, axis_a)
      call body_b%marker_kinematics(q_b, marker_b, need_b, r_b, frame_b, pos_b, axis_b)
      wr_a = 0.0_dp
      wr_b = 0.0_dp
      wx_a = 0.0_dp
      wx_b = 0.0_dp
      if (kind == JOINT_REVOLUTE) then
         ! lambda (cos f y_a - sin f x_a) . x_b
         wx_a(:, 1) = -lambda * sin(f) * frame_b(:, 1)
         wx_a(:, 2) = lambda * cos(f) * frame_b(:, 1)
         wx_b(:, 1) = lambda * (cos(f) * frame_a(:, 2) - sin(f) * frame_a(:, 1))
         K_aa = 0.0_dp
         K_ab = lambda * matmul(transpose(cos(f) * axis_a(:, :, 2) - sin(f) * axis_a(:, :, 1)), &
            axis_b(:, :, 1))
      else
         ! lambda z_a . (r_b - r_a)
         d = r_b - r_a
         wx_a(:, 3) = lambda * d
         wr_a = -lambda * frame_a(:, 3)
         wr_b = lambda * frame_a(:, 3)
         K_aa = -lambda * (matmul(transpose(axis_a(:, :, 3)), pos_a) + &
            matmul(transpose(pos_a), axis_a(:, :, 3)))
         K_ab = lambda * matmul(transpose(axis_a(:, :, 3)), pos_b)
      end if
      K_bb = 0.0_dp
      if (size(q_a) > 0) then
         block
            real(dp) :: hess(size(q_a), size(q_a))
            call body_a%marker_hessian(q_a, marker_a, wr_a, wx_a, hess)
            K_aa = K_aa + hess
         end block
      end if
      if (size(q_b) > 0) call body_b%marker_hessian(q_b, marker_b, wr_b, wx_b, K_bb)
   end subroutine driver_hessian

end module ffrf_mbs_joint_driver
