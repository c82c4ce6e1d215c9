!> The abstract body of a mechanism, as the joints, the loads and the mechanism see it: generalized
!> coordinates q (num_coordinates), numbered markers, mass matrix, quadratic velocity vector,
!> elastic force and their Newton tangents (theory.md sections 3 and 3.5). The rigid body and the
!> ground (ffrf_mbs_rigid_body) and the reduced flexible body (ffrf_mbs_flexible_body) extend it,
!> so that a joint or a mechanism loops over bodies without knowing their kind.
!>
!> Markers. Every body carries numbered markers k = 1..num_markers, each a point with an
!> orthonormal frame: global position r_k(q) and orientation A_k(q) (marker frame -> global;
!> its columns are the marker's x, y, z axes in global components); a flexible body's markers
!> are its interfaces (virtual nodes).
!>
!> Equations of motion of a body (right-hand-side convention of theory.md 3.4):
!>     M(q) v_dot = f_v(q, v) + Q_e(q, v) + Q(loads) - C_q^T lambda,
!> f_v the quadratic velocity vector, Q_e the elastic and damping force (zero for rigid bodies).
!>
!> Tangents for the Newton iteration of a mechanism (per body, all n_b x n_b): force_tangents
!> (-d(f_v + Q_e)/dq, -d(f_v + Q_e)/dv), mass_stiffness (d(M a)/dq at fixed a), marker_hessian
!> (d^2/dq^2 of w_r . r_k + sum_j w_j . A_k e_j, for the joints' constraint stiffness) and
!> marker_force_tangent (d(L_r^T F + L_w^T M)/dq at fixed F, M). The defaults here are central
!> differences over the body's own coordinates (fd_step, cheap: per body); the rigid body
!> overrides them with exact forms, the flexible body with forms exact but for the second
!> derivative of the exponential map of its marker rotations (a 3 x 3 central difference).
!> marker_kinematics gives a marker's position, orientation and Jacobians in one call (the
!> joints use it); the default calls the separate marker procedures. Energies: kinetic_energy
!> v^T M v / 2; strain_energy and damping_power (power dissipated by the body's own damping) are
!> zero unless a body overrides them.
module ffrf_mbs_body
   use ffrf_core_kinds, only: dp
   use ffrf_mbs_dae_system, only: fd_step
   implicit none
   private
   public :: body_t
   !> The central-difference defaults, public so that a body with analytic overrides can be
   !> checked against them (as ffrf_mbs_dae_system's)
   public :: body_force_tangents_fd, body_mass_stiffness_fd, body_marker_hessian_fd
   public :: body_marker_force_tangent_fd

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
      !> Strain energy (J); zero for a body without elastic coordinates (the default)
      procedure :: strain_energy => body_strain_energy
      !> Power dissipated by the body's own damping (W); zero by default
      procedure :: damping_power => body_damping_power
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

   !> Strain energy of a body without elastic coordinates: 0 J.
   pure function body_strain_energy(self, q) result(energy)
      !> The body
      class(body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      real(dp) :: energy
      energy = 0.0_dp * real(size(q) + self%num_coordinates, dp)
   end function body_strain_energy

   !> Damping power of a body without damping: 0 W.
   pure function body_damping_power(self, v) result(power)
      !> The body
      class(body_t), intent(in) :: self
      !> Velocities dq/dt
      real(dp), intent(in) :: v(:)
      real(dp) :: power
      power = 0.0_dp * real(size(v) + self%num_coordinates, dp)
   end function body_damping_power

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
      integer :: j
      do j = 1, size(q)
         K(:, j) = -force_difference(j)
      end do
      do j = 1, size(v)
         C(:, j) = -force_difference(size(q) + j)
      end do

   contains

      !> (f(x + delta e_i) - f(x - delta e_i)) / (2 delta) over x = [q; v], f the quadratic
      !> velocity vector plus the elastic force.
      pure function force_difference(i) result(df)
         integer, intent(in) :: i
         real(dp) :: df(size(q))
         real(dp) :: x_plus(size(q) + size(v)), x_minus(size(q) + size(v)), delta
         call difference_points([q, v], i, x_plus, x_minus, delta)
         df = (force(x_plus) - force(x_minus)) / (2.0_dp * delta)
      end function force_difference

      !> f at x = [q; v].
      pure function force(x) result(f)
         real(dp), intent(in) :: x(:)
         real(dp) :: f(size(q))
         f = self%quadratic_velocity(x(:size(q)), x(size(q) + 1:)) + &
            self%elastic_force(x(:size(q)), x(size(q) + 1:))
      end function force

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
      real(dp) :: x_plus(size(q)), x_minus(size(q)), delta
      integer :: j
      do j = 1, size(q)
         call difference_points(q, j, x_plus, x_minus, delta)
         K(:, j) = (matmul(self%mass_matrix(x_plus), a) - matmul(self%mass_matrix(x_minus), a)) &
            / (2.0_dp * delta)
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
      real(dp) :: x_plus(size(q)), x_minus(size(q)), delta
      integer :: j
      do j = 1, size(q)
         call difference_points(q, j, x_plus, x_minus, delta)
         H(:, j) = (weighted_gradient(x_plus) - weighted_gradient(x_minus)) / (2.0_dp * delta)
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
      real(dp) :: x_plus(size(q)), x_minus(size(q)), delta
      integer :: j
      do j = 1, size(q)
         call difference_points(q, j, x_plus, x_minus, delta)
         tangent(:, j) = (self%marker_generalized_force(x_plus, k, force, moment) - &
            self%marker_generalized_force(x_minus, k, force, moment)) / (2.0_dp * delta)
      end do
   end subroutine body_marker_force_tangent_fd

   !> The points x -+ delta e_j of a central difference in x(j), delta = fd_step(x(j)) (the
   !> default tangents' column j is (g(x_plus) - g(x_minus)) / (2 delta)).
   pure subroutine difference_points(x, j, x_plus, x_minus, delta)
      real(dp), intent(in) :: x(:)
      integer, intent(in) :: j
      real(dp), intent(out) :: x_plus(:), x_minus(:), delta
      delta = fd_step(x(j))
      x_plus = x
      x_minus = x
      x_plus(j) = x(j) + delta
      x_minus(j) = x(j) - delta
   end subroutine difference_points

end module ffrf_mbs_body
