!> One reduced flexible body in the floating frame of reference (FFRF) with modal coordinates
!> (theory.md section 3; Shabana, Dynamics of Multibody Systems, 3rd ed., ch. 5): an extension
!> of the abstract body body_t (ffrf_mbs_body) whose markers are its interfaces.
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
!> Marker frames: markers 1..(number of interfaces) carry the virtual node's frame; add_marker
!> adds markers at a virtual node with a constant orientation C (columns: the marker axes in the
!> node frame), frame A exp(phi~) C, so that a joint at an interface takes any axis. C is
!> constant, so the position, the angular velocity (L_w) and the generalized force are the
!> node's; the axes b_j = exp(phi~) C e_j enter the axis Jacobians exactly (d b / d phi =
!> -b~ T(phi)) and the Hessian through the weights w_axes C^T. C = I takes no product (the
!> interface markers' numbers are unchanged by it, bit for bit).
!>
!> Geometric (centrifugal) stiffening, optional (set_geometric_stiffness; linear modal FFRF
!> without it). The modal stiffness of the spinning body becomes K_ff + K_G(omega_bar),
!> K_G(omega) = sum_c p_c(omega) K_G^(c), p = [w1^2, w2^2, w3^2, w1 w2, w2 w3, w1 w3] and K_G^(c)
!> the modes' geometric stiffness of the six centrifugal load cases
!> (ffrf_modes_modal_geometric_stiffness). The force -K_G(omega_bar) zeta is quadratic in the
!> velocities: it is the motion-induced stiffness of the inertia forces (Kane, Ryan & Banerjee,
!> J. Guidance 10 (1987) 139), so it is added to f_v (quadratic_velocity) and its exact
!> derivatives to quadratic_velocity_tangents; strain_energy stays zeta^T K_ff zeta / 2.
!>
!> Uniform gravity g (theory.md 3.6): the potential V = -int rho g . r dV = -g . (m R + A S(zeta)),
!> S(zeta) = m chi + M_PhitPsi zeta = int rho u dV (the first moment: M_PhitPsi = Phi_t^T M Psi is
!> Shabana's shape integral S_bar = int rho Psi dV, an invariant of 3.2), and its generalized force
!> Q_g = -dV/dq = [m g; G_bar^T (S~ A^T g); M_PhitPsi^T A^T g] acts on the translation, the
!> rotation and the modal coordinates; gravity_tangent gives dQ_g/dq exactly.
module ffrf_mbs_flexible_body
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: csr_t, csr_matvec
   use ffrf_fe_geometric_stiffness, only: centrifugal_products, centrifugal_product_jacobian, &
      NUM_CENTRIFUGAL_CASES
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar, skew3, identity3, &
      rotated_vector_jacobian, rotation_vector_matrix, rotation_vector_tangent, check_rotation
   use ffrf_mbs_body, only: body_t
   implicit none
   private
   public :: flexible_body_t

   !> Reduced flexible body: inertia invariants, modal stiffness and damping, markers (one per
   !> interface). num_coordinates = 7 + m; num_markers = number of interfaces.
   type, extends(body_t) :: flexible_body_t
      !> Number of FE nodes, of modes m
      integer :: num_nodes = 0, num_modes = 0
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
      !> Virtual-node mode rows (6 num_markers x m): [Psi_Vt; Psi_Vr] per interface
      real(dp), allocatable :: virtual_shapes(:, :)
      !> Virtual node positions x_V in the body frame (3, number of interfaces) (m)
      real(dp), allocatable :: virtual_xyz(:, :)
      !> Virtual node of each marker (num_markers): markers 1..number of interfaces are the
      !> interfaces' virtual nodes with the node frame, later ones added by add_marker
      integer, allocatable :: marker_node(:)
      !> Constant orientation C of each marker relative to its virtual node's (deformed) frame
      !> (3, 3, num_markers): marker frame A exp(phi~) C (module header)
      real(dp), allocatable :: marker_frame(:, :, :)
      !> The marker has a frame C /= I (identity markers skip the product: no round-off)
      logical, allocatable :: framed(:)
      !> Modal geometric stiffness K_G^(c) (m x m x 6) of the centrifugal load cases (module
      !> header); not allocated: linear modal FFRF, no stiffening (the default)
      real(dp), allocatable :: geometric_stiffness(:, :, :)
   contains
      procedure :: init => flexible_body_init
      procedure :: set_modal_damping => flexible_body_set_modal_damping
      !> A further marker at a virtual node with a constant orientation C (joint frames)
      procedure :: add_marker => flexible_body_add_marker
      !> Turn on the geometric stiffening with the K_G^(c) of the six centrifugal load cases
      procedure :: set_geometric_stiffness => flexible_body_set_geometric_stiffness
      procedure :: mass_matrix => flexible_body_mass_matrix
      procedure :: quadratic_velocity => flexible_body_quadratic_velocity
      !> Exact -df_v/dq and -df_v/dv (Newton tangents of the mechanism)
      procedure :: quadratic_velocity_tangents => flexible_body_quadratic_velocity_tangents
      !> Exact -d(f_v + Q_e)/dq and -d(f_v + Q_e)/dv
      procedure :: force_tangents => flexible_body_force_tangents
      !> Hessian of weighted marker position and axes (joints' constraint stiffness)
      procedure :: marker_hessian => flexible_body_marker_hessian
      !> d(marker_generalized_force)/dq at a fixed force and moment
      procedure :: marker_force_tangent => flexible_body_marker_force_tangent
      !> d(M(q) a)/dq at a fixed a
      procedure :: mass_stiffness => flexible_body_mass_stiffness
      !> Marker position, orientation, position and axis Jacobians in one call
      procedure :: marker_kinematics => flexible_body_marker_kinematics
      procedure :: elastic_force => flexible_body_elastic_force
      procedure :: strain_energy => flexible_body_strain_energy
      !> Power of the modal damping zeta_dot^T D_ff zeta_dot (W)
      procedure :: damping_power => flexible_body_damping_power
      procedure :: marker_position => flexible_body_marker_position
      procedure :: marker_orientation => flexible_body_marker_orientation
      procedure :: marker_velocity_jacobian => flexible_body_marker_velocity_jacobian
      procedure :: marker_position_jacobian => flexible_body_marker_position_jacobian
      procedure :: marker_rotation_jacobian => flexible_body_marker_rotation_jacobian
      procedure :: marker_axis_jacobian => flexible_body_marker_axis_jacobian
      procedure :: marker_generalized_force => flexible_body_marker_generalized_force
      !> First moment of mass int rho u dV = m chi + M_PhitPsi zeta, body frame (kg m)
      procedure :: first_moment => flexible_body_first_moment
      !> Potential of uniform gravity V = -g . (m R + A (m chi + M_PhitPsi zeta)) (J)
      procedure :: gravity_potential => flexible_body_gravity_potential
      !> Generalized gravity force Q_g = -dV/dq (theory.md 3.6)
      procedure :: gravity_force => flexible_body_gravity_force
      !> dQ_g/dq at fixed g (the mechanism subtracts it from -df/dq)
      procedure :: gravity_tangent => flexible_body_gravity_tangent
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
      !> Virtual-node rows of the modes (6 num_markers, m): [u; theta] per interface, as
      !> body_modes_t%virtual_node_shape
      real(dp), intent(in) :: virtual_shapes(:, :)
      !> Virtual node positions (3, num_markers) (m), body frame
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
      self%num_markers = size(virtual_xyz, 2)
      self%num_coordinates = 7 + nm
      self%stiffness = eigenvalues
      allocate (self%damping(nm), source=0.0_dp)
      self%virtual_shapes = virtual_shapes
      self%virtual_xyz = virtual_xyz
      self%marker_node = [(i, i=1, self%num_markers)]
      allocate (self%marker_frame(3, 3, self%num_markers), source=0.0_dp)
      do i = 1, self%num_markers
         self%marker_frame(:, :, i) = identity3()
      end do
      allocate (self%framed(self%num_markers), source=.false.)

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

   !> Add marker num_markers + 1 at virtual node `node` with the constant orientation `frame` (C,
   !> marker axes in the virtual node's frame; module header): its frame is A exp(phi~) C. C
   !> must be a rotation (check_rotation: |C C^T - I| <= 1e-9, det C > 0).
   subroutine flexible_body_add_marker(self, node, frame, marker, error)
      class(flexible_body_t), intent(inout) :: self
      !> Interface (virtual node) number, 1..size(virtual_xyz, 2)
      integer, intent(in) :: node
      !> C (3 x 3), columns the marker axes in the virtual node's frame
      real(dp), intent(in) :: frame(3, 3)
      !> Number of the new marker
      integer, intent(out) :: marker
      type(error_t), allocatable, intent(out) :: error
      marker = 0
      if (node < 1 .or. node > size(self%virtual_xyz, 2)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body marker: virtual node ' // &
            to_str(node) // ' out of range 1..' // to_str(size(self%virtual_xyz, 2)) // &
            '; pass an interface number')
         return
      end if
      call check_rotation(frame, 'flexible body marker at interface ' // to_str(node) // &
         ': the frame', error)
      if (allocated(error)) return
      self%num_markers = self%num_markers + 1
      marker = self%num_markers
      self%marker_node = [self%marker_node, node]
      self%marker_frame = reshape([self%marker_frame, frame], [3, 3, marker])
      self%framed = [self%framed, any(frame /= identity3())]
   end subroutine flexible_body_add_marker

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

   !> Geometric stiffening (module header): K_G^(c), one symmetric m x m matrix per centrifugal
   !> load case in the order of centrifugal_products (ffrf_modes_modal_geometric_stiffness).
   subroutine flexible_body_set_geometric_stiffness(self, geometric_stiffness, error)
      class(flexible_body_t), intent(inout) :: self
      !> K_G^(c) (m, m, 6); dimensionless for mass-normalised modes (p_c K_G^(c) is in 1/s^2)
      real(dp), intent(in) :: geometric_stiffness(:, :, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: m
      m = self%num_modes
      if (size(geometric_stiffness, 1) /= m .or. size(geometric_stiffness, 2) /= m .or. &
         size(geometric_stiffness, 3) /= NUM_CENTRIFUGAL_CASES) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: geometric stiffness ' // &
            to_str(size(geometric_stiffness, 1)) // ' x ' // to_str(size(geometric_stiffness, &
            2)) // ' x ' // to_str(size(geometric_stiffness, 3)) // ' for ' // to_str(m) // &
            ' modes; pass one m x m matrix per centrifugal load case (m x m x 6)')
         return
      end if
      if (.not. all(ieee_is_finite(geometric_stiffness))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: NaN or Inf in the ' // &
            'geometric stiffness')
         return
      end if
      self%geometric_stiffness = geometric_stiffness
   end subroutine flexible_body_set_geometric_stiffness

   !> K_G(omega) = sum_c p_c(omega) K_G^(c) (m x m; module header).
   pure function geometric_matrix(self, omega) result(K_G)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: omega(3)
      real(dp) :: K_G(self%num_modes, self%num_modes)
      real(dp) :: p(NUM_CENTRIFUGAL_CASES)
      integer :: load_case
      p = centrifugal_products(omega)
      K_G = 0.0_dp
      do load_case = 1, NUM_CENTRIFUGAL_CASES
         K_G = K_G + p(load_case) * self%geometric_stiffness(:, :, load_case)
      end do
   end function geometric_matrix

   !> Exact tangents of f_G = -K_G(omega) zeta added to K = -df/dq and C = -df/dv. With
   !> g_c = K_G^(c) zeta, P = dp/domega (6 x 3) and omega = G_bar(theta) theta_dot
   !> = -G_bar(theta_dot) theta:  -df/dzeta = K_G(omega), -df/dtheta = -g P G_bar(theta_dot),
   !> -df/dtheta_dot = g P G_bar(theta).
   pure subroutine add_geometric_tangents(self, q, omega, G_bar, G_dot, K, C)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: q(:), omega(3), G_bar(3, 4), G_dot(3, 4)
      real(dp), intent(inout) :: K(:, :), C(:, :)
      real(dp) :: g(self%num_modes, NUM_CENTRIFUGAL_CASES), gp(self%num_modes, 3)
      integer :: nc, load_case
      nc = self%num_coordinates
      do load_case = 1, NUM_CENTRIFUGAL_CASES
         g(:, load_case) = matmul(self%geometric_stiffness(:, :, load_case), q(8:nc))
      end do
      gp = matmul(g, centrifugal_product_jacobian(omega))
      K(8:nc, 8:nc) = K(8:nc, 8:nc) + geometric_matrix(self, omega)
      K(8:nc, 4:7) = K(8:nc, 4:7) - matmul(gp, G_dot)
      C(8:nc, 4:7) = C(8:nc, 4:7) + matmul(gp, G_bar)
   end subroutine add_geometric_tangents

   !> sum_j z_j B(:, 3j-2:3j) = B (z (x) I3), for B with 3 rows and 3m columns (3 x 3; a
   !> fixed-size result: no heap temporary in the per-evaluation paths).
   pure function times_z(B, z) result(c)
      real(dp), intent(in) :: B(:, :), z(:)
      real(dp) :: c(3, 3)
      integer :: j
      c = 0.0_dp
      do j = 1, size(z)
         c = c + z(j) * B(1:3, 3 * j - 2:3 * j)
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

   !> P = N (z (x) I3) for N with 3m columns (P: size(N, 1) x 3): column c is
   !> sum_k z_k N(:, 3k-3+c), contiguous column updates that vectorise (a subroutine: a function
   !> result of run-time size would go through the heap).
   pure subroutine n_times_z(N, z, P)
      real(dp), intent(in) :: N(:, :), z(:)
      real(dp), intent(out) :: P(:, :)
      integer :: k, c
      P = 0.0_dp
      do k = 1, size(z)
         do c = 1, 3
            P(:, c) = P(:, c) + z(k) * N(:, 3 * k - 3 + c)
         end do
      end do
   end subroutine n_times_z

   !> (z (x) I3)^T N (y (x) I3) = sum_jk z_j y_k N(3j-2:3j, 3k-2:3k) for N with 3m x 3m (3 x 3),
   !> as (z (x) I3)^T P with P = N (y (x) I3).
   pure function z_times_z(z, N, y) result(c)
      real(dp), intent(in) :: z(:), N(:, :), y(:)
      real(dp) :: c(3, 3), P(size(N, 1), 3)
      integer :: j
      call n_times_z(N, y, P)
      c = 0.0_dp
      do j = 1, size(z)
         c = c + z(j) * P(3 * j - 2:3 * j, :)
      end do
   end function z_times_z

   !> Deformed inertia I_thth(zeta) = Theta_u + M_xPsi~ (z(x)I) + (z(x)I)^T M_xPsi~^T
   !> + (z(x)I)^T M_Psi~Psi~ (z(x)I) (theory.md 3.3) = u~^T M u~ (kg m^2).
   pure function deformed_inertia(self, zeta, P) result(inertia)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: zeta(:)
      !> N (zeta (x) I3), N = M_Psi~Psi~ (n_times_z), if the caller has it already
      real(dp), intent(in), optional :: P(:, :)
      real(dp) :: inertia(3, 3), x(3, 3)
      integer :: j
      x = times_z(self%m_x_psit, zeta)
      inertia = self%theta_u + x + transpose(x)
      if (present(P)) then
         do j = 1, size(zeta)
            inertia = inertia + zeta(j) * P(3 * j - 2:3 * j, :)
         end do
      else
         inertia = inertia + z_times_z(zeta, self%m_psit_psit, zeta)
      end if
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
      real(dp) :: A(3, 3), G_bar(3, 4), h(3)
      integer :: nc, j, l
      nc = self%num_coordinates
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      associate (zeta => q(8:nc))
         mass_matrix = 0.0_dp
         do j = 1, 3
            mass_matrix(j, j) = self%mass
         end do
         mass_matrix(1:3, 4:7) = -matmul(A, matmul(first_moment_skew(self, zeta), G_bar))
         mass_matrix(4:7, 4:7) = matmul(transpose(G_bar), &
            matmul(deformed_inertia(self, zeta), G_bar))
         ! Column by column (3-vectors): no m-sized temporaries
         do l = 1, self%num_modes
            mass_matrix(1:3, 7 + l) = matmul(A, self%m_phit_psi(:, l))
            h = self%m_x_psi(:, l)
            do j = 1, self%num_modes
               h = h + zeta(j) * self%m_psit_psi(3 * j - 2:3 * j, l)
            end do
            mass_matrix(4:7, 7 + l) = -matmul(h, G_bar)
         end do
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
   !> With the geometric stiffening on, f_vf also has -K_G(w) z (module header).
   pure function flexible_body_quadratic_velocity(self, q, v) result(f_v)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Velocities [R_dot; theta_dot; zeta_dot]
      real(dp), intent(in) :: v(:)
      real(dp) :: f_v(self%num_coordinates)
      real(dp) :: A(3, 3), G_bar(3, 4), omega(3), w_skew(3, 3), coriolis(3, 3), W_j(3, 3)
      real(dp) :: P(3 * self%num_modes, 3)
      integer :: nc, j, k
      nc = self%num_coordinates
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      omega = matmul(G_bar, v(4:7))
      w_skew = skew3(omega)
      associate (zeta => q(8:nc), zeta_dot => v(8:nc))
         ! P = N (z (x) I3): the quadratic term of I_thth and the sums in W_j below
         call n_times_z(self%m_psit_psit, zeta, P)
         f_v(1:3) = matmul(A, matmul(w_skew, matmul(first_moment_skew(self, zeta), omega)) + &
            2.0_dp * matmul(times_z(self%m_phit_psit, zeta_dot), omega))
         coriolis = times_z(self%m_x_psit, zeta_dot) + &
            z_times_z(zeta, self%m_psit_psit, zeta_dot)
         f_v(4:7) = -matmul(transpose(G_bar), matmul(w_skew, &
            matmul(deformed_inertia(self, zeta, P), omega)) + 2.0_dp * matmul(coriolis, omega))
         ! W_j = M_xPsi~(:, 3j-2:3j)^T + sum_k z_k N_jk (3 x 3 blocks of the header's W), the
         ! sums being the blocks of P
         do j = 1, self%num_modes
            W_j = transpose(self%m_x_psit(:, 3 * j - 2:3 * j)) + P(3 * j - 2:3 * j, :)
            f_v(7 + j) = dot_product(omega, matmul(W_j, omega))
            do k = 1, self%num_modes
               f_v(7 + j) = f_v(7 + j) + 2.0_dp * zeta_dot(k) * &
                  dot_product(self%m_psit_psi(3 * k - 2:3 * k, j), omega)
            end do
         end do
         ! Geometric stiffening, optional: -K_G(omega) zeta (module header)
         if (allocated(self%geometric_stiffness)) f_v(8:nc) = f_v(8:nc) - &
            matmul(geometric_matrix(self, omega), zeta)
      end associate
   end function flexible_body_quadratic_velocity

   !> Exact -df_v/dq and -df_v/dv of the quadratic velocity vector
   !> (flexible_body_quadratic_velocity) by the chain rule through
   !> omega = G_bar(theta) theta_dot = -G_bar(theta_dot) theta:
   !> f_v = [A a; -G_bar^T b; c] with the body-frame vectors
   !>     a = w~ S w + 2 T w,  S = m chi~ + sum_k z_k P_k,  T = sum_k zd_k P_k,
   !>     b = w~ I w + 2 Cor w, I = I_thth(zeta), Cor = sum_k zd_k (Q_k + sum_j z_j N_jk),
   !>     c_j = w^T (Q_j^T + sum_k z_k N_jk) w + 2 sum_k zd_k m_Psi~Psi(3k-2:3k, j) . w,
   !> P_k, Q_k the 3 x 3 blocks of M_PhitPsi~ and M_xPsi~, N_jk those of M_Psi~Psi~ (z = zeta,
   !> zd = zeta_dot, w = omega); derivatives in w, z and zd are linear algebra on these blocks.
   pure subroutine flexible_body_quadratic_velocity_tangents(self, q, v, K, C)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Velocities [R_dot; theta_dot; zeta_dot]
      real(dp), intent(in) :: v(:)
      !> -df_v/dq, (7+m) x (7+m)
      real(dp), intent(out) :: K(:, :)
      !> -df_v/dv, (7+m) x (7+m)
      real(dp), intent(out) :: C(:, :)
      real(dp) :: A(3, 3), G_bar(3, 4), G_dot(3, 4), omega(3), w_skew(3, 3), S(3, 3), T(3, 3)
      real(dp) :: inertia(3, 3), coriolis(3, 3), a_vec(3), b_vec(3), a_w(3, 3), b_w(3, 3)
      real(dp) :: a_z(3, self%num_modes), a_zd(3, self%num_modes), b_z(3, self%num_modes)
      real(dp) :: b_zd(3, self%num_modes), c_w(self%num_modes, 3), c_z(self%num_modes, &
         self%num_modes), c_zd(self%num_modes, self%num_modes), W_j(3, 3), D(3, 3)
      integer :: m, nc, j, l
      m = self%num_modes
      nc = self%num_coordinates
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      G_dot = euler_g_bar(v(4:7))
      omega = matmul(G_bar, v(4:7))
      w_skew = skew3(omega)
      associate (zeta => q(8:nc), zeta_dot => v(8:nc))
         S = first_moment_skew(self, zeta)
         T = times_z(self%m_phit_psit, zeta_dot)
         inertia = deformed_inertia(self, zeta)
         coriolis = times_z(self%m_x_psit, zeta_dot) + &
            z_times_z(zeta, self%m_psit_psit, zeta_dot)
         a_vec = matmul(w_skew, matmul(S, omega)) + 2.0_dp * matmul(T, omega)
         b_vec = matmul(w_skew, matmul(inertia, omega)) + 2.0_dp * matmul(coriolis, omega)
         a_w = -skew3(matmul(S, omega)) + matmul(w_skew, S) + 2.0_dp * T
         b_w = -skew3(matmul(inertia, omega)) + matmul(w_skew, inertia) + 2.0_dp * coriolis
         c_w = 0.0_dp
         do l = 1, m
            associate (P_l => self%m_phit_psit(:, 3 * l - 2:3 * l), &
               Q_l => self%m_x_psit(:, 3 * l - 2:3 * l))
               a_z(:, l) = matmul(w_skew, matmul(P_l, omega))
               a_zd(:, l) = 2.0_dp * matmul(P_l, omega)
               ! dI/dz_k = Q_l + Q_l^T + sum_j z_j (N_jk + N_kj); dCor/dz_k = sum_l zd_l N_kl;
               ! dCor/dzd_k = Q_l + sum_j z_j N_jk
               D = Q_l + transpose(Q_l)
               do j = 1, m
                  D = D + zeta(j) * (self%m_psit_psit(3 * j - 2:3 * j, 3 * l - 2:3 * l) + &
                     self%m_psit_psit(3 * l - 2:3 * l, 3 * j - 2:3 * j))
               end do
               b_z(:, l) = matmul(w_skew, matmul(D, omega)) + 2.0_dp * &
                  matmul(times_z(self%m_psit_psit(3 * l - 2:3 * l, :), zeta_dot), omega)
               D = Q_l
               do j = 1, m
                  D = D + zeta(j) * self%m_psit_psit(3 * j - 2:3 * j, 3 * l - 2:3 * l)
               end do
               b_zd(:, l) = 2.0_dp * matmul(D, omega)
            end associate
         end do
         do j = 1, m
            W_j = transpose(self%m_x_psit(:, 3 * j - 2:3 * j)) + &
               times_z(self%m_psit_psit(3 * j - 2:3 * j, :), zeta)
            c_w(j, :) = matmul(W_j + transpose(W_j), omega)
            do l = 1, m
               c_w(j, :) = c_w(j, :) + 2.0_dp * zeta_dot(l) * &
                  self%m_psit_psi(3 * l - 2:3 * l, j)
               c_z(j, l) = dot_product(omega, matmul(self%m_psit_psit(3 * j - 2:3 * j, &
                  3 * l - 2:3 * l), omega))
               c_zd(j, l) = 2.0_dp * dot_product(self%m_psit_psi(3 * l - 2:3 * l, j), omega)
            end do
         end do
      end associate
      ! df/dq and df/dv, then the signs of K = -df/dq, C = -df/dv
      K = 0.0_dp
      C = 0.0_dp
      K(1:3, 4:7) = rotated_vector_jacobian(q(4:7), a_vec) - matmul(A, matmul(a_w, G_dot))
      K(1:3, 8:nc) = matmul(A, a_z)
      C(1:3, 4:7) = matmul(A, matmul(a_w, G_bar))
      C(1:3, 8:nc) = matmul(A, a_zd)
      K(4:7, 4:7) = -g_bar_transpose_derivative(b_vec) + &
         matmul(transpose(G_bar), matmul(b_w, G_dot))
      K(4:7, 8:nc) = -matmul(transpose(G_bar), b_z)
      C(4:7, 4:7) = -matmul(transpose(G_bar), matmul(b_w, G_bar))
      C(4:7, 8:nc) = -matmul(transpose(G_bar), b_zd)
      K(8:nc, 4:7) = -matmul(c_w, G_dot)
      K(8:nc, 8:nc) = c_z
      C(8:nc, 4:7) = matmul(c_w, G_bar)
      C(8:nc, 8:nc) = c_zd
      K = -K
      C = -C
      if (allocated(self%geometric_stiffness)) call add_geometric_tangents(self, q, omega, &
         G_bar, G_dot, K, C)
   end subroutine flexible_body_quadratic_velocity_tangents

   !> d(G_bar(theta)^T p)/dtheta = 2 [[0, -p^T], [p, -p~]] (4 x 4; G_bar is linear in theta).
   pure function g_bar_transpose_derivative(p) result(B)
      real(dp), intent(in) :: p(3)
      real(dp) :: B(4, 4)
      B(1, 1) = 0.0_dp
      B(1, 2:4) = -2.0_dp * p
      B(2:4, 1) = 2.0_dp * p
      B(2:4, 2:4) = -2.0_dp * skew3(p)
   end function g_bar_transpose_derivative

   !> Hessian (7+m) x (7+m) of w_r . r_V + sum_j w_j . A_V e_j for marker k (the second
   !> derivatives of joint equations, weighted by their multipliers; a marker frame C turns the
   !> weights into the node frame's, W = w_axes C^T). With b_p = x_V + Psi_Vt zeta
   !> and b_j = exp(phi~) e_j, phi = Psi_Vr zeta, every term is w . A(theta) b(zeta):
   !> - theta-theta: exact, constant in theta (A + I is a quadratic form in theta): euler terms
   !>   of X = w_r b_p^T + sum_j w_j b_j^T;
   !> - theta-zeta: exact, d(w . A b)/dtheta is linear in b (Z(w) b, Z 4 x 3) with
   !>   db_p/dzeta = Psi_Vt, db_j/dzeta = -b_j~ T(phi) Psi_Vr;
   !> - zeta-zeta: the position is linear in zeta; the axes give Psi_Vr^T dt/dphi Psi_Vr with
   !>   t(phi) = T(phi)^T sum_j b_j x (A^T w_j), dt/dphi (3 x 3) by central differences in phi
   !>   (the exponential map's second derivative);
   !> - rows and columns of R: zero.
   pure subroutine flexible_body_marker_hessian(self, q, k, w_position, w_axes, H)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      !> Weight of the marker position (3)
      real(dp), intent(in) :: w_position(3)
      !> Weights of the marker axes (3 x 3, column j for axis j)
      real(dp), intent(in) :: w_axes(3, 3)
      !> The Hessian ((7+m) x (7+m))
      real(dp), intent(out) :: H(:, :)
      real(dp) :: A(3, 3), E(3, 3), X(3, 3), phi(3), delta, b_p(3), Z(4, 3), y(3, 3)
      real(dp) :: T(3, 3), Z_axes(4, 3, 3), column(4), t_l(3), dt(3, 3), t_plus(3), t_minus(3)
      real(dp) :: shifted(3), W(3, 3)
      logical :: need(3)
      integer :: m, j, l
      integer :: row
      row = 6 * self%marker_node(k)
      ! sum_j w_j . A E C e_j = sum_i (W C^T)(:, i) . A E e_i: the node frame's weights
      if (self%framed(k)) then
         W = matmul(w_axes, transpose(self%marker_frame(:, :, k)))
      else
         W = w_axes
      end if
      m = self%num_modes
      A = euler_rotation(q(4:7))
      phi = marker_rotation_vector(self, q, k)
      E = rotation_vector_matrix(phi)
      b_p = marker_local(self, q, k)
      H = 0.0_dp
      ! theta-theta
      X = matmul(W, transpose(E))
      do j = 1, 3
         X(:, j) = X(:, j) + w_position * b_p(j)
      end do
      H(4:7, 4:7) = euler_quadratic_hessian(X)
      ! theta-zeta, mode by mode (3-vectors, no m-sized temporaries)
      T = rotation_vector_tangent(phi)
      Z = theta_gradient_matrix(q(4:7), w_position)
      do j = 1, 3
         need(j) = .not. all(W(:, j) == 0.0_dp)
         if (need(j)) Z_axes(:, :, j) = matmul(theta_gradient_matrix(q(4:7), W(:, j)), &
            skew3(E(:, j)))
      end do
      do l = 1, m
         column = matmul(Z, self%virtual_shapes(row - 5:row - 3, l))
         t_l = matmul(T, self%virtual_shapes(row - 2:row, l))
         do j = 1, 3
            if (need(j)) column = column - matmul(Z_axes(:, :, j), t_l)
         end do
         H(4:7, 7 + l) = column
         H(7 + l, 4:7) = column
      end do
      ! zeta-zeta
      if (any(W /= 0.0_dp)) then
         y = matmul(transpose(A), W)
         do j = 1, 3
            delta = epsilon(1.0_dp)**(1.0_dp / 3.0_dp) * max(abs(phi(j)), 1.0_dp)
            shifted = phi
            shifted(j) = phi(j) + delta
            t_plus = axis_term(shifted)
            shifted(j) = phi(j) - delta
            t_minus = axis_term(shifted)
            dt(:, j) = (t_plus - t_minus) / (2.0_dp * delta)
         end do
         dt = 0.5_dp * (dt + transpose(dt))
         do l = 1, m
            t_l = matmul(dt, self%virtual_shapes(row - 2:row, l))
            do j = 1, m
               H(7 + j, 7 + l) = dot_product(self%virtual_shapes(row - 2:row, j), t_l)
            end do
         end do
      end if
   contains
      !> t(phi) = T(phi)^T sum_j exp(phi~) e_j x y_j.
      pure function axis_term(rotation) result(t)
         real(dp), intent(in) :: rotation(3)
         real(dp) :: t(3)
         real(dp) :: exp_matrix(3, 3)
         integer :: i
         exp_matrix = rotation_vector_matrix(rotation)
         t = 0.0_dp
         do i = 1, 3
            t = t + cross_product(exp_matrix(:, i), y(:, i))
         end do
         t = matmul(transpose(rotation_vector_tangent(rotation)), t)
      end function axis_term
   end subroutine flexible_body_marker_hessian

   !> Z(theta, w) (4 x 3) with Z b = d(w . A(theta) b)/dtheta = rotated_vector_jacobian(theta,
   !> b)^T w, linear in b.
   pure function theta_gradient_matrix(theta, w) result(Z)
      real(dp), intent(in) :: theta(4), w(3)
      real(dp) :: Z(4, 3)
      real(dp), parameter :: unit_axes(3, 3) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3])
      integer :: c
      do c = 1, 3
         Z(:, c) = matmul(w, rotated_vector_jacobian(theta, unit_axes(:, c)))
      end do
   end function theta_gradient_matrix

   !> Hessian in theta of sum w^T A(theta) b, from X = sum w b^T (4 x 4; A + I = 2 e0^2 I
   !> + 2 e e^T + 2 e0 e~ is a quadratic form): H_00 = 4 tr X, H_ee = 2 (X + X^T),
   !> H_0e = 2 sum b x w.
   pure function euler_quadratic_hessian(X) result(H)
      real(dp), intent(in) :: X(3, 3)
      real(dp) :: H(4, 4)
      H(1, 1) = 4.0_dp * (X(1, 1) + X(2, 2) + X(3, 3))
      H(2:4, 1) = 2.0_dp * [X(3, 2) - X(2, 3), X(1, 3) - X(3, 1), X(2, 1) - X(1, 2)]
      H(1, 2:4) = H(2:4, 1)
      H(2:4, 2:4) = 2.0_dp * (X + transpose(X))
   end function euler_quadratic_hessian

   !> d(L_r^T F + L_w^T M)/dq at fixed global F, M ((7+m) x (7+m)). With u = x_V + Psi_Vt zeta,
   !> phi = Psi_Vr zeta and y = A^T F, n = A^T M: rows theta are G_bar^T (u x y + n), rows zeta
   !> Psi_Vt^T y + Psi_Vr^T T(phi)^T n. Exact in theta (A, A^T quadratic, G_bar linear) and in
   !> zeta but for d(T(phi)^T n)/dphi (3 x 3), central differences of T (moment loads only).
   pure subroutine flexible_body_marker_force_tangent(self, q, k, force, moment, tangent)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      !> Force, global (N)
      real(dp), intent(in) :: force(3)
      !> Moment, global (N m)
      real(dp), intent(in) :: moment(3)
      !> The derivative ((7+m) x (7+m))
      real(dp), intent(out) :: tangent(:, :)
      real(dp) :: A(3, 3), G_bar(3, 4), u(3), y(3), n(3), p(3), dy(3, 4), dn(3, 4), phi(3)
      real(dp) :: psi_r(3, self%num_modes), delta, t_plus(3), t_minus(3), shifted(3), dt(3, 3)
      integer :: m, nc, l
      integer :: row
      row = 6 * self%marker_node(k)
      m = self%num_modes
      nc = self%num_coordinates
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      u = marker_local(self, q, k)
      y = matmul(transpose(A), force)
      n = matmul(transpose(A), moment)
      p = cross_product(u, y) + n
      dy = transposed_rotation_derivative(q(4:7), force)
      dn = transposed_rotation_derivative(q(4:7), moment)
      psi_r = self%virtual_shapes(row - 2:row, :)
      phi = matmul(psi_r, q(8:nc))
      tangent = 0.0_dp
      tangent(4:7, 4:7) = g_bar_transpose_derivative(p) + matmul(transpose(G_bar), &
         matmul(skew3(u), dy) + dn)
      do l = 1, m
         tangent(4:7, 7 + l) = matmul(transpose(G_bar), &
            cross_product(self%virtual_shapes(row - 5:row - 3, l), y))
      end do
      tangent(8:nc, 4:7) = matmul(transpose(self%virtual_shapes(row - 5:row - 3, :)), dy) &
         + matmul(transpose(psi_r), matmul(transpose(rotation_vector_tangent(phi)), dn))
      if (any(moment /= 0.0_dp)) then
         ! Psi_Vr^T d(T(phi)^T n)/dphi Psi_Vr, the 3 x 3 derivative by central differences
         do l = 1, 3
            delta = epsilon(1.0_dp)**(1.0_dp / 3.0_dp) * max(abs(phi(l)), 1.0_dp)
            shifted = phi
            shifted(l) = phi(l) + delta
            t_plus = matmul(transpose(rotation_vector_tangent(shifted)), n)
            shifted(l) = phi(l) - delta
            t_minus = matmul(transpose(rotation_vector_tangent(shifted)), n)
            dt(:, l) = (t_plus - t_minus) / (2.0_dp * delta)
         end do
         tangent(8:nc, 8:nc) = matmul(transpose(psi_r), matmul(dt, psi_r))
      end if
   end subroutine flexible_body_marker_force_tangent

   !> d(A(theta)^T x)/dtheta (3 x 4): A^T is A at the conjugate [e0, -e].
   pure function transposed_rotation_derivative(theta, x) result(jac)
      real(dp), intent(in) :: theta(4), x(3)
      real(dp) :: jac(3, 4)
      jac = rotated_vector_jacobian([theta(1), -theta(2:4)], x)
      jac(:, 2:4) = -jac(:, 2:4)
   end function transposed_rotation_derivative

   pure function cross_product(a, b) result(c)
      real(dp), intent(in) :: a(3), b(3)
      real(dp) :: c(3)
      c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
   end function cross_product

   !> Exact d(M(q) a)/dq ((7+m) x (7+m)) at fixed a = [a_R; a_theta; a_zeta]. With
   !> alpha = G_bar a_theta = -G_bar(a_theta) theta, S = m chi~ + sum_l z_l P_l (skew),
   !> I = I_thth(zeta), H = M_xPsi + (z (x) I)^T M_Psi~Psi:
   !>     M a = [m a_R + A (-S alpha + M_PhitPsi a_z);
   !>            G_bar^T (S A^T a_R + I alpha - H a_z);
   !>            M_PhitPsi^T A^T a_R - H^T alpha + M_PsiPsi a_z],
   !> differentiated in theta (A, A^T quadratic, G_bar linear) and zeta (S, H linear, I quadratic).
   pure subroutine flexible_body_mass_stiffness(self, q, a, K)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Acceleration held fixed
      real(dp), intent(in) :: a(:)
      !> d(M a)/dq ((7+m) x (7+m))
      real(dp), intent(out) :: K(:, :)
      real(dp) :: rot(3, 3), G_bar(3, 4), G_a(3, 4), S(3, 3), inertia(3, 3), alpha(3), p(3)
      real(dp) :: H(3, self%num_modes), y(3), dy(3, 4), D(3, 3)
      integer :: m, nc, j, l
      m = self%num_modes
      nc = self%num_coordinates
      rot = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      G_a = euler_g_bar(a(4:7))
      alpha = matmul(G_bar, a(4:7))
      y = matmul(transpose(rot), a(1:3))
      dy = transposed_rotation_derivative(q(4:7), a(1:3))
      associate (zeta => q(8:nc), a_z => a(8:nc))
         S = first_moment_skew(self, zeta)
         inertia = deformed_inertia(self, zeta)
         H = self%m_x_psi + z_times(zeta, self%m_psit_psi)
         p = matmul(S, y) + matmul(inertia, alpha) - matmul(H, a_z)
         K = 0.0_dp
         K(1:3, 4:7) = rotated_vector_jacobian(q(4:7), -matmul(S, alpha) + &
            matmul(self%m_phit_psi, a_z)) + matmul(rot, matmul(S, G_a))
         K(4:7, 4:7) = g_bar_transpose_derivative(p) + matmul(transpose(G_bar), &
            matmul(S, dy) - matmul(inertia, G_a))
         K(8:nc, 4:7) = matmul(transpose(self%m_phit_psi), dy) + matmul(transpose(H), G_a)
         do l = 1, m
            associate (P_l => self%m_phit_psit(:, 3 * l - 2:3 * l), &
               Q_l => self%m_x_psit(:, 3 * l - 2:3 * l), &
               N_l => self%m_psit_psi(3 * l - 2:3 * l, :))
               K(1:3, 7 + l) = -matmul(rot, matmul(P_l, alpha))
               D = Q_l + transpose(Q_l)
               do j = 1, m
                  D = D + zeta(j) * (self%m_psit_psit(3 * j - 2:3 * j, 3 * l - 2:3 * l) + &
                     self%m_psit_psit(3 * l - 2:3 * l, 3 * j - 2:3 * j))
               end do
               K(4:7, 7 + l) = matmul(transpose(G_bar), matmul(P_l, y) + matmul(D, alpha) - &
                  matmul(N_l, a_z))
               K(8:nc, 7 + l) = -matmul(transpose(N_l), alpha)
            end associate
         end do
      end associate
   end subroutine flexible_body_mass_stiffness

   !> Marker k in one call, sharing A, u_V, phi, exp(phi~) and T(phi): position R + A u_V,
   !> orientation A exp(phi~), dr/dq = [I, d(A u_V)/dtheta, A Psi_Vt] and, for need_axes(j),
   !> d(A_V e_j)/dq = [0, d(A b_j)/dtheta, -A b_j~ T(phi) Psi_Vr], b_j = exp(phi~) e_j (as the
   !> separate marker functions).
   pure subroutine flexible_body_marker_kinematics(self, q, k, need_axes, position, &
         orientation, position_jacobian, axis_jacobian)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Interface (marker) number
      integer, intent(in) :: k
      !> Which axis Jacobians to form (x, y, z)
      logical, intent(in) :: need_axes(3)
      !> Global position (m)
      real(dp), intent(out) :: position(3)
      !> Orientation, marker frame -> global
      real(dp), intent(out) :: orientation(3, 3)
      !> dr/dq (3 x (7+m))
      real(dp), intent(out) :: position_jacobian(:, :)
      !> d(A_V e_j)/dq (3 x (7+m) x 3)
      real(dp), intent(inout) :: axis_jacobian(:, :, :)
      real(dp) :: A(3, 3), u(3), phi(3), E(3, 3), T(3, 3), t_l(3), AE_skew(3, 3, 3)
      integer :: j, l
      integer :: row
      row = 6 * self%marker_node(k)
      A = euler_rotation(q(4:7))
      u = marker_local(self, q, k)
      phi = marker_rotation_vector(self, q, k)
      E = rotation_vector_matrix(phi)
      if (self%framed(k)) E = matmul(E, self%marker_frame(:, :, k))
      position = q(1:3) + matmul(A, u)
      orientation = matmul(A, E)
      position_jacobian(:, 1:3) = identity3()
      position_jacobian(:, 4:7) = rotated_vector_jacobian(q(4:7), u)
      ! Mode by mode (3-vectors): no m-sized temporaries
      do l = 1, self%num_modes
         position_jacobian(:, 7 + l) = matmul(A, self%virtual_shapes(row - 5:row - 3, l))
      end do
      if (.not. any(need_axes)) return
      T = rotation_vector_tangent(phi)
      do j = 1, 3
         if (.not. need_axes(j)) cycle
         axis_jacobian(:, 1:3, j) = 0.0_dp
         axis_jacobian(:, 4:7, j) = rotated_vector_jacobian(q(4:7), E(:, j))
         AE_skew(:, :, j) = -matmul(A, skew3(E(:, j)))
      end do
      do l = 1, self%num_modes
         t_l = matmul(T, self%virtual_shapes(row - 2:row, l))
         do j = 1, 3
            if (need_axes(j)) axis_jacobian(:, 7 + l, j) = matmul(AE_skew(:, :, j), t_l)
         end do
      end do
   end subroutine flexible_body_marker_kinematics

   !> -d(f_v + Q_e)/dq, -d(f_v + Q_e)/dv, exact: the FFRF quadratic velocity vector
   !> (quadratic_velocity_tangents) and the modal stiffness K_ff and damping D_ff
   !> (Q_e = [0; 0; -K_ff zeta - D_ff zeta_dot]).
   pure subroutine flexible_body_force_tangents(self, q, v, K, C)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Velocities [R_dot; theta_dot; zeta_dot]
      real(dp), intent(in) :: v(:)
      !> -df/dq ((7+m) x (7+m))
      real(dp), intent(out) :: K(:, :)
      !> -df/dv ((7+m) x (7+m))
      real(dp), intent(out) :: C(:, :)
      integer :: j
      call self%quadratic_velocity_tangents(q, v, K, C)
      do j = 1, self%num_modes
         K(7 + j, 7 + j) = K(7 + j, 7 + j) + self%stiffness(j)
         if (allocated(self%damping)) C(7 + j, 7 + j) = C(7 + j, 7 + j) + self%damping(j)
      end do
   end subroutine flexible_body_force_tangents

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

   !> Strain energy zeta^T K_ff zeta / 2 (J).
   pure function flexible_body_strain_energy(self, q) result(energy)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates
      real(dp), intent(in) :: q(:)
      real(dp) :: energy
      energy = 0.5_dp * sum(self%stiffness * q(8:self%num_coordinates)**2)
   end function flexible_body_strain_energy

   !> Power of the modal damping, zeta_dot^T D_ff zeta_dot (W).
   pure function flexible_body_damping_power(self, v) result(power)
      class(flexible_body_t), intent(in) :: self
      !> Velocities [R_dot; theta_dot; zeta_dot]
      real(dp), intent(in) :: v(:)
      real(dp) :: power
      power = 0.0_dp
      if (allocated(self%damping)) power = sum(self%damping * v(8:self%num_coordinates)**2)
   end function flexible_body_damping_power

   !> Deformed position of virtual node k in the body frame, u_V = x_V + Psi_Vt zeta.
   pure function marker_local(self, q, k) result(u)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: q(:)
      integer, intent(in) :: k
      real(dp) :: u(3)
      integer :: l
      integer :: row
      row = 6 * self%marker_node(k)
      u = self%virtual_xyz(:, self%marker_node(k))
      do l = 1, self%num_modes
         u = u + q(7 + l) * self%virtual_shapes(row - 5:row - 3, l)
      end do
   end function marker_local

   !> Elastic rotation vector of virtual node k, phi = Psi_Vr zeta (body frame, rad).
   pure function marker_rotation_vector(self, q, k) result(phi)
      class(flexible_body_t), intent(in) :: self
      real(dp), intent(in) :: q(:)
      integer, intent(in) :: k
      real(dp) :: phi(3)
      integer :: l
      integer :: row
      row = 6 * self%marker_node(k)
      phi = 0.0_dp
      do l = 1, self%num_modes
         phi = phi + q(7 + l) * self%virtual_shapes(row - 2:row, l)
      end do
   end function marker_rotation_vector

   !> Global position of marker k, r_V = R + A (x_V + Psi_Vt zeta) (m). k in 1..num_markers.
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

   !> Orientation of marker k (marker frame -> global), A_V = A exp(skew(Psi_Vr zeta)) C.
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
      if (self%framed(k)) R = matmul(R, self%marker_frame(:, :, k))
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
      integer :: row
      row = 6 * self%marker_node(k)
      A = euler_rotation(q(4:7))
      jac(:, 1:3) = identity3()
      jac(:, 4:7) = -matmul(A, matmul(skew3(marker_local(self, q, k)), euler_g_bar(q(4:7))))
      jac(:, 8:) = matmul(A, self%virtual_shapes(row - 5:row - 3, :))
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
      integer :: row
      row = 6 * self%marker_node(k)
      jac(:, 1:3) = identity3()
      jac(:, 4:7) = rotated_vector_jacobian(q(4:7), marker_local(self, q, k))
      jac(:, 8:) = matmul(euler_rotation(q(4:7)), self%virtual_shapes(row - 5:row - 3, :))
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
      integer :: row
      row = 6 * self%marker_node(k)
      A = euler_rotation(q(4:7))
      jac(:, 1:3) = 0.0_dp
      jac(:, 4:7) = matmul(A, euler_g_bar(q(4:7)))
      jac(:, 8:) = matmul(matmul(A, rotation_vector_tangent(marker_rotation_vector(self, q, k))), &
         self%virtual_shapes(row - 2:row, :))
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
      integer :: row
      row = 6 * self%marker_node(k)
      A = euler_rotation(q(4:7))
      phi = marker_rotation_vector(self, q, k)
      if (self%framed(k)) then
         b = matmul(rotation_vector_matrix(phi), matmul(self%marker_frame(:, :, k), axis))
      else
         b = matmul(rotation_vector_matrix(phi), axis)
      end if
      jac(:, 1:3) = 0.0_dp
      jac(:, 4:7) = rotated_vector_jacobian(q(4:7), b)
      jac(:, 8:) = -matmul(matmul(A, matmul(skew3(b), rotation_vector_tangent(phi))), &
         self%virtual_shapes(row - 2:row, :))
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
      real(dp) :: A(3, 3), u(3), y(3), n(3), T(3, 3), Tn(3)
      integer :: l
      ! The header's closed forms (= matmul(force, L_r) + matmul(moment, L_w) without the
      ! 3 x (7+m) Jacobians)
      integer :: row
      row = 6 * self%marker_node(k)
      A = euler_rotation(q(4:7))
      u = marker_local(self, q, k)
      y = matmul(force, A)
      n = matmul(moment, A)
      T = rotation_vector_tangent(marker_rotation_vector(self, q, k))
      Tn = matmul(n, T)
      gen(1:3) = force
      gen(4:7) = matmul(cross_product(u, y) + n, euler_g_bar(q(4:7)))
      do l = 1, self%num_modes
         gen(7 + l) = dot_product(self%virtual_shapes(row - 5:row - 3, l), y) + &
            dot_product(self%virtual_shapes(row - 2:row, l), Tn)
      end do
   end function flexible_body_marker_generalized_force

   !> First moment of mass in the body frame, S(zeta) = int rho u dV = m chi + M_PhitPsi zeta
   !> (kg m; theory.md 3.2, 3.6): the mass times the deformed centre of mass.
   pure function flexible_body_first_moment(self, q) result(moment)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      real(dp) :: moment(3)
      moment = self%mass * self%center_of_mass + matmul(self%m_phit_psi, &
         q(8:self%num_coordinates))
   end function flexible_body_first_moment

   !> Potential energy of the uniform gravity field g (theory.md 3.6, eq. 3.6a):
   !>     V = -int rho g . r dV = -g . (m R + A S(zeta))   (J),
   !> zero at R = 0 in the undeformed pose A = I with the centre of mass at the origin.
   pure function flexible_body_gravity_potential(self, q, gravity) result(energy)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Gravity acceleration, global (m/s^2)
      real(dp), intent(in) :: gravity(3)
      real(dp) :: energy
      energy = -dot_product(gravity, self%mass * q(1:3) + &
         matmul(euler_rotation(q(4:7)), self%first_moment(q)))
   end function flexible_body_gravity_potential

   !> Generalized force of the uniform gravity field g, Q_g = -dV/dq (theory.md 3.6, eq. 3.6b):
   !>     Q_R = m g,  Q_th = G_bar^T (S x A^T g),  Q_f = M_PhitPsi^T A^T g,
   !> with S = m chi + M_PhitPsi zeta. Q_g . v = -dV/dt on the constraint manifold (|theta| = 1),
   !> and Q_th is the tangent part of -dV/dtheta (G_bar theta = 0: no component along theta,
   !> which the normalisation constraint carries). Q_f is the modal load S_f^T A^T g of the
   !> body's weight seen in the body frame.
   pure function flexible_body_gravity_force(self, q, gravity) result(gen)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Gravity acceleration, global (m/s^2)
      real(dp), intent(in) :: gravity(3)
      real(dp) :: gen(self%num_coordinates)
      real(dp) :: y(3)
      y = matmul(gravity, euler_rotation(q(4:7)))
      gen(1:3) = self%mass * gravity
      gen(4:7) = matmul(cross_product(self%first_moment(q), y), euler_g_bar(q(4:7)))
      gen(8:) = matmul(y, self%m_phit_psi)
   end function flexible_body_gravity_force

   !> dQ_g/dq at fixed g ((7+m) x (7+m)), exact (theory.md 3.6, eq. 3.6c). With y = A^T g,
   !> S = m chi + M_PhitPsi zeta, dy/dtheta = d(A^T g)/dtheta:
   !>     rows theta, cols theta: d(G_bar^T p)/dtheta at p = S x y, plus G_bar^T S~ dy/dtheta,
   !>     rows theta, col zeta_l: G_bar^T (M_PhitPsi(:, l) x y),
   !>     rows zeta,  cols theta: M_PhitPsi^T dy/dtheta;
   !> the R rows and columns and the zeta-zeta block are zero (Q_g does not depend on R, and is
   !> linear in zeta only through the theta rows).
   pure subroutine flexible_body_gravity_tangent(self, q, gravity, tangent)
      class(flexible_body_t), intent(in) :: self
      !> Coordinates [R; theta; zeta]
      real(dp), intent(in) :: q(:)
      !> Gravity acceleration, global (m/s^2)
      real(dp), intent(in) :: gravity(3)
      !> The derivative ((7+m) x (7+m))
      real(dp), intent(out) :: tangent(:, :)
      real(dp) :: G_bar(3, 4), y(3), dy(3, 4), moment(3)
      integer :: l, nc
      nc = self%num_coordinates
      G_bar = euler_g_bar(q(4:7))
      y = matmul(gravity, euler_rotation(q(4:7)))
      dy = transposed_rotation_derivative(q(4:7), gravity)
      moment = self%first_moment(q)
      tangent = 0.0_dp
      tangent(4:7, 4:7) = g_bar_transpose_derivative(cross_product(moment, y)) + &
         matmul(transpose(G_bar), matmul(skew3(moment), dy))
      do l = 1, self%num_modes
         tangent(4:7, 7 + l) = matmul(transpose(G_bar), cross_product(self%m_phit_psi(:, l), y))
      end do
      tangent(8:nc, 4:7) = matmul(transpose(self%m_phit_psi), dy)
   end subroutine flexible_body_gravity_tangent

end module ffrf_mbs_flexible_body
