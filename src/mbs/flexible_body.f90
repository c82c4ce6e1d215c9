!> One reduced flexible body in the floating frame of reference (FFRF) with modal coordinates
!> (theory.md section 3; Shabana, Dynamics of Multibody Systems, 3rd ed., ch. 5).
!>
!> Position of a material point (node i): r_i = R + A(theta) (x_i + Psi_i zeta), with the
!> coordinates q = [R (3); theta (4 Euler parameters, ffrf_mbs_rotation); zeta (m)] and the
!> velocities v = dq/dt (theta_dot, not omega: the mass matrix carries G_bar). Nodal velocity
!>     r_i_dot = R_dot + A (omega_bar x u_i) + A Psi_i zeta_dot,   u_i = x_i + Psi_i zeta,
!> omega_bar = G_bar theta_dot. The inertia invariants of theory.md 3.2 are computed once, exactly,
!> from the consistent FE mass matrix (Zwoelfer and Gerstmayr, Multibody Syst. Dyn. 49 (2020)
!> 291): every invariant is a Gram matrix Z^T M Z of the columns Z = [Phi_t, x~, x, Psi, Psi~].
!> The M-blocks 3.3 rotate with A only if M = Ms (x) I3 (the same scalar mass for x, y, z: true for
!> the consistent mass of solid elements and for lumped masses); init checks this structure.
!>
!> Equations of motion (right-hand-side convention of theory.md 3.4):
!>     M(q) v_dot = f_v(q, v) + Q_e(q, v) + Q(forces) - C_q^T lambda,
!> Q_e = [0; 0; -K_ff zeta - D_ff zeta_dot], K_ff = diag(omega_j^2), D_ff = diag(2 xi_j omega_j),
!> and the Euler-parameter normalisation theta^T theta = 1 among the constraints C.
!>
!> Markers (one per interface, at its virtual node V; theory.md 3.5). The modal pipeline's
!> virtual-node rows Psi_V = [Psi_Vt; Psi_Vr] follow the RBE2/RBE3 convention u = u_V + theta_V x r
!> (F_i = [I, -skew(r_i)]): Psi_Vr zeta is the small elastic rotation vector of V in the body
!> frame, right-handed. Marker position r_V = R + A (x_V + Psi_Vt zeta). Marker orientation
!> A_V = A exp(skew(phi)), phi = Psi_Vr zeta: equal to theory.md's A (I + skew(phi)) to first order
!> in zeta (the FFRF model is linear in zeta) but orthonormal, so that joint equations on marker
!> axes are exact functions of q with exact Jacobians. Angular velocity of the marker (global)
!> omega_V = A (omega_bar + T(phi) Psi_Vr zeta_dot), T the tangent operator of exp (T = I + O(phi)).
module ffrf_mbs_flexible_body
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: csr_t, csr_matvec
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar, skew3, identity3, &
      rotated_vector_jacobian, rotation_vector_matrix, rotation_vector_tangent
   implicit none
   private
   public :: flexible_body_t

   !> Reduced flexible body: inertia invariants, modal stiffness and damping, markers.
   type :: flexible_body_t
      !> Number of FE nodes, of modes m, of interfaces (markers)
      integer :: num_nodes = 0, num_modes = 0, num_interfaces = 0
      !> Number of coordinates, 7 + m
      integer :: num_coordinates = 0
      !> Total mass m (kg)
      real(dp) :: mass = 0.0_dp
      !> Centre of mass chi in the body frame (m)
      real(dp) :: center_of_mass(3) = 0.0_dp
      !> Theta_u = x~^T M x~: inertia tensor about the body-frame origin (kg m^2)
      real(dp) :: theta_u(3, 3) = 0.0_dp
      !> M_PhitPsi = Phi_t^T M Psi (3 x m)
      real(dp), allocatable :: m_phit_psi(:, :)
      !> M_PhitPsi~ = Phi_t^T M Psi~ (3 x 3m)
      real(dp), allocatable :: m_phit_psit(:, :)
      !> M_xPsi = x~^T M Psi (3 x m)
      real(dp), allocatable :: m_x_psi(:, :)
      !> M_xPsi~ = x~^T M Psi~ (3 x 3m)
      real(dp), allocatable :: m_x_psit(:, :)
      !> M_Psi~Psi = Psi~^T M Psi (3m x m)
      real(dp), allocatable :: m_psit_psi(:, :)
      !> M_Psi~Psi~ = Psi~^T M Psi~ (3m x 3m)
      real(dp), allocatable :: m_psit_psit(:, :)
      !> M_PsiPsi = Psi^T M Psi (m x m; I for mass-normalised modes)
      real(dp), allocatable :: m_psi_psi(:, :)
      !> Modal stiffness K_ff = diag(omega_j^2) (1/s^2 for mass-normalised modes)
      real(dp), allocatable :: stiffness(:)
      !> Modal damping D_ff = diag(2 xi_j omega_j) (1/s); zero unless set_modal_damping
      real(dp), allocatable :: damping(:)
      !> Virtual-node mode rows (6 num_interfaces x m): [Psi_Vt; Psi_Vr] per interface
      real(dp), allocatable :: virtual_shapes(:, :)
      !> Virtual node positions x_V in the body frame (3, num_interfaces) (m)
      real(dp), allocatable :: virtual_xyz(:, :)
   contains
      procedure :: init => flexible_body_init
      procedure :: set_modal_damping => flexible_body_set_modal_damping
      procedure :: mass_matrix => flexible_body_mass_matrix
      procedure :: quadratic_velocity => flexible_body_quadratic_velocity
      procedure :: elastic_force => flexible_body_elastic_force
      procedure :: kinetic_energy => flexible_body_kinetic_energy
      procedure :: strain_energy => flexible_body_strain_energy
      procedure :: marker_position => flexible_body_marker_position
      procedure :: marker_orientation => flexible_body_marker_orientation
      procedure :: marker_velocity_jacobian => flexible_body_marker_velocity_jacobian
      procedure :: marker_position_jacobian => flexible_body_marker_position_jacobian
      procedure :: marker_rotation_jacobian => flexible_body_marker_rotation_jacobian
      procedure :: marker_axis_jacobian => flexible_body_marker_axis_jacobian
      procedure :: marker_generalized_force => flexible_body_marker_generalized_force
   end type flexible_body_t

contains

   !> Precompute the inertia invariants of theory.md 3.2 from the full consistent mass matrix and
   !> the modes. Checks sizes, finiteness, non-negative eigenvalues and M = Ms (x) I3.
   subroutine flexible_body_init(self, M, xyz, shapes, eigenvalues, virtual_shapes, virtual_xyz, &
         error)
      class(flexible_body_t), intent(out) :: self
      !> Consistent mass matrix (kg), 3n x 3n, both triangles stored, dof 3 (node - 1) + c
      type(csr_t), intent(in) :: M
      !> Node coordinates in the body frame (3, n) (m)
      real(dp), intent(in) :: xyz(:, :)
      !> Mode shapes Psi (3n, m), mass-normalised (Psi^T M Psi = I expected, not required)
      real(dp), intent(in) :: shapes(:, :)
      !> Eigenvalues omega_j^2 (1/s^2): the modal stiffness
      real(dp), intent(in) :: eigenvalues(:)
      !> Virtual-node rows of the modes (6 num_interfaces, m): [u; theta] per interface, as
      !> body_modes_t%virtual_node_shape
      real(dp), intent(in) :: virtual_shapes(:, :)
      !> Virtual node positions (3, num_interfaces) (m), body frame
      real(dp), intent(in) :: virtual_xyz(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: Z(:, :), MZ(:, :), gram(:, :)
      integer :: n, nm, ncol, i, j, c, stat, col_psi, col_psit
      character(len=*), parameter :: where = 'flexible body: '

      n = size(xyz, 2)
      nm = size(shapes, 2)
      if (size(xyz, 1) /= 3 .or. M%num_rows /= 3 * n .or. M%num_cols /= 3 * n .or. &
         size(shapes, 1) /= 3 * n) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'sizes do not match: xyz (' // &
            to_str(size(xyz, 1)) // ', ' // to_str(n) // '), M ' // to_str(M%num_rows) // &
            ' x ' // to_str(M%num_cols) // ', shapes ' // to_str(size(shapes, 1)) // ' rows; ' // &
            'pass xyz(3, n), M 3n x 3n and shapes with 3n rows')
         return
      end if
      if (size(eigenvalues) /= nm .or. size(virtual_shapes, 2) /= nm .or. &
         size(virtual_xyz, 1) /= 3 .or. size(virtual_shapes, 1) /= 6 * size(virtual_xyz, 2)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // to_str(nm) // ' modes but ' // &
            to_str(size(eigenvalues)) // ' eigenvalues, virtual shapes ' // &
            to_str(size(virtual_shapes, 1)) // ' x ' // to_str(size(virtual_shapes, 2)) // &
            ' for ' // to_str(size(virtual_xyz, 2)) // ' virtual nodes; pass one eigenvalue ' // &
            'per mode and 6 virtual-shape rows per virtual node')
         return
      end if
      do j = 1, nm
         if (.not. ieee_is_finite(eigenvalues(j)) .or. eigenvalues(j) < 0.0_dp) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'eigenvalue of mode ' // &
               to_str(j) // ' = ' // to_str(eigenvalues(j)) // '; must be finite and >= 0')
            return
         end if
      end do
      if (.not. (all(ieee_is_finite(shapes)) .and. all(ieee_is_finite(xyz)) .and. &
         all(ieee_is_finite(virtual_shapes)) .and. all(ieee_is_finite(virtual_xyz)) .and. &
         all(ieee_is_finite(M%val)))) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'NaN or Inf in the mass matrix, ' // &
            'node coordinates, mode shapes or virtual-node data')
         return
      end if

      self%num_nodes = n
      self%num_modes = nm
      self%num_interfaces = size(virtual_xyz, 2)
      self%num_coordinates = 7 + nm
      self%stiffness = eigenvalues
      allocate (self%damping(nm), source=0.0_dp)
      self%virtual_shapes = virtual_shapes
      self%virtual_xyz = virtual_xyz

      call check_scalar_mass(M, n, error)
      if (allocated(error)) return

      ! Columns Z = [Phi_t (3), x~ (3), x (1), Psi (m), Psi~ (3m)], theory.md 3.2
      ncol = 7 + 4 * nm
      col_psi = 7
      col_psit = 7 + nm
      allocate (Z(3 * n, ncol), MZ(3 * n, ncol), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, where // 'cannot allocate 2 x ' // &
            to_str(3 * n) // ' x ' // to_str(ncol) // ' reals for the inertia invariants')
         return
      end if
      Z = 0.0_dp
      do i = 1, n
         associate (rows => 3 * (i - 1) + [1, 2, 3])
            Z(rows, 1:3) = identity3()
            Z(rows, 4:6) = skew3(xyz(:, i))
            Z(rows, 7) = xyz(:, i)
            do j = 1, nm
               Z(rows, col_psi + j) = shapes(rows, j)
               Z(rows, col_psit + 3 * (j - 1) + 1:col_psit + 3 * j) = skew3(shapes(rows, j))
            end do
         end associate
      end do
      do c = 1, ncol
         call csr_matvec(M, Z(:, c), MZ(:, c))
      end do
      gram = matmul(transpose(Z), MZ)
      gram = 0.5_dp * (gram + transpose(gram))
      if (.not. all(ieee_is_finite(gram))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, where // 'NaN or Inf in the inertia ' // &
            'invariants Z^T M Z')
         return
      end if

      self%mass = gram(1, 1)
      if (.not. self%mass > 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'mass Phi_t^T M Phi_t = ' // &
            to_str(self%mass) // ' kg; the mass matrix must be positive definite')
         return
      end if
      self%center_of_mass = gram(1:3, 7) / self%mass
      self%theta_u = gram(4:6, 4:6)
      associate (psi => col_psi + [(j, j=1, nm)], psit => col_psit + [(j, j=1, 3 * nm)])
         self%m_phit_psi = gram(1:3, psi)
         self%m_phit_psit = gram(1:3, psit)
         self%m_x_psi = gram(4:6, psi)
         self%m_x_psit = gram(4:6, psit)
         self%m_psit_psi = gram(psit, psi)
         self%m_psit_psit = gram(psit, psit)
         self%m_psi_psi = gram(psi, psi)
      end associate
   end subroutine flexible_body_init

   !> M = Ms (x) I3: M applied to p (x) e_c (p a fixed node field) has only c-components, the
   !> same for c = 1, 2, 3, to 1e-12 relative. Else the invariants would not be exact under A.
   subroutine check_scalar_mass(M, n, error)
      type(csr_t), intent(in) :: M
      integer, intent(in) :: n
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: p(:), y(:, :)
      real(dp) :: scale, misfit
      integer :: c, i
      allocate (p(3 * n), y(3 * n, 3))
      do c = 1, 3
         p = 0.0_dp
         do i = 1, n
            p(3 * (i - 1) + c) = 1.0_dp + 0.5_dp * cos(real(i, dp))
         end do
         call csr_matvec(M, p, y(:, c))
      end do
      scale = maxval(abs(y))
      misfit = 0.0_dp
      do c = 1, 3
         do i = 1, n
            misfit = max(misfit, maxval(abs(y(3 * (i - 1) + [1, 2, 3], c) - &
               merge(y(3 * (i - 1) + 1, 1), 0.0_dp, [1, 2, 3] == c))))
         end do
      end do
      if (misfit > 1.0e-12_dp * scale) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: the mass matrix is not of ' // &
            'the form Ms (x) I3 (relative misfit ' // to_str(misfit / scale, 3) // '); the ' // &
            'FFRF invariants need the same scalar mass for x, y and z (consistent or lumped ' // &
            'mass of solid elements)')
      end if
   end subroutine check_scalar_mass

   !> Modal damping D_ff = diag(2 xi_j omega_j).
   subroutine flexible_body_set_modal_damping(self, damping_ratio, error)
      class(flexible_body_t), intent(inout) :: self
      !> Damping ratios xi (one for all modes, or one per mode), >= 0
      real(dp), intent(in) :: damping_ratio(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: xi(self%num_modes)
      if (size(damping_ratio) /= 1 .and. size(damping_ratio) /= self%num_modes) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: ' // &
            to_str(size(damping_ratio)) // ' damping ratios for ' // to_str(self%num_modes) // &
            ' modes; give one for all or one per mode')
         return
      end if
      if (size(damping_ratio) == 1) then
         xi = damping_ratio(1)
      else
         xi = damping_ratio
      end if
      if (any(.not. ieee_is_finite(xi)) .or. any(xi < 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: damping ratio ' // &
            to_str(minval(xi)) // ' is negative or not finite; must be >= 0')
         return
      end if
      self%damping = 2.0_dp * xi * sqrt(self%stiffness)
   end subroutine flexible_body_set_modal_damping

   !> sum_j z_j B(:, 3j-2:3j) = B (z (x) I3), for B with 3m columns (r x 3).
   pure function times_z(B, z) result(c)
      real(dp), intent(in) :: B(:, :), z(:)
      real(dp) :: c(size(B, 1), 3)
      integer :: j
      c = 0.0_dp
      do j = 1, size(z)
         c = c + z(j) * B(:, 3 * j - 2:3 * j)
      end do
   end function times_z

   !> sum_j z_j B(3j-2:3j, :) = (z (x) I3)^T B, for B with 3m rows (3 x s).
   pure function z_times(z, B) result(c)
      real(dp), intent(in) :: z(:), B(:, :)
      real(dp) :: c(3, size(B, 2))
      integer :: j
      c = 0.0_dp
      do j = 1, size(z)
         c = c + z(j) * B(3 * j - 2:3 * j, :)
      end do
   end function z_times

   !> Deformed inertia I_thth(zeta) = Theta_u + M_xPsi~ (z(x)I) + (z(x)I)^T M_xPsi~^T
   !> + (z(x)I)^T M_Psi~Psi~ (z(x)I) (theory.md 3.3) = u~^T M u~ (kg m^2).
   pure function deformed_inertia(self, zeta) result(inertia)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: zeta(:)
      real(dp) :: inertia(3, 3), x(3, 3)
      x = times_z(self%m_x_psit, zeta)
      inertia = self%theta_u + x + transpose(x) + z_times(zeta, times_z(self%m_psit_psit, zeta))
   end function deformed_inertia

   !> First moment skew: m chi~ + M_PhitPsi~ (z(x)I) = skew(int rho u dV) (kg m).
   pure function first_moment_skew(self, zeta) result(s)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: zeta(:)
      real(dp) :: s(3, 3)
      s = skew3(self%mass * self%center_of_mass) + times_z(self%m_phit_psit, zeta)
   end function first_moment_skew

   !> Mass matrix M(q) ((7+m) x (7+m), symmetric), theory.md 3.3:
   !>     m_RR = m I,  m_Rth = -A [m chi~ + M_PhitPsi~ (z(x)I)] G_bar,  m_Rf = A M_PhitPsi,
   !>     m_thth = G_bar^T I_thth(zeta) G_bar,  m_thf = -G_bar^T [M_xPsi + (z(x)I)^T M_Psi~Psi],
   !>     m_ff = M_PsiPsi.
   !> The theta block has rank 3 (G_bar theta = 0): the normalisation constraint completes it.
   pure function flexible_body_mass_matrix(self, q) result(mass_matrix)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      real(dp) :: mass_matrix(self%num_coordinates, self%num_coordinates)
      real(dp) :: A(3, 3), G_bar(3, 4)
      integer :: nc, j
      nc = self%num_coordinates
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      associate (zeta => q(8:nc))
         mass_matrix = 0.0_dp
         do j = 1, 3
            mass_matrix(j, j) = self%mass
         end do
         mass_matrix(1:3, 4:7) = -matmul(A, matmul(first_moment_skew(self, zeta), G_bar))
         mass_matrix(1:3, 8:nc) = matmul(A, self%m_phit_psi)
         mass_matrix(4:7, 4:7) = matmul(transpose(G_bar), &
            matmul(deformed_inertia(self, zeta), G_bar))
         mass_matrix(4:7, 8:nc) = -matmul(transpose(G_bar), &
            self%m_x_psi + z_times(zeta, self%m_psit_psi))
         mass_matrix(8:nc, 8:nc) = self%m_psi_psi
      end associate
      mass_matrix(4:nc, 1:3) = transpose(mass_matrix(1:3, 4:nc))
      mass_matrix(8:nc, 4:7) = transpose(mass_matrix(4:7, 8:nc))
   end function flexible_body_mass_matrix

   !> Quadratic velocity vector f_v(q, v) (right-hand side), theory.md 3.4, omega = G_bar theta_dot:
   !>   f_vR  = A w~ [m chi~ + M_PhitPsi~(z(x)I)] w + 2 A M_PhitPsi~ (zd(x)I) w
   !>   f_vth = -G_bar^T w~ I_thth w
   !>           - 2 G_bar^T [M_xPsi~ (zd(x)I) + (z(x)I)^T M_Psi~Psi~ (zd(x)I)] w
   !>   f_vf  = (I (x) w)^T [M_xPsi~^T + M_Psi~Psi~ (z(x)I)] w + 2 M_Psi~Psi^T (zd (x) w)
   !> (z = zeta, zd = zeta_dot). It equals -(dM/dt) v + d(v^T M v / 2)/dq of Lagrange's equations
   !> up to a multiple of theta in the theta rows (taken by the normalisation constraint).
   pure function flexible_body_quadratic_velocity(self, q, v) result(f_v)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Velocities [R_dot; theta_dot; zeta_dot]
      real(dp), intent(in) :: v(:)
      real(dp) :: f_v(self%num_coordinates)
      real(dp) :: A(3, 3), G_bar(3, 4), omega(3), w_skew(3, 3), coriolis(3, 3)
      real(dp) :: W(3 * self%num_modes, 3)
      integer :: nc, j
      nc = self%num_coordinates
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      omega = matmul(G_bar, v(4:7))
      w_skew = skew3(omega)
      associate (zeta => q(8:nc), zeta_dot => v(8:nc))
         f_v(1:3) = matmul(A, matmul(w_skew, matmul(first_moment_skew(self, zeta), omega)) + &
            2.0_dp * matmul(times_z(self%m_phit_psit, zeta_dot), omega))
         coriolis = times_z(self%m_x_psit, zeta_dot) + &
            z_times(zeta, times_z(self%m_psit_psit, zeta_dot))
         f_v(4:7) = -matmul(transpose(G_bar), matmul(w_skew, &
            matmul(deformed_inertia(self, zeta), omega)) + 2.0_dp * matmul(coriolis, omega))
         W = transpose(self%m_x_psit) + times_z(self%m_psit_psit, zeta)
         do j = 1, self%num_modes
            f_v(7 + j) = dot_product(omega, matmul(W(3 * j - 2:3 * j, :), omega)) + &
               2.0_dp * dot_product(self%m_psit_psi(:, j), kron_vector(zeta_dot, omega))
         end do
      end associate
   end function flexible_body_quadratic_velocity

   !> z (x) w: the 3m-vector [z_1 w; ...; z_m w].
   pure function kron_vector(z, w) result(zw)
      real(dp), intent(in) :: z(:), w(3)
      real(dp) :: zw(3 * size(z))
      integer :: j
      do j = 1, size(z)
         zw(3 * j - 2:3 * j) = z(j) * w
      end do
   end function kron_vector

   !> Elastic and damping generalized force Q_e = [0; 0; -K_ff zeta - D_ff zeta_dot].
   pure function flexible_body_elastic_force(self, q, v) result(force)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Velocities
      real(dp), intent(in) :: v(:)
      real(dp) :: force(self%num_coordinates)
      force = 0.0_dp
      force(8:) = -self%stiffness * q(8:self%num_coordinates) - &
         self%damping * v(8:self%num_coordinates)
   end function flexible_body_elastic_force

   !> Kinetic energy T = v^T M(q) v / 2 (J).
   pure function flexible_body_kinetic_energy(self, q, v) result(energy)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Velocities
      real(dp), intent(in) :: v(:)
      real(dp) :: energy
      real(dp) :: mass_matrix(self%num_coordinates, self%num_coordinates)
      mass_matrix = self%mass_matrix(q)
      energy = 0.5_dp * dot_product(v, matmul(mass_matrix, v))
   end function flexible_body_kinetic_energy

   !> Strain energy zeta^T K_ff zeta / 2 (J).
   pure function flexible_body_strain_energy(self, q) result(energy)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      real(dp) :: energy
      energy = 0.5_dp * sum(self%stiffness * q(8:self%num_coordinates)**2)
   end function flexible_body_strain_energy

   !> Deformed position of virtual node k in the body frame, u_V = x_V + Psi_Vt zeta.
   pure function marker_local(self, q, k) result(u)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: q(:)
      integer, intent(in) :: k
      real(dp) :: u(3)
      u = self%virtual_xyz(:, k) + matmul(self%virtual_shapes(6 * k - 5:6 * k - 3, :), &
         q(8:self%num_coordinates))
   end function marker_local

   !> Elastic rotation vector of virtual node k, phi = Psi_Vr zeta (body frame, rad).
   pure function marker_rotation_vector(self, q, k) result(phi)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: q(:)
      integer, intent(in) :: k
      real(dp) :: phi(3)
      phi = matmul(self%virtual_shapes(6 * k - 2:6 * k, :), q(8:self%num_coordinates))
   end function marker_rotation_vector

   !> Global position of marker k, r_V = R + A (x_V + Psi_Vt zeta) (m). k in 1..num_interfaces.
   pure function flexible_body_marker_position(self, q, k) result(r)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      real(dp) :: r(3)
      real(dp) :: A(3, 3), u(3)
      A = euler_rotation(q(4:7))
      u = marker_local(self, q, k)
      r = q(1:3) + matmul(A, u)
   end function flexible_body_marker_position

   !> Orientation of marker k (body of V -> global), A_V = A exp(skew(Psi_Vr zeta)).
   pure function flexible_body_marker_orientation(self, q, k) result(A_v)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      real(dp) :: A_v(3, 3)
      real(dp) :: A(3, 3), R(3, 3)
      A = euler_rotation(q(4:7))
      R = rotation_vector_matrix(marker_rotation_vector(self, q, k))
      A_v = matmul(A, R)
   end function flexible_body_marker_orientation

   !> Velocity Jacobian L_r of marker k, r_V_dot = L_r v = [I, -A u_V~ G_bar, A Psi_Vt] v
   !> (3 x (7+m)); equals marker_position_jacobian on tangent velocities (theta^T theta_dot = 0,
   !> |theta| = 1). Its transpose maps a global force to generalized forces (theory.md 3.5).
   pure function flexible_body_marker_velocity_jacobian(self, q, k) result(jac)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      real(dp) :: A(3, 3)
      A = euler_rotation(q(4:7))
      jac(:, 1:3) = identity3()
      jac(:, 4:7) = -matmul(A, matmul(skew3(marker_local(self, q, k)), euler_g_bar(q(4:7))))
      jac(:, 8:) = matmul(A, self%virtual_shapes(6 * k - 5:6 * k - 3, :))
   end function flexible_body_marker_velocity_jacobian

   !> Exact partial derivatives of the marker position, dr_V/dq (3 x (7+m)), in all four
   !> Euler-parameter directions (rotated_vector_jacobian): the Jacobian of position-level joint
   !> equations Phi(q) = 0.
   pure function flexible_body_marker_position_jacobian(self, q, k) result(jac)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      jac(:, 1:3) = identity3()
      jac(:, 4:7) = rotated_vector_jacobian(q(4:7), marker_local(self, q, k))
      jac(:, 8:) = matmul(euler_rotation(q(4:7)), self%virtual_shapes(6 * k - 5:6 * k - 3, :))
   end function flexible_body_marker_position_jacobian

   !> Rotation Jacobian L_w of marker k (3 x (7+m)) = [0, A G_bar, A T(phi) Psi_Vr]: the global
   !> angular velocity omega_V = L_w v, and the global small rotation dpi_V of the marker frame
   !> (dA_V = skew(dpi_V) A_V) for a tangent variation dq. Its transpose maps a global moment to
   !> generalized forces (theory.md 3.5; T = I + O(zeta)).
   pure function flexible_body_marker_rotation_jacobian(self, q, k) result(jac)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      real(dp) :: jac(3, self%num_coordinates)
      real(dp) :: A(3, 3)
      A = euler_rotation(q(4:7))
      jac(:, 1:3) = 0.0_dp
      jac(:, 4:7) = matmul(A, euler_g_bar(q(4:7)))
      jac(:, 8:) = matmul(matmul(A, rotation_vector_tangent(marker_rotation_vector(self, q, k))), &
         self%virtual_shapes(6 * k - 2:6 * k, :))
   end function flexible_body_marker_rotation_jacobian

   !> Exact partial derivatives d(A_V a)/dq (3 x (7+m)) of a marker-fixed axis a, all four
   !> Euler-parameter directions included: the Jacobian of joint equations on marker axes
   !> (revolute, universal, prismatic: dot products of axes).
   pure function flexible_body_marker_axis_jacobian(self, q, k, axis) result(jac)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      !> Axis in the marker frame
      real(dp), intent(in) :: axis(3)
      real(dp) :: jac(3, self%num_coordinates)
      real(dp) :: A(3, 3), phi(3), b(3)
      A = euler_rotation(q(4:7))
      phi = marker_rotation_vector(self, q, k)
      b = matmul(rotation_vector_matrix(phi), axis)
      jac(:, 1:3) = 0.0_dp
      jac(:, 4:7) = rotated_vector_jacobian(q(4:7), b)
      jac(:, 8:) = -matmul(matmul(A, matmul(skew3(b), rotation_vector_tangent(phi))), &
         self%virtual_shapes(6 * k - 2:6 * k, :))
   end function flexible_body_marker_axis_jacobian

   !> Generalized force of a global force F and a global moment M_V applied at marker k, by
   !> virtual work Q = L_r^T F + L_w^T M_V (theory.md 3.5):
   !>     Q_R = F,  Q_th = G_bar^T (u_V~ A^T F + A^T M_V),
   !>     Q_f = Psi_Vt^T A^T F + Psi_Vr^T T^T A^T M_V.
   pure function flexible_body_marker_generalized_force(self, q, k, force, moment) result(gen)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      !> Force, global components (N)
      real(dp), intent(in) :: force(3)
      !> Moment, global components (N m)
      real(dp), intent(in) :: moment(3)
      real(dp) :: gen(self%num_coordinates)
      real(dp) :: L_r(3, self%num_coordinates), L_w(3, self%num_coordinates)
      L_r = self%marker_velocity_jacobian(q, k)
      L_w = self%marker_rotation_jacobian(q, k)
      gen = matmul(force, L_r) + matmul(moment, L_w)
   end function flexible_body_marker_generalized_force

end module ffrf_mbs_flexible_body
