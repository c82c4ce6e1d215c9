!> The rigid body `rigid_body_t` and the ground `ground_t`, two extensions of the abstract body
!> `body_t` (ffrf_mbs_body: coordinates, markers, mass matrix, quadratic velocity vector and
!> their tangents; theory.md sections 3 and 3.5). The reduced flexible body extends body_t too
!> (ffrf_mbs_flexible_body).
!>
!> Rigid body (Shabana, Dynamics of Multibody Systems, 3rd ed., ch. 3; Nikravesh 1988, ch. 6):
!> coordinates q = [R (3); theta (4 Euler parameters, ffrf_mbs_rotation)], R the global position
!> of the body reference point O (any point fixed in the body: the centre of mass, a joint
!> centre, ...). With the centre of mass chi (body frame, from O), the inertia tensor J_c about
!> the centre of mass and J_O = J_c + m (|chi|^2 I - chi chi^T) (parallel axes), the mass matrix
!> and quadratic velocity vector are those of theory.md 3.3/3.4 with no modes (Psi = 0):
!>     M = [[m I, -A m chi~ G_bar], [sym, G_bar^T J_O G_bar]]                         (7 x 7)
!>     f_v = [A w~ (m chi~) w; -G_bar^T w~ J_O w],  w = G_bar theta_dot (body frame)
!> (right-hand side of M v_dot = f_v + Q - C_q^T lambda). A marker at s_k (body frame, from O)
!> with frame C_k (body frame): r_k = R + A s_k, A_k = A C_k.
!>
!> Ground: no coordinates (num_coordinates = 0), markers at fixed global poses; its Jacobians
!> are 3 x 0, so a joint to ground is a joint to a body without unknowns.
!>
!> Tangents for the Newton iteration of a mechanism (body_t, per body, all n_b x n_b):
!> force_tangents, mass_stiffness, marker_hessian and marker_force_tangent. The rigid body
!> overrides body_t's central differences with exact forms (A(theta) is quadratic and G_bar
!> linear in theta, see rigid_* below) and gives marker_kinematics in one call; the ground keeps
!> the defaults (0 x 0 matrices).
module ffrf_mbs_rigid_body
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_dense, only: symmetric_eigen
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar, skew3, identity3, &
      rotated_vector_jacobian, cross3, euler_hessian
   use ffrf_mbs_body, only: body_t
   implicit none
   private
   public :: rigid_body_t, ground_t
   public :: point_load_tangent

   !> Rigid body: q = [R; theta], mass, centre of mass, inertia about it, markers.
   type, extends(body_t) :: rigid_body_t
      !> Mass m (kg)
      real(dp) :: mass = 0.0_dp
      !> Centre of mass chi in the body frame, from the reference point O (m)
      real(dp) :: center_of_mass(3) = 0.0_dp
      !> Inertia tensor J_c about the centre of mass, body frame (kg m^2)
      real(dp) :: inertia(3, 3) = 0.0_dp
      !> Inertia tensor J_O about the reference point O, body frame (kg m^2)
      real(dp) :: inertia_origin(3, 3) = 0.0_dp
      !> Marker positions s_k in the body frame, from O (3, num_markers) (m)
      real(dp), allocatable :: marker_xyz(:, :)
      !> Marker frames C_k in the body frame (3, 3, num_markers), columns = marker axes
      real(dp), allocatable :: marker_frames(:, :, :)
   contains
      procedure :: init => rigid_body_init
      procedure :: marker_position => rigid_marker_position
      procedure :: marker_orientation => rigid_marker_orientation
      procedure :: marker_velocity_jacobian => rigid_marker_velocity_jacobian
      procedure :: marker_position_jacobian => rigid_marker_position_jacobian
      procedure :: marker_rotation_jacobian => rigid_marker_rotation_jacobian
      procedure :: marker_axis_jacobian => rigid_marker_axis_jacobian
      procedure :: marker_generalized_force => rigid_marker_generalized_force
      procedure :: mass_matrix => rigid_mass_matrix
      procedure :: quadratic_velocity => rigid_quadratic_velocity
      procedure :: elastic_force => rigid_elastic_force
      procedure :: force_tangents => rigid_force_tangents
      procedure :: mass_stiffness => rigid_mass_stiffness
      procedure :: marker_hessian => rigid_marker_hessian
      procedure :: marker_force_tangent => rigid_marker_force_tangent
      procedure :: marker_kinematics => rigid_marker_kinematics
   end type rigid_body_t

   !> Ground: no coordinates, markers at fixed global poses.
   type, extends(body_t) :: ground_t
      !> Marker positions, global (3, num_markers) (m)
      real(dp), allocatable :: marker_xyz(:, :)
      !> Marker frames, global (3, 3, num_markers), columns = marker axes
      real(dp), allocatable :: marker_frames(:, :, :)
   contains
      procedure :: init => ground_init
      procedure :: marker_position => ground_marker_position
      procedure :: marker_orientation => ground_marker_orientation
      procedure :: marker_velocity_jacobian => ground_marker_jacobian
      procedure :: marker_position_jacobian => ground_marker_jacobian
      procedure :: marker_rotation_jacobian => ground_marker_jacobian
      procedure :: marker_axis_jacobian => ground_marker_axis_jacobian
      procedure :: marker_generalized_force => ground_marker_generalized_force
      procedure :: mass_matrix => ground_mass_matrix
      procedure :: quadratic_velocity => ground_state_vector
      procedure :: elastic_force => ground_state_vector
   end type ground_t


   !> Relative tolerance of the symmetry check of the inertia tensor, of the triangle
   !> inequalities of the principal moments and of the orthonormality of marker frames
   real(dp), parameter :: input_rtol = 1.0e-9_dp

contains

   ! ----------------------------------------------------------------------------------------------
   ! Rigid body

   !> Rigid body from its mass properties and markers. Checks: m > 0 and finite; J_c finite,
   !> symmetric, positive definite, and its principal moments J1 <= J2 <= J3 satisfy the triangle
   !> inequality J1 + J2 >= J3 (true of every mass distribution: J1 + J2 - J3 = 2 int rho z^2 dV
   !> in principal axes); marker frames orthonormal with det +1. Errors are FFRF_INPUT_ERROR
   !> naming the offending value.
   subroutine rigid_body_init(self, mass, center_of_mass, inertia, marker_xyz, marker_frames, &
         error)
      !> The body
      class(rigid_body_t), intent(out) :: self
      !> Mass m (kg)
      real(dp), intent(in) :: mass
      !> Centre of mass in the body frame, from the reference point O (m)
      real(dp), intent(in) :: center_of_mass(3)
      !> Inertia tensor J_c about the centre of mass, body frame (kg m^2)
      real(dp), intent(in) :: inertia(3, 3)
      !> Marker positions in the body frame, from O (3, num_markers) (m)
      real(dp), intent(in) :: marker_xyz(:, :)
      !> Marker frames in the body frame (3, 3, num_markers), columns = marker x, y, z axes
      real(dp), intent(in) :: marker_frames(:, :, :)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: where = 'rigid body: '
      real(dp) :: moments(3), vectors(3, 3), scale, chi(3)

      if (.not. (ieee_is_finite(mass) .and. mass > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'mass = ' // to_str(mass) // &
            ' kg; must be positive and finite')
         return
      end if
      if (.not. (all(ieee_is_finite(inertia)) .and. all(ieee_is_finite(center_of_mass)))) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'NaN or Inf in the inertia ' // &
            'tensor or the centre of mass')
         return
      end if
      scale = maxval(abs(inertia))
      if (maxval(abs(inertia - transpose(inertia))) > input_rtol * scale) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'inertia tensor is not symmetric: ' &
            // 'J(1,2) = ' // to_str(inertia(1, 2)) // ', J(2,1) = ' // to_str(inertia(2, 1)) // &
            ', J(1,3) = ' // to_str(inertia(1, 3)) // ', J(3,1) = ' // to_str(inertia(3, 1)) // &
            ', J(2,3) = ' // to_str(inertia(2, 3)) // ', J(3,2) = ' // to_str(inertia(3, 2)) // &
            ' kg m^2; give the products of inertia once for both triangles')
         return
      end if
      call symmetric_eigen(0.5_dp * (inertia + transpose(inertia)), moments, vectors, error)
      if (allocated(error)) return
      if (.not. moments(1) > 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'inertia tensor is not positive ' // &
            'definite: principal moments ' // principal_text(moments) // ' kg m^2; every ' // &
            'principal moment of a body with volume is positive (check signs of the products ' // &
            'of inertia and the units)')
         return
      end if
      if (moments(1) + moments(2) < moments(3) * (1.0_dp - input_rtol)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'principal moments of inertia ' // &
            principal_text(moments) // ' kg m^2 violate the triangle inequality J1 + J2 >= J3 (' &
            // to_str(moments(1) + moments(2)) // ' < ' // to_str(moments(3)) // '); no mass ' // &
            'distribution has this inertia: check the values, their axes and units')
         return
      end if
      self%num_coordinates = 7
      self%mass = mass
      self%center_of_mass = center_of_mass
      self%inertia = 0.5_dp * (inertia + transpose(inertia))
      chi = center_of_mass
      self%inertia_origin = self%inertia + mass * (dot_product(chi, chi) * identity3() - &
         spread(chi, 2, 3) * spread(chi, 1, 3))
      call set_markers(marker_xyz, marker_frames, where, self%num_markers, self%marker_xyz, &
         self%marker_frames, error)
   end subroutine rigid_body_init

   !> "(J1, J2, J3)" for messages.
   pure function principal_text(moments) result(text)
      real(dp), intent(in) :: moments(3)
      character(len=:), allocatable :: text
      text = '(' // to_str(moments(1)) // ', ' // to_str(moments(2)) // ', ' // &
         to_str(moments(3)) // ')'
   end function principal_text

   !> Check the marker positions ((3, n), finite) and frames (one per marker, orthonormal,
   !> det +1) and copy them; `where` starts the messages.
   subroutine set_markers(given_xyz, given, where, num_markers, xyz, frames, error)
      real(dp), intent(in) :: given_xyz(:, :)
      real(dp), intent(in) :: given(:, :, :)
      character(len=*), intent(in) :: where
      integer, intent(out) :: num_markers
      real(dp), allocatable, intent(out) :: xyz(:, :)
      real(dp), allocatable, intent(out) :: frames(:, :, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: C(3, 3), det
      integer :: k
      num_markers = size(given_xyz, 2)
      if (size(given_xyz, 1) /= 3 .or. .not. all(ieee_is_finite(given_xyz))) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'marker positions must be a (3, n) ' &
            // 'array of finite values; got ' // to_str(size(given_xyz, 1)) // ' rows')
         return
      end if
      xyz = given_xyz
      if (size(given, 1) /= 3 .or. size(given, 2) /= 3 .or. size(given, 3) /= num_markers) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'marker frames must be (3, 3, ' // &
            to_str(num_markers) // '), one per marker; got (' // to_str(size(given, 1)) // &
            ', ' // to_str(size(given, 2)) // ', ' // to_str(size(given, 3)) // ')')
         return
      end if
      do k = 1, num_markers
         C = given(:, :, k)
         det = dot_product(C(:, 1), matmul(skew3(C(:, 2)), C(:, 3)))
         if (.not. (maxval(abs(matmul(transpose(C), C) - identity3())) <= input_rtol .and. &
            det > 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'frame of marker ' // &
               to_str(k) // ' is not a rotation (max |C^T C - I| = ' // &
               to_str(maxval(abs(matmul(transpose(C), C) - identity3()))) // ', det = ' // &
               to_str(det) // '); give orthonormal right-handed axes as columns')
            return
         end if
      end do
      frames = given
   end subroutine set_markers

   !> r_k = R + A s_k (m).
   pure function rigid_marker_position(self, q, k) result(r)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      real(dp) :: r(3)
      real(dp) :: A(3, 3)
      A = euler_rotation(q(4:7))
      r = q(1:3) + matmul(A, self%marker_xyz(:, k))
   end function rigid_marker_position

   !> A_k = A C_k.
   pure function rigid_marker_orientation(self, q, k) result(frame)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      real(dp) :: frame(3, 3)
      real(dp) :: A(3, 3)
      A = euler_rotation(q(4:7))
      frame = matmul(A, self%marker_frames(:, :, k))
   end function rigid_marker_orientation

   !> L_r = [I, -A s_k~ G_bar] (3 x 7): r_k_dot = L_r v.
   pure function rigid_marker_velocity_jacobian(self, q, k) result(jac)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      jac(:, 1:3) = identity3()
      jac(:, 4:7) = -matmul(euler_rotation(q(4:7)), matmul(skew3(self%marker_xyz(:, k)), &
         euler_g_bar(q(4:7))))
   end function rigid_marker_velocity_jacobian

   !> dr_k/dq = [I, d(A s_k)/dtheta] (3 x 7), exact in all four Euler directions.
   pure function rigid_marker_position_jacobian(self, q, k) result(jac)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      jac(:, 1:3) = identity3()
      jac(:, 4:7) = rotated_vector_jacobian(q(4:7), self%marker_xyz(:, k))
   end function rigid_marker_position_jacobian

   !> L_w = [0, A G_bar] (3 x 7): omega_k = L_w v (global).
   pure function rigid_marker_rotation_jacobian(self, q, k) result(jac)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      real(dp) :: A(3, 3), G_bar(3, 4)
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      jac(:, 1:3) = 0.0_dp
      jac(:, 4:7) = matmul(A, G_bar)
      if (k < 1) jac = 0.0_dp     ! (k is in the common interface; every marker turns with A)
   end function rigid_marker_rotation_jacobian

   !> d(A C_k a)/dq = [0, d(A b)/dtheta], b = C_k a (3 x 7), exact in all four Euler directions.
   pure function rigid_marker_axis_jacobian(self, q, k, axis) result(jac)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Axis in the marker frame
      real(dp), intent(in) :: axis(3)
      real(dp) :: jac(3, self%num_coordinates)
      jac(:, 1:3) = 0.0_dp
      jac(:, 4:7) = rotated_vector_jacobian(q(4:7), matmul(self%marker_frames(:, :, k), axis))
   end function rigid_marker_axis_jacobian

   !> Q = L_r^T F + L_w^T M = [F; G_bar^T (s_k~ A^T F + A^T M)] (theory.md 3.5, Psi = 0).
   pure function rigid_marker_generalized_force(self, q, k, force, moment) result(gen)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Force, global components (N)
      real(dp), intent(in) :: force(3)
      !> Moment, global components (N m)
      real(dp), intent(in) :: moment(3)
      real(dp) :: gen(self%num_coordinates)
      real(dp) :: A(3, 3)
      A = euler_rotation(q(4:7))
      gen(1:3) = force
      gen(4:7) = matmul(transpose(euler_g_bar(q(4:7))), matmul(skew3(self%marker_xyz(:, k)), &
         matmul(transpose(A), force)) + matmul(transpose(A), moment))
   end function rigid_marker_generalized_force

   !> M = [[m I, -A m chi~ G_bar], [sym, G_bar^T J_O G_bar]] (theory.md 3.3 with Psi = 0).
   pure function rigid_mass_matrix(self, q) result(mass_matrix)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      real(dp) :: mass_matrix(self%num_coordinates, self%num_coordinates)
      real(dp) :: G_bar(3, 4)
      G_bar = euler_g_bar(q(4:7))
      mass_matrix = 0.0_dp
      mass_matrix(1:3, 1:3) = self%mass * identity3()
      mass_matrix(1:3, 4:7) = -self%mass * matmul(euler_rotation(q(4:7)), &
         matmul(skew3(self%center_of_mass), G_bar))
      mass_matrix(4:7, 1:3) = transpose(mass_matrix(1:3, 4:7))
      mass_matrix(4:7, 4:7) = matmul(transpose(G_bar), matmul(self%inertia_origin, G_bar))
   end function rigid_mass_matrix

   !> f_v = [A w~ (m chi~) w; -G_bar^T w~ J_O w], w = G_bar theta_dot (theory.md 3.4, Psi = 0):
   !> the centrifugal force -A w x (w x m chi) and the gyroscopic moment -w x J_O w.
   pure function rigid_quadratic_velocity(self, q, v) result(f)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Velocities [R_dot; theta_dot]
      real(dp), intent(in) :: v(:)
      real(dp) :: f(self%num_coordinates)
      real(dp) :: G_bar(3, 4), omega(3), w_skew(3, 3)
      G_bar = euler_g_bar(q(4:7))
      omega = matmul(G_bar, v(4:7))
      w_skew = skew3(omega)
      f(1:3) = matmul(euler_rotation(q(4:7)), matmul(w_skew, &
         matmul(skew3(self%mass * self%center_of_mass), omega)))
      f(4:7) = -matmul(transpose(G_bar), matmul(w_skew, matmul(self%inertia_origin, omega)))
   end function rigid_quadratic_velocity

   !> A rigid body has no elastic force: zeros.
   pure function rigid_elastic_force(self, q, v) result(f)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Velocities
      real(dp), intent(in) :: v(:)
      real(dp) :: f(self%num_coordinates)
      f = merge(0.0_dp, 0.0_dp, size(q) == size(v))    ! (q, v are in the common interface)
   end function rigid_elastic_force

   !> Marker kinematics of a rigid body in one call: r = R + A s_k, A C_k, [I, d(A s_k)/dtheta],
   !> [0, d(A C_k e_j)/dtheta].
   pure subroutine rigid_marker_kinematics(self, q, k, need_axes, position, orientation, &
         position_jacobian, axis_jacobian)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Which axis Jacobians to form (x, y, z)
      logical, intent(in) :: need_axes(3)
      !> Global position (m)
      real(dp), intent(out) :: position(3)
      !> Orientation, marker frame -> global
      real(dp), intent(out) :: orientation(3, 3)
      !> dr/dq (3 x 7)
      real(dp), intent(out) :: position_jacobian(:, :)
      !> d(A C_k e_j)/dq (3 x 7 x 3)
      real(dp), intent(inout) :: axis_jacobian(:, :, :)
      real(dp) :: A(3, 3)
      integer :: j
      A = euler_rotation(q(4:7))
      position = q(1:3) + matmul(A, self%marker_xyz(:, k))
      orientation = matmul(A, self%marker_frames(:, :, k))
      position_jacobian(:, 1:3) = identity3()
      position_jacobian(:, 4:7) = rotated_vector_jacobian(q(4:7), self%marker_xyz(:, k))
      do j = 1, 3
         if (.not. need_axes(j)) cycle
         axis_jacobian(:, 1:3, j) = 0.0_dp
         axis_jacobian(:, 4:7, j) = rotated_vector_jacobian(q(4:7), &
            self%marker_frames(:, j, k))
      end do
   end subroutine rigid_marker_kinematics

   !> Exact -df_v/dq and -df_v/dv (rigid_quadratic_velocity; no elastic force). With
   !> omega = G_bar(theta) theta_dot = -G_bar(theta_dot) theta (G_bar linear), c = m chi:
   !>     f1 = A g,       g = omega x (c x omega),  dg/domega = -(c x omega)~ + omega~ c~
   !>     f2 = -G_bar^T h, h = omega x J_O omega,   dh/domega = omega~ J_O - (J_O omega)~
   !> df1/dtheta = d(A g)/dtheta - A dg G_bar(theta_dot), df1/dtheta_dot = A dg G_bar,
   !> df2/dtheta = -B(h) + G_bar^T dh G_bar(theta_dot), df2/dtheta_dot = -G_bar^T dh G_bar,
   !> B(p) = d(G_bar(theta)^T p)/dtheta (g_bar_transpose_jacobian).
   pure subroutine rigid_force_tangents(self, q, v, K, C)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Velocities [R_dot; theta_dot]
      real(dp), intent(in) :: v(:)
      !> -df/dq (7 x 7)
      real(dp), intent(out) :: K(:, :)
      !> -df/dv (7 x 7)
      real(dp), intent(out) :: C(:, :)
      real(dp) :: G_bar(3, 4), G_dot(3, 4), A(3, 3), omega(3), cm(3), g(3), h(3)
      real(dp) :: dg(3, 3), dh(3, 3)
      G_bar = euler_g_bar(q(4:7))
      G_dot = euler_g_bar(v(4:7))
      A = euler_rotation(q(4:7))
      omega = matmul(G_bar, v(4:7))
      cm = self%mass * self%center_of_mass
      g = cross3(omega, cross3(cm, omega))
      dg = -skew3(cross3(cm, omega)) + matmul(skew3(omega), skew3(cm))
      h = cross3(omega, matmul(self%inertia_origin, omega))
      dh = matmul(skew3(omega), self%inertia_origin) - skew3(matmul(self%inertia_origin, omega))
      K = 0.0_dp
      C = 0.0_dp
      K(1:3, 4:7) = -(rotated_vector_jacobian(q(4:7), g) - matmul(A, matmul(dg, G_dot)))
      C(1:3, 4:7) = -matmul(A, matmul(dg, G_bar))
      K(4:7, 4:7) = g_bar_transpose_jacobian(h) - matmul(transpose(G_bar), matmul(dh, G_dot))
      C(4:7, 4:7) = matmul(transpose(G_bar), matmul(dh, G_bar))
   end subroutine rigid_force_tangents

   !> Exact d(M a)/dq (rigid_mass_matrix), alpha = G_bar a_theta = -G_bar(a_theta) theta:
   !>     rows 1:3 = -m A (chi x alpha):        d/dtheta = -m d(A (chi x alpha))/dtheta
   !>                                                      + m A chi~ G_bar(a_theta)
   !>     rows 4:7 = G_bar^T p, p = m chi~ A^T a_R + J_O alpha:
   !>                d/dtheta = B(p) + G_bar^T (m chi~ d(A^T a_R)/dtheta - J_O G_bar(a_theta)).
   pure subroutine rigid_mass_stiffness(self, q, a, K)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Acceleration held fixed
      real(dp), intent(in) :: a(:)
      !> d(M a)/dq (7 x 7)
      real(dp), intent(out) :: K(:, :)
      real(dp) :: G_bar(3, 4), G_a(3, 4), rot(3, 3), alpha(3), p(3), chi_skew(3, 3)
      G_bar = euler_g_bar(q(4:7))
      G_a = euler_g_bar(a(4:7))
      rot = euler_rotation(q(4:7))
      chi_skew = skew3(self%center_of_mass)
      alpha = matmul(G_bar, a(4:7))
      p = self%mass * matmul(chi_skew, matmul(transpose(rot), a(1:3))) + &
         matmul(self%inertia_origin, alpha)
      K = 0.0_dp
      K(1:3, 4:7) = -self%mass * rotated_vector_jacobian(q(4:7), &
         cross3(self%center_of_mass, alpha)) + self%mass * matmul(rot, matmul(chi_skew, G_a))
      K(4:7, 4:7) = g_bar_transpose_jacobian(p) + matmul(transpose(G_bar), &
         self%mass * matmul(chi_skew, transposed_rotation_jacobian(q(4:7), a(1:3))) - &
         matmul(self%inertia_origin, G_a))
   end subroutine rigid_mass_stiffness

   !> Exact Hessian of w_r . (R + A s_k) + sum_j w_j . A C_k e_j: only the theta-theta block,
   !> constant because A(theta) + I is a quadratic form in theta (euler_hessian).
   pure subroutine rigid_marker_hessian(self, q, k, w_position, w_axes, H)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Weight of the marker position (3)
      real(dp), intent(in) :: w_position(3)
      !> Weights of the marker axes (3 x 3, column j for axis j)
      real(dp), intent(in) :: w_axes(3, 3)
      !> The Hessian (7 x 7)
      real(dp), intent(out) :: H(:, :)
      real(dp) :: X(3, 3)
      integer :: i
      ! X = w_r s_k^T + W C_k^T: sum of the outer products w b^T of the terms w . A b
      X = matmul(w_axes, transpose(self%marker_frames(:, :, k)))
      do i = 1, 3
         X(:, i) = X(:, i) + w_position * self%marker_xyz(i, k)
      end do
      H = 0.0_dp
      H(4:7, 4:7) = euler_hessian(X)
      if (size(q) < 0) H = 0.0_dp     ! (q is in the common interface; H does not depend on it)
   end subroutine rigid_marker_hessian

   !> Exact d(L_r^T F + L_w^T M)/dq at fixed F, M: rows 4:7 are G_bar^T p with
   !> p = s_k~ A^T F + A^T M, so d/dtheta = B(p) + G_bar^T (s_k~ d(A^T F) + d(A^T M))/dtheta.
   pure subroutine rigid_marker_force_tangent(self, q, k, force, moment, tangent)
      class(rigid_body_t), intent(in) :: self
      !> Coordinates [R; theta]
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Force, global (N)
      real(dp), intent(in) :: force(3)
      !> Moment, global (N m)
      real(dp), intent(in) :: moment(3)
      !> The derivative (7 x 7)
      real(dp), intent(out) :: tangent(:, :)
      tangent = 0.0_dp
      tangent(4:7, 4:7) = point_load_tangent(q(4:7), self%marker_xyz(:, k), force, moment)
   end subroutine rigid_marker_force_tangent

   !> d/dtheta [G_bar^T (s~ A^T F + A^T M)] (4 x 4): the Euler rows of the generalized force of
   !> a force F at the body-fixed point s and a moment M (global), at fixed F and M.
   pure function point_load_tangent(theta, s, force, moment) result(jac)
      !> Euler parameters
      real(dp), intent(in) :: theta(4)
      !> Body-fixed point (m)
      real(dp), intent(in) :: s(3)
      !> Force, global (N)
      real(dp), intent(in) :: force(3)
      !> Moment, global (N m)
      real(dp), intent(in) :: moment(3)
      real(dp) :: jac(4, 4)
      real(dp) :: A(3, 3), p(3)
      A = euler_rotation(theta)
      p = cross3(s, matmul(transpose(A), force)) + matmul(transpose(A), moment)
      jac = g_bar_transpose_jacobian(p) + matmul(transpose(euler_g_bar(theta)), &
         matmul(skew3(s), transposed_rotation_jacobian(theta, force)) + &
         transposed_rotation_jacobian(theta, moment))
   end function point_load_tangent

   !> B(p) = d(G_bar(theta)^T p)/dtheta = 2 [[0, -p^T], [p, -p~]] (4 x 4; G_bar linear).
   pure function g_bar_transpose_jacobian(p) result(B)
      real(dp), intent(in) :: p(3)
      real(dp) :: B(4, 4)
      B(1, 1) = 0.0_dp
      B(1, 2:4) = -2.0_dp * p
      B(2:4, 1) = 2.0_dp * p
      B(2:4, 2:4) = -2.0_dp * skew3(p)
   end function g_bar_transpose_jacobian

   !> d(A(theta)^T x)/dtheta (3 x 4): A^T is A of the conjugate [e0, -e], so the derivative is
   !> rotated_vector_jacobian at the conjugate with the e columns negated.
   pure function transposed_rotation_jacobian(theta, x) result(jac)
      real(dp), intent(in) :: theta(4)
      real(dp), intent(in) :: x(3)
      real(dp) :: jac(3, 4)
      jac = rotated_vector_jacobian([theta(1), -theta(2:4)], x)
      jac(:, 2:4) = -jac(:, 2:4)
   end function transposed_rotation_jacobian

   ! ----------------------------------------------------------------------------------------------
   ! Ground

   !> Ground with markers at fixed global poses.
   subroutine ground_init(self, marker_xyz, marker_frames, error)
      !> The ground
      class(ground_t), intent(out) :: self
      !> Marker positions, global (3, num_markers) (m)
      real(dp), intent(in) :: marker_xyz(:, :)
      !> Marker frames, global (3, 3, num_markers), columns = marker axes
      real(dp), intent(in) :: marker_frames(:, :, :)
      type(error_t), allocatable, intent(out) :: error
      self%num_coordinates = 0
      call set_markers(marker_xyz, marker_frames, 'ground: ', self%num_markers, self%marker_xyz, &
         self%marker_frames, error)
   end subroutine ground_init

   !> Fixed global position of marker k.
   pure function ground_marker_position(self, q, k) result(r)
      class(ground_t), intent(in) :: self
      !> Coordinates (none)
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      real(dp) :: r(3)
      r = self%marker_xyz(:, k) + 0.0_dp * sum(q)
   end function ground_marker_position

   !> Fixed frame of marker k.
   pure function ground_marker_orientation(self, q, k) result(frame)
      class(ground_t), intent(in) :: self
      !> Coordinates (none)
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      real(dp) :: frame(3, 3)
      frame = self%marker_frames(:, :, k) + 0.0_dp * sum(q)
   end function ground_marker_orientation

   !> Jacobians of ground markers: 3 x 0.
   pure function ground_marker_jacobian(self, q, k) result(jac)
      class(ground_t), intent(in) :: self
      !> Coordinates (none)
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      jac = 0.0_dp * (sum(q) + k)
   end function ground_marker_jacobian

   !> Axis Jacobian of a ground marker: 3 x 0.
   pure function ground_marker_axis_jacobian(self, q, k, axis) result(jac)
      class(ground_t), intent(in) :: self
      !> Coordinates (none)
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Axis in the marker frame
      real(dp), intent(in) :: axis(3)
      real(dp) :: jac(3, self%num_coordinates)
      jac = 0.0_dp * (sum(q) + k + axis(1))
   end function ground_marker_axis_jacobian

   !> Generalized force on the ground: empty.
   pure function ground_marker_generalized_force(self, q, k, force, moment) result(gen)
      class(ground_t), intent(in) :: self
      !> Coordinates (none)
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Force (N)
      real(dp), intent(in) :: force(3)
      !> Moment (N m)
      real(dp), intent(in) :: moment(3)
      real(dp) :: gen(self%num_coordinates)
      gen = 0.0_dp * (sum(q) + k + force(1) + moment(1))
   end function ground_marker_generalized_force

   !> Mass matrix of the ground: 0 x 0.
   pure function ground_mass_matrix(self, q) result(mass_matrix)
      class(ground_t), intent(in) :: self
      !> Coordinates (none)
      real(dp), intent(in) :: q(:)
      real(dp) :: mass_matrix(self%num_coordinates, self%num_coordinates)
      mass_matrix = 0.0_dp * sum(q)
   end function ground_mass_matrix

   !> Forces on the ground: empty.
   pure function ground_state_vector(self, q, v) result(f)
      class(ground_t), intent(in) :: self
      !> Coordinates (none)
      real(dp), intent(in) :: q(:)
      !> Velocities (none)
      real(dp), intent(in) :: v(:)
      real(dp) :: f(self%num_coordinates)
      f = 0.0_dp * (sum(q) + sum(v))
   end function ground_state_vector

end module ffrf_mbs_rigid_body
