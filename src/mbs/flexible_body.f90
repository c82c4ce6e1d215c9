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
!> interface markers' numbers are unchanged by it, bit for bit). add_point adds a virtual node at
!> a mesh point that is no interface (a node or a physical surface's RBE3 point, no stiffness
!> and no constraint: docs/mechanisms.md "Markers at mesh points") whose rows G Psi_B follow the
!> interfaces'; its markers (add_marker) then move and carry loads as the interfaces' do.
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
      rotated_vector_jacobian, rotation_vector_matrix, rotation_vector_tangent, check_rotation, &
      euler_hessian
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
      !> A further virtual node at a mesh point that is no interface (its mode rows given)
      procedure :: add_point => flexible_body_add_point
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

   interface
      !> Precompute the inertia invariants of theory.md 3.2 from the full consistent mass matrix and
      !> the modes. Checks sizes, finiteness, non-negative eigenvalues and M = Ms (x) I3.
      module subroutine flexible_body_init(self, M, xyz, shapes, eigenvalues, virtual_shapes, &
            virtual_xyz, error)
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
      end subroutine flexible_body_init

      !> Add marker num_markers + 1 at virtual node `node` with the constant orientation `frame` (C,
      !> marker axes in the virtual node's frame; module header): its frame is A exp(phi~) C. C
      !> must be a rotation (check_rotation: |C C^T - I| <= 1e-9, det C > 0).
      module subroutine flexible_body_add_marker(self, node, frame, marker, error)
         class(flexible_body_t), intent(inout) :: self
         !> Interface (virtual node) number, 1..size(virtual_xyz, 2)
         integer, intent(in) :: node
         !> C (3 x 3), columns the marker axes in the virtual node's frame
         real(dp), intent(in) :: frame(3, 3)
         !> Number of the new marker
         integer, intent(out) :: marker
         type(error_t), allocatable, intent(out) :: error
      end subroutine flexible_body_add_marker

      !> Add virtual node size(virtual_xyz, 2) + 1 at a mesh point that is no interface (a node,
      !> or a physical surface's RBE3 point: ffrf_mpc_mesh_point), its rows [Psi_Pt; Psi_Pr] =
      !> G Psi_B of the modes; add_marker then places markers there. No marker is added: the
      !> interfaces' marker numbers are unchanged.
      module subroutine flexible_body_add_point(self, rows, xyz, node, error)
         class(flexible_body_t), intent(inout) :: self
         !> Mode rows of the point (6, m): translation, then the small rotation vector
         real(dp), intent(in) :: rows(:, :)
         !> The point in the body frame (m)
         real(dp), intent(in) :: xyz(3)
         !> Number of the new virtual node
         integer, intent(out) :: node
         type(error_t), allocatable, intent(out) :: error
      end subroutine flexible_body_add_point

      !> Modal damping D_ff = diag(2 xi_j omega_j).
      module subroutine flexible_body_set_modal_damping(self, damping_ratio, error)
         class(flexible_body_t), intent(inout) :: self
         !> Damping ratios xi (one for all modes, or one per mode), >= 0
         real(dp), intent(in) :: damping_ratio(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine flexible_body_set_modal_damping

      !> Geometric stiffening (module header): K_G^(c), one symmetric m x m matrix per centrifugal
      !> load case in the order of centrifugal_products (ffrf_modes_modal_geometric_stiffness).
      module subroutine flexible_body_set_geometric_stiffness(self, geometric_stiffness, error)
         class(flexible_body_t), intent(inout) :: self
         !> K_G^(c) (m, m, 6); dimensionless for mass-normalised modes (p_c K_G^(c) is in 1/s^2)
         real(dp), intent(in) :: geometric_stiffness(:, :, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine flexible_body_set_geometric_stiffness

      !> K_G(omega) = sum_c p_c(omega) K_G^(c) (m x m; module header).
      pure module function geometric_matrix(self, omega) result(K_G)
         class(flexible_body_t), intent(in) :: self
         real(dp), intent(in) :: omega(3)
         real(dp) :: K_G(self%num_modes, self%num_modes)
      end function geometric_matrix

      !> Exact tangents of f_G = -K_G(omega) zeta added to K = -df/dq and C = -df/dv. With
      !> g_c = K_G^(c) zeta, P = dp/domega (6 x 3) and omega = G_bar(theta) theta_dot
      !> = -G_bar(theta_dot) theta:  -df/dzeta = K_G(omega), -df/dtheta = -g P G_bar(theta_dot),
      !> -df/dtheta_dot = g P G_bar(theta).
      pure module subroutine add_geometric_tangents(self, q, omega, G_bar, G_dot, K, C)
         class(flexible_body_t), intent(in) :: self
         real(dp), intent(in) :: q(:), omega(3), G_bar(3, 4), G_dot(3, 4)
         real(dp), intent(inout) :: K(:, :), C(:, :)
      end subroutine add_geometric_tangents

      !> Mass matrix M(q) ((7+m) x (7+m), symmetric), theory.md 3.3:
      !>     m_RR = m I,  m_Rth = -A [m chi~ + M_PhitPsi~ (z(x)I)] G_bar,  m_Rf = A M_PhitPsi,
      !>     m_thth = G_bar^T I_thth(zeta) G_bar,  m_thf = -G_bar^T [M_xPsi + (z(x)I)^T M_Psi~Psi],
      !>     m_ff = M_PsiPsi.
      !> The theta block has rank 3 (G_bar theta = 0): the normalisation constraint completes it.
      pure module function flexible_body_mass_matrix(self, q) result(mass_matrix)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         real(dp) :: mass_matrix(self%num_coordinates, self%num_coordinates)
      end function flexible_body_mass_matrix

      !> Quadratic velocity vector f_v(q, v) (right-hand side), theory.md 3.4, omega = G_bar
      !> theta_dot:
      !>   f_vR  = A w~ [m chi~ + M_PhitPsi~(z(x)I)] w + 2 A M_PhitPsi~ (zd(x)I) w
      !>   f_vth = -G_bar^T w~ I_thth w
      !>           - 2 G_bar^T [M_xPsi~ (zd(x)I) + (z(x)I)^T M_Psi~Psi~ (zd(x)I)] w
      !>   f_vf  = (I (x) w)^T [M_xPsi~^T + M_Psi~Psi~ (z(x)I)] w + 2 M_Psi~Psi^T (zd (x) w)
      !> (z = zeta, zd = zeta_dot). It equals -(dM/dt) v + d(v^T M v / 2)/dq of Lagrange's equations
      !> up to a multiple of theta in the theta rows (taken by the normalisation constraint).
      !> With the geometric stiffening on, f_vf also has -K_G(w) z (module header).
      pure module function flexible_body_quadratic_velocity(self, q, v) result(f_v)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         !> Velocities [R_dot; theta_dot; zeta_dot]
         real(dp), intent(in) :: v(:)
         real(dp) :: f_v(self%num_coordinates)
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
      pure module subroutine flexible_body_quadratic_velocity_tangents(self, q, v, K, C)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         !> Velocities [R_dot; theta_dot; zeta_dot]
         real(dp), intent(in) :: v(:)
         !> -df_v/dq, (7+m) x (7+m)
         real(dp), intent(out) :: K(:, :)
         !> -df_v/dv, (7+m) x (7+m)
         real(dp), intent(out) :: C(:, :)
      end subroutine flexible_body_quadratic_velocity_tangents

      !> d(G_bar(theta)^T p)/dtheta = 2 [[0, -p^T], [p, -p~]] (4 x 4; G_bar is linear in theta).
      pure module function g_bar_transpose_derivative(p) result(B)
         real(dp), intent(in) :: p(3)
         real(dp) :: B(4, 4)
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
      pure module subroutine flexible_body_marker_hessian(self, q, k, w_position, w_axes, H)
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
      end subroutine flexible_body_marker_hessian

      !> d(L_r^T F + L_w^T M)/dq at fixed global F, M ((7+m) x (7+m)). With u = x_V + Psi_Vt zeta,
      !> phi = Psi_Vr zeta and y = A^T F, n = A^T M: rows theta are G_bar^T (u x y + n), rows zeta
      !> Psi_Vt^T y + Psi_Vr^T T(phi)^T n. Exact in theta (A, A^T quadratic, G_bar linear) and in
      !> zeta but for d(T(phi)^T n)/dphi (3 x 3), central differences of T (moment loads only).
      pure module subroutine flexible_body_marker_force_tangent(self, q, k, force, moment, tangent)
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
      end subroutine flexible_body_marker_force_tangent

      !> d(A(theta)^T x)/dtheta (3 x 4): A^T is A at the conjugate [e0, -e].
      pure module function transposed_rotation_derivative(theta, x) result(jac)
         real(dp), intent(in) :: theta(4), x(3)
         real(dp) :: jac(3, 4)
      end function transposed_rotation_derivative

      pure module function cross_product(a, b) result(c)
         real(dp), intent(in) :: a(3), b(3)
         real(dp) :: c(3)
      end function cross_product

      !> Exact d(M(q) a)/dq ((7+m) x (7+m)) at fixed a = [a_R; a_theta; a_zeta]. With
      !> alpha = G_bar a_theta = -G_bar(a_theta) theta, S = m chi~ + sum_l z_l P_l (skew),
      !> I = I_thth(zeta), H = M_xPsi + (z (x) I)^T M_Psi~Psi:
      !>     M a = [m a_R + A (-S alpha + M_PhitPsi a_z);
      !>            G_bar^T (S A^T a_R + I alpha - H a_z);
      !>            M_PhitPsi^T A^T a_R - H^T alpha + M_PsiPsi a_z],
      !> differentiated in theta (A, A^T quadratic, G_bar linear) and zeta (S, H linear, I
      !> quadratic).
      pure module subroutine flexible_body_mass_stiffness(self, q, a, K)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         !> Acceleration held fixed
         real(dp), intent(in) :: a(:)
         !> d(M a)/dq ((7+m) x (7+m))
         real(dp), intent(out) :: K(:, :)
      end subroutine flexible_body_mass_stiffness

      !> Marker k in one call, sharing A, u_V, phi, exp(phi~) and T(phi): position R + A u_V,
      !> orientation A exp(phi~), dr/dq = [I, d(A u_V)/dtheta, A Psi_Vt] and, for need_axes(j),
      !> d(A_V e_j)/dq = [0, d(A b_j)/dtheta, -A b_j~ T(phi) Psi_Vr], b_j = exp(phi~) e_j (as the
      !> separate marker functions).
      pure module subroutine flexible_body_marker_kinematics(self, q, k, need_axes, position, &
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
      end subroutine flexible_body_marker_kinematics

      !> -d(f_v + Q_e)/dq, -d(f_v + Q_e)/dv, exact: the FFRF quadratic velocity vector
      !> (quadratic_velocity_tangents) and the modal stiffness K_ff and damping D_ff
      !> (Q_e = [0; 0; -K_ff zeta - D_ff zeta_dot]).
      pure module subroutine flexible_body_force_tangents(self, q, v, K, C)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         !> Velocities [R_dot; theta_dot; zeta_dot]
         real(dp), intent(in) :: v(:)
         !> -df/dq ((7+m) x (7+m))
         real(dp), intent(out) :: K(:, :)
         !> -df/dv ((7+m) x (7+m))
         real(dp), intent(out) :: C(:, :)
      end subroutine flexible_body_force_tangents

      !> Elastic and damping generalized force Q_e = [0; 0; -K_ff zeta - D_ff zeta_dot].
      pure module function flexible_body_elastic_force(self, q, v) result(force)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         !> Velocities
         real(dp), intent(in) :: v(:)
         real(dp) :: force(self%num_coordinates)
      end function flexible_body_elastic_force

      !> Strain energy zeta^T K_ff zeta / 2 (J).
      pure module function flexible_body_strain_energy(self, q) result(energy)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         real(dp) :: energy
      end function flexible_body_strain_energy

      !> Power of the modal damping, zeta_dot^T D_ff zeta_dot (W).
      pure module function flexible_body_damping_power(self, v) result(power)
         class(flexible_body_t), intent(in) :: self
         !> Velocities [R_dot; theta_dot; zeta_dot]
         real(dp), intent(in) :: v(:)
         real(dp) :: power
      end function flexible_body_damping_power

      !> Global position of marker k, r_V = R + A (x_V + Psi_Vt zeta) (m). k in 1..num_markers.
      pure module function flexible_body_marker_position(self, q, k) result(r)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Interface (marker) number
         integer, intent(in) :: k
         real(dp) :: r(3)
      end function flexible_body_marker_position

      !> Orientation of marker k (marker frame -> global), A_V = A exp(skew(Psi_Vr zeta)) C.
      pure module function flexible_body_marker_orientation(self, q, k) result(A_v)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Interface (marker) number
         integer, intent(in) :: k
         real(dp) :: A_v(3, 3)
      end function flexible_body_marker_orientation

      !> Velocity Jacobian L_r of marker k, r_V_dot = L_r v = [I, -A u_V~ G_bar, A Psi_Vt] v
      !> (3 x (7+m)); equals marker_position_jacobian on tangent velocities (theta^T theta_dot = 0,
      !> |theta| = 1). Its transpose maps a global force to generalized forces (theory.md 3.5).
      pure module function flexible_body_marker_velocity_jacobian(self, q, k) result(jac)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Interface (marker) number
         integer, intent(in) :: k
         real(dp) :: jac(3, self%num_coordinates)
      end function flexible_body_marker_velocity_jacobian

      !> Exact partial derivatives of the marker position, dr_V/dq (3 x (7+m)), in all four
      !> Euler-parameter directions (rotated_vector_jacobian): the Jacobian of position-level joint
      !> equations Phi(q) = 0.
      pure module function flexible_body_marker_position_jacobian(self, q, k) result(jac)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Interface (marker) number
         integer, intent(in) :: k
         real(dp) :: jac(3, self%num_coordinates)
      end function flexible_body_marker_position_jacobian

      !> Rotation Jacobian L_w of marker k (3 x (7+m)) = [0, A G_bar, A T(phi) Psi_Vr]: the global
      !> angular velocity omega_V = L_w v, and the global small rotation dpi_V of the marker frame
      !> (dA_V = skew(dpi_V) A_V) for a tangent variation dq. Its transpose maps a global moment to
      !> generalized forces (theory.md 3.5; T = I + O(zeta)).
      pure module function flexible_body_marker_rotation_jacobian(self, q, k) result(jac)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Interface (marker) number
         integer, intent(in) :: k
         real(dp) :: jac(3, self%num_coordinates)
      end function flexible_body_marker_rotation_jacobian

      !> Exact partial derivatives d(A_V a)/dq (3 x (7+m)) of a marker-fixed axis a, all four
      !> Euler-parameter directions included: the Jacobian of joint equations on marker axes
      !> (revolute, universal, prismatic: dot products of axes).
      pure module function flexible_body_marker_axis_jacobian(self, q, k, axis) result(jac)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates
         real(dp), intent(in) :: q(:)
         !> Interface (marker) number
         integer, intent(in) :: k
         !> Axis in the marker frame
         real(dp), intent(in) :: axis(3)
         real(dp) :: jac(3, self%num_coordinates)
      end function flexible_body_marker_axis_jacobian

      !> Generalized force of a global force F and a global moment M_V applied at marker k, by
      !> virtual work Q = L_r^T F + L_w^T M_V (theory.md 3.5):
      !>     Q_R = F,  Q_th = G_bar^T (u_V~ A^T F + A^T M_V),
      !>     Q_f = Psi_Vt^T A^T F + Psi_Vr^T T^T A^T M_V.
      pure module function flexible_body_marker_generalized_force(self, q, k, force, moment) &
         result(gen)
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
      end function flexible_body_marker_generalized_force

      !> First moment of mass in the body frame, S(zeta) = int rho u dV = m chi + M_PhitPsi zeta
      !> (kg m; theory.md 3.2, 3.6): the mass times the deformed centre of mass.
      pure module function flexible_body_first_moment(self, q) result(moment)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         real(dp) :: moment(3)
      end function flexible_body_first_moment

      !> Potential energy of the uniform gravity field g (theory.md 3.6, eq. 3.6a):
      !>     V = -int rho g . r dV = -g . (m R + A S(zeta))   (J),
      !> zero at R = 0 in the undeformed pose A = I with the centre of mass at the origin.
      pure module function flexible_body_gravity_potential(self, q, gravity) result(energy)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         !> Gravity acceleration, global (m/s^2)
         real(dp), intent(in) :: gravity(3)
         real(dp) :: energy
      end function flexible_body_gravity_potential

      !> Generalized force of the uniform gravity field g, Q_g = -dV/dq (theory.md 3.6, eq. 3.6b):
      !>     Q_R = m g,  Q_th = G_bar^T (S x A^T g),  Q_f = M_PhitPsi^T A^T g,
      !> with S = m chi + M_PhitPsi zeta. Q_g . v = -dV/dt on the constraint manifold (|theta| = 1),
      !> and Q_th is the tangent part of -dV/dtheta (G_bar theta = 0: no component along theta,
      !> which the normalisation constraint carries). Q_f is the modal load S_f^T A^T g of the
      !> body's weight seen in the body frame.
      pure module function flexible_body_gravity_force(self, q, gravity) result(gen)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         !> Gravity acceleration, global (m/s^2)
         real(dp), intent(in) :: gravity(3)
         real(dp) :: gen(self%num_coordinates)
      end function flexible_body_gravity_force

      !> dQ_g/dq at fixed g ((7+m) x (7+m)), exact (theory.md 3.6, eq. 3.6c). With y = A^T g,
      !> S = m chi + M_PhitPsi zeta, dy/dtheta = d(A^T g)/dtheta:
      !>     rows theta, cols theta: d(G_bar^T p)/dtheta at p = S x y, plus G_bar^T S~ dy/dtheta,
      !>     rows theta, col zeta_l: G_bar^T (M_PhitPsi(:, l) x y),
      !>     rows zeta,  cols theta: M_PhitPsi^T dy/dtheta;
      !> the R rows and columns and the zeta-zeta block are zero (Q_g does not depend on R, and is
      !> linear in zeta only through the theta rows).
      pure module subroutine flexible_body_gravity_tangent(self, q, gravity, tangent)
         class(flexible_body_t), intent(in) :: self
         !> Coordinates [R; theta; zeta]
         real(dp), intent(in) :: q(:)
         !> Gravity acceleration, global (m/s^2)
         real(dp), intent(in) :: gravity(3)
         !> The derivative ((7+m) x (7+m))
         real(dp), intent(out) :: tangent(:, :)
      end subroutine flexible_body_gravity_tangent
   end interface

contains

end module ffrf_mbs_flexible_body
