!> Bodies as the joints and the mechanism see them: an abstract `body_t` (coordinates, markers,
!> mass matrix, quadratic velocity vector), the rigid body `rigid_body_t`, the ground `ground_t`
!> and `flexible_body_adapter_t`, a thin wrapper that gives a reduced flexible body
!> (ffrf_mbs_flexible_body) the same interface, so that a joint or a mechanism loops over bodies
!> without knowing their kind (theory.md sections 3 and 3.5).
!>
!> Markers. Every body carries numbered markers k = 1..num_markers, each a point with an
!> orthonormal frame: global position r_k(q) and orientation A_k(q) (marker frame -> global;
!> its columns are the marker's x, y, z axes in global components). The marker procedures have
!> the names and argument lists of flexible_body_t (marker_position(q, k), ...), so the adapter
!> only forwards.
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
!> force_tangents (-d(f_v + Q_e)/dq, -d(f_v + Q_e)/dv), mass_stiffness (d(M a)/dq at fixed a),
!> marker_hessian (d^2/dq^2 of w_r . r_k + sum_j w_j . A_k e_j, for the joints' constraint
!> stiffness) and marker_force_tangent (d(L_r^T F + L_w^T M)/dq at fixed F, M). The body_t
!> defaults are central differences over the body's own coordinates (fd_step, cheap: per body);
!> the rigid body overrides all four with exact forms (A(theta) is quadratic and G_bar linear in
!> theta, see rigid_* below); the flexible adapter forwards to flexible_body_t's forms: exact
!> quadratic-velocity tangents, modal stiffness and damping, and mass stiffness; marker Hessian
!> and marker force tangent exact but for the second derivative of the exponential map of the
!> marker rotation (a 3 x 3 central difference in the rotation vector). marker_kinematics gives a
!> marker's position, orientation and Jacobians in one call (the joints use it).
module ffrf_mbs_rigid_body
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_dense, only: symmetric_eigen
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar, skew3, identity3, &
      rotated_vector_jacobian
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_dae_system, only: fd_step
   implicit none
   private
   public :: body_t, rigid_body_t, ground_t, flexible_body_adapter_t
   public :: euler_hessian, point_load_tangent

   !> A body with num_coordinates generalized coordinates and num_markers markers.
   type, abstract :: body_t
      !> Number of generalized coordinates (7 rigid, 7 + m flexible, 0 ground)
      integer :: num_coordinates = 0
      !> Number of markers
      integer :: num_markers = 0
   contains
      !> Global position of marker k (m)
      procedure(body_marker_vector), deferred :: marker_position
      !> Orientation of marker k, marker frame -> global (columns: marker axes)
      procedure(body_marker_frame), deferred :: marker_orientation
      !> L_r: marker velocity = L_r v (3 x num_coordinates)
      procedure(body_marker_jacobian), deferred :: marker_velocity_jacobian
      !> Exact partial derivatives dr_k/dq (3 x num_coordinates), all Euler directions
      procedure(body_marker_jacobian), deferred :: marker_position_jacobian
      !> L_w: marker angular velocity (global) = L_w v (3 x num_coordinates)
      procedure(body_marker_jacobian), deferred :: marker_rotation_jacobian
      !> Exact partial derivatives d(A_k a)/dq of a marker-fixed axis a (3 x num_coordinates)
      procedure(body_axis_jacobian), deferred :: marker_axis_jacobian
      !> Generalized force L_r^T F + L_w^T M of a global force and moment at marker k
      procedure(body_marker_force), deferred :: marker_generalized_force
      !> Mass matrix M(q) (num_coordinates x num_coordinates)
      procedure(body_mass_matrix), deferred :: mass_matrix
      !> Quadratic velocity vector f_v(q, v) (right-hand side)
      procedure(body_state_vector), deferred :: quadratic_velocity
      !> Elastic and damping generalized force (right-hand side; zero for rigid bodies)
      procedure(body_state_vector), deferred :: elastic_force
      !> Kinetic energy v^T M(q) v / 2 (J)
      procedure :: kinetic_energy => body_kinetic_energy
      !> -d(f_v + Q_e)/dq and -d(f_v + Q_e)/dv (default: central differences per body)
      procedure :: force_tangents => body_force_tangents_fd
      !> d(M(q) a)/dq at fixed a (default: central differences per body)
      procedure :: mass_stiffness => body_mass_stiffness_fd
      !> d^2/dq^2 [w_r . r_k + sum_j w_axes(:, j) . A_k e_j] (default: differences of the
      !> exact marker Jacobians)
      procedure :: marker_hessian => body_marker_hessian_fd
      !> d(marker_generalized_force)/dq at a fixed force and moment (default: differences)
      procedure :: marker_force_tangent => body_marker_force_tangent_fd
      !> Position, orientation and the exact position and axis Jacobians of marker k in one
      !> call (for the joints; bodies override it to share the work)
      procedure :: marker_kinematics => body_marker_kinematics
   end type body_t

   abstract interface
      !> A 3-vector of marker k.
      pure function body_marker_vector(self, q, k) result(r)
         import :: body_t, dp
         implicit none
         !> The body
         class(body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Marker number, 1..num_markers
         integer, intent(in) :: k
         real(dp) :: r(3)
      end function body_marker_vector

      !> A 3 x 3 frame of marker k.
      pure function body_marker_frame(self, q, k) result(frame)
         import :: body_t, dp
         implicit none
         !> The body
         class(body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Marker number, 1..num_markers
         integer, intent(in) :: k
         real(dp) :: frame(3, 3)
      end function body_marker_frame

      !> A 3 x num_coordinates Jacobian of marker k.
      pure function body_marker_jacobian(self, q, k) result(jac)
         import :: body_t, dp
         implicit none
         !> The body
         class(body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Marker number, 1..num_markers
         integer, intent(in) :: k
         real(dp) :: jac(3, self%num_coordinates)
      end function body_marker_jacobian

      !> d(A_k a)/dq for a marker-fixed axis a.
      pure function body_axis_jacobian(self, q, k, axis) result(jac)
         import :: body_t, dp
         implicit none
         !> The body
         class(body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Marker number, 1..num_markers
         integer, intent(in) :: k
         !> Axis in the marker frame
         real(dp), intent(in) :: axis(3)
         real(dp) :: jac(3, self%num_coordinates)
      end function body_axis_jacobian

      !> Generalized force of a global force and moment at marker k.
      pure function body_marker_force(self, q, k, force, moment) result(gen)
         import :: body_t, dp
         implicit none
         !> The body
         class(body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Marker number, 1..num_markers
         integer, intent(in) :: k
         !> Force, global components (N)
         real(dp), intent(in) :: force(3)
         !> Moment, global components (N m)
         real(dp), intent(in) :: moment(3)
         real(dp) :: gen(self%num_coordinates)
      end function body_marker_force

      !> Mass matrix M(q).
      pure function body_mass_matrix(self, q) result(mass_matrix)
         import :: body_t, dp
         implicit none
         !> The body
         class(body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         real(dp) :: mass_matrix(self%num_coordinates, self%num_coordinates)
      end function body_mass_matrix

      !> A generalized force of the state (q, v).
      pure function body_state_vector(self, q, v) result(f)
         import :: body_t, dp
         implicit none
         !> The body
         class(body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Velocities dq/dt
         real(dp), intent(in) :: v(:)
         real(dp) :: f(self%num_coordinates)
      end function body_state_vector
   end interface

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

   !> A reduced flexible body seen as a body_t: markers = its interfaces (virtual nodes). Holds a
   !> copy of the flexible body (the invariants are small: O(m^2)).
   type, extends(body_t) :: flexible_body_adapter_t
      !> The flexible body
      type(flexible_body_t) :: flexible
   contains
      procedure :: init => adapter_init
      procedure :: marker_position => adapter_marker_position
      procedure :: marker_orientation => adapter_marker_orientation
      procedure :: marker_velocity_jacobian => adapter_marker_velocity_jacobian
      procedure :: marker_position_jacobian => adapter_marker_position_jacobian
      procedure :: marker_rotation_jacobian => adapter_marker_rotation_jacobian
      procedure :: marker_axis_jacobian => adapter_marker_axis_jacobian
      procedure :: marker_generalized_force => adapter_marker_generalized_force
      procedure :: mass_matrix => adapter_mass_matrix
      procedure :: quadratic_velocity => adapter_quadratic_velocity
      procedure :: elastic_force => adapter_elastic_force
      procedure :: force_tangents => adapter_force_tangents
      procedure :: marker_hessian => adapter_marker_hessian
      procedure :: marker_force_tangent => adapter_marker_force_tangent
      procedure :: mass_stiffness => adapter_mass_stiffness
      procedure :: marker_kinematics => adapter_marker_kinematics
   end type flexible_body_adapter_t

   !> Relative tolerance of the symmetry check of the inertia tensor, of the triangle
   !> inequalities of the principal moments and of the orthonormality of marker frames
   real(dp), parameter :: input_rtol = 1.0e-9_dp

contains

   !> Kinetic energy v^T M(q) v / 2 (J).
   pure function body_kinetic_energy(self, q, v) result(energy)
      !> The body
      class(body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Velocities
      real(dp), intent(in) :: v(:)
      real(dp) :: energy
      real(dp) :: mass_matrix(self%num_coordinates, self%num_coordinates)
      mass_matrix = self%mass_matrix(q)
      energy = 0.5_dp * dot_product(v, matmul(mass_matrix, v))
   end function body_kinetic_energy

   !> Marker k: position r, orientation (columns: axes), dr/dq and, for the axes j with
   !> need_axes(j), d(A_k e_j)/dq in axis_jacobian(:, :, j) (others untouched); from the
   !> separate marker procedures.
   pure subroutine body_marker_kinematics(self, q, k, need_axes, position, orientation, &
         position_jacobian, axis_jacobian)
      !> The body
      class(body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Which axis Jacobians to form (x, y, z)
      logical, intent(in) :: need_axes(3)
      !> Global position (m)
      real(dp), intent(out) :: position(3)
      !> Orientation, marker frame -> global
      real(dp), intent(out) :: orientation(3, 3)
      !> dr/dq (3 x n_b)
      real(dp), intent(out) :: position_jacobian(:, :)
      !> d(A_k e_j)/dq (3 x n_b x 3)
      real(dp), intent(inout) :: axis_jacobian(:, :, :)
      real(dp), parameter :: unit_axes(3, 3) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
      integer :: j
      position = self%marker_position(q, k)
      orientation = self%marker_orientation(q, k)
      position_jacobian = self%marker_position_jacobian(q, k)
      do j = 1, 3
         if (need_axes(j)) axis_jacobian(:, :, j) = self%marker_axis_jacobian(q, k, &
            unit_axes(:, j))
      end do
   end subroutine body_marker_kinematics

   !> -d(f_v + Q_e)/dq, -d(f_v + Q_e)/dv by central differences over the body's coordinates.
   pure subroutine body_force_tangents_fd(self, q, v, K, C)
      !> The body
      class(body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Velocities
      real(dp), intent(in) :: v(:)
      !> -df/dq (n_b x n_b)
      real(dp), intent(out) :: K(:, :)
      !> -df/dv (n_b x n_b)
      real(dp), intent(out) :: C(:, :)
      real(dp) :: x(size(q)), f_plus(size(q)), f_minus(size(q)), delta
      integer :: j
      x = q
      do j = 1, size(q)
         delta = fd_step(q(j))
         x(j) = q(j) + delta
         f_plus = self%quadratic_velocity(x, v) + self%elastic_force(x, v)
         x(j) = q(j) - delta
         f_minus = self%quadratic_velocity(x, v) + self%elastic_force(x, v)
         x(j) = q(j)
         K(:, j) = -(f_plus - f_minus) / (2.0_dp * delta)
      end do
      x = v
      do j = 1, size(v)
         delta = fd_step(v(j))
         x(j) = v(j) + delta
         f_plus = self%quadratic_velocity(q, x) + self%elastic_force(q, x)
         x(j) = v(j) - delta
         f_minus = self%quadratic_velocity(q, x) + self%elastic_force(q, x)
         x(j) = v(j)
         C(:, j) = -(f_plus - f_minus) / (2.0_dp * delta)
      end do
   end subroutine body_force_tangents_fd

   !> d(M(q) a)/dq by central differences over the body's coordinates.
   pure subroutine body_mass_stiffness_fd(self, q, a, K)
      !> The body
      class(body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Acceleration held fixed
      real(dp), intent(in) :: a(:)
      !> d(M a)/dq (n_b x n_b)
      real(dp), intent(out) :: K(:, :)
      real(dp) :: x(size(q)), delta
      integer :: j
      x = q
      do j = 1, size(q)
         delta = fd_step(q(j))
         x(j) = q(j) + delta
         K(:, j) = matmul(self%mass_matrix(x), a)
         x(j) = q(j) - delta
         K(:, j) = (K(:, j) - matmul(self%mass_matrix(x), a)) / (2.0_dp * delta)
         x(j) = q(j)
      end do
   end subroutine body_mass_stiffness_fd

   !> Hessian of w_r . r_k + sum_j w_axes(:, j) . A_k e_j by central differences of the exact
   !> marker Jacobians (marker_position_jacobian, marker_axis_jacobian).
   pure subroutine body_marker_hessian_fd(self, q, k, w_position, w_axes, H)
      !> The body
      class(body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Weight of the marker position (3)
      real(dp), intent(in) :: w_position(3)
      !> Weights of the marker axes x, y, z (3 x 3, column j for axis j)
      real(dp), intent(in) :: w_axes(3, 3)
      !> The Hessian (n_b x n_b)
      real(dp), intent(out) :: H(:, :)
      real(dp) :: x(size(q)), delta
      integer :: j
      x = q
      do j = 1, size(q)
         delta = fd_step(q(j))
         x(j) = q(j) + delta
         H(:, j) = weighted_gradient(x)
         x(j) = q(j) - delta
         H(:, j) = (H(:, j) - weighted_gradient(x)) / (2.0_dp * delta)
         x(j) = q(j)
      end do
      H = 0.5_dp * (H + transpose(H))
   contains
      pure function weighted_gradient(y) result(g)
         real(dp), intent(in) :: y(:)
         real(dp) :: g(size(y))
         real(dp), parameter :: unit_axes(3, 3) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
            1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
         integer :: i
         g = matmul(w_position, self%marker_position_jacobian(y, k))
         do i = 1, 3
            if (any(w_axes(:, i) /= 0.0_dp)) g = g + matmul(w_axes(:, i), &
               self%marker_axis_jacobian(y, k, unit_axes(:, i)))
         end do
      end function weighted_gradient
   end subroutine body_marker_hessian_fd

   !> d(L_r^T F + L_w^T M)/dq at fixed F, M by central differences.
   pure subroutine body_marker_force_tangent_fd(self, q, k, force, moment, tangent)
      !> The body
      class(body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Marker number
      integer, intent(in) :: k
      !> Force, global (N)
      real(dp), intent(in) :: force(3)
      !> Moment, global (N m)
      real(dp), intent(in) :: moment(3)
      !> The derivative (n_b x n_b)
      real(dp), intent(out) :: tangent(:, :)
      real(dp) :: x(size(q)), delta
      integer :: j
      x = q
      do j = 1, size(q)
         delta = fd_step(q(j))
         x(j) = q(j) + delta
         tangent(:, j) = self%marker_generalized_force(x, k, force, moment)
         x(j) = q(j) - delta
         tangent(:, j) = (tangent(:, j) - self%marker_generalized_force(x, k, force, moment)) / &
            (2.0_dp * delta)
         x(j) = q(j)
      end do
   end subroutine body_marker_force_tangent_fd

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
      if (size(marker_xyz, 1) /= 3 .or. .not. all(ieee_is_finite(marker_xyz))) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'marker positions must be a (3, n) ' &
            // 'array of finite values; got ' // to_str(size(marker_xyz, 1)) // ' rows')
         return
      end if
      self%num_coordinates = 7
      self%num_markers = size(marker_xyz, 2)
      self%mass = mass
      self%center_of_mass = center_of_mass
      self%inertia = 0.5_dp * (inertia + transpose(inertia))
      chi = center_of_mass
      self%inertia_origin = self%inertia + mass * (dot_product(chi, chi) * identity3() - &
         spread(chi, 2, 3) * spread(chi, 1, 3))
      self%marker_xyz = marker_xyz
      call set_marker_frames(self%num_markers, marker_frames, self%marker_frames, where, error)
   end subroutine rigid_body_init

   !> "(J1, J2, J3)" for messages.
   pure function principal_text(moments) result(text)
      real(dp), intent(in) :: moments(3)
      character(len=:), allocatable :: text
      text = '(' // to_str(moments(1)) // ', ' // to_str(moments(2)) // ', ' // &
         to_str(moments(3)) // ')'
   end function principal_text

   !> Check marker frames (one per marker, orthonormal, det +1) and copy them.
   subroutine set_marker_frames(num_markers, given, frames, where, error)
      integer, intent(in) :: num_markers
      real(dp), intent(in) :: given(:, :, :)
      real(dp), allocatable, intent(out) :: frames(:, :, :)
      character(len=*), intent(in) :: where
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: C(3, 3), det
      integer :: k
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
   end subroutine set_marker_frames

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

   pure function cross3(a, b) result(c)
      real(dp), intent(in) :: a(3), b(3)
      real(dp) :: c(3)
      c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
   end function cross3

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
      if (size(marker_xyz, 1) /= 3 .or. .not. all(ieee_is_finite(marker_xyz))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'ground: marker positions must be a (3, n) ' &
            // 'array of finite values; got ' // to_str(size(marker_xyz, 1)) // ' rows')
         return
      end if
      self%num_coordinates = 0
      self%num_markers = size(marker_xyz, 2)
      self%marker_xyz = marker_xyz
      call set_marker_frames(self%num_markers, marker_frames, self%marker_frames, 'ground: ', &
         error)
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

   ! ----------------------------------------------------------------------------------------------
   ! Flexible body adapter: forwards to flexible_body_t (markers = interfaces)

   !> Wrap a copy of an initialised flexible body.
   subroutine adapter_init(self, flexible, error)
      !> The adapter
      class(flexible_body_adapter_t), intent(out) :: self
      !> Initialised flexible body (flexible_body_t%init)
      type(flexible_body_t), intent(in) :: flexible
      type(error_t), allocatable, intent(out) :: error
      if (flexible%num_coordinates /= 7 + flexible%num_modes .or. &
         .not. allocated(flexible%virtual_xyz)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'flexible body adapter: the flexible ' // &
            'body is not initialised (' // to_str(flexible%num_coordinates) // &
            ' coordinates); call flexible_body_t%init first')
         return
      end if
      self%flexible = flexible
      self%num_coordinates = flexible%num_coordinates
      self%num_markers = flexible%num_interfaces
   end subroutine adapter_init

   !> Marker position (flexible_body_t%marker_position).
   pure function adapter_marker_position(self, q, k) result(r)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      real(dp) :: r(3)
      r = self%flexible%marker_position(q, k)
   end function adapter_marker_position

   !> Marker orientation (flexible_body_t%marker_orientation).
   pure function adapter_marker_orientation(self, q, k) result(frame)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      real(dp) :: frame(3, 3)
      frame = self%flexible%marker_orientation(q, k)
   end function adapter_marker_orientation

   !> Marker velocity Jacobian (flexible_body_t%marker_velocity_jacobian).
   pure function adapter_marker_velocity_jacobian(self, q, k) result(jac)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      jac = self%flexible%marker_velocity_jacobian(q, k)
   end function adapter_marker_velocity_jacobian

   !> Marker position Jacobian (flexible_body_t%marker_position_jacobian).
   pure function adapter_marker_position_jacobian(self, q, k) result(jac)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      jac = self%flexible%marker_position_jacobian(q, k)
   end function adapter_marker_position_jacobian

   !> Marker rotation Jacobian (flexible_body_t%marker_rotation_jacobian).
   pure function adapter_marker_rotation_jacobian(self, q, k) result(jac)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      jac = self%flexible%marker_rotation_jacobian(q, k)
   end function adapter_marker_rotation_jacobian

   !> Marker axis Jacobian (flexible_body_t%marker_axis_jacobian).
   pure function adapter_marker_axis_jacobian(self, q, k, axis) result(jac)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      !> Axis in the marker frame
      real(dp), intent(in) :: axis(3)
      real(dp) :: jac(3, self%num_coordinates)
      jac = self%flexible%marker_axis_jacobian(q, k, axis)
   end function adapter_marker_axis_jacobian

   !> Generalized force at a marker (flexible_body_t%marker_generalized_force).
   pure function adapter_marker_generalized_force(self, q, k, force, moment) result(gen)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      !> Force, global components (N)
      real(dp), intent(in) :: force(3)
      !> Moment, global components (N m)
      real(dp), intent(in) :: moment(3)
      real(dp) :: gen(self%num_coordinates)
      gen = self%flexible%marker_generalized_force(q, k, force, moment)
   end function adapter_marker_generalized_force

   !> Mass matrix (flexible_body_t%mass_matrix).
   pure function adapter_mass_matrix(self, q) result(mass_matrix)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      real(dp) :: mass_matrix(self%num_coordinates, self%num_coordinates)
      mass_matrix = self%flexible%mass_matrix(q)
   end function adapter_mass_matrix

   !> Quadratic velocity vector (flexible_body_t%quadratic_velocity).
   pure function adapter_quadratic_velocity(self, q, v) result(f)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Velocities
      real(dp), intent(in) :: v(:)
      real(dp) :: f(self%num_coordinates)
      f = self%flexible%quadratic_velocity(q, v)
   end function adapter_quadratic_velocity

   !> Modal elastic and damping force (flexible_body_t%elastic_force).
   pure function adapter_elastic_force(self, q, v) result(f)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Velocities
      real(dp), intent(in) :: v(:)
      real(dp) :: f(self%num_coordinates)
      f = self%flexible%elastic_force(q, v)
   end function adapter_elastic_force

   !> -d(f_v + Q_e)/dq, -d(f_v + Q_e)/dv, exact: the FFRF quadratic velocity vector
   !> (flexible_body_t%quadratic_velocity_tangents) and the modal stiffness K_ff and damping D_ff
   !> (Q_e = [0; 0; -K_ff zeta - D_ff zeta_dot]).
   pure subroutine adapter_force_tangents(self, q, v, K, C)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Velocities
      real(dp), intent(in) :: v(:)
      !> -df/dq (n_b x n_b)
      real(dp), intent(out) :: K(:, :)
      !> -df/dv (n_b x n_b)
      real(dp), intent(out) :: C(:, :)
      integer :: j
      call self%flexible%quadratic_velocity_tangents(q, v, K, C)
      do j = 1, self%flexible%num_modes
         K(7 + j, 7 + j) = K(7 + j, 7 + j) + self%flexible%stiffness(j)
         if (allocated(self%flexible%damping)) C(7 + j, 7 + j) = C(7 + j, 7 + j) + &
            self%flexible%damping(j)
      end do
   end subroutine adapter_force_tangents

   !> Hessian of the weighted marker position and axes (flexible_body_t%marker_hessian: exact
   !> but for the zeta-zeta block of the axes, central differences of exact first derivatives).
   pure subroutine adapter_marker_hessian(self, q, k, w_position, w_axes, H)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      !> Weight of the marker position (3)
      real(dp), intent(in) :: w_position(3)
      !> Weights of the marker axes (3 x 3, column j for axis j)
      real(dp), intent(in) :: w_axes(3, 3)
      !> The Hessian (n_b x n_b)
      real(dp), intent(out) :: H(:, :)
      call self%flexible%marker_hessian(q, k, w_position, w_axes, H)
   end subroutine adapter_marker_hessian

   !> d(L_r^T F + L_w^T M)/dq at fixed F, M (flexible_body_t%marker_force_tangent).
   pure subroutine adapter_marker_force_tangent(self, q, k, force, moment, tangent)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      !> Force, global (N)
      real(dp), intent(in) :: force(3)
      !> Moment, global (N m)
      real(dp), intent(in) :: moment(3)
      !> The derivative (n_b x n_b)
      real(dp), intent(out) :: tangent(:, :)
      call self%flexible%marker_force_tangent(q, k, force, moment, tangent)
   end subroutine adapter_marker_force_tangent

   !> d(M(q) a)/dq at fixed a (flexible_body_t%mass_stiffness, exact).
   pure subroutine adapter_mass_stiffness(self, q, a, K)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Acceleration held fixed
      real(dp), intent(in) :: a(:)
      !> d(M a)/dq (n_b x n_b)
      real(dp), intent(out) :: K(:, :)
      call self%flexible%mass_stiffness(q, a, K)
   end subroutine adapter_mass_stiffness

   !> Marker kinematics in one call (flexible_body_t%marker_kinematics).
   pure subroutine adapter_marker_kinematics(self, q, k, need_axes, position, orientation, &
         position_jacobian, axis_jacobian)
      class(flexible_body_adapter_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Marker (interface) number
      integer, intent(in) :: k
      !> Which axis Jacobians to form (x, y, z)
      logical, intent(in) :: need_axes(3)
      !> Global position (m)
      real(dp), intent(out) :: position(3)
      !> Orientation, marker frame -> global
      real(dp), intent(out) :: orientation(3, 3)
      !> dr/dq (3 x n_b)
      real(dp), intent(out) :: position_jacobian(:, :)
      !> d(A_V e_j)/dq (3 x n_b x 3)
      real(dp), intent(inout) :: axis_jacobian(:, :, :)
      call self%flexible%marker_kinematics(q, k, need_axes, position, orientation, &
         position_jacobian, axis_jacobian)
   end subroutine adapter_marker_kinematics

end module ffrf_mbs_rigid_body
