!> Rigid bodies and ground (ffrf_mbs_rigid_body), the flexible body as a body_t
!> (ffrf_mbs_flexible_body) and joints between markers (ffrf_mbs_joints). References: closed
!> forms (rigid-body mass matrix of theory.md 3.3 with Psi = 0, kinetic energy of the centre of
!> mass plus rotation), a second implementation (flexible_body_t of point masses at zeta = 0),
!> Lagrange's equations and joint Jacobians by central finite differences, motions that a joint
!> allows or forbids by construction, virtual work of the reactions, and the planar slider-crank
!> of scene.md (Gruebler count, closed-form piston position). The flexible body is the crank_lc8
!> mesh with RC set 3 (B2 clamped), 8 modes.
module test_mbs_joints
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t, add_context
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_fe_material, only: material_t
   use ffrf_fe_assembly, only: assemble_stiffness_mass
   use ffrf_la_sparse, only: csr_t, csr_from_coo
   use ffrf_la_dense, only: singular_values, numerical_rank
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_body, only: body_input_t
   use ffrf_input_modes, only: modes_input_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_app_body_modes, only: compute_input_body_modes
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar, euler_g, euler_from_axis_angle, &
      euler_from_rotation, euler_normalized, skew3, identity3, rotation_vector_matrix
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_body, only: body_t
   use ffrf_mbs_rigid_body, only: rigid_body_t, ground_t
   use ffrf_mbs_joints, only: joint_t, new_joint, joint_reaction, joint_kind_name, &
      JOINT_SPHERICAL, JOINT_REVOLUTE, JOINT_UNIVERSAL, JOINT_PRISMATIC, JOINT_FIXED, &
      JOINT_CYLINDRICAL
   use ffrf_mbs_galpha_linalg, only: find_redundant_rows
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, test_mesh_dir, report
   implicit none
   private
   public :: collect_mbs_joints

   interface
      !> Least squares min |A x - b| by QR (LAPACK), full column rank.
      subroutine dgels(trans, m, n, nrhs, a, lda, b, ldb, work, lwork, info)
         import :: dp, ip
         implicit none
         character, intent(in) :: trans
         integer(ip), intent(in) :: m, n, nrhs, lda, ldb, lwork
         real(dp), intent(inout) :: a(lda, *), b(ldb, *)
         real(dp), intent(out) :: work(*)
         integer(ip), intent(out) :: info
      end subroutine dgels
   end interface

   !> A joint with the mechanism indices of its bodies (0 = ground)
   type :: joint_box_t
      class(joint_t), allocatable :: joint
      integer :: a = 0, b = 0
   end type joint_box_t

   real(dp), parameter :: young = 210.0e9_dp, poisson = 0.3_dp, density = 7850.0_dp
   character(len=11), parameter :: kinds(6) = [character(len=11) :: 'spherical', 'revolute', &
      'universal', 'prismatic', 'fixed', 'cylindrical']
   !> Their kinds (new_joint), in the order of `kinds`
   integer, parameter :: kind_codes(6) = [JOINT_SPHERICAL, JOINT_REVOLUTE, JOINT_UNIVERSAL, &
      JOINT_PRISMATIC, JOINT_FIXED, JOINT_CYLINDRICAL]
   !> Slider-crank of scene.md: crank radius and conrod length (m)
   real(dp), parameter :: crank_radius = 0.045_dp, rod_length = 0.150_dp

   !> The crank (RC set 3) as a flexible body, computed once
   type(flexible_body_t), save :: crank
   logical, save :: crank_ready = .false.

contains

   subroutine collect_mbs_joints(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('rigid_body_rejects_bad_input', test_bad_input), &
         new_unittest('rigid_mass_matrix_and_energy', test_rigid_mass_matrix), &
         new_unittest('rigid_vs_flexible_point_masses', test_rigid_vs_flexible), &
         new_unittest('rigid_quadratic_velocity_lagrange', test_rigid_quadratic_velocity), &
         new_unittest('rigid_marker_jacobians', test_rigid_markers), &
         new_unittest('joint_factory_and_connect', test_factory), &
         new_unittest('joint_free_and_forbidden_motions', test_joint_motions), &
         new_unittest('joint_jacobians_finite_differences', test_joint_jacobians), &
         new_unittest('joint_reaction_virtual_work', test_joint_reactions), &
         new_unittest('slider_crank_rank_and_position', test_slider_crank), &
         new_unittest('redundant_rows_ties_go_to_the_first', test_redundant_ties), &
         new_unittest('redundant_rows_keep_protected_rows', test_redundant_protected)]
   end subroutine collect_mbs_joints

   ! ----------------------------------------------------------------------------------------------
   ! Helpers

   !> Deterministic pseudo-random numbers in [-1, 1].
   function random_vector(n, seed) result(x)
      integer, intent(in) :: n, seed
      real(dp) :: x(n)
      integer :: i
      do i = 1, n
         x(i) = sin(12.9898_dp * real(i + 37 * seed, dp) + 78.233_dp * real(seed, dp))
         x(i) = 2.0_dp * (x(i) * 43758.5453_dp - floor(x(i) * 43758.5453_dp)) - 1.0_dp
      end do
   end function random_vector

   !> A random rotation matrix.
   function random_rotation(seed) result(A)
      integer, intent(in) :: seed
      real(dp) :: A(3, 3)
      A = euler_rotation(euler_normalized(random_vector(4, seed)))
   end function random_rotation

   !> Random coordinates of a body: R ~ 0.1 m, unit theta, modal coordinates ~ 0.02.
   function random_coordinates(n, seed) result(q)
      integer, intent(in) :: n, seed
      real(dp) :: q(n)
      if (n == 0) return
      q = random_vector(n, seed)
      q(1:3) = 0.1_dp * q(1:3)
      q(4:7) = euler_normalized(q(4:7))
      q(8:n) = 0.02_dp * q(8:n)
   end function random_coordinates

   !> Random velocities tangent to |theta| = 1 (theta^T theta_dot = 0), omega ~ 100 rad/s.
   function random_velocities(q, seed) result(v)
      real(dp), intent(in) :: q(:)
      integer, intent(in) :: seed
      real(dp) :: v(size(q))
      integer :: n
      n = size(q)
      if (n == 0) return
      v = random_vector(n, seed)
      v(1:3) = 5.0_dp * v(1:3)
      v(4:7) = 50.0_dp * (v(4:7) - dot_product(v(4:7), q(4:7)) * q(4:7))
      v(8:n) = 2.0_dp * v(8:n)
   end function random_velocities

   function max_abs(a) result(s)
      real(dp), intent(in) :: a(:, :)
      real(dp) :: s
      s = 0.0_dp
      if (size(a) > 0) s = maxval(abs(a))
   end function max_abs

   pure function cross(a, b) result(c)
      real(dp), intent(in) :: a(3), b(3)
      real(dp) :: c(3)
      c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
   end function cross

   !> Rotation by angle about a (global) axis.
   function axis_rotation(axis, angle) result(Q)
      real(dp), intent(in) :: axis(3), angle
      real(dp) :: Q(3, 3)
      Q = euler_rotation(euler_from_axis_angle(axis, angle))
   end function axis_rotation

   !> A rigid test body: m = 2.5 kg, centre of mass off the reference point, a full inertia
   !> tensor (principal moments 0.02, 0.03, 0.04 in rotated axes), 2 markers with random frames.
   subroutine test_rigid_body(seed, body, error)
      integer, intent(in) :: seed
      type(rigid_body_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: frames(3, 3, 2), P(3, 3), inertia(3, 3)
      frames(:, :, 1) = random_rotation(seed + 1)
      frames(:, :, 2) = random_rotation(seed + 2)
      P = random_rotation(seed + 3)
      inertia = matmul(P, matmul(reshape([0.02_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.03_dp, 0.0_dp, &
         0.0_dp, 0.0_dp, 0.04_dp], [3, 3]), transpose(P)))
      call body%init(2.5_dp, [0.02_dp, -0.01_dp, 0.03_dp], inertia, &
         0.1_dp * reshape(random_vector(6, seed + 4), [3, 2]), frames, error)
   end subroutine test_rigid_body

   !> The crank of scene.md (crank_lc8, RBE3 B1 B2 B3, RC set 3), 8 modes, as a body_t.
   subroutine get_crank(error)
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t) :: input
      type(interface_input_t) :: faces(3)
      type(modes_input_t) :: modes_input
      type(body_modes_t) :: modes
      type(logger_t) :: log
      type(stage_times_t) :: times
      type(csr_t) :: stiffness_matrix, mass_matrix
      character(len=2), parameter :: names(3) = ['B1', 'B2', 'B3']
      real(dp) :: virtual_xyz(3, 3)
      integer :: k
      if (crank_ready) return
      input = body_input_t('crank', 'crank_lc8.msh', '', young, poisson, density)
      input%volumes(1) = 'crank'
      do k = 1, 3
         faces(k)%body = 'crank'
         faces(k)%name = names(k)
         faces(k)%mpc = 'RBE3'
         faces(k)%rc = ''
      end do
      faces(2)%rc = 'Tx Ty Tz Rx Ry Rz'
      modes_input%num_modes = 8
      log%level = LOG_QUIET
      call compute_input_body_modes(input, faces, modes_input, test_mesh_dir(), &
         log, times, modes, error)
      if (allocated(error)) then
         call add_context(error, 'crank_lc8.msh')
         return
      end if
      call assemble_stiffness_mass(modes%mesh%xyz, modes%mesh%tets, modes%mesh%tet_tags, &
         material_t(young, poisson, density, 'steel'), stiffness_matrix, mass_matrix, error)
      if (allocated(error)) return
      do k = 1, 3
         virtual_xyz(:, k) = modes%interfaces(k)%virtual_xyz
      end do
      call crank%init(mass_matrix, modes%mesh%xyz, modes%shape, &
         (2.0_dp * pi * modes%frequency_hz)**2, modes%virtual_node_shape, virtual_xyz, error)
      crank_ready = .not. allocated(error)
   end subroutine get_crank

   ! ----------------------------------------------------------------------------------------------
   ! Rigid body

   !> init refuses a non-positive mass, an unsymmetric inertia, a non-positive-definite one and
   !> one whose principal moments break the triangle inequality (each message names the value),
   !> and a marker frame that is not a rotation; a thin plate (J3 = J1 + J2 exactly) is accepted.
   subroutine test_bad_input(error)
      type(error_t), allocatable, intent(out) :: error
      type(rigid_body_t) :: body
      real(dp) :: inertia(3, 3), markers(3, 1), frames(3, 3, 1)
      markers = 0.0_dp
      call expect_failure(-1.0_dp, diagonal([1.0_dp, 1.0_dp, 1.0_dp]), 'mass = -1', error)
      if (allocated(error)) return
      inertia = diagonal([1.0_dp, 2.0_dp, 2.5_dp])
      inertia(1, 2) = 0.1_dp
      call expect_failure(1.0_dp, inertia, 'not symmetric', error)
      if (allocated(error)) return
      call expect_failure(1.0_dp, diagonal([-0.5_dp, 2.0_dp, 2.0_dp]), 'not positive definite', &
         error)
      if (allocated(error)) return
      call expect_failure(1.0_dp, diagonal([1.0_dp, 1.0_dp, 3.0_dp]), 'triangle inequality', &
         error)
      if (allocated(error)) return
      call body%init(1.0_dp, [0.0_dp, 0.0_dp, 0.0_dp], diagonal([1.0_dp, 2.0_dp, 3.0_dp]), &
         markers, axes(1), error)
      if (allocated(error)) then
         call add_context(error, 'a thin plate (J3 = J1 + J2) must be accepted')
         return
      end if
      frames(:, :, 1) = identity3()
      frames(1, 1, 1) = -1.0_dp
      block
         type(error_t), allocatable :: failure
         call body%init(1.0_dp, [0.0_dp, 0.0_dp, 0.0_dp], diagonal([1.0_dp, 2.0_dp, 2.0_dp]), &
            markers, frames, failure)
         call check(error, 'a reflected marker frame is refused', allocated(failure))
         if (allocated(error)) return
         call report('frame: ' // failure%message)
         call check(error, 'message names the marker and det: ' // failure%message, &
            index(failure%message, 'marker 1') > 0 .and. index(failure%message, 'det = -1') > 0)
      end block
   contains
      subroutine expect_failure(mass, inertia, needle, error)
         real(dp), intent(in) :: mass, inertia(3, 3)
         character(len=*), intent(in) :: needle
         type(error_t), allocatable, intent(out) :: error
         type(error_t), allocatable :: failure
         call body%init(mass, [0.0_dp, 0.0_dp, 0.0_dp], inertia, markers, axes(1), failure)
         call check(error, 'refused: ' // needle, allocated(failure))
         if (allocated(error)) return
         call report(failure%message)
         call check(error, 'message contains "' // needle // '": ' // failure%message, &
            index(failure%message, needle) > 0)
      end subroutine expect_failure
   end subroutine test_bad_input

   !> n marker frames equal to the body axes.
   function axes(n) result(frames)
      integer, intent(in) :: n
      real(dp) :: frames(3, 3, n)
      integer :: k
      do k = 1, n
         frames(:, :, k) = identity3()
      end do
   end function axes

   function diagonal(d) result(a)
      real(dp), intent(in) :: d(3)
      real(dp) :: a(3, 3)
      a = 0.0_dp
      a(1, 1) = d(1)
      a(2, 2) = d(2)
      a(3, 3) = d(3)
   end function diagonal

   !> Mass matrix against theory.md 3.3 with Psi = 0 written out here (m I, -A m chi~ G_bar,
   !> G_bar^T J_O G_bar with J_O = J_c - m chi~ chi~), 1e-14 of max |M|; kinetic energy
   !> v^T M v / 2 against 1/2 m |v_c|^2 + 1/2 w^T (A J_c A^T) w with v_c = R_dot + w x (A chi) and
   !> w = G theta_dot global (independent formulas: no G_bar, no J_O), 1e-12 relative.
   subroutine test_rigid_mass_matrix(error)
      type(error_t), allocatable, intent(out) :: error
      type(rigid_body_t) :: body
      real(dp) :: q(7), v(7), A(3, 3), G_bar(3, 4), J_o(3, 3), expected(7, 7), omega(3), v_c(3)
      real(dp) :: energy
      integer :: seed
      call test_rigid_body(1, body, error)
      if (allocated(error)) return
      do seed = 1, 4
         q = random_coordinates(7, 10 + seed)
         v = random_velocities(q, 20 + seed)
         A = euler_rotation(q(4:7))
         G_bar = euler_g_bar(q(4:7))
         J_o = body%inertia - body%mass * matmul(skew3(body%center_of_mass), &
            skew3(body%center_of_mass))
         expected = 0.0_dp
         expected(1:3, 1:3) = body%mass * identity3()
         expected(1:3, 4:7) = -body%mass * matmul(A, matmul(skew3(body%center_of_mass), G_bar))
         expected(4:7, 1:3) = transpose(expected(1:3, 4:7))
         expected(4:7, 4:7) = matmul(transpose(G_bar), matmul(J_o, G_bar))
         call check_close(error, 'max |M - closed form|', max_abs(body%mass_matrix(q) - &
            expected), 0.0_dp, atol=1.0e-14_dp * max_abs(expected))
         if (allocated(error)) return
         omega = matmul(euler_g(q(4:7)), v(4:7))
         v_c = v(1:3) + cross(omega, matmul(A, body%center_of_mass))
         energy = 0.5_dp * body%mass * dot_product(v_c, v_c) + 0.5_dp * dot_product(omega, &
            matmul(matmul(A, matmul(body%inertia, transpose(A))), omega))
         call check_close(error, 'kinetic energy v^T M v / 2', body%kinetic_energy(q, v), &
            energy, rtol=1.0e-12_dp)
         if (allocated(error)) return
      end do
      call report('kinetic energy (last state) ' // to_str(energy, 12) // ' J')
   end subroutine test_rigid_mass_matrix

   !> Second implementation: flexible_body_t of four point masses (lumped mass matrix, one
   !> mode, zeta = zeta_dot = 0) has the rigid body's m, chi and J_c (computed here from the
   !> points); its 7 x 7 rigid block of M(q), the rigid rows of f_v and its marker (virtual node
   !> with zero mode rows) equal the rigid body's to 1e-12 relative.
   subroutine test_rigid_vs_flexible(error)
      type(error_t), allocatable, intent(out) :: error
      type(flexible_body_t) :: points
      type(rigid_body_t) :: body
      type(csr_t) :: M
      real(dp) :: xyz(3, 4), masses(4), chi(3), inertia(3, 3), x(3), q(8), v(8), s(3, 1)
      real(dp), allocatable :: mf(:, :), mr(:, :), ff(:), fr(:), lf(:, :)
      real(dp) :: shapes(12, 1), virtual_shapes(6, 1)
      integer :: i, seed
      xyz = reshape([0.1_dp, 0.0_dp, 0.02_dp, -0.05_dp, 0.08_dp, 0.0_dp, 0.0_dp, -0.06_dp, &
         0.07_dp, 0.03_dp, 0.01_dp, -0.09_dp], [3, 4])
      masses = [0.7_dp, 1.1_dp, 0.4_dp, 0.9_dp]
      call csr_from_coo(12_ip, 12_ip, [(int(i, ip), i=1, 12)], [(int(i, ip), i=1, 12)], &
         [(masses(i), masses(i), masses(i), i=1, 4)], M, error)
      if (allocated(error)) return
      shapes(:, 1) = random_vector(12, 5)
      virtual_shapes = 0.0_dp
      s(:, 1) = [0.04_dp, -0.02_dp, 0.05_dp]
      call points%init(M, xyz, shapes, [1.0_dp], virtual_shapes, s, error)
      if (allocated(error)) return
      chi = matmul(xyz, masses) / sum(masses)
      inertia = 0.0_dp
      do i = 1, 4
         x = xyz(:, i) - chi
         inertia = inertia + masses(i) * (dot_product(x, x) * identity3() - &
            spread(x, 2, 3) * spread(x, 1, 3))
      end do
      call body%init(sum(masses), chi, inertia, s, axes(1), error)
      if (allocated(error)) return
      do seed = 1, 3
         q = [random_coordinates(7, 30 + seed), 0.0_dp]
         v = [random_velocities(q(1:7), 40 + seed), 0.0_dp]
         mf = points%mass_matrix(q)
         mr = body%mass_matrix(q(1:7))
         call check_close(error, 'rigid block of M: rigid_body_t vs flexible_body_t', &
            max_abs(mf(1:7, 1:7) - mr), 0.0_dp, atol=1.0e-12_dp * max_abs(mr))
         if (allocated(error)) return
         ff = points%quadratic_velocity(q, v)
         fr = body%quadratic_velocity(q(1:7), v(1:7))
         call check_close(error, 'rigid rows of f_v: rigid_body_t vs flexible_body_t', &
            maxval(abs(ff(1:7) - fr)), 0.0_dp, atol=1.0e-12_dp * maxval(abs(fr)))
         if (allocated(error)) return
         call check_close(error, 'marker position', maxval(abs(points%marker_position(q, 1) - &
            body%marker_position(q(1:7), 1))), 0.0_dp, atol=1.0e-15_dp)
         if (allocated(error)) return
         lf = points%marker_velocity_jacobian(q, 1)
         call check_close(error, 'marker velocity Jacobian', &
            max_abs(body%marker_velocity_jacobian(q(1:7), 1) - lf(:, 1:7)), 0.0_dp, &
            atol=1.0e-14_dp)
         if (allocated(error)) return
      end do
      call report('point masses: m = ' // to_str(sum(masses), 6) // ' kg, |f_v| = ' // &
         to_str(maxval(abs(fr)), 5))
   end subroutine test_rigid_vs_flexible

   !> f_v against Lagrange's equations by central differences (as for the flexible body):
   !> f_L = -(dM/dt) v + d(v^T M v / 2)/dq, compared in the R rows and, in the theta rows, in the
   !> part tangent to |theta| = 1 (the theta-component is the normalisation multiplier's).
   !> Tolerance 1e-8 of |f_v| (quadratic functions, h = 1e-5: truncation ~1e-10).
   subroutine test_rigid_quadratic_velocity(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-5_dp
      type(rigid_body_t) :: body
      real(dp) :: q(7), v(7), f_v(7), f_l(7), dq(7), mass_dot(7, 7), theta(4), hv
      integer :: i, seed
      call test_rigid_body(2, body, error)
      if (allocated(error)) return
      do seed = 1, 3
         q = random_coordinates(7, 50 + seed)
         v = random_velocities(q, 60 + seed)
         f_v = body%quadratic_velocity(q, v)
         hv = h / norm2(v(4:7))
         mass_dot = (body%mass_matrix(q + hv * v) - body%mass_matrix(q - hv * v)) / (2.0_dp * hv)
         f_l = -matmul(mass_dot, v)
         do i = 1, 7
            dq = 0.0_dp
            dq(i) = h
            f_l(i) = f_l(i) + 0.25_dp * dot_product(v, matmul(body%mass_matrix(q + dq) - &
               body%mass_matrix(q - dq), v)) / h
         end do
         theta = q(4:7)
         f_l(4:7) = f_l(4:7) - dot_product(theta, f_l(4:7)) * theta
         call check_close(error, '|f_v - f_Lagrange|, state ' // to_str(seed), &
            norm2(f_v - f_l), 0.0_dp, atol=1.0e-8_dp * norm2(f_v))
         if (allocated(error)) return
      end do
      call report('|f_v| = ' // to_str(norm2(f_v), 6) // ', |f_v - f_L| = ' // &
         to_str(norm2(f_v - f_l), 3))
   end subroutine test_rigid_quadratic_velocity

   !> Rigid markers: dr/dq and d(A_k a)/dq against central differences (h = 1e-6, 1e-7 of
   !> max |J|); on tangent velocities L_r v = (dr/dq) v and L_w v = axial(dA_k/dt A_k^T)
   !> (differences along a path on |theta| = 1, 1e-7); Q . v of a force and moment at the marker
   !> equals F . r_dot + M . omega (1e-12).
   subroutine test_rigid_markers(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-6_dp
      type(rigid_body_t) :: body
      real(dp) :: q(7), v(7), dq(7), fd(3, 7), jac(3, 7), axis(3), A_dot(3, 3), omega(3)
      real(dp) :: force(3), moment(3), qp(7), qm(7), hp
      integer :: k, i
      call test_rigid_body(3, body, error)
      if (allocated(error)) return
      q = random_coordinates(7, 70)
      v = random_velocities(q, 71)
      axis = [0.3_dp, -0.5_dp, 0.8_dp]
      do k = 1, body%num_markers
         jac = body%marker_position_jacobian(q, k)
         do i = 1, 7
            dq = 0.0_dp
            dq(i) = h
            fd(:, i) = (body%marker_position(q + dq, k) - body%marker_position(q - dq, k)) / &
               (2.0_dp * h)
         end do
         call check_close(error, 'dr/dq vs differences', max_abs(jac - fd), 0.0_dp, &
            atol=1.0e-7_dp * max_abs(jac))
         if (allocated(error)) return
         jac = body%marker_axis_jacobian(q, k, axis)
         do i = 1, 7
            dq = 0.0_dp
            dq(i) = h
            fd(:, i) = (matmul(body%marker_orientation(q + dq, k), axis) - &
               matmul(body%marker_orientation(q - dq, k), axis)) / (2.0_dp * h)
         end do
         call check_close(error, 'd(A_k a)/dq vs differences', max_abs(jac - fd), 0.0_dp, &
            atol=1.0e-7_dp * max_abs(jac))
         if (allocated(error)) return
         call check_close(error, 'L_r v vs (dr/dq) v', norm2(matmul( &
            body%marker_velocity_jacobian(q, k) - body%marker_position_jacobian(q, k), v)), &
            0.0_dp, atol=1.0e-12_dp * norm2(v))
         if (allocated(error)) return
         hp = h / norm2(v(4:7))
         qp = q + hp * v
         qp(4:7) = euler_normalized(qp(4:7))
         qm = q - hp * v
         qm(4:7) = euler_normalized(qm(4:7))
         A_dot = (body%marker_orientation(qp, k) - body%marker_orientation(qm, k)) / (2.0_dp * hp)
         A_dot = matmul(A_dot, transpose(body%marker_orientation(q, k)))
         omega = 0.5_dp * [A_dot(3, 2) - A_dot(2, 3), A_dot(1, 3) - A_dot(3, 1), &
            A_dot(2, 1) - A_dot(1, 2)]
         call check_close(error, 'L_w v vs axial(dA/dt A^T)', norm2(matmul( &
            body%marker_rotation_jacobian(q, k), v) - omega), 0.0_dp, atol=1.0e-7_dp * norm2(omega))
         if (allocated(error)) return
         force = [10.0_dp, -4.0_dp, 7.0_dp]
         moment = [0.5_dp, 1.5_dp, -2.0_dp]
         call check_close(error, 'Q . v vs F . r_dot + M . omega', dot_product( &
            body%marker_generalized_force(q, k, force, moment), v), &
            dot_product(force, matmul(body%marker_velocity_jacobian(q, k), v)) + &
            dot_product(moment, omega), rtol=1.0e-7_dp)
         if (allocated(error)) return
      end do
   end subroutine test_rigid_markers

   ! ----------------------------------------------------------------------------------------------
   ! Joints

   !> new_joint: every kind with its number of equations and name; an unknown kind lists the
   !> valid ones; connect refuses a marker the body does not have.
   subroutine test_factory(error)
      type(error_t), allocatable, intent(out) :: error
      class(joint_t), allocatable :: joint
      type(error_t), allocatable :: failure
      type(rigid_body_t) :: body
      type(ground_t) :: ground
      integer, parameter :: expected(6) = [3, 5, 4, 5, 6, 4]
      integer :: i
      do i = 1, size(kinds)
         call new_joint(kind_codes(i), joint, error)
         if (allocated(error)) return
         call check(error, trim(kinds(i)) // ': ' // to_str(joint%num_equations) // &
            ' equations, expected ' // to_str(expected(i)) // '; kind_name ' // joint%kind_name(), &
            joint%num_equations == expected(i) .and. joint%kind_name() == trim(kinds(i)) .and. &
            joint_kind_name(kind_codes(i)) == trim(kinds(i)))
         if (allocated(error)) return
      end do
      call new_joint(0, joint, failure)
      call check(error, 'unknown kind refused', allocated(failure))
      if (allocated(error)) return
      call report(failure%message)
      call check(error, 'message lists the kinds: ' // failure%message, index(failure%message, &
         'joint kind 0') > 0 .and. index(failure%message, 'revolute, prismatic, spherical, ' // &
         'universal, fixed, cylindrical') > 0)
      if (allocated(error)) return
      call check(error, 'joint_kind_name of no kind: ' // joint_kind_name(99), &
         joint_kind_name(99) == 'unknown')
      if (allocated(error)) return
      deallocate (failure)
      call test_rigid_body(4, body, error)
      if (allocated(error)) return
      call ground%init(reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), axes(1), error)
      if (allocated(error)) return
      call new_joint(JOINT_SPHERICAL, joint, error)
      if (allocated(error)) return
      call joint%connect(ground, 1, body, 3, failure)
      call check(error, 'marker 3 of a 2-marker body refused', allocated(failure))
      if (allocated(error)) return
      call report(failure%message)
      call check(error, 'message names the marker: ' // failure%message, &
         index(failure%message, 'marker 3') > 0)
   end subroutine test_factory

   !> Two rigid bodies placed so that marker 1 of body a and marker 2 of body b coincide (random
   !> body poses and marker frames): Phi = 0 (1e-14); Phi stays 0 (1e-14) under a rigid motion of
   !> the pair and under the joint's free motions (spherical: rotation about a random axis
   !> through the joint; revolute: rotation about z; universal: rotation about x_a then about the
   !> rotated y_b; prismatic: translation along z; cylindrical: rotation about z and translation
   !> along z at once), and becomes non-zero (> 1e-3) for a forbidden motion (translation along x
   !> for spherical, revolute and universal; rotation about x for the revolute and cylindrical;
   !> translation along y for prismatic and cylindrical; rotation about z for the universal,
   !> prismatic and fixed).
   subroutine test_joint_motions(error)
      type(error_t), allocatable, intent(out) :: error
      type(rigid_body_t) :: body_a, body_b
      class(joint_t), allocatable :: joint
      real(dp) :: q_a(7), q_b(7), q_bm(7), q_am(7), A_b(3, 3), r_a(3), frame_a(3, 3), Q(3, 3)
      real(dp) :: worst_free, least_forbidden, y_b(3), frame_b(3, 3), turn, tilt(3)
      integer :: i
      call test_rigid_body(5, body_a, error)
      if (.not. allocated(error)) call test_rigid_body(6, body_b, error)
      if (allocated(error)) return
      q_a = random_coordinates(7, 80)
      r_a = body_a%marker_position(q_a, 1)
      frame_a = body_a%marker_orientation(q_a, 1)
      A_b = matmul(frame_a, transpose(body_b%marker_frames(:, :, 2)))
      q_b(4:7) = euler_from_rotation(A_b)
      q_b(1:3) = r_a - matmul(A_b, body_b%marker_xyz(:, 2))
      worst_free = 0.0_dp
      least_forbidden = huge(1.0_dp)
      do i = 1, size(kinds)
         call new_joint(kind_codes(i), joint, error)
         if (.not. allocated(error)) call joint%connect(body_a, 1, body_b, 2, error)
         if (allocated(error)) return
         call expect_zero('assembled', q_a, q_b)
         if (allocated(error)) return
         ! Rigid motion of the pair
         Q = random_rotation(81)
         q_am = moved(body_a, q_a, Q, [0.0_dp, 0.0_dp, 0.0_dp], [0.3_dp, -0.2_dp, 0.1_dp])
         q_bm = moved(body_b, q_b, Q, [0.0_dp, 0.0_dp, 0.0_dp], [0.3_dp, -0.2_dp, 0.1_dp])
         call expect_zero('rigid motion of the pair', q_am, q_bm)
         if (allocated(error)) return
         select case (kinds(i))
         case ('spherical')
            q_bm = moved(body_b, q_b, axis_rotation([0.2_dp, -0.7_dp, 0.4_dp], 0.8_dp), r_a, &
               [0.0_dp, 0.0_dp, 0.0_dp])
            call expect_zero('rotation about a random axis', q_a, q_bm)
            if (.not. allocated(error)) call expect_nonzero('translation along x', q_a, &
               moved(body_b, q_b, identity3(), r_a, 0.01_dp * frame_a(:, 1)))
         case ('revolute')
            q_bm = moved(body_b, q_b, axis_rotation(frame_a(:, 3), 1.3_dp), r_a, &
               [0.0_dp, 0.0_dp, 0.0_dp])
            call expect_zero('rotation about z', q_a, q_bm)
            if (.not. allocated(error)) call expect_nonzero('rotation about x', q_a, &
               moved(body_b, q_b, axis_rotation(frame_a(:, 1), 0.1_dp), r_a, &
               [0.0_dp, 0.0_dp, 0.0_dp]))
            if (.not. allocated(error)) call expect_nonzero('translation along x', q_a, &
               moved(body_b, q_b, identity3(), r_a, 0.01_dp * frame_a(:, 1)))
         case ('universal')
            q_bm = moved(body_b, q_b, axis_rotation(frame_a(:, 1), 0.6_dp), r_a, &
               [0.0_dp, 0.0_dp, 0.0_dp])
            frame_b = body_b%marker_orientation(q_bm, 2)
            y_b = frame_b(:, 2)
            q_bm = moved(body_b, q_bm, axis_rotation(y_b, -0.9_dp), r_a, [0.0_dp, 0.0_dp, 0.0_dp])
            call expect_zero('rotation about x_a, then about y_b', q_a, q_bm)
            if (.not. allocated(error)) call expect_nonzero('rotation about z', q_a, &
               moved(body_b, q_b, axis_rotation(frame_a(:, 3), 0.1_dp), r_a, &
               [0.0_dp, 0.0_dp, 0.0_dp]))
            if (.not. allocated(error)) call expect_nonzero('translation along x', q_a, &
               moved(body_b, q_b, identity3(), r_a, 0.01_dp * frame_a(:, 1)))
         case ('prismatic', 'cylindrical')
            ! the cylinder also turns about z; what the guide forbids instead is a tilt about x
            turn = 0.0_dp
            tilt = frame_a(:, 3)
            if (kinds(i) == 'cylindrical') then
               turn = 1.3_dp
               tilt = frame_a(:, 1)
            end if
            q_bm = moved(body_b, q_b, axis_rotation(frame_a(:, 3), turn), r_a, &
               0.07_dp * frame_a(:, 3))
            call expect_zero('translation along z (cylindrical: turning about z)', q_a, q_bm)
            if (.not. allocated(error)) call expect_nonzero('rotation about z (cylindrical: ' // &
               'about x)', q_a, moved(body_b, q_b, axis_rotation(tilt, 0.1_dp), r_a, &
               [0.0_dp, 0.0_dp, 0.0_dp]))
            if (.not. allocated(error)) call expect_nonzero('translation along y', q_a, &
               moved(body_b, q_b, identity3(), r_a, 0.01_dp * frame_a(:, 2)))
         case default
            call expect_nonzero('rotation about z', q_a, &
               moved(body_b, q_b, axis_rotation(frame_a(:, 3), 0.1_dp), r_a, &
               [0.0_dp, 0.0_dp, 0.0_dp]))
            if (.not. allocated(error)) call expect_nonzero('translation along z', q_a, &
               moved(body_b, q_b, identity3(), r_a, 0.01_dp * frame_a(:, 3)))
         end select
         if (allocated(error)) return
      end do
      call report('worst |Phi| on allowed motions ' // to_str(worst_free, 3) // &
         ', least max |Phi| on forbidden motions ' // to_str(least_forbidden, 3))
   contains
      subroutine expect_zero(what, qa, qb)
         character(len=*), intent(in) :: what
         real(dp), intent(in) :: qa(7), qb(7)
         real(dp) :: phi(joint%num_equations)
         call joint%residual(body_a, qa, body_b, qb, phi)
         worst_free = max(worst_free, maxval(abs(phi)))
         call check_close(error, trim(kinds(i)) // ', ' // what // ': max |Phi|', &
            maxval(abs(phi)), 0.0_dp, atol=1.0e-14_dp)
      end subroutine expect_zero
      subroutine expect_nonzero(what, qa, qb)
         character(len=*), intent(in) :: what
         real(dp), intent(in) :: qa(7), qb(7)
         real(dp) :: phi(joint%num_equations)
         call joint%residual(body_a, qa, body_b, qb, phi)
         least_forbidden = min(least_forbidden, maxval(abs(phi)))
         call check(error, trim(kinds(i)) // ', forbidden ' // what // ': max |Phi| = ' // &
            to_str(maxval(abs(phi)), 3) // ' must exceed 1e-3', maxval(abs(phi)) > 1.0e-3_dp)
      end subroutine expect_nonzero
   end subroutine test_joint_motions

   !> Coordinates of a rigid body after the motion x -> p + Q (x - p) + t of space.
   function moved(body, q, rot, p, t) result(qm)
      type(rigid_body_t), intent(in) :: body
      real(dp), intent(in) :: q(7), rot(3, 3), p(3), t(3)
      real(dp) :: qm(7), A(3, 3)
      A = euler_rotation(q(4:7))
      qm(1:3) = p + matmul(rot, q(1:3) - p) + t
      qm(4:7) = euler_from_rotation(matmul(rot, A))
      if (body%num_coordinates /= 7) qm = 0.0_dp
   end function moved

   !> Each kind, for the pairs rigid-rigid, ground-rigid, rigid-ground and rigid-flexible (crank
   !> marker B2, zeta ~ 0.02): dPhi/dq_a and dPhi/dq_b against central differences of Phi in
   !> every coordinate of both bodies (Euler parameters one by one, h = 1e-6), at poses that are
   !> NOT assembled (d /= 0, so the lateral terms count); tolerance 1e-7 of max |Phi_q|
   !> (quadratic and trigonometric functions: truncation ~h^2 = 1e-12 relative).
   subroutine test_joint_jacobians(error)
      type(error_t), allocatable, intent(out) :: error
      type(rigid_body_t) :: body_a, body_b
      type(ground_t) :: ground
      real(dp) :: worst
      integer :: i
      call test_rigid_body(7, body_a, error)
      if (.not. allocated(error)) call test_rigid_body(8, body_b, error)
      if (.not. allocated(error)) call ground%init(reshape([0.1_dp, -0.05_dp, 0.02_dp], &
         [3, 1]), reshape(random_rotation(9), [3, 3, 1]), error)
      if (.not. allocated(error)) call get_crank(error)
      if (allocated(error)) return
      worst = 0.0_dp
      do i = 1, size(kinds)
         call check_pair(kinds(i), 'rigid-rigid', body_a, 1, body_b, 2, 90 + i, worst, error)
         if (.not. allocated(error)) call check_pair(kinds(i), 'ground-rigid', ground, 1, &
            body_b, 1, 100 + i, worst, error)
         if (.not. allocated(error)) call check_pair(kinds(i), 'rigid-ground', body_a, 2, &
            ground, 1, 110 + i, worst, error)
         if (.not. allocated(error)) call check_pair(kinds(i), 'rigid-flexible', body_a, 1, &
            crank, 2, 120 + i, worst, error)
         if (.not. allocated(error)) call check_pair(kinds(i), 'flexible-rigid', crank, 3, &
            body_b, 1, 130 + i, worst, error)
         if (allocated(error)) return
      end do
      call report('worst relative Jacobian error over ' // to_str(size(kinds)) // &
         ' kinds x 5 pairs: ' // to_str(worst, 3))
   end subroutine test_joint_jacobians

   subroutine check_pair(kind, pair, body_a, marker_a, body_b, marker_b, seed, worst, error)
      character(len=*), intent(in) :: kind, pair
      class(body_t), intent(in) :: body_a, body_b
      integer, intent(in) :: marker_a, marker_b, seed
      real(dp), intent(inout) :: worst
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-6_dp
      class(joint_t), allocatable :: joint
      real(dp), allocatable :: q_a(:), q_b(:), jac_a(:, :), jac_b(:, :), fd_a(:, :), fd_b(:, :)
      real(dp), allocatable :: phi_p(:), phi_m(:), dq(:)
      real(dp) :: scale
      integer :: j, ne
      call new_joint(kind_code(kind), joint, error)
      if (.not. allocated(error)) call joint%connect(body_a, marker_a, body_b, marker_b, error)
      if (allocated(error)) return
      ne = joint%num_equations
      q_a = random_coordinates(body_a%num_coordinates, seed)
      q_b = random_coordinates(body_b%num_coordinates, seed + 500)
      allocate (jac_a(ne, size(q_a)), jac_b(ne, size(q_b)), fd_a(ne, size(q_a)), &
         fd_b(ne, size(q_b)), phi_p(ne), phi_m(ne))
      call joint%jacobian(body_a, q_a, body_b, q_b, jac_a, jac_b)
      dq = 0.0_dp * q_a
      do j = 1, size(q_a)
         dq(j) = h
         call joint%residual(body_a, q_a + dq, body_b, q_b, phi_p)
         call joint%residual(body_a, q_a - dq, body_b, q_b, phi_m)
         fd_a(:, j) = (phi_p - phi_m) / (2.0_dp * h)
         dq(j) = 0.0_dp
      end do
      dq = 0.0_dp * q_b
      do j = 1, size(q_b)
         dq(j) = h
         call joint%residual(body_a, q_a, body_b, q_b + dq, phi_p)
         call joint%residual(body_a, q_a, body_b, q_b - dq, phi_m)
         fd_b(:, j) = (phi_p - phi_m) / (2.0_dp * h)
         dq(j) = 0.0_dp
      end do
      scale = max(max_abs(jac_a), max_abs(jac_b))
      worst = max(worst, max(max_abs(jac_a - fd_a), max_abs(jac_b - fd_b)) / scale)
      call check_close(error, trim(kind) // ' ' // pair // ': max |dPhi/dq_a - FD|', &
         max_abs(jac_a - fd_a), 0.0_dp, atol=1.0e-7_dp * scale)
      if (.not. allocated(error)) call check_close(error, trim(kind) // ' ' // pair // &
         ': max |dPhi/dq_b - FD|', max_abs(jac_b - fd_b), 0.0_dp, atol=1.0e-7_dp * scale)
   end subroutine check_pair

   !> joint_reaction: for random multipliers, poses and velocities tangent to |theta| = 1, the
   !> virtual power of the constraint force on each body, -lambda^T Phi_q v, equals that of the
   !> reported force and moment at its marker, F . (L_r v) + M . (L_w v) (1e-10 of the sum of the
   !> magnitudes of the terms); F_a = -F_b (round-off). Pairs rigid-rigid and rigid-flexible.
   subroutine test_joint_reactions(error)
      type(error_t), allocatable, intent(out) :: error
      type(rigid_body_t) :: body_a
      real(dp) :: worst
      integer :: i
      worst = 0.0_dp
      call test_rigid_body(10, body_a, error)
      if (.not. allocated(error)) call get_crank(error)
      if (allocated(error)) return
      do i = 1, size(kinds)
         call check_reaction(kinds(i), body_a, 1, crank, 2, 140 + i, worst, error)
         if (.not. allocated(error)) call check_reaction(kinds(i), crank, 1, body_a, 2, &
            150 + i, worst, error)
         if (allocated(error)) return
      end do
      call report('worst |power difference| / (sum of term magnitudes): ' // to_str(worst, 3))
   end subroutine test_joint_reactions

   subroutine check_reaction(kind, body_a, marker_a, body_b, marker_b, seed, worst, error)
      character(len=*), intent(in) :: kind
      class(body_t), intent(in) :: body_a, body_b
      integer, intent(in) :: marker_a, marker_b, seed
      real(dp), intent(inout) :: worst
      type(error_t), allocatable, intent(out) :: error
      class(joint_t), allocatable :: joint
      real(dp), allocatable :: q_a(:), q_b(:), v_a(:), v_b(:), jac_a(:, :), jac_b(:, :)
      real(dp), allocatable :: lambda(:)
      real(dp) :: force(3, 2), moment(3, 2), power(2), expected(2), size_terms(2)
      integer :: ne
      call new_joint(kind_code(kind), joint, error)
      if (.not. allocated(error)) call joint%connect(body_a, marker_a, body_b, marker_b, error)
      if (allocated(error)) return
      ne = joint%num_equations
      q_a = random_coordinates(body_a%num_coordinates, seed)
      q_b = random_coordinates(body_b%num_coordinates, seed + 500)
      v_a = random_velocities(q_a, seed + 1)
      v_b = random_velocities(q_b, seed + 501)
      lambda = 100.0_dp * random_vector(ne, seed + 2)
      allocate (jac_a(ne, size(q_a)), jac_b(ne, size(q_b)))
      call joint%jacobian(body_a, q_a, body_b, q_b, jac_a, jac_b)
      call joint_reaction(joint, body_a, q_a, body_b, q_b, lambda, force, moment)
      expected = [-dot_product(lambda, matmul(jac_a, v_a)), &
         -dot_product(lambda, matmul(jac_b, v_b))]
      power(1) = dot_product(force(:, 1), matmul(body_a%marker_velocity_jacobian(q_a, &
         marker_a), v_a)) + dot_product(moment(:, 1), matmul(body_a%marker_rotation_jacobian( &
         q_a, marker_a), v_a))
      power(2) = dot_product(force(:, 2), matmul(body_b%marker_velocity_jacobian(q_b, &
         marker_b), v_b)) + dot_product(moment(:, 2), matmul(body_b%marker_rotation_jacobian( &
         q_b, marker_b), v_b))
      size_terms = [sum(abs(lambda)) * max_abs(jac_a) * sum(abs(v_a)), &
         sum(abs(lambda)) * max_abs(jac_b) * sum(abs(v_b))]
      worst = max(worst, maxval(abs(power - expected) / size_terms))
      call check_close(error, trim(kind) // ': power on body a, F_a . r_a_dot + M_a . w_a', &
         power(1), expected(1), atol=1.0e-10_dp * size_terms(1))
      if (.not. allocated(error)) call check_close(error, trim(kind) // ': power on body b', &
         power(2), expected(2), atol=1.0e-10_dp * size_terms(2))
      if (.not. allocated(error)) call check_close(error, trim(kind) // ': |F_a + F_b|', &
         norm2(force(:, 1) + force(:, 2)), 0.0_dp, atol=1.0e-13_dp * sum(abs(lambda)))
   end subroutine check_reaction

   ! ----------------------------------------------------------------------------------------------
   ! Slider-crank

   !> Which of two dependent rows is dropped must not hang on round-off (issue 21: LAPACK's
   !> dgeqp3 dropped one main bearing's axial row on one BLAS kernel and the other's on
   !> another). Reference: the rule itself (norms tied within 1e-10 go to the earlier row),
   !> exact in exact arithmetic. Seven independent rows of 9 columns (deterministic entries) and
   !> an eighth that repeats row 3: exactly (trial 1), or with one entry 1e-12 larger or smaller
   !> in magnitude (trials 2, 3: a norm 1e-13 above or below row 3's, a pair still dependent to
   !> 1e-12, far inside rank_rtol); trial 4 repeats row 2 instead, 1e-12 larger. Every time row 8,
   !> the later of the pair, is dropped, alone. (dgeqp3 on the same matrices drops row 3 in trial
   !> 2 and row 2 in trial 4: the larger norm wins.)
   subroutine test_redundant_ties(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: jac(8, 9)
      integer, allocatable :: active(:), dropped(:)
      integer :: i, j, trial
      do trial = 1, 4
         do j = 1, 9
            do i = 1, 7
               jac(i, j) = cos(1.7_dp * i + 0.31_dp * j * j) + merge(2.0_dp, 0.0_dp, i == j)
            end do
         end do
         jac(8, :) = jac(3, :)
         if (trial == 2) jac(8, 5) = jac(8, 5) + sign(1.0e-12_dp, jac(8, 5))
         if (trial == 3) jac(8, 5) = jac(8, 5) - sign(1.0e-12_dp, jac(8, 5))
         if (trial == 4) then
            jac(8, :) = jac(2, :)
            jac(8, 6) = jac(8, 6) + sign(1.0e-12_dp, jac(8, 6))
         end if
         call find_redundant_rows(jac, 1.0e-9_dp, active, dropped, error)
         if (allocated(error)) return
         call report('ties, trial ' // to_str(trial) // ': dropped ' // to_str(size(dropped)) // &
            ' row(s), the first ' // to_str(merge(dropped(1), 0, size(dropped) > 0)))
         call check(error, 'trial ' // to_str(trial) // ': the later row of the dependent ' // &
            'pair (8) is dropped, alone', size(dropped) == 1 .and. size(active) == 7)
         if (allocated(error)) return
         call check(error, 'trial ' // to_str(trial) // ': dropped row ' // to_str(dropped(1)) &
            // ', expected 8', dropped(1) == 8)
         if (allocated(error)) return
      end do
   end subroutine test_redundant_ties

   !> A protected row (an Euler-parameter normalisation) is never dropped (issue 24, IFToMM A04:
   !> Bricard's loop dropped a body's normalisation, its Euler parameters drifted and the run
   !> stopped at t = 2.5 s). Reference: the rule, exact. Seven independent rows of 9 columns (as
   !> test_redundant_ties) and an eighth = row 2 + row 5, so rows 2, 5, 8 are one dependent set.
   !> Unprotected the search drops one of them (row 2: row 8 has the larger norm); with that row
   !> protected it is kept and another of the set is dropped, alone, and the kept rows have full
   !> rank 7 (smallest singular value above 1e-3 of the largest); protecting rows outside the set
   !> (1 and 3) changes nothing.
   subroutine test_redundant_protected(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: jac(8, 9)
      real(dp), allocatable :: s(:)
      integer, allocatable :: active(:), dropped(:)
      logical :: protect(8)
      integer :: i, j, first_dropped
      do j = 1, 9
         do i = 1, 7
            jac(i, j) = cos(1.7_dp * i + 0.31_dp * j * j) + merge(2.0_dp, 0.0_dp, i == j)
         end do
      end do
      jac(8, :) = jac(2, :) + jac(5, :)
      call find_redundant_rows(jac, 1.0e-9_dp, active, dropped, error)
      if (allocated(error)) return
      call check(error, 'unprotected: one row of 2, 5, 8 dropped', size(dropped) == 1)
      if (allocated(error)) return
      first_dropped = dropped(1)
      call check(error, 'unprotected: dropped row ' // to_str(first_dropped) // ', one of 2, ' &
         // '5, 8', any(first_dropped == [2, 5, 8]))
      if (allocated(error)) return
      protect = .false.
      protect(first_dropped) = .true.
      call find_redundant_rows(jac, 1.0e-9_dp, active, dropped, error, protect)
      if (allocated(error)) return
      call report('unprotected: row ' // to_str(first_dropped) // ' dropped; with it ' // &
         'protected: row ' // to_str(dropped(1)))
      call check(error, 'row ' // to_str(first_dropped) // ' protected: it is kept and one ' // &
         'other row of 2, 5, 8 dropped', size(dropped) == 1 .and. any(dropped(1) == [2, 5, 8]) &
         .and. dropped(1) /= first_dropped)
      if (allocated(error)) return
      call singular_values(jac(active, :), s, error)
      if (allocated(error)) return
      call check(error, 'protected: the kept rows are independent, sigma_min / sigma_max = ' &
         // to_str(minval(s) / maxval(s)), minval(s) > 1.0e-3_dp * maxval(s))
      if (allocated(error)) return
      protect = .false.
      protect([1, 3]) = .true.
      call find_redundant_rows(jac, 1.0e-9_dp, active, dropped, error, protect)
      if (allocated(error)) return
      call check(error, 'rows 1, 3 protected: row ' // to_str(first_dropped) // ' dropped, ' // &
         'alone, as unprotected', size(dropped) == 1 .and. dropped(1) == first_dropped)
   end subroutine test_redundant_protected

   !> Planar slider-crank of scene.md (r = 0.045 m, l = 0.150 m) from rigid bodies and these
   !> joints: ground-crank revolute, crank-rod revolute, rod-piston revolute, piston-ground
   !> prismatic along y. 3 bodies x 7 = 21 coordinates; 20 joint equations + 3 Euler
   !> normalisations = 23 rows.
   !> (1) At the assembled pose for theta = 0.7 rad, Phi = 0 (1e-15) and rank Phi_q = 20
   !>     (singular values, rtol 1e-10): Gruebler (theory.md 4.3) gives 6 x 3 - 20 = -2 for a
   !>     mechanism of mobility 1 (21 - 20 = 1 here), so 3 equations are redundant; the
   !>     rank-revealing QR of the integrator (find_redundant_rows) drops 3 rows too.
   !> (2) Gauss-Newton (least squares, dgels) on Phi plus a driver x_crank . n(theta) = 0 from a
   !>     perturbed pose (5 mm, 0.05 rad): the piston pin height equals r cos(theta) +
   !>     sqrt(l^2 - r^2 sin^2(theta)) to 1e-12 relative at four crank angles.
   subroutine test_slider_crank(error)
      type(error_t), allocatable, intent(out) :: error
      type(ground_t), target :: ground
      type(rigid_body_t), target :: crank_body, rod, piston
      type(joint_box_t) :: joints(4)
      real(dp) :: q(21), frames(3, 3, 2), jac(23, 21), y_exact, theta
      real(dp), allocatable :: s(:)
      integer, allocatable :: active(:), dropped(:)
      integer :: rank, iterations, i
      character(len=:), allocatable :: text
      real(dp), parameter :: angles(4) = [0.3_dp, 1.2_dp, 2.5_dp, 4.0_dp]
      real(dp), parameter :: inertia(3, 3) = reshape([2.0e-4_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         3.0e-4_dp, 0.0_dp, 0.0_dp, 0.0_dp, 4.0e-4_dp], [3, 3])
      ! Markers: frame 1 = body axes (revolutes about z); frame 2 has z along the body's y
      ! (prismatic along the cylinder axis): columns x, y, z = (1,0,0), (0,0,-1), (0,1,0).
      frames(:, :, 1) = identity3()
      frames(:, :, 2) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, &
         1.0_dp, 0.0_dp], [3, 3])
      call ground%init(reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], [3, 2]), &
         frames, error)
      if (.not. allocated(error)) call crank_body%init(2.0_dp, [0.0_dp, 0.01_dp, 0.0_dp], &
         inertia, reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, crank_radius, 0.0_dp], [3, 2]), &
         axes(2), error)
      if (.not. allocated(error)) call rod%init(0.6_dp, [0.0_dp, 0.05_dp, 0.0_dp], inertia, &
         reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, rod_length, 0.0_dp], [3, 2]), axes(2), error)
      if (.not. allocated(error)) call piston%init(0.45_dp, [0.0_dp, 0.0_dp, 0.0_dp], &
         3.0e-4_dp * identity3(), reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
         [3, 2]), frames, error)
      if (allocated(error)) return
      call make_joint(joints(1), 'revolute', ground, 1, crank_body, 1, 0, 1, error)
      if (.not. allocated(error)) call make_joint(joints(2), 'revolute', crank_body, 2, rod, 1, &
         1, 2, error)
      if (.not. allocated(error)) call make_joint(joints(3), 'revolute', rod, 2, piston, 1, 2, &
         3, error)
      if (.not. allocated(error)) call make_joint(joints(4), 'prismatic', ground, 2, piston, 2, &
         0, 3, error)
      if (allocated(error)) return

      ! (1) Rank at the assembled pose
      theta = 0.7_dp
      q = assembled(theta)
      call check_close(error, 'max |Phi| at the assembled pose', maxval(abs(residual(q))), &
         0.0_dp, atol=1.0e-15_dp)
      if (allocated(error)) return
      jac = jacobian(q)
      call singular_values(jac, s, error)
      if (allocated(error)) return
      rank = numerical_rank(s, 1.0e-10_dp)
      call report('slider-crank: 23 equations (20 joint + 3 Euler), 21 coordinates, rank ' // &
         to_str(rank) // ', redundant ' // to_str(23 - rank) // '; sigma_20/sigma_1 = ' // &
         to_str(s(20) / s(1), 3) // ', sigma_21/sigma_1 = ' // to_str(s(21) / s(1), 3))
      call check(error, 'rank of Phi_q = ' // to_str(rank) // ', expected 20 (mobility 1)', &
         rank == 20)
      if (allocated(error)) return
      call check(error, 'redundant equations = ' // to_str(23 - rank) // ', Gruebler: ' // &
         '1 - (6 x 3 - 20) = 3', 23 - rank == 1 - (6 * 3 - 20))
      if (allocated(error)) return
      call find_redundant_rows(jac, 1.0e-9_dp, active, dropped, error)
      if (allocated(error)) return
      text = ''
      do i = 1, size(dropped)
         text = text // ' ' // to_str(dropped(i))
      end do
      call report('find_redundant_rows drops rows' // text // ' (1-5 ground-crank, 6-10 ' // &
         'crank-rod, 11-15 rod-piston, 16-20 piston-ground, 21-23 Euler)')
      call check(error, 'find_redundant_rows drops ' // to_str(size(dropped)) // &
         ' rows, expected 3', size(dropped) == 3)
      if (allocated(error)) return

      ! (2) Piston position by Newton at given crank angles
      do i = 1, size(angles)
         theta = angles(i)
         q = assembled(theta)
         q(8:21) = q(8:21) + [0.005_dp * random_vector(3, 200 + i), &
            0.05_dp * random_vector(4, 210 + i), 0.005_dp * random_vector(3, 220 + i), &
            0.05_dp * random_vector(4, 230 + i)]
         q(1:7) = q(1:7) + [0.005_dp * random_vector(3, 240 + i), &
            0.05_dp * random_vector(4, 250 + i)]
         call solve_position(theta, q, iterations, error)
         if (allocated(error)) return
         y_exact = crank_radius * cos(theta) + sqrt(rod_length**2 - &
            (crank_radius * sin(theta))**2)
         call report('theta = ' // to_str(theta, 3) // ' rad: ' // to_str(iterations) // &
            ' Gauss-Newton iterations, piston y = ' // to_str(q(16), 15) // ' m, error ' // &
            to_str(q(16) - y_exact, 3) // ', max |Phi| = ' // &
            to_str(maxval(abs(residual(q))), 3))
         call check_close(error, 'piston y at theta = ' // to_str(theta, 3), q(16), y_exact, &
            rtol=1.0e-12_dp)
         if (allocated(error)) return
         call check_close(error, 'max |Phi| after Newton', maxval(abs(residual(q))), 0.0_dp, &
            atol=1.0e-14_dp)
         if (allocated(error)) return
      end do

   contains

      !> Closed-form assembly: crank turned by theta about z, rod from the pin to the piston pin.
      function assembled(angle) result(qa)
         real(dp), intent(in) :: angle
         real(dp) :: qa(21), pin(3), y, beta
         y = crank_radius * cos(angle) + sqrt(rod_length**2 - (crank_radius * sin(angle))**2)
         pin = crank_radius * [-sin(angle), cos(angle), 0.0_dp]
         beta = atan2(pin(1) / rod_length, (y - pin(2)) / rod_length)   ! y_rod = (-sin, cos)
         qa(1:3) = 0.0_dp
         qa(4:7) = euler_from_axis_angle([0.0_dp, 0.0_dp, 1.0_dp], angle)
         qa(8:10) = pin
         qa(11:14) = euler_from_axis_angle([0.0_dp, 0.0_dp, 1.0_dp], beta)
         qa(15:17) = [0.0_dp, y, 0.0_dp]
         qa(18:21) = [1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      end function assembled

      !> The 7 coordinates of body number b (0 = ground: none).
      function coords(qall, b) result(qb)
         real(dp), intent(in) :: qall(21)
         integer, intent(in) :: b
         real(dp), allocatable :: qb(:)
         if (b == 0) then
            allocate (qb(0))
         else
            qb = qall(7 * b - 6:7 * b)
         end if
      end function coords

      function body_of(b) result(ptr)
         integer, intent(in) :: b
         class(body_t), pointer :: ptr
         select case (b)
         case (0)
            ptr => ground
         case (1)
            ptr => crank_body
         case (2)
            ptr => rod
         case default
            ptr => piston
         end select
      end function body_of

      !> All 23 residuals: joints 1..4, then the Euler normalisations of crank, rod, piston.
      function residual(qall) result(phi)
         real(dp), intent(in) :: qall(21)
         real(dp) :: phi(23)
         integer :: j, row, b
         row = 0
         do j = 1, 4
            associate (jt => joints(j))
               call jt%joint%residual(body_of(jt%a), coords(qall, jt%a), body_of(jt%b), &
                  coords(qall, jt%b), phi(row + 1:row + 5))
            end associate
            row = row + 5
         end do
         do b = 1, 3
            phi(20 + b) = dot_product(qall(7 * b - 3:7 * b), qall(7 * b - 3:7 * b)) - 1.0_dp
         end do
      end function residual

      function jacobian(qall) result(jq)
         real(dp), intent(in) :: qall(21)
         real(dp) :: jq(23, 21)
         real(dp), allocatable :: ja(:, :), jb(:, :)
         integer :: j, row, b
         jq = 0.0_dp
         row = 0
         do j = 1, 4
            associate (jt => joints(j))
               allocate (ja(5, 7 * min(jt%a, 1)), jb(5, 7 * min(jt%b, 1)))
               call jt%joint%jacobian(body_of(jt%a), coords(qall, jt%a), body_of(jt%b), &
                  coords(qall, jt%b), ja, jb)
               if (jt%a > 0) jq(row + 1:row + 5, 7 * jt%a - 6:7 * jt%a) = ja
               if (jt%b > 0) jq(row + 1:row + 5, 7 * jt%b - 6:7 * jt%b) = jb
               deallocate (ja, jb)
            end associate
            row = row + 5
         end do
         do b = 1, 3
            jq(20 + b, 7 * b - 3:7 * b) = 2.0_dp * qall(7 * b - 3:7 * b)
         end do
      end function jacobian

      !> Gauss-Newton on [Phi; driver] = 0, driver = x_crank . (-sin(angle), cos(angle), 0).
      subroutine solve_position(angle, qall, iterations, error)
         real(dp), intent(in) :: angle
         real(dp), intent(inout) :: qall(21)
         integer, intent(out) :: iterations
         type(error_t), allocatable, intent(out) :: error
         real(dp) :: a(24, 21), rhs(24, 1), work(1000), normal(3), step, frame(3, 3)
         integer(ip) :: info
         integer :: it
         normal = [-sin(angle), cos(angle), 0.0_dp]
         iterations = 0
         do it = 1, 30
            a(1:23, :) = jacobian(qall)
            a(24, :) = 0.0_dp
            a(24, 1:7) = matmul(normal, crank_body%marker_axis_jacobian(qall(1:7), 1, &
               [1.0_dp, 0.0_dp, 0.0_dp]))
            rhs(1:23, 1) = -residual(qall)
            frame = crank_body%marker_orientation(qall(1:7), 1)
            rhs(24, 1) = -dot_product(normal, frame(:, 1))
            call dgels('N', 24_ip, 21_ip, 1_ip, a, 24_ip, rhs, 24_ip, work, 1000_ip, info)
            call check(error, 'dgels info = ' // to_str(info), info == 0)
            if (allocated(error)) return
            qall = qall + rhs(1:21, 1)
            iterations = it
            step = maxval(abs(rhs(1:21, 1)))
            if (step < 1.0e-15_dp) exit
         end do
         call check(error, 'Gauss-Newton converged in 30 iterations (last step ' // &
            to_str(step, 3) // ')', step < 1.0e-13_dp)
      end subroutine solve_position

   end subroutine test_slider_crank

   !> A joint with the bodies it connects (mechanism indices, 0 = ground).
   subroutine make_joint(box, kind, body_a, marker_a, body_b, marker_b, a, b, error)
      type(joint_box_t), intent(out) :: box
      character(len=*), intent(in) :: kind
      class(body_t), intent(in) :: body_a, body_b
      integer, intent(in) :: marker_a, marker_b, a, b
      type(error_t), allocatable, intent(out) :: error
      call new_joint(kind_code(kind), box%joint, error)
      if (.not. allocated(error)) call box%joint%connect(body_a, marker_a, body_b, marker_b, &
         error)
      box%a = a
      box%b = b
   end subroutine make_joint

   !> The kind (new_joint) of the joint kind called `name` (one of `kinds`).
   pure integer function kind_code(name)
      character(len=*), intent(in) :: name
      kind_code = kind_codes(findloc(kinds, name, dim=1))
   end function kind_code

end module test_mbs_joints

program main_mbs_joints
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_joints, only: collect_mbs_joints
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_joints(tests)
   call run_suite('mbs_joints', tests)
end program main_mbs_joints
