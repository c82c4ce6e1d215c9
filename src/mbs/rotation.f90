!> Euler parameters (unit quaternions) for the reference rotation of a body (theory.md section
!> 3.1; Nikravesh, Computer-Aided Analysis of Mechanical Systems, 1988, ch. 6; Shabana, Dynamics
!> of Multibody Systems, 3rd ed., ch. 2).
!>
!> theta = [e0, e1, e2, e3] = [cos(phi/2), sin(phi/2) n] for a rotation by phi about the unit
!> axis n; e = [e1, e2, e3]. Conventions (all functions pure):
!>
!>     A(theta) = (2 e0^2 - 1) I + 2 (e e^T + e0 e~)     body -> global, r = R + A x_bar
!>     G_bar    = 2 [-e, e0 I - e~]  (3 x 4)             omega_bar = G_bar theta_dot (body frame)
!>     G        = 2 [-e, e0 I + e~]  (3 x 4) = A G_bar   omega     = G theta_dot     (global)
!>
!> with a~ b = a x b. Identities used by the dynamics (valid for |theta| = 1):
!> G_bar theta = 0, G_bar G_bar^T = 4 I3, G_bar^T G_bar = 4 (I4 - theta theta^T),
!> G_bar(theta) theta_dot = -G_bar(theta_dot) theta, hence G_bar_dot theta_dot = 0.
!> The parameters are constrained by C_e = theta^T theta - 1 = 0 with Jacobian 2 theta^T; A is
!> the formula above also off the constraint (it is then not orthogonal).
module ffrf_mbs_rotation
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: euler_rotation, euler_g_bar, euler_g, euler_hessian, euler_constraint, &
      euler_constraint_jacobian
   public :: euler_from_rotation, euler_from_axis_angle, euler_normalized
   public :: rotated_vector_jacobian, rotation_vector_matrix, rotation_vector_tangent
   public :: frame_from_axis, rotation_defect, determinant3, check_rotation, ROTATION_TOLERANCE
   public :: skew3, axial3, identity3, cross3

   !> Largest |A A^T - I| of a rotation matrix given as input (&body and &marker orientation,
   !> marker frames)
   real(dp), parameter :: ROTATION_TOLERANCE = 1.0e-9_dp

contains

   !> skew3(a) b = a x b (3 x 3).
   pure function skew3(a) result(s)
      !> Vector a
      real(dp), intent(in) :: a(3)
      real(dp) :: s(3, 3)
      ! element by element: a reshape of a constructor costs a library call per use
      s(1, 1) = 0.0_dp
      s(2, 1) = a(3)
      s(3, 1) = -a(2)
      s(1, 2) = -a(3)
      s(2, 2) = 0.0_dp
      s(3, 2) = a(1)
      s(1, 3) = a(2)
      s(2, 3) = -a(1)
      s(3, 3) = 0.0_dp
   end function skew3

   !> Cross product a x b (= skew3(a) b).
   pure function cross3(a, b) result(c)
      !> Vectors a and b
      real(dp), intent(in) :: a(3), b(3)
      real(dp) :: c(3)
      c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
   end function cross3

   !> Axial vector of the skew-symmetric part of a 3 x 3 matrix: axial3(skew3(a)) = a.
   pure function axial3(s) result(a)
      !> Matrix (only its skew-symmetric part counts)
      real(dp), intent(in) :: s(3, 3)
      real(dp) :: a(3)
      a = 0.5_dp * [s(3, 2) - s(2, 3), s(1, 3) - s(3, 1), s(2, 1) - s(1, 2)]
   end function axial3

   !> The 3 x 3 identity.
   pure function identity3() result(eye)
      real(dp) :: eye(3, 3)
      eye = 0.0_dp
      eye(1, 1) = 1.0_dp
      eye(2, 2) = 1.0_dp
      eye(3, 3) = 1.0_dp
   end function identity3

   !> Rotation matrix A(theta) = (2 e0^2 - 1) I + 2 (e e^T + e0 e~) (theory.md 3.1).
   pure function euler_rotation(theta) result(A)
      !> Euler parameters [e0, e1, e2, e3]
      real(dp), intent(in) :: theta(4)
      real(dp) :: A(3, 3)
      real(dp) :: e(3)
      integer :: j
      e = theta(2:4)
      A = 2.0_dp * theta(1) * skew3(e)
      do j = 1, 3
         A(:, j) = A(:, j) + 2.0_dp * e(j) * e
         A(j, j) = A(j, j) + 2.0_dp * theta(1)**2 - 1.0_dp
      end do
   end function euler_rotation

   !> G_bar(theta) = 2 [-e, e0 I - e~] (3 x 4): body-frame angular velocity omega_bar = G_bar
   !> theta_dot (theory.md 3.1).
   pure function euler_g_bar(theta) result(G_bar)
      !> Euler parameters (or any 4-vector: G_bar is linear in its argument)
      real(dp), intent(in) :: theta(4)
      real(dp) :: G_bar(3, 4)
      G_bar(:, 1) = -2.0_dp * theta(2:4)
      G_bar(:, 2:4) = 2.0_dp * (theta(1) * identity3() - skew3(theta(2:4)))
   end function euler_g_bar

   !> G(theta) = 2 [-e, e0 I + e~] = A G_bar (3 x 4): global angular velocity omega = G theta_dot.
   pure function euler_g(theta) result(G)
      !> Euler parameters (or any 4-vector: G is linear in its argument)
      real(dp), intent(in) :: theta(4)
      real(dp) :: G(3, 4)
      G(:, 1) = -2.0_dp * theta(2:4)
      G(:, 2:4) = 2.0_dp * (theta(1) * identity3() + skew3(theta(2:4)))
   end function euler_g

   !> Hessian d^2(w^T A(theta) b)/dtheta^2 summed over terms, from X = sum w b^T (4 x 4): with
   !> A + I = 2 e0^2 I + 2 e e^T + 2 e0 e~ quadratic in theta, w^T (A + I) b = 2 e0^2 w.b
   !> + 2 (w.e)(e.b) + 2 e0 e.(b x w), hence H_00 = 4 tr X, H_ee = 2 (X + X^T),
   !> H_0e = 2 sum b x w = 4 axial(X).
   pure function euler_hessian(X) result(H)
      real(dp), intent(in) :: X(3, 3)
      real(dp) :: H(4, 4)
      H(1, 1) = 4.0_dp * (X(1, 1) + X(2, 2) + X(3, 3))
      H(2:4, 1) = 2.0_dp * [X(3, 2) - X(2, 3), X(1, 3) - X(3, 1), X(2, 1) - X(1, 2)]
      H(1, 2:4) = H(2:4, 1)
      H(2:4, 2:4) = 2.0_dp * (X + transpose(X))
   end function euler_hessian

   !> Normalisation constraint C_e = theta^T theta - 1.
   pure function euler_constraint(theta) result(c_e)
      !> Euler parameters
      real(dp), intent(in) :: theta(4)
      real(dp) :: c_e
      c_e = dot_product(theta, theta) - 1.0_dp
   end function euler_constraint

   !> Jacobian of the normalisation constraint, dC_e/dtheta = 2 theta^T (1 x 4, as a 4-vector).
   pure function euler_constraint_jacobian(theta) result(jac)
      !> Euler parameters
      real(dp), intent(in) :: theta(4)
      real(dp) :: jac(4)
      jac = 2.0_dp * theta
   end function euler_constraint_jacobian

   !> theta / |theta| (theta unchanged if it is zero).
   pure function euler_normalized(theta) result(unit)
      !> Euler parameters
      real(dp), intent(in) :: theta(4)
      real(dp) :: unit(4)
      real(dp) :: length
      length = norm2(theta)
      unit = theta
      if (length > 0.0_dp) unit = theta / length
   end function euler_normalized

   !> Euler parameters of a rotation by `angle` (rad) about `axis` (any non-zero length; a zero
   !> axis gives the identity): theta = [cos(angle/2), sin(angle/2) axis/|axis|].
   pure function euler_from_axis_angle(axis, angle) result(theta)
      !> Rotation axis (normalised here)
      real(dp), intent(in) :: axis(3)
      !> Rotation angle (rad), right-handed about axis
      real(dp), intent(in) :: angle
      real(dp) :: theta(4)
      real(dp) :: length
      length = norm2(axis)
      theta = [1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      if (.not. length > 0.0_dp) return
      theta = [cos(0.5_dp * angle), sin(0.5_dp * angle) * axis / length]
   end function euler_from_axis_angle

   !> Euler parameters of a rotation matrix (Shepperd 1978: the largest of e0^2..e3^2 is taken
   !> from the trace and the diagonal, the others from the off-diagonal sums; no loss of
   !> precision near 180 degrees). Returns e0 >= 0.
   pure function euler_from_rotation(A) result(theta)
      !> Proper orthogonal matrix
      real(dp), intent(in) :: A(3, 3)
      real(dp) :: theta(4)
      real(dp) :: t(4), s
      integer :: i
      t(1) = 1.0_dp + A(1, 1) + A(2, 2) + A(3, 3)
      t(2) = 1.0_dp + A(1, 1) - A(2, 2) - A(3, 3)
      t(3) = 1.0_dp - A(1, 1) + A(2, 2) - A(3, 3)
      t(4) = 1.0_dp - A(1, 1) - A(2, 2) + A(3, 3)
      i = maxloc(t, dim=1)
      s = 0.5_dp * sqrt(max(t(i), 0.0_dp))     ! = |theta(i)|, 4 theta(i)^2 = t(i)
      select case (i)
      case (1)
         theta = [s, (A(3, 2) - A(2, 3)), (A(1, 3) - A(3, 1)), (A(2, 1) - A(1, 2))] / (4.0_dp * s)
         theta(1) = s
      case (2)
         theta = [(A(3, 2) - A(2, 3)), s, (A(2, 1) + A(1, 2)), (A(1, 3) + A(3, 1))] / (4.0_dp * s)
         theta(2) = s
      case (3)
         theta = [(A(1, 3) - A(3, 1)), (A(2, 1) + A(1, 2)), s, (A(3, 2) + A(2, 3))] / (4.0_dp * s)
         theta(3) = s
      case default
         theta = [(A(2, 1) - A(1, 2)), (A(1, 3) + A(3, 1)), (A(3, 2) + A(2, 3)), s] / (4.0_dp * s)
         theta(4) = s
      end select
      if (theta(1) < 0.0_dp) theta = -theta
      theta = euler_normalized(theta)
   end function euler_from_rotation

   !> Exact partial derivative d(A(theta) b)/dtheta (3 x 4) of a rotated body-fixed vector b, in
   !> all four directions (the normalisation constraint is not used):
   !>     d(A b)/de0 = 4 e0 b + 2 e x b,    d(A b)/de = 2 [(e.b) I + e b^T - e0 b~].
   !> On |theta| = 1 and for tangent variations (theta^T dtheta = 0) it equals -A b~ G_bar; along
   !> theta itself it gives 2 (A + I) b (absorbed by the normalisation constraint's multiplier).
   pure function rotated_vector_jacobian(theta, b) result(jac)
      !> Euler parameters
      real(dp), intent(in) :: theta(4)
      !> Body-fixed vector
      real(dp), intent(in) :: b(3)
      real(dp) :: jac(3, 4)
      real(dp) :: e(3)
      integer :: j
      e = theta(2:4)
      jac(:, 1) = 4.0_dp * theta(1) * b + 2.0_dp * [e(2) * b(3) - e(3) * b(2), &
         e(3) * b(1) - e(1) * b(3), e(1) * b(2) - e(2) * b(1)]
      jac(:, 2:4) = -2.0_dp * theta(1) * skew3(b)
      do j = 1, 3
         jac(:, 1 + j) = jac(:, 1 + j) + 2.0_dp * b(j) * e
         jac(j, 1 + j) = jac(j, 1 + j) + 2.0_dp * dot_product(e, b)
      end do
   end function rotated_vector_jacobian

   !> Rotation matrix of a rotation vector phi (exponential map, Rodrigues):
   !> exp(phi~) = I + sin(a)/a phi~ + (1 - cos(a))/a^2 phi~^2, a = |phi| (series for small a).
   pure function rotation_vector_matrix(phi) result(R)
      !> Rotation vector (rad)
      real(dp), intent(in) :: phi(3)
      real(dp) :: R(3, 3)
      real(dp) :: s(3, 3), c1, c2
      call exp_coefficients(phi, c1, c2)
      s = skew3(phi)
      R = identity3() + c1 * s + c2 * matmul(s, s)
   end function rotation_vector_matrix

   !> Tangent operator T(phi) of the exponential map in the global (spatial) form:
   !> d(exp(phi~)) exp(phi~)^T = skew(T(phi) dphi), T = I + (1 - cos a)/a^2 phi~
   !> + (a - sin a)/a^3 phi~^2 (Bruls, Cardona, Arnold, Mech. Mach. Theory 48 (2012) 121, with
   !> the sign of the left-trivialised form). T(0) = I.
   pure function rotation_vector_tangent(phi) result(T)
      !> Rotation vector (rad)
      real(dp), intent(in) :: phi(3)
      real(dp) :: T(3, 3)
      real(dp) :: s(3, 3), a2, c2, c3
      a2 = dot_product(phi, phi)
      if (a2 < 1.0e-6_dp) then
         c2 = 0.5_dp - a2 / 24.0_dp + a2**2 / 720.0_dp
         c3 = 1.0_dp / 6.0_dp - a2 / 120.0_dp + a2**2 / 5040.0_dp
      else
         c2 = (1.0_dp - cos(sqrt(a2))) / a2
         c3 = (sqrt(a2) - sin(sqrt(a2))) / (a2 * sqrt(a2))
      end if
      s = skew3(phi)
      T = identity3() + c2 * s + c3 * matmul(s, s)
   end function rotation_vector_tangent

   !> sin(a)/a and (1 - cos a)/a^2 with their Taylor series below a^2 = 1e-6.
   pure subroutine exp_coefficients(phi, c1, c2)
      real(dp), intent(in) :: phi(3)
      real(dp), intent(out) :: c1, c2
      real(dp) :: a2
      a2 = dot_product(phi, phi)
      if (a2 < 1.0e-6_dp) then
         c1 = 1.0_dp - a2 / 6.0_dp + a2**2 / 120.0_dp
         c2 = 0.5_dp - a2 / 24.0_dp + a2**2 / 720.0_dp
      else
         c1 = sin(sqrt(a2)) / sqrt(a2)
         c2 = (1.0_dp - cos(sqrt(a2))) / a2
      end if
   end subroutine exp_coefficients

   !> The marker frame of a joint axis: z along the axis, x the unit projection of e_x (e_y if the
   !> axis is near e_x) normal to it, y = z x x (ffrf_app_mechanism_builder); frame_from_axis(e_z)
   !> = I.
   pure function frame_from_axis(axis) result(frame)
      real(dp), intent(in) :: axis(3)
      real(dp) :: frame(3, 3)
      real(dp) :: z(3), x(3), helper(3)
      z = axis / norm2(axis)
      helper = [1.0_dp, 0.0_dp, 0.0_dp]
      if (abs(z(1)) > 0.9_dp) helper = [0.0_dp, 1.0_dp, 0.0_dp]
      x = helper - dot_product(helper, z) * z
      x = x / norm2(x)
      frame(:, 1) = x
      frame(:, 2) = [z(2) * x(3) - z(3) * x(2), z(3) * x(1) - z(1) * x(3), &
         z(1) * x(2) - z(2) * x(1)]
      frame(:, 3) = z
   end function frame_from_axis

   !> Largest entry of |A A^T - I|: how far A is from orthonormal.
   pure real(dp) function rotation_defect(A) result(defect)
      real(dp), intent(in) :: A(3, 3)
      real(dp) :: product(3, 3)
      integer :: i
      product = matmul(A, transpose(A))
      do i = 1, 3
         product(i, i) = product(i, i) - 1.0_dp
      end do
      defect = maxval(abs(product))
   end function rotation_defect

   !> Determinant of a 3 x 3 matrix.
   pure real(dp) function determinant3(A) result(det)
      real(dp), intent(in) :: A(3, 3)
      det = A(1, 1) * (A(2, 2) * A(3, 3) - A(2, 3) * A(3, 2)) &
         - A(1, 2) * (A(2, 1) * A(3, 3) - A(2, 3) * A(3, 1)) &
         + A(1, 3) * (A(2, 1) * A(3, 2) - A(2, 2) * A(3, 1))
   end function determinant3

   !> An input error unless A is a rotation: |A A^T - I| <= ROTATION_TOLERANCE and det A > 0.
   !> `what` starts the one-line message (where the matrix was given).
   subroutine check_rotation(A, what, error)
      real(dp), intent(in) :: A(3, 3)
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      if (.not. rotation_defect(A) <= ROTATION_TOLERANCE) then
         call fatal_error(error, FFRF_INPUT_ERROR, what // ' is not orthonormal: largest ' // &
            '|A A^T - I| = ' // to_str(rotation_defect(A)) // ' > 1e-9 (give the rotation ' // &
            'matrix by rows, 9 reals, its columns the axes)')
      else if (.not. determinant3(A) > 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, what // ' has det = ' // &
            to_str(determinant3(A)) // ', a reflection, not a rotation (det must be +1: ' // &
            'right-handed axes)')
      end if
   end subroutine check_rotation

end module ffrf_mbs_rotation
