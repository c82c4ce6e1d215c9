!> Reduced flexible body in the floating frame of reference (ffrf_mbs_flexible_body) and Euler
!> parameters (ffrf_mbs_rotation), theory.md section 3. Bodies: the reference crank (crank_lc8
!> Tet10 mesh, RBE3 interfaces B1 B2 B3, RC set 3 = B2 clamped, 8 constrained modes) and the
!> free-free beam (beam_lc6, RBE3 ends, no RCs, 6 flexible modes). References: closed forms
!> (Rodrigues, rigid-body mass matrix), a second computation from the FE mass matrix (kinetic
!> energy of the nodal velocities), central finite differences (angular velocity, Lagrange's
!> equations, marker Jacobians) and the mean-axis property of free-free modes (theory.md 7).
module test_mbs_flexible_body
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_fe_material, only: material_t
   use ffrf_fe_assembly, only: assemble_stiffness_mass
   use ffrf_la_sparse, only: csr_t, csr_matvec, csr_from_coo
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_body, only: body_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_body_modes, only: compute_input_body_modes
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar, euler_g, euler_from_axis_angle, &
      euler_from_rotation, euler_normalized, euler_constraint, euler_constraint_jacobian, &
      skew3, axial3, identity3, rotation_vector_matrix, rotation_vector_tangent
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, test_mesh_dir, report
   implicit none
   private
   public :: collect_mbs_flexible_body

   real(dp), parameter :: young = 210.0e9_dp, poisson = 0.3_dp, density = 7850.0_dp

   !> The crank (RC set 3) and the free-free beam, computed once for all tests
   type(body_modes_t), save :: crank_modes, beam_modes
   type(csr_t), save :: crank_mass, beam_mass
   type(flexible_body_t), save :: crank, beam
   logical, save :: crank_ready = .false., beam_ready = .false.

contains

   subroutine collect_mbs_flexible_body(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('rotation_matrix_closed_forms', test_rotation_matrix), &
         new_unittest('angular_velocity_finite_differences', test_angular_velocity), &
         new_unittest('rotation_vector_tangent', test_rotation_vector), &
         new_unittest('invariants_mass_properties', test_invariants), &
         new_unittest('kinetic_energy_from_fe_mass', test_kinetic_energy), &
         new_unittest('quadratic_velocity_lagrange', test_quadratic_velocity), &
         new_unittest('mean_axis_free_free', test_mean_axis), &
         new_unittest('marker_jacobians', test_marker_jacobians), &
         new_unittest('framed_marker_jacobians', test_framed_markers), &
         new_unittest('marker_rigid_motion_and_forces', test_marker_forces), &
         new_unittest('stiff_modes_rigid_limit', test_rigid_limit), &
         new_unittest('init_rejects_bad_input', test_bad_input)]
   end subroutine collect_mbs_flexible_body

   ! ----------------------------------------------------------------------------------------------
   ! Fixtures

   !> Modes and consistent mass of one body; the FE mass is assembled again from the body's mesh
   !> (the same nodes as the modes).
   subroutine load_body(mesh_file, volume, names, rcs, num_modes, modes, M, body, error)
      character(len=*), intent(in) :: mesh_file, volume, names(:), rcs(:)
      integer, intent(in) :: num_modes
      type(body_modes_t), intent(out) :: modes
      type(csr_t), intent(out) :: M
      type(flexible_body_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t) :: input
      type(interface_input_t) :: faces(size(names))
      type(modes_input_t) :: modes_input
      type(logger_t) :: log
      type(stage_times_t) :: times
      type(csr_t) :: stiffness_matrix
      real(dp), allocatable :: virtual_xyz(:, :)
      integer :: k
      input = body_input_t(volume, mesh_file, '', young, poisson, density)
      input%volumes(1) = volume
      do k = 1, size(names)
         faces(k)%body = volume
         faces(k)%name = names(k)
         faces(k)%mpc = 'RBE3'
         faces(k)%rc = rcs(k)
      end do
      modes_input%num_modes = num_modes
      log%level = LOG_QUIET
      call compute_input_body_modes(input, faces, modes_input, test_mesh_dir(), &
         log, times, modes, error)
      if (allocated(error)) then
         call add_context(error, mesh_file)
         return
      end if
      call assemble_stiffness_mass(modes%mesh%xyz, modes%mesh%tets, modes%mesh%tet_tags, &
         material_t(young, poisson, density, 'steel'), stiffness_matrix, M, error)
      if (allocated(error)) return
      allocate (virtual_xyz(3, size(modes%interfaces)))
      do k = 1, size(modes%interfaces)
         virtual_xyz(:, k) = modes%interfaces(k)%virtual_xyz
      end do
      call body%init(M, modes%mesh%xyz, modes%shape, (2.0_dp * pi * modes%frequency_hz)**2, &
         modes%virtual_node_shape, virtual_xyz, error)
   end subroutine load_body

   subroutine get_crank(error)
      type(error_t), allocatable, intent(out) :: error
      if (crank_ready) return
      call load_body('crank_lc8.msh', 'crank', ['B1', 'B2', 'B3'], &
         [character(len=20) :: '', 'Tx Ty Tz Rx Ry Rz', ''], 8, crank_modes, crank_mass, crank, &
         error)
      crank_ready = .not. allocated(error)
   end subroutine get_crank

   subroutine get_beam(error)
      type(error_t), allocatable, intent(out) :: error
      if (beam_ready) return
      call load_body('beam_lc6.msh', 'beam', ['end0', 'end1'], [character(len=4) :: '', ''], 6, &
         beam_modes, beam_mass, beam, error)
      beam_ready = .not. allocated(error)
   end subroutine get_beam

   !> Deterministic pseudo-random numbers in [-1, 1] (a fixed sequence, no state).
   function random_vector(n, seed) result(x)
      integer, intent(in) :: n, seed
      real(dp) :: x(n)
      integer :: i
      do i = 1, n
         x(i) = sin(12.9898_dp * real(i + 37 * seed, dp) + 78.233_dp * real(seed, dp))
         x(i) = 2.0_dp * (x(i) * 43758.5453_dp - floor(x(i) * 43758.5453_dp)) - 1.0_dp
      end do
   end function random_vector

   !> A random state of a body: R ~ 0.1 m, unit theta, zeta ~ zeta_scale; velocities with
   !> theta^T theta_dot = 0 (the derivative of the constraint), omega ~ 300 rad/s.
   subroutine random_state(body, seed, zeta_scale, q, v)
      type(flexible_body_t), intent(in) :: body
      integer, intent(in) :: seed
      real(dp), intent(in) :: zeta_scale
      real(dp), allocatable, intent(out) :: q(:), v(:)
      integer :: nc
      nc = body%num_coordinates
      q = random_vector(nc, seed)
      v = random_vector(nc, seed + 1000)
      q(1:3) = 0.1_dp * q(1:3)
      q(4:7) = euler_normalized(q(4:7))
      q(8:nc) = zeta_scale * q(8:nc)
      v(1:3) = 10.0_dp * v(1:3)
      v(4:7) = 150.0_dp * (v(4:7) - dot_product(v(4:7), q(4:7)) * q(4:7))
      v(8:nc) = 100.0_dp * zeta_scale * v(8:nc)
   end subroutine random_state

   !> The point q(t) = [R + t R_dot; theta(t); zeta + t zeta_dot] of a path on the constraint
   !> manifold with q(0) = q, q_dot(0) = v: theta(t) = (theta + t theta_dot)/|.|, whose
   !> derivative at 0 is theta_dot when theta^T theta_dot = 0.
   function path_point(q, v, t) result(qt)
      real(dp), intent(in) :: q(:), v(:), t
      real(dp) :: qt(size(q))
      qt = q + t * v
      qt(4:7) = euler_normalized(qt(4:7))
   end function path_point

   !> Central differences (3 x nc) of A_V a, marker k, in every coordinate (step h).
   function axis_differences(body, q, k, axis, h) result(fd)
      type(flexible_body_t), intent(in) :: body
      real(dp), intent(in) :: q(:), axis(3), h
      integer, intent(in) :: k
      real(dp) :: fd(3, size(q))
      real(dp) :: dq(size(q))
      integer :: i
      do i = 1, size(q)
         dq = 0.0_dp
         dq(i) = h
         fd(:, i) = (matmul(body%marker_orientation(q + dq, k), axis) - &
            matmul(body%marker_orientation(q - dq, k), axis)) / (2.0_dp * h)
      end do
   end function axis_differences

   !> [|axial(dA_V/dt A_V^T) - L_w v|, |L_w v|] of marker k along the path through q with
   !> velocity v (central differences, path step hp).
   function angular_velocity_defect(body, q, v, k, hp) result(d)
      type(flexible_body_t), intent(in) :: body
      real(dp), intent(in) :: q(:), v(:), hp
      integer, intent(in) :: k
      real(dp) :: d(2)
      real(dp) :: A_v(3, 3), A_dot(3, 3), omega(3)
      A_v = body%marker_orientation(q, k)
      A_dot = (body%marker_orientation(path_point(q, v, hp), k) - &
         body%marker_orientation(path_point(q, v, -hp), k)) / (2.0_dp * hp)
      omega = matmul(body%marker_rotation_jacobian(q, k), v)
      d = [norm2(axial3(matmul(A_dot, transpose(A_v))) - omega), norm2(omega)]
   end function angular_velocity_defect

   function max_abs(a) result(s)
      real(dp), intent(in) :: a(:, :)
      real(dp) :: s
      s = maxval(abs(a))
   end function max_abs

   ! ----------------------------------------------------------------------------------------------
   ! Rotation

   !> A(theta) orthonormal with det 1 for random unit theta (round-off, 1e-14); A from
   !> axis-angle equals Rodrigues' closed form cos(phi) I + sin(phi) n~ + (1 - cos(phi)) n n^T
   !> (1e-14); euler_from_rotation inverts A (all four branches of Shepperd's method, 1e-14);
   !> G = A G_bar, G_bar theta = 0, G_bar G_bar^T = 4 I (1e-14); constraint and its Jacobian.
   subroutine test_rotation_matrix(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: theta(4), A(3, 3), n(3), phi, angle(1), rodrigues(3, 3), back(4), det
      integer :: seed
      do seed = 1, 8
         theta = euler_normalized(random_vector(4, seed))
         ! Put the largest component in each position in turn (the Shepperd branches).
         theta = cshift(theta, maxloc(abs(theta), dim=1) - 1 - mod(seed, 4))
         A = euler_rotation(theta)
         call check_close(error, 'max |A^T A - I|', max_abs(matmul(transpose(A), A) - &
            identity3()), 0.0_dp, atol=1.0e-14_dp)
         if (allocated(error)) return
         det = dot_product(A(:, 1), matmul(skew3(A(:, 2)), A(:, 3)))
         call check_close(error, 'det A', det, 1.0_dp, atol=1.0e-14_dp)
         if (allocated(error)) return
         back = euler_from_rotation(A)
         call check_close(error, 'Euler parameters from A(theta), seed ' // to_str(seed), &
            maxval(abs(back - sign(1.0_dp, theta(1)) * theta)), 0.0_dp, atol=1.0e-14_dp)
         if (allocated(error)) return
         call check_close(error, 'max |G - A G_bar|', max_abs(euler_g(theta) - &
            matmul(A, euler_g_bar(theta))), 0.0_dp, atol=1.0e-14_dp)
         if (.not. allocated(error)) call check_close(error, 'max |G_bar theta|', &
            maxval(abs(matmul(euler_g_bar(theta), theta))), 0.0_dp, atol=1.0e-14_dp)
         if (.not. allocated(error)) call check_close(error, 'max |G_bar G_bar^T - 4 I|', &
            max_abs(matmul(euler_g_bar(theta), transpose(euler_g_bar(theta))) - &
            4.0_dp * identity3()), 0.0_dp, atol=1.0e-14_dp)
         if (allocated(error)) return
         n = random_vector(3, seed + 50)
         angle = pi * random_vector(1, seed + 60)
         phi = angle(1)
         A = euler_rotation(euler_from_axis_angle(n, phi))
         n = n / norm2(n)
         rodrigues = cos(phi) * identity3() + sin(phi) * skew3(n) + (1.0_dp - cos(phi)) * &
            spread(n, 2, 3) * spread(n, 1, 3)
         call check_close(error, 'A(axis, angle) vs Rodrigues', max_abs(A - rodrigues), 0.0_dp, &
            atol=1.0e-14_dp)
         if (allocated(error)) return
      end do
      theta = [0.6_dp, 0.0_dp, 0.8_dp, 0.1_dp]
      call check_close(error, 'C_e = |theta|^2 - 1', euler_constraint(theta), 0.01_dp, &
         atol=1.0e-15_dp)
      if (.not. allocated(error)) call check_close(error, 'dC_e/dtheta', &
         maxval(abs(euler_constraint_jacobian(theta) - 2.0_dp * theta)), 0.0_dp, atol=0.0_dp)
   end subroutine test_rotation_matrix

   !> omega_bar = G_bar theta_dot equals axial(A^T dA/dt) with dA/dt by central differences
   !> along a path on |theta| = 1 (h = 1e-5: truncation ~h^2 |theta_dot|^3 ~ 1e-10, round-off
   !> ~eps/h ~ 1e-11; tolerance 1e-8), the symmetric part of A^T dA/dt vanishes, and
   !> G_bar_dot theta_dot = 0 (d/dt G_bar(theta(t)) theta_dot by central differences, 1e-8),
   !> theory.md 3.1.
   subroutine test_angular_velocity(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-5_dp
      real(dp) :: theta(4), theta_dot(4), a_dot(3, 3), at_ad(3, 3), g_dot(3, 4), omega(3)
      integer :: seed
      do seed = 1, 5
         theta = euler_normalized(random_vector(4, seed))
         theta_dot = random_vector(4, seed + 10)
         theta_dot = theta_dot - dot_product(theta, theta_dot) * theta
         a_dot = (euler_rotation(euler_normalized(theta + h * theta_dot)) - &
            euler_rotation(euler_normalized(theta - h * theta_dot))) / (2.0_dp * h)
         at_ad = matmul(transpose(euler_rotation(theta)), a_dot)
         omega = matmul(euler_g_bar(theta), theta_dot)
         call check_close(error, 'omega_bar = G_bar theta_dot vs axial(A^T dA/dt), seed ' // &
            to_str(seed), maxval(abs(axial3(at_ad) - omega)), 0.0_dp, atol=1.0e-8_dp * &
            norm2(omega))
         if (.not. allocated(error)) call check_close(error, 'symmetric part of A^T dA/dt', &
            max_abs(at_ad + transpose(at_ad)), 0.0_dp, atol=1.0e-8_dp * norm2(omega))
         if (allocated(error)) return
         g_dot = (euler_g_bar(euler_normalized(theta + h * theta_dot)) - &
            euler_g_bar(euler_normalized(theta - h * theta_dot))) / (2.0_dp * h)
         call check_close(error, 'G_bar_dot theta_dot', maxval(abs(matmul(g_dot, theta_dot))), &
            0.0_dp, atol=1.0e-8_dp * norm2(theta_dot)**2)
         if (allocated(error)) return
      end do
   end subroutine test_angular_velocity

   !> exp(phi~) is a rotation by |phi| about phi (vs the Euler-parameter route, 1e-14) and its
   !> tangent operator T(phi) gives the spatial angular velocity: axial(dR/dt R^T) = T dphi/dt
   !> by central differences (1e-8), at a large and at a small (series branch) rotation vector.
   subroutine test_rotation_vector(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-5_dp
      real(dp) :: phi(3), dphi(3), R_dot(3, 3), R(3, 3), scale
      integer :: trial
      do trial = 1, 2
         scale = merge(1.2_dp, 3.0e-4_dp, trial == 1)
         phi = scale * random_vector(3, 7 + trial)
         dphi = random_vector(3, 17 + trial)
         R = rotation_vector_matrix(phi)
         call check_close(error, 'exp(phi~) vs A(axis, angle)', max_abs(R - &
            euler_rotation(euler_from_axis_angle(phi, norm2(phi)))), 0.0_dp, atol=1.0e-14_dp)
         if (allocated(error)) return
         R_dot = (rotation_vector_matrix(phi + h * dphi) - rotation_vector_matrix(phi - h * &
            dphi)) / (2.0_dp * h)
         call check_close(error, 'axial(dR/dt R^T) vs T(phi) dphi, |phi| = ' // &
            to_str(norm2(phi), 3), maxval(abs(axial3(matmul(R_dot, transpose(R))) - &
            matmul(rotation_vector_tangent(phi), dphi))), 0.0_dp, atol=1.0e-8_dp)
         if (allocated(error)) return
      end do
   end subroutine test_rotation_vector

   ! ----------------------------------------------------------------------------------------------
   ! Invariants and mass matrix

   !> m, chi from the invariants equal body_mass_properties (a separate loop over the scalar
   !> mass) to 1e-12 relative; Theta_u - m (|chi|^2 I - chi chi^T) (parallel axes) equals the
   !> inertia about the centre of mass to 1e-12 of its norm; M_PsiPsi = I to 1e-10
   !> (mass-normalised modes; the modal pipeline's orthonormality floor).
   subroutine test_invariants(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: chi(3), inertia(3, 3)
      real(dp), allocatable :: deviation(:, :)
      integer :: j
      call get_crank(error)
      if (allocated(error)) return
      call check_close(error, 'mass (kg)', crank%mass, crank_modes%mass, rtol=1.0e-12_dp)
      if (allocated(error)) return
      chi = crank%center_of_mass
      call check_close(error, 'centre of mass', maxval(abs(chi - crank_modes%center_of_mass)), &
         0.0_dp, atol=1.0e-12_dp * norm2(crank_modes%center_of_mass))
      if (allocated(error)) return
      inertia = crank%theta_u - crank%mass * (dot_product(chi, chi) * identity3() - &
         spread(chi, 2, 3) * spread(chi, 1, 3))
      call check_close(error, 'inertia about the centre of mass', &
         max_abs(inertia - crank_modes%inertia), 0.0_dp, atol=1.0e-12_dp * &
         max_abs(crank_modes%inertia))
      if (allocated(error)) return
      deviation = crank%m_psi_psi
      do j = 1, crank%num_modes
         deviation(j, j) = deviation(j, j) - 1.0_dp
      end do
      call check_close(error, 'max |M_PsiPsi - I|', max_abs(deviation), 0.0_dp, atol=1.0e-10_dp)
      if (allocated(error)) return
      call report('relative deviations: m ' // to_str(crank%mass / crank_modes%mass - 1.0_dp, &
         2) // ', chi ' // to_str(maxval(abs(chi - crank_modes%center_of_mass)) / &
         norm2(chi), 2) // ', J_c ' // to_str(max_abs(inertia - crank_modes%inertia) / &
         max_abs(crank_modes%inertia), 2) // ', max |M_PsiPsi - I| ' // &
         to_str(max_abs(deviation), 2))
      call report('crank: m = ' // to_str(crank%mass, 8) // ' kg, chi = (' // &
         to_str(chi(1), 4) // ', ' // to_str(chi(2), 4) // ', ' // to_str(chi(3), 4) // &
         ') m, ' // to_str(crank%num_modes) // ' modes, f1 = ' // &
         to_str(crank_modes%frequency_hz(1), 6) // ' Hz')
   end subroutine test_invariants

   !> The strongest check of M(q): for random states (unit theta, theta^T theta_dot = 0, zeta
   !> large enough to make every zeta-term count), v^T M(q) v / 2 equals the kinetic energy of
   !> the nodal velocities r_i_dot = R_dot + A (omega_bar x u_i) + A Psi_i zeta_dot summed with
   !> the FE mass matrix, r_dot^T M_FE r_dot / 2 (1e-10 relative: both are sums of the same
   !> quadratic form in a different order).
   subroutine test_kinetic_energy(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: q(:), v(:), r_dot(:), m_r_dot(:)
      real(dp) :: A(3, 3), omega(3), u(3), energy_fe, energy
      integer :: seed, i, nc
      call get_crank(error)
      if (allocated(error)) return
      nc = crank%num_coordinates
      allocate (r_dot(3 * crank%num_nodes), m_r_dot(3 * crank%num_nodes))
      do seed = 1, 3
         call random_state(crank, seed, 0.02_dp, q, v)
         A = euler_rotation(q(4:7))
         omega = matmul(euler_g_bar(q(4:7)), v(4:7))
         do i = 1, crank%num_nodes
            associate (rows => 3 * (i - 1) + [1, 2, 3])
               u = crank_modes%mesh%xyz(:, i) + matmul(crank_modes%shape(rows, :), q(8:nc))
               r_dot(rows) = v(1:3) + matmul(A, matmul(skew3(omega), u) + &
                  matmul(crank_modes%shape(rows, :), v(8:nc)))
            end associate
         end do
         call csr_matvec(crank_mass, r_dot, m_r_dot)
         energy_fe = 0.5_dp * dot_product(r_dot, m_r_dot)
         energy = crank%kinetic_energy(q, v)
         call report('state ' // to_str(seed) // ': T = ' // to_str(energy, 12) // ' J, ' // &
            'from the FE mass ' // to_str(energy_fe, 12) // ' J, relative difference ' // &
            to_str(energy / energy_fe - 1.0_dp, 2))
         call check_close(error, 'kinetic energy (J), state ' // to_str(seed), energy, &
            energy_fe, rtol=1.0e-10_dp)
         if (allocated(error)) return
      end do
   end subroutine test_kinetic_energy

   !> f_v against Lagrange's equations with the coordinates treated as independent:
   !>     f_L = -(dM/dt) v + d(v^T M v / 2)/dq,   (dM/dt) v = d/de M(q + e v) v,
   !> both by central differences of mass_matrix (steps of 1e-5 in theta and zeta; M is a
   !> polynomial of degree <= 3 in theta and 2 in zeta: truncation ~h^2, round-off ~eps/h).
   !> What is compared: R and zeta rows as they are; in the theta rows only the part tangent to
   !> |theta| = 1, (I - theta theta^T) f_L. The theta rows of Lagrange's equations are defined
   !> only up to a multiple of theta: the 4 x 4 block G_bar^T I G_bar has rank 3 and theta
   !> spans its null space, and any theta-component is taken by the normalisation multiplier
   !> (C_e = theta^T theta - 1, force 2 theta lambda). theory.md's f_vth = G_bar^T(...) has no
   !> theta-component (G_bar theta = 0). Tolerance 1e-8 of |f_v| (measured ~2e-11); the removed
   !> theta-component of f_L (of the order of |f_v|) is reported.
   subroutine test_quadratic_velocity(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-5_dp
      real(dp), allocatable :: q(:), v(:), f_v(:), f_l(:), dq(:), mass_dot(:, :)
      real(dp) :: theta(4), radial, hv
      integer :: seed, nc, i
      call get_crank(error)
      if (allocated(error)) return
      nc = crank%num_coordinates
      do seed = 1, 3
         call random_state(crank, 10 + seed, 0.02_dp, q, v)
         f_v = crank%quadratic_velocity(q, v)
         ! Step along v scaled so that the theta step is h (|theta_dot| ~ 300 1/s here).
         hv = h / norm2(v(4:nc))
         mass_dot = (crank%mass_matrix(q + hv * v) - crank%mass_matrix(q - hv * v)) / (2.0_dp * hv)
         f_l = -matmul(mass_dot, v)
         allocate (dq(nc))
         do i = 1, nc
            dq = 0.0_dp
            dq(i) = h
            f_l(i) = f_l(i) + 0.25_dp * dot_product(v, matmul(crank%mass_matrix(q + dq) - &
               crank%mass_matrix(q - dq), v)) / h
         end do
         deallocate (dq)
         theta = q(4:7)
         radial = dot_product(theta, f_l(4:7))
         f_l(4:7) = f_l(4:7) - radial * theta
         call report('state ' // to_str(seed) // ': |f_v| = ' // to_str(norm2(f_v), 6) // &
            ', |f_v - f_Lagrange| = ' // to_str(norm2(f_v - f_l), 3) // &
            ', theta-component of f_Lagrange removed = ' // to_str(radial, 4))
         call check_close(error, '|f_v - f_Lagrange| (tangent part), state ' // to_str(seed), &
            norm2(f_v - f_l), 0.0_dp, atol=1.0e-8_dp * norm2(f_v))
         if (allocated(error)) return
         call check_close(error, 'theta . f_vtheta', dot_product(theta, f_v(4:7)), 0.0_dp, &
            atol=1.0e-12_dp * norm2(f_v))
         if (allocated(error)) return
      end do
   end subroutine test_quadratic_velocity

   !> Free-free modes are M-orthogonal to the rigid motions, so they satisfy the linear mean-axis
   !> (Buckens) conditions Phi_t^T M Psi = 0 and x~^T M Psi = 0 (theory.md 7): m_Rf = A M_PhitPsi
   !> vanishes. Scale: |Phi_t^T M psi| <= sqrt(m) (Cauchy-Schwarz, psi^T M psi = 1), likewise
   !> sqrt(max diag Theta_u); tolerance 1e-10 of these (the modes' M-orthonormality floor).
   !> The crank's modes with B2 clamped (RC set 3) are not mean-axis modes: the same ratio
   !> is above 1e-2.
   subroutine test_mean_axis(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: linear, angular, linear_crank
      real(dp), allocatable :: q(:), mm(:, :)
      call get_beam(error)
      if (.not. allocated(error)) call get_crank(error)
      if (allocated(error)) return
      linear = max_abs(beam%m_phit_psi) / sqrt(beam%mass)
      angular = max_abs(beam%m_x_psi) / sqrt(maxval([beam%theta_u(1, 1), beam%theta_u(2, 2), &
         beam%theta_u(3, 3)]))
      linear_crank = max_abs(crank%m_phit_psi) / sqrt(crank%mass)
      call report('free-free beam: |Phi_t^T M Psi|/sqrt(m) = ' // to_str(linear, 3) // &
         ', |x~^T M Psi|/sqrt(J) = ' // to_str(angular, 3) // '; crank RC set 3: ' // &
         to_str(linear_crank, 3))
      q = [0.0_dp, 0.0_dp, 0.0_dp, euler_from_axis_angle([1.0_dp, 2.0_dp, 3.0_dp], 0.7_dp), &
         [real(dp) :: 0.01, 0.02, 0.03, 0.04, 0.05, 0.06]]
      mm = beam%mass_matrix(q)
      call check_close(error, 'beam: max |m_Rf| / sqrt(m) from mass_matrix', &
         max_abs(mm(1:3, 8:)) / sqrt(beam%mass), 0.0_dp, atol=1.0e-10_dp)
      if (.not. allocated(error)) call check_close(error, 'beam: max |x~^T M Psi| / sqrt(J)', &
         angular, 0.0_dp, atol=1.0e-10_dp)
      if (.not. allocated(error)) call check(error, 'crank RC set 3 modes are not mean-axis ' // &
         'modes: max |Phi_t^T M Psi|/sqrt(m) = ' // to_str(linear_crank, 3) // ' > 1e-2', &
         linear_crank > 1.0e-2_dp)
   end subroutine test_mean_axis

   ! ----------------------------------------------------------------------------------------------
   ! Markers

   !> On the crank's three markers, random state (zeta ~ 0.02, elastic rotations ~1e-2 rad):
   !> marker_position_jacobian and marker_axis_jacobian against central differences in every
   !> coordinate, the four Euler parameters included (h = 1e-6, tolerance 1e-7 of max |J|:
   !> quadratic/trigonometric functions, truncation ~h^2); along a path on |theta| = 1, the
   !> velocity Jacobian L_r v equals dr_V/dt and L_w v equals axial(dA_V/dt A_V^T) (central
   !> differences, 1e-7 relative), and L_r v = (dr_V/dq) v for tangent v to 1e-12.
   subroutine test_marker_jacobians(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-6_dp
      real(dp), allocatable :: q(:), v(:), dq(:), jac(:, :), fd(:, :), jac_axis(:, :)
      real(dp) :: axis(3), r_dot(3), A_v(3, 3), worst(4), hp, spin(2)
      integer :: k, i, nc
      worst = 0.0_dp
      call get_crank(error)
      if (allocated(error)) return
      nc = crank%num_coordinates
      call random_state(crank, 21, 0.02_dp, q, v)
      hp = h / norm2(v(4:7))      ! path step: theta moves by h
      axis = [0.3_dp, -0.5_dp, 0.8_dp]
      allocate (dq(nc), fd(3, nc))
      do k = 1, crank%num_markers
         jac = crank%marker_position_jacobian(q, k)
         jac_axis = crank%marker_axis_jacobian(q, k, axis)
         do i = 1, nc
            dq = 0.0_dp
            dq(i) = h
            fd(:, i) = (crank%marker_position(q + dq, k) - crank%marker_position(q - dq, k)) / &
               (2.0_dp * h)
         end do
         worst(1) = max(worst(1), max_abs(jac - fd) / max_abs(jac))
         call check_close(error, 'marker ' // to_str(k) // ': dr_V/dq vs central differences', &
            max_abs(jac - fd), 0.0_dp, atol=1.0e-7_dp * max_abs(jac))
         if (allocated(error)) return
         fd = axis_differences(crank, q, k, axis, h)
         worst(2) = max(worst(2), max_abs(jac_axis - fd) / max_abs(jac_axis))
         call check_close(error, 'marker ' // to_str(k) // ': d(A_V a)/dq vs central ' // &
            'differences', max_abs(jac_axis - fd), 0.0_dp, atol=1.0e-7_dp * max_abs(jac_axis))
         if (allocated(error)) return
         ! Along the path on the constraint manifold
         r_dot = (crank%marker_position(path_point(q, v, hp), k) - &
            crank%marker_position(path_point(q, v, -hp), k)) / (2.0_dp * hp)
         worst(3) = max(worst(3), norm2(matmul(crank%marker_velocity_jacobian(q, k), v) - &
            r_dot) / norm2(r_dot))
         call check_close(error, 'marker ' // to_str(k) // ': L_r v vs dr_V/dt', &
            norm2(matmul(crank%marker_velocity_jacobian(q, k), v) - r_dot), 0.0_dp, &
            atol=1.0e-7_dp * norm2(r_dot))
         if (allocated(error)) return
         call check_close(error, 'marker ' // to_str(k) // ': L_r v vs (dr_V/dq) v', &
            norm2(matmul(crank%marker_velocity_jacobian(q, k) - jac, v)), 0.0_dp, &
            atol=1.0e-12_dp * norm2(r_dot))
         if (allocated(error)) return
         spin = angular_velocity_defect(crank, q, v, k, hp)
         worst(4) = max(worst(4), spin(1) / spin(2))
         call check_close(error, 'marker ' // to_str(k) // ': L_w v vs axial(dA_V/dt A_V^T)', &
            spin(1), 0.0_dp, atol=1.0e-7_dp * spin(2))
         A_v = crank%marker_orientation(q, k)
         if (allocated(error)) return
         call check_close(error, 'marker ' // to_str(k) // ': A_V orthonormal', &
            max_abs(matmul(transpose(A_v), A_v) - identity3()), 0.0_dp, atol=1.0e-14_dp)
         if (allocated(error)) return
      end do
      call report('worst relative errors over 3 markers x ' // to_str(nc) // ' coordinates: ' // &
         'dr_V/dq ' // to_str(worst(1), 2) // ', d(A_V a)/dq ' // to_str(worst(2), 2) // &
         ', L_r v ' // to_str(worst(3), 2) // ', L_w v ' // to_str(worst(4), 2))
   end subroutine test_marker_jacobians

   !> Framed markers (add_marker, marker frame A exp(phi~) C) at the crank's three virtual nodes,
   !> C a rotation by 1.1 rad about (1, 2, -2)/3 (it takes the node's x axis far from any body
   !> axis), random state (zeta ~ 0.02): against an independent product the orientation is the
   !> node marker's times C (1e-14); marker_axis_jacobian, marker_kinematics' axis Jacobians and
   !> its orientation against central differences of marker_orientation (h = 1e-6, 1e-7 of max
   !> |J|); the Hessian of w_r . r + sum_j w_j . A_V e_j against central differences of its
   !> exact gradient (from the position and axis Jacobians; 1e-6 of max |H|: the zeta-zeta
   !> block is itself a central difference of the exponential map); L_w v against
   !> axial(dA_V/dt A_V^T) along a path (1e-7); the position, L_r and the generalized force
   !> equal the node marker's (C is constant). A marker with C = I gives the node marker's
   !> numbers bit for bit (no product), and C not a rotation is refused with its interface.
   subroutine test_framed_markers(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-6_dp
      type(flexible_body_t) :: body
      real(dp), allocatable :: q(:), v(:), dq(:), jac(:, :), fd(:, :), pj(:, :), aj(:, :, :)
      real(dp), allocatable :: hess(:, :), fd_hess(:, :), node_aj(:, :, :)
      real(dp) :: C(3, 3), axis(3), r(3), frame(3, 3), A_v(3, 3), omega(3)
      real(dp) :: w_p(3), W(3, 3), worst(4), hp, bad(3, 3), spin(2)
      integer :: k, kf, i, j, nc, nodes, marker
      logical :: refused
      character(len=:), allocatable :: message
      worst = 0.0_dp
      call get_crank(error)
      if (allocated(error)) return
      body = crank
      nc = body%num_coordinates
      nodes = body%num_markers
      C = euler_rotation(euler_from_axis_angle([1.0_dp, 2.0_dp, -2.0_dp] / 3.0_dp, 1.1_dp))
      do k = 1, nodes
         call body%add_marker(k, C, marker, error)
         if (allocated(error)) return
         call check(error, 'add_marker numbers markers after the interfaces: ' // &
            to_str(marker), marker == nodes + k)
         if (allocated(error)) return
      end do
      call random_state(body, 23, 0.02_dp, q, v)
      hp = h / norm2(v(4:7))
      axis = [0.3_dp, -0.5_dp, 0.8_dp]
      w_p = [0.7_dp, -0.2_dp, 0.4_dp]
      W = reshape([0.5_dp, -1.0_dp, 0.3_dp, 0.2_dp, 0.9_dp, -0.6_dp, -0.4_dp, 0.1_dp, 0.8_dp], &
         [3, 3])
      allocate (dq(nc), fd(3, nc), pj(3, nc), aj(3, nc, 3), hess(nc, nc), fd_hess(nc, nc), &
         node_aj(3, nc, 3))
      do k = 1, nodes
         kf = nodes + k
         call check_close(error, 'framed marker ' // to_str(kf) // ': A_V = A_node C', &
            max_abs(body%marker_orientation(q, kf) - matmul(body%marker_orientation(q, k), C)), &
            0.0_dp, atol=1.0e-14_dp)
         if (allocated(error)) return
         call check_close(error, 'framed marker ' // to_str(kf) // ': position = the node''s', &
            norm2(body%marker_position(q, kf) - body%marker_position(q, k)), 0.0_dp, atol=0.0_dp)
         if (allocated(error)) return
         call check_close(error, 'framed marker ' // to_str(kf) // ': L_r, L_w and the ' // &
            'generalized force = the node''s', max_abs(body%marker_velocity_jacobian(q, kf) - &
            body%marker_velocity_jacobian(q, k)) + max_abs(body%marker_rotation_jacobian(q, kf) &
            - body%marker_rotation_jacobian(q, k)) + maxval(abs(body%marker_generalized_force(q, &
            kf, w_p, axis) - body%marker_generalized_force(q, k, w_p, axis))), 0.0_dp, atol=0.0_dp)
         if (allocated(error)) return
         ! d(A_V a)/dq
         jac = body%marker_axis_jacobian(q, kf, axis)
         fd = axis_differences(body, q, kf, axis, h)
         worst(1) = max(worst(1), max_abs(jac - fd) / max_abs(jac))
         call check_close(error, 'framed marker ' // to_str(kf) // ': d(A_V a)/dq vs ' // &
            'central differences', max_abs(jac - fd), 0.0_dp, atol=1.0e-7_dp * max_abs(jac))
         if (allocated(error)) return
         ! marker_kinematics: orientation and the three axis Jacobians
         call body%marker_kinematics(q, kf, [.true., .true., .true.], r, frame, pj, aj)
         call check_close(error, 'framed marker ' // to_str(kf) // ': kinematics orientation', &
            max_abs(frame - body%marker_orientation(q, kf)), 0.0_dp, atol=1.0e-15_dp)
         if (allocated(error)) return
         do j = 1, 3
            fd = axis_differences(body, q, kf, unit(j), h)
            worst(2) = max(worst(2), max_abs(aj(:, :, j) - fd) / max_abs(aj(:, :, j)))
            call check_close(error, 'framed marker ' // to_str(kf) // ': kinematics ' // &
               'd(A_V e_' // to_str(j) // ')/dq vs central differences', &
               max_abs(aj(:, :, j) - fd), 0.0_dp, atol=1.0e-7_dp * max_abs(aj(:, :, j)))
            if (allocated(error)) return
         end do
         ! Hessian of the weighted position and axes
         call body%marker_hessian(q, kf, w_p, W, hess)
         do i = 1, nc
            dq = 0.0_dp
            dq(i) = h
            fd_hess(:, i) = (gradient(q + dq) - gradient(q - dq)) / (2.0_dp * h)
         end do
         worst(3) = max(worst(3), max_abs(hess - fd_hess) / max_abs(hess))
         call check_close(error, 'framed marker ' // to_str(kf) // ': Hessian vs central ' // &
            'differences of the gradient', max_abs(hess - fd_hess), 0.0_dp, &
            atol=1.0e-6_dp * max_abs(hess))
         if (allocated(error)) return
         ! angular velocity along a path on |theta| = 1
         spin = angular_velocity_defect(body, q, v, kf, hp)
         worst(4) = max(worst(4), spin(1) / spin(2))
         call check_close(error, 'framed marker ' // to_str(kf) // ': L_w v vs ' // &
            'axial(dA_V/dt A_V^T)', spin(1), 0.0_dp, atol=1.0e-7_dp * spin(2))
         if (allocated(error)) return
      end do
      ! C = I: the node marker's numbers, bit for bit
      call body%add_marker(2, identity3(), marker, error)
      if (allocated(error)) return
      call body%marker_kinematics(q, marker, [.true., .true., .true.], r, frame, pj, aj)
      call body%marker_kinematics(q, 2, [.true., .true., .true.], omega, A_v, jac, node_aj)
      call body%marker_hessian(q, marker, w_p, W, hess)
      call body%marker_hessian(q, 2, w_p, W, fd_hess)
      call check(error, 'a marker with C = I reproduces the node marker bit for bit', &
         all(frame == body%marker_orientation(q, 2)) .and. all(frame == A_v) .and. &
         all(aj == node_aj) .and. all(pj == jac) .and. all(r == omega) .and. &
         all(body%marker_axis_jacobian(q, marker, axis) == body%marker_axis_jacobian(q, 2, &
         axis)) .and. all(hess == fd_hess))
      if (allocated(error)) return
      ! C not a rotation
      bad = C
      bad(1, 1) = bad(1, 1) + 1.0e-6_dp
      call body%add_marker(3, bad, marker, error)
      refused = allocated(error)
      message = ''
      if (refused) message = error%message
      call check(error, 'add_marker refuses a non-orthonormal frame, naming the interface ' // &
         'and the defect: "' // message // '"', refused .and. index(message, 'interface 3') > 0 &
         .and. index(message, 'not orthonormal') > 0)
      if (allocated(error)) return
      call body%add_marker(3, -C, marker, error)
      refused = allocated(error)
      message = ''
      if (refused) message = error%message
      call check(error, 'add_marker refuses a reflection (det -1): "' // message // '"', &
         refused .and. index(message, 'det =') > 0)
      if (allocated(error)) return
      call report('framed markers, worst relative errors over 3 markers x ' // to_str(nc) // &
         ' coordinates: d(A_V a)/dq ' // to_str(worst(1), 2) // ', kinematics axes ' // &
         to_str(worst(2), 2) // ', Hessian ' // to_str(worst(3), 2) // ', L_w v ' // &
         to_str(worst(4), 2))

   contains

      !> Exact gradient of w_p . r + sum_j W(:, j) . A_V e_j of marker kf (position and axis
      !> Jacobians).
      function gradient(x) result(g)
         real(dp), intent(in) :: x(:)
         real(dp) :: g(size(x))
         integer :: c
         g = matmul(w_p, body%marker_position_jacobian(x, kf))
         do c = 1, 3
            g = g + matmul(W(:, c), body%marker_axis_jacobian(x, kf, unit(c)))
         end do
      end function gradient

      function unit(c) result(e)
         integer, intent(in) :: c
         real(dp) :: e(3)
         e = 0.0_dp
         e(c) = 1.0_dp
      end function unit

   end subroutine test_framed_markers

   !> Rigid motion (zeta = 0): every marker sits at R + A x_V and turns with A (round-off,
   !> 1e-15 of the scale). Generalized force of a force F and moment M_V at a marker: its
   !> virtual power Q . v equals F . r_V_dot + M_V . omega_V with the marker velocities from
   !> central differences along a manifold path (1e-7), and at zeta = 0 equals theory.md 3.5's
   !> closed form Q_R = F, Q_th = G_bar^T (u_V~ A^T F + A^T M_V), Q_f = Psi_Vt^T A^T F +
   !> Psi_Vr^T A^T M_V (1e-12 relative).
   subroutine test_marker_forces(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-6_dp
      real(dp), allocatable :: q(:), v(:), gen(:), expected(:)
      real(dp) :: A(3, 3), G_bar(3, 4), force(3), moment(3), r_dot(3), omega(3), power
      real(dp) :: A_dot(3, 3), A_v(3, 3), hp
      integer :: k, nc
      call get_crank(error)
      if (allocated(error)) return
      nc = crank%num_coordinates
      force = [120.0_dp, -340.0_dp, 75.0_dp]
      moment = [-8.0_dp, 3.0_dp, 14.0_dp]
      ! Rigid motion
      call random_state(crank, 31, 0.0_dp, q, v)
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      do k = 1, crank%num_markers
         call check_close(error, 'marker ' // to_str(k) // ' at zeta = 0: |r_V - R - A x_V|', &
            norm2(crank%marker_position(q, k) - q(1:3) - matmul(A, crank%virtual_xyz(:, k))), &
            0.0_dp, atol=1.0e-15_dp)
         if (.not. allocated(error)) call check_close(error, 'marker ' // to_str(k) // &
            ' at zeta = 0: |A_V - A|', max_abs(crank%marker_orientation(q, k) - A), 0.0_dp, &
            atol=1.0e-15_dp)
         if (allocated(error)) return
         gen = crank%marker_generalized_force(q, k, force, moment)
         expected = [force, matmul(transpose(G_bar), matmul(skew3(crank%virtual_xyz(:, k)), &
            matmul(transpose(A), force)) + matmul(transpose(A), moment)), &
            matmul(transpose(crank%virtual_shapes(6 * k - 5:6 * k - 3, :)), &
            matmul(transpose(A), force)) + &
            matmul(transpose(crank%virtual_shapes(6 * k - 2:6 * k, :)), &
            matmul(transpose(A), moment))]
         call check_close(error, 'marker ' // to_str(k) // ': Q vs theory.md 3.5 at zeta = 0', &
            maxval(abs(gen - expected)), 0.0_dp, atol=1.0e-12_dp * maxval(abs(expected)))
         if (allocated(error)) return
      end do
      ! Deformed state: virtual power
      call random_state(crank, 32, 0.02_dp, q, v)
      hp = h / norm2(v(4:7))      ! path step: theta moves by h
      do k = 1, crank%num_markers
         gen = crank%marker_generalized_force(q, k, force, moment)
         r_dot = (crank%marker_position(path_point(q, v, hp), k) - &
            crank%marker_position(path_point(q, v, -hp), k)) / (2.0_dp * hp)
         A_v = crank%marker_orientation(q, k)
         A_dot = (crank%marker_orientation(path_point(q, v, hp), k) - &
            crank%marker_orientation(path_point(q, v, -hp), k)) / (2.0_dp * hp)
         omega = axial3(matmul(A_dot, transpose(A_v)))
         power = dot_product(force, r_dot) + dot_product(moment, omega)
         call check_close(error, 'marker ' // to_str(k) // ': Q . v vs F . r_V_dot + ' // &
            'M . omega_V', dot_product(gen, v), power, rtol=1.0e-7_dp)
         if (allocated(error)) return
      end do
   end subroutine test_marker_forces

   ! ----------------------------------------------------------------------------------------------
   ! Rigid limit and input checks

   !> Modes made very stiff (eigenvalues x 1e8) with zeta = zeta_dot = 0: the rigid blocks of
   !> M(q) equal the rigid-body mass matrix from body_mass_properties' m, chi, J_c
   !> (m I, -A m chi~ G_bar, G_bar^T J_O G_bar with J_O = J_c + m (|chi|^2 I - chi chi^T)), and
   !> the rigid rows of f_v the rigid closed forms -A w x (w x m chi) and -G_bar^T w x (J_O w)
   !> (1e-12 relative); the strain energy of a given zeta scales by 1e8 (1e-14).
   subroutine test_rigid_limit(error)
      type(error_t), allocatable, intent(out) :: error
      type(flexible_body_t) :: stiff
      real(dp), allocatable :: q(:), v(:), mm(:, :), f_v(:), virtual_xyz(:, :), rigid(:, :)
      real(dp) :: A(3, 3), G_bar(3, 4), chi(3), J_o(3, 3), omega(3), m, f_rigid(7), zeta_energy
      integer :: k, nc
      call get_crank(error)
      if (allocated(error)) return
      allocate (virtual_xyz(3, crank%num_markers))
      do k = 1, crank%num_markers
         virtual_xyz(:, k) = crank_modes%interfaces(k)%virtual_xyz
      end do
      call stiff%init(crank_mass, crank_modes%mesh%xyz, crank_modes%shape, &
         1.0e8_dp * crank%stiffness, crank_modes%virtual_node_shape, virtual_xyz, error)
      if (allocated(error)) return
      nc = stiff%num_coordinates
      call random_state(stiff, 41, 0.0_dp, q, v)
      v(8:) = 0.0_dp
      m = crank_modes%mass
      chi = crank_modes%center_of_mass
      J_o = crank_modes%inertia + m * (dot_product(chi, chi) * identity3() - &
         spread(chi, 2, 3) * spread(chi, 1, 3))
      A = euler_rotation(q(4:7))
      G_bar = euler_g_bar(q(4:7))
      allocate (rigid(7, 7), source=0.0_dp)
      rigid(1:3, 1:3) = m * identity3()
      rigid(1:3, 4:7) = -m * matmul(A, matmul(skew3(chi), G_bar))
      rigid(4:7, 1:3) = transpose(rigid(1:3, 4:7))
      rigid(4:7, 4:7) = matmul(transpose(G_bar), matmul(J_o, G_bar))
      mm = stiff%mass_matrix(q)
      call check_close(error, 'rigid block of M(q) vs rigid-body mass matrix', &
         max_abs(mm(1:7, 1:7) - rigid), 0.0_dp, atol=1.0e-12_dp * max_abs(rigid))
      if (allocated(error)) return
      omega = matmul(G_bar, v(4:7))
      f_rigid(1:3) = -matmul(A, cross(omega, cross(omega, m * chi)))
      f_rigid(4:7) = -matmul(transpose(G_bar), cross(omega, matmul(J_o, omega)))
      f_v = stiff%quadratic_velocity(q, v)
      call check_close(error, 'rigid rows of f_v vs rigid-body closed form', &
         maxval(abs(f_v(1:7) - f_rigid)), 0.0_dp, atol=1.0e-12_dp * maxval(abs(f_rigid)))
      if (allocated(error)) return
      q(8:) = 1.0e-3_dp
      zeta_energy = crank%strain_energy(q)
      call check_close(error, 'strain energy ratio stiff/normal', &
         stiff%strain_energy(q) / zeta_energy, 1.0e8_dp, rtol=1.0e-14_dp)
      call report('rigid limit: m = ' // to_str(m, 8) // ' kg, |f_v rigid rows| = ' // &
         to_str(maxval(abs(f_rigid)), 4) // ', elastic rows |f_vf| = ' // &
         to_str(maxval(abs(f_v(8:nc))), 4))
   end subroutine test_rigid_limit

   pure function cross(a, b) result(c)
      real(dp), intent(in) :: a(3), b(3)
      real(dp) :: c(3)
      c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
   end function cross

   !> init rejects mismatched sizes, a negative eigenvalue and a mass matrix that is not
   !> Ms (x) I3 (an x-y coupling entry), each with a message naming the problem.
   subroutine test_bad_input(error)
      type(error_t), allocatable, intent(out) :: error
      type(flexible_body_t) :: body
      type(csr_t) :: M
      type(error_t), allocatable :: failure
      real(dp) :: xyz(3, 2), shapes(6, 1), virtual_shapes(6, 1), virtual_xyz(3, 1)
      xyz = reshape([0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp], [3, 2])
      shapes = 0.1_dp
      virtual_shapes = 0.0_dp
      virtual_xyz = 0.0_dp
      ! Two unit point masses, plus an x-y coupling of 0.1 at node 1
      call csr_from_coo(6_ip, 6_ip, [integer(ip) :: 1, 2, 3, 4, 5, 6, 1, 2], &
         [integer(ip) :: 1, 2, 3, 4, 5, 6, 2, 1], [1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, &
         1.0_dp, 0.1_dp, 0.1_dp], M, error)
      if (allocated(error)) return
      call body%init(M, xyz, shapes, [1.0_dp], virtual_shapes, virtual_xyz, failure)
      call check(error, 'a coupled mass matrix is rejected', allocated(failure))
      if (allocated(error)) return
      call check(error, 'message names Ms (x) I3: ' // failure%message, &
         index(failure%message, 'Ms (x) I3') > 0)
      if (allocated(error)) return
      deallocate (failure)
      call csr_from_coo(6_ip, 6_ip, [integer(ip) :: 1, 2, 3, 4, 5, 6], &
         [integer(ip) :: 1, 2, 3, 4, 5, 6], [1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], &
         M, error)
      if (allocated(error)) return
      call body%init(M, xyz, shapes, [1.0_dp], virtual_shapes, virtual_xyz, failure)
      call check(error, 'two point masses are accepted', .not. allocated(failure))
      if (allocated(error)) return
      call check_close(error, 'two point masses: m', body%mass, 2.0_dp, atol=0.0_dp)
      if (allocated(error)) return
      call body%init(M, xyz, shapes, [-1.0_dp], virtual_shapes, virtual_xyz, failure)
      call check(error, 'a negative eigenvalue is rejected', allocated(failure))
      if (allocated(error)) return
      deallocate (failure)
      call body%init(M, xyz, shapes(1:3, :), [1.0_dp], virtual_shapes, virtual_xyz, failure)
      call check(error, 'shapes with 3 rows for 2 nodes are rejected', allocated(failure))
   end subroutine test_bad_input

end module test_mbs_flexible_body

program main_mbs_flexible_body
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_flexible_body, only: collect_mbs_flexible_body
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_flexible_body(tests)
   call run_suite('mbs_flexible_body', tests)
end program main_mbs_flexible_body
