!> Analytic tangents of the mechanism's Newton iteration (ffrf_mbs_mechanism, analytic_tangents =
!> .true.) against the reference: dae_system_t's central differences over the whole mechanism
!> (analytic_tangents = .false.): stiffness -df/dq, damping -df/dq', constraint stiffness
!> d(Phi_q^T lambda)/dq and mass stiffness d(M a)/dq.
!>
!> Systems: the engine of scene.md (ground, crank, flywheel welded to the crank, conrod,
!> piston; revolutes B1, B3, crank pin, piston pin, prismatic cylinder; in-cylinder pressure on the
!> piston, starter and drag torques on the crank) (1) with a rigid crank, gravity on and a
!> driving constraint on the flywheel (so that every kind of term is present: rigid bodies, all
!> joint kinds but the universal and spherical ones, loads through the crank angle and speed,
!> gravity, the drive row, the Euler rows), and (2) with a flexible crank, a synthetic reduced
!> body (8 point masses, 3 random modes with modal damping, 3 interfaces with random mode
!> rows), gravity off. A further mechanism (3) joins two rigid bodies by a universal and a
!> spherical joint. Each at a random, non-trivial state: coordinates off the assembled pose
!> (|theta| within 1e-3 of 1), velocities ~ 100 rad/s, multipliers ~ 1e3, accelerations ~ 1e4.
!>
!> Tolerance. The reference's error is that of a central difference with
!> delta_j = eps**(1/3) max(|x_j|, 1) ~ 6e-6: truncation delta**2 |f'''| / 6 plus round-off
!> eps |f| / delta, both ~ 4e-11 relative to the scale of the function; the analytic tangents
!> are exact, or (flexible marker rotations' exponential map, load laws in crank angle and
!> speed) small central differences with the same error. Asserted: max |analytic - reference|
!> <= 1e-8 max |reference| per matrix. Measured (this suite's report lines): 6e-12 to 6e-11
!> (engine, rigid crank), 2e-15 to 8e-10 (flexible crank; the 8e-10 is the reference's
!> round-off in -df/dq' next to K_ff zeta ~ 1e5 N), 8e-12 to 4e-11 (universal/spherical). A
!> wrong term shows at O(1): a slip in the flexible marker Hessian (b_p(j) written as b_p)
!> gave 1.8e-2.
!> The last test runs the engine with both paths and checks that no step is rejected.
!> Each compared mechanism also checks the block-sparse interface of the sparse path (issue 24;
!> compare_sparse): M, Phi, Phi_q and C_t equal to the dense ones, K within 1e-14 of the dense
!> sum (measured 0 to 1.2e-16), the block products M a and Phi_q^T lambda within 1e-14 of matmul.
!> Spring-dampers (ffrf_mbs_spring_damper): (4) a rigid body and the synthetic flexible crank
!> joined to the ground and to each other by three springs with dampers (ground - rigid marker,
!> rigid marker - flexible virtual node, flexible virtual node - ground), no joints: the springs'
!> exact K and C against the same central differences (same tolerance; measured 6.7e-10 for
!> -df/dq, the reference's round-off next to k = 5e4 N/m, and 1.6e-10 for -df/dv). A wrong sign
!> of the damper's geometric term c w^T N gives 1.6e-2.
!> Torsion spring-dampers (ffrf_mbs_torsion_spring): (5) the ground, a rigid body and the
!> synthetic flexible crank joined by two revolute joints (ground - rigid, rigid - flexible
!> virtual node), each with a torsion spring-damper (k = 40 and 300 N m/rad, c = 0.7 and
!> 0.2 N m s/rad; free angles 0.3 and -0.2 rad): the springs' exact K and C against the same
!> central differences at the random state (off the joints: the rate z_a . (w_b - w_a) and the
!> angle atan2(y_a . x_b, x_a . x_b) both vary with every coordinate), same tolerance. A spring
!> that refuses a prismatic joint, an unknown joint, a negative k or c is checked after it.
!> Bushings (ffrf_mbs_bushing): (6) the ground, a rigid body and the synthetic flexible crank
!> joined by three damped bushings (ground - rigid with a rotated marker frame, rigid - flexible
!> virtual node, flexible - ground): C = E^T C E exact and K by the bushing's own central
!> differences against the whole mechanism's central differences, same tolerance; and the
!> conservative part: with the damping off, at a random state on the Euler parameters' manifold
!> (|theta| = 1, theta . theta' = 0, where L_w v is the angular velocity), the power of the
!> bushings' force Q . v equals -dU/dt of U = sum e^T K e / 2 (central difference of U along v, s = 1e-7: truncation
!> (s |v|)^2 ~ 1e-10 with Euler rates ~ 50 /s) to 1e-8 relative, each bushing alone (an independent check of E, the rate matrix e' = E v); then the refusals of
!> add_bushing.
!> Geometric stiffening (flexible_body_t%set_geometric_stiffness, random symmetric K_G^(c)
!> of order 1 so that -K_G(omega) zeta and its omega derivatives count): the flexible body's
!> force tangents against central differences (as the flexible-body test) and the engine with
!> that crank; measured 2e-11 (body -df/dq), 2e-12 (-df/dv), 7e-12 to 4e-11 (engine). Changing
!> the sign of the theta or theta_dot column of the K_G term gives 3e-2.
!> body_t's central-difference defaults (force_tangents, mass_stiffness, marker_hessian,
!> marker_force_tangent: the tangents of a body type that brings no analytic ones): (7) called on
!> a rigid body, against its exact tangents at a random state, same tolerance.
module test_mbs_tangents
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: csr_t, csr_from_coo
   use ffrf_mbs_rotation, only: identity3, euler_normalized
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_body, only: body_t, body_force_tangents_fd, body_mass_stiffness_fd, &
      body_marker_hessian_fd, body_marker_force_tangent_fd
   use ffrf_mbs_rigid_body, only: rigid_body_t, ground_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_joints, only: JOINT_FIXED, JOINT_PRISMATIC, JOINT_REVOLUTE, JOINT_SPHERICAL, &
      JOINT_UNIVERSAL
   use ffrf_mbs_mechanism_loads, only: polynomial_drive_t
   use ffrf_mbs_spring_damper, only: spring_damper_t
   use ffrf_mbs_torsion_spring, only: torsion_spring_t
   use ffrf_mbs_bushing, only: bushing_t
   use ffrf_test_rigid_engine, only: add_engine_loads, diagonal, crank_radius, rod_length
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t, &
      GALPHA_NEWTON_FULL
   use ffrf_testing, only: unittest_t, new_unittest, check, report
   use ffrf_la_block_sparse, only: block_sparse_t
   implicit none
   private
   public :: collect_mbs_tangents

   !> Relative tolerance of an analytic tangent against the central differences (module header)
   real(dp), parameter :: tangent_rtol = 1.0e-8_dp

contains

   !> The suite.
   subroutine collect_mbs_tangents(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('rigid_engine_tangents_match_differences', test_rigid_engine), &
         new_unittest('flexible_crank_tangents_match_differences', test_flexible_engine), &
         new_unittest('flexible_body_force_tangents_match_differences', test_flexible_body), &
         new_unittest('universal_spherical_tangents_match_differences', test_universal), &
         new_unittest('geometric_stiffness_tangents_match_differences', &
         test_geometric_stiffness), &
         new_unittest('engine_run_analytic_equals_differences', test_engine_run), &
         new_unittest('spring_damper_tangents_match_differences', test_springs), &
         new_unittest('spring_damper_refuses_bad_input', test_spring_refusals), &
         new_unittest('torsion_spring_tangents_match_differences', test_torsion_springs), &
         new_unittest('bushing_tangents_and_power', test_bushings), &
         new_unittest('body_default_tangents_match_rigid', test_body_defaults)]
   end subroutine collect_mbs_tangents

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

   !> A synthetic reduced crank: 8 point masses (lumped M = diag(m_i) (x) I3), 3 random modes
   !> with eigenvalues (2 pi 2, 3, 5 kHz)^2 and 2 % modal damping, interfaces B1 (0, 0, -0.03),
   !> B2 (0, r, 0), B3 (0, 0, 0.03) with random mode rows.
   subroutine synthetic_crank(crank, frequency_scale, error)
      type(flexible_body_t), intent(out) :: crank
      !> Factor on the modal frequencies
      real(dp), intent(in) :: frequency_scale
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: M
      real(dp) :: xyz(3, 8), masses(8), shapes(24, 3), virtual_shapes(18, 3), virtual_xyz(3, 3)
      integer :: i
      xyz = 0.04_dp * reshape(random_vector(24, 3), [3, 8])
      masses = 0.3_dp + 0.1_dp * random_vector(8, 4)
      call csr_from_coo(24_ip, 24_ip, [(int(i, ip), i=1, 24)], [(int(i, ip), i=1, 24)], &
         [(masses(i), masses(i), masses(i), i=1, 8)], M, error)
      if (allocated(error)) return
      shapes = reshape(random_vector(72, 5), [24, 3])
      virtual_shapes = 0.5_dp * reshape(random_vector(54, 6), [18, 3])
      virtual_xyz = reshape([0.0_dp, 0.0_dp, -0.03_dp, 0.0_dp, crank_radius, 0.0_dp, 0.0_dp, &
         0.0_dp, 0.03_dp], [3, 3])
      call crank%init(M, xyz, shapes, (2.0_dp * pi * frequency_scale * [2000.0_dp, 3000.0_dp, &
         5000.0_dp])**2, &
         virtual_shapes, virtual_xyz, error)
      if (allocated(error)) return
      call crank%set_modal_damping([0.02_dp], error)
   end subroutine synthetic_crank

   !> The engine (module header) with the crank `crank_body` (markers B1, B2, B3 at (0, 0, -0.03),
   !> (0, r, 0), (0, 0, 0.03) in its frame).
   subroutine build_engine(mech, crank_body, error)
      type(mechanism_t), intent(out) :: mech
      class(body_t), intent(in) :: crank_body
      type(error_t), allocatable, intent(out) :: error
      type(ground_t) :: ground
      type(rigid_body_t) :: flywheel, rod, piston
      real(dp) :: frames(3, 3, 3), ground_xyz(3, 3)
      integer :: ig, ic, iw, ir, ip_
      frames(:, :, 1) = identity3()
      frames(:, :, 2) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, &
         1.0_dp, 0.0_dp], [3, 3])
      frames(:, :, 3) = identity3()
      ground_xyz = reshape([0.0_dp, 0.0_dp, -0.03_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         0.03_dp], [3, 3])
      call ground%init(ground_xyz, frames, error)
      if (allocated(error)) return
      call flywheel%init(4.0_dp, [0.0_dp, 0.0_dp, 0.08_dp], diagonal([0.016_dp, 0.016_dp, &
         0.030_dp]), reshape([0.0_dp, 0.0_dp, 0.03_dp], [3, 1]), frames(:, :, [1]), error)
      if (allocated(error)) return
      call rod%init(0.865_dp, [0.0_dp, 0.049_dp, 0.0_dp], diagonal([3.3e-3_dp, 2.0e-4_dp, &
         3.3e-3_dp]), reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, rod_length, 0.0_dp], [3, 2]), &
         frames(:, :, [1, 1]), error)
      if (allocated(error)) return
      call piston%init(0.45_dp, [0.0_dp, 0.0_dp, 0.0_dp], 3.0e-4_dp * identity3(), &
         reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], [3, 2]), frames(:, :, 1:2), &
         error)
      if (allocated(error)) return
      call mech%add_body(ground, 'ground', ig, error)
      if (.not. allocated(error)) call mech%add_body(crank_body, 'crank', ic, error)
      if (.not. allocated(error)) call mech%add_body(flywheel, 'flywheel', iw, error)
      if (.not. allocated(error)) call mech%add_body(rod, 'conrod', ir, error)
      if (.not. allocated(error)) call mech%add_body(piston, 'piston', ip_, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_REVOLUTE, 'B1', ig, 1, ic, 1, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_REVOLUTE, 'B3', ig, 3, ic, 3, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_FIXED, 'flywheel', ic, 3, iw, 1, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_REVOLUTE, 'crank pin', ic, 2, ir, 1, &
         error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_REVOLUTE, 'piston pin', ir, 2, ip_, 1, &
         error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_PRISMATIC, 'cylinder', ig, 2, ip_, 2, &
         error)
      if (.not. allocated(error)) call mech%set_rotor(ic, error)
      if (allocated(error)) return
      call add_engine_loads(mech, ic, ip_, 3, error)
   end subroutine build_engine

   !> A random state: per body R ~ 0.05 m, theta a unit quaternion times (1 + 1e-3 noise),
   !> modal coordinates ~ 1e-4, velocities ~ 1 m/s and 50 rad/s per Euler rate, modal rates ~ 1;
   !> multipliers ~ 1e3, accelerations ~ 1e4.
   subroutine random_state(mech, seed, q, v, lambda, a)
      type(mechanism_t), intent(in) :: mech
      integer, intent(in) :: seed
      real(dp), allocatable, intent(out) :: q(:), v(:), lambda(:), a(:)
      integer :: b, k, nb
      q = random_vector(mech%num_coordinates(), seed)
      v = random_vector(mech%num_coordinates(), seed + 1)
      lambda = 1.0e3_dp * random_vector(mech%num_constraints(), seed + 2)
      a = 1.0e4_dp * random_vector(mech%num_coordinates(), seed + 3)
      do b = 1, size(mech%bodies)
         k = mech%bodies(b)%offset
         nb = mech%bodies(b)%body%num_coordinates
         if (nb == 0) cycle
         q(k + 1:k + 3) = 0.05_dp * q(k + 1:k + 3)
         q(k + 4:k + 7) = euler_normalized(q(k + 4:k + 7)) * (1.0_dp + 1.0e-3_dp * q(k + 4))
         q(k + 8:k + nb) = 1.0e-4_dp * q(k + 8:k + nb)
         v(k + 4:k + 7) = 50.0_dp * v(k + 4:k + 7)
      end do
   end subroutine random_state

   !> Each analytic tangent of `mech` against the central differences at a random state
   !> (module header); reports the relative differences under `what`.
   subroutine compare_tangents(mech, what, seed, error)
      type(mechanism_t), intent(inout) :: mech
      character(len=*), intent(in) :: what
      integer, intent(in) :: seed
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: q(:), v(:), lambda(:), a(:), exact(:, :), reference(:, :)
      real(dp) :: t, differences(4)
      character(len=*), parameter :: names(4) = ['stiffness -df/dq          ', &
         'damping -df/dv            ', 'constraint stiffness      ', 'mass stiffness d(M a)/dq  ']
      integer :: i, n
      call random_state(mech, seed, q, v, lambda, a)
      n = mech%num_coordinates()
      t = 0.01_dp
      allocate (exact(n, n), reference(n, n))
      do i = 1, 4
         mech%analytic_tangents = .true.
         call tangent(i, exact)
         if (allocated(error)) return
         mech%analytic_tangents = .false.
         call tangent(i, reference)
         if (allocated(error)) return
         differences(i) = maxval(abs(exact - reference)) / max(maxval(abs(reference)), &
            tiny(1.0_dp))
         call report(what // ': ' // trim(names(i)) // ' max |analytic - FD| / max |FD| = ' // &
            to_str(differences(i), 3) // ' (scale ' // to_str(maxval(abs(reference)), 3) // ')')
         call check(error, what // ': ' // trim(names(i)) // ' within ' // &
            to_str(tangent_rtol) // ' of the central differences, got ' // &
            to_str(differences(i), 3), differences(i) <= tangent_rtol)
         if (allocated(error)) return
      end do
      mech%analytic_tangents = .true.
      call compare_sparse(mech, what, q, v, lambda, a, t, error)
   contains
      subroutine tangent(which, matrix)
         integer, intent(in) :: which
         real(dp), intent(out) :: matrix(:, :)
         select case (which)
         case (1)
            call mech%stiffness(q, v, t, matrix, error)
         case (2)
            call mech%damping(q, v, t, matrix, error)
         case (3)
            call mech%constraint_stiffness(q, t, lambda, matrix, error)
         case default
            call mech%mass_stiffness(q, a, matrix, error)
         end select
      end subroutine tangent
   end subroutine compare_tangents

   !> The block-sparse interface of the sparse path (mass_sparse,
   !> constraints_and_jacobian_sparse, tangents_sparse; issue 24) against the dense one at the
   !> same state: M, Phi, Phi_q and C_t hold the same numbers (the same operations per entry:
   !> asserted equal), K = K_t + d(M a)/dq + d(Phi_q^T lambda)/dq sums the same terms in
   !> another order (asserted within 1e-14 of its scale: a few roundings of eps = 2.2e-16);
   !> the products M a and Phi_q^T lambda of the block storage against matmul, same 1e-14.
   subroutine compare_sparse(mech, what, q, v, lambda, a, t, error)
      type(mechanism_t), intent(inout) :: mech
      character(len=*), intent(in) :: what
      real(dp), intent(in) :: q(:), v(:), lambda(:), a(:), t
      type(error_t), allocatable, intent(out) :: error
      type(block_sparse_t) :: M_s, jacobian_s, K_s, C_s
      real(dp), allocatable :: dense(:, :), from_blocks(:, :), work(:, :), Phi_q(:, :), &
         residual(:), residual_s(:), y(:)
      real(dp) :: difference
      integer :: n, nc
      n = mech%num_coordinates()
      nc = mech%num_constraints()
      allocate (dense(n, n), from_blocks(n, n), work(n, n), Phi_q(nc, n), residual(nc), residual_s(nc), &
         y(n))
      call mech%mass(q, dense, error)
      if (.not. allocated(error)) call mech%mass_sparse(q, M_s, error)
      if (allocated(error)) return
      call M_s%to_dense(from_blocks)
      call check(error, what // ': block-sparse M equals the dense M', &
         all(from_blocks == dense))
      if (allocated(error)) return
      call M_s%matvec(a, y)
      difference = maxval(abs(y - matmul(dense, a))) / maxval(abs(matmul(abs(dense), abs(a))))
      call check(error, what // ': block-sparse M a against matmul, ' // to_str(difference, 3), &
         difference <= 1.0e-14_dp)
      if (allocated(error)) return
      call mech%constraints_and_jacobian(q, t, residual, Phi_q, error)
      if (.not. allocated(error)) call mech%constraints_and_jacobian_sparse(q, t, residual_s, jacobian_s, &
         error)
      if (allocated(error)) return
      deallocate (from_blocks)
      allocate (from_blocks(nc, n))
      call jacobian_s%to_dense(from_blocks)
      call check(error, what // ': block-sparse Phi_q and Phi equal the dense ones', &
         all(from_blocks == Phi_q) .and. all(residual_s == residual))
      if (allocated(error)) return
      call jacobian_s%matvec(lambda, y, transposed=.true.)
      difference = maxval(abs(y - matmul(lambda, Phi_q))) / maxval(abs(matmul(abs(lambda), &
         abs(Phi_q))))
      call check(error, what // ': block-sparse Phi_q^T lambda against matmul, ' // &
         to_str(difference, 3), difference <= 1.0e-14_dp)
      if (allocated(error)) return
      deallocate (from_blocks)
      allocate (from_blocks(n, n))
      call mech%tangents_sparse(q, v, a, t, lambda, K_s, C_s, error)
      if (.not. allocated(error)) call mech%stiffness(q, v, t, dense, error)
      if (.not. allocated(error)) call mech%mass_stiffness(q, a, work, error)
      if (allocated(error)) return
      dense = dense + work
      call mech%constraint_stiffness(q, t, lambda, work, error)
      if (allocated(error)) return
      dense = dense + work
      call K_s%to_dense(from_blocks)
      difference = maxval(abs(from_blocks - dense)) / maxval(abs(dense))
      call report(what // ': block-sparse K against the dense sum, ' // to_str(difference, 3))
      call check(error, what // ': block-sparse K within 1e-14 of the dense sum, ' // &
         to_str(difference, 3), difference <= 1.0e-14_dp)
      if (allocated(error)) return
      call mech%damping(q, v, t, dense, error)
      if (allocated(error)) return
      call C_s%to_dense(from_blocks)
      call check(error, what // ': block-sparse C_t equals the dense one', &
         all(from_blocks == dense))
   end subroutine compare_sparse

   !> Engine with a rigid crank (crank m = 2.92 kg, chi = (0, 0.0175, 0), J_c = diag(4.0, 1.5,
   !> 3.5) 1e-3 kg m^2 as test_mbs_mechanism), gravity (0, -9.81, 0) and a polynomial drive of
   !> the flywheel (module header).
   subroutine test_rigid_engine(error)
      type(error_t), allocatable, intent(out) :: error
      type(rigid_body_t) :: crank
      type(mechanism_t) :: mech
      type(polynomial_drive_t) :: drive
      real(dp) :: frames(3, 3, 3)
      frames = spread(identity3(), 3, 3)
      call crank%init(2.92_dp, [0.0_dp, 0.0175_dp, 0.0_dp], diagonal([4.0e-3_dp, 1.5e-3_dp, &
         3.5e-3_dp]), reshape([0.0_dp, 0.0_dp, -0.03_dp, 0.0_dp, crank_radius, 0.0_dp, 0.0_dp, &
         0.0_dp, 0.03_dp], [3, 3]), frames, error)
      if (allocated(error)) return
      call build_engine(mech, crank, error)
      if (allocated(error)) return
      mech%gravity = [0.0_dp, -9.81_dp, 0.0_dp]
      drive%angle = 0.3_dp
      drive%speed = 150.0_dp
      drive%acceleration = 200.0_dp
      call mech%set_drive(3, drive, error)
      if (allocated(error)) return
      call compare_tangents(mech, 'rigid engine', 11, error)
   end subroutine test_rigid_engine

   !> Engine with the synthetic flexible crank (module header), gravity off; again with the modal
   !> frequencies divided by 1000, so that the modal stiffness K_ff (exact in both paths) does not
   !> set the scale of -df/dq and the quadratic-velocity and load terms are compared.
   subroutine test_flexible_engine(error)
      type(error_t), allocatable, intent(out) :: error
      type(flexible_body_t) :: crank
      type(mechanism_t) :: mech
      real(dp), parameter :: scales(2) = [1.0_dp, 1.0e-3_dp]
      integer :: i
      do i = 1, 2
         call synthetic_crank(crank, scales(i), error)
         if (allocated(error)) return
         call build_engine(mech, crank, error)
         if (allocated(error)) return
         call compare_tangents(mech, 'flexible crank, frequencies x ' // to_str(scales(i)), &
            21, error)
         if (allocated(error)) return
      end do
   end subroutine test_flexible_engine

   !> One flexible body alone (the synthetic crank, frequencies / 1000 so that the FFRF
   !> quadratic velocity vector sets the scale): force_tangents (exact quadratic-velocity tangents
   !> plus modal stiffness and damping) against central differences of quadratic_velocity +
   !> elastic_force in each coordinate and velocity, at a random state with large modal
   !> coordinates (zeta ~ 1e-2, zeta_dot ~ 10, omega ~ 100 rad/s) so that every zeta term counts.
   !> Steps 1e-6 in q (truncation ~1e-12, round-off eps |f| / 1e-6 ~ 1e-10 relative) and 1e-3
   !> in v (f_v is quadratic in v: no truncation error). Measured 2e-11 (q) and 1e-12 (v).
   !> Also marker_hessian (exact but for the zeta-zeta block of the axes) against differences of
   !> the exact marker Jacobians at the same state (zeta ~ 1e-2): measured 2e-10 (round-off of
   !> the step 1e-6: eps |g| / 1e-6); and marker_force_tangent (exact but for the derivative of
   !> the exponential map's tangent operator, by differences) for a force of 100 N and a moment
   !> of 10 N m: measured 5e-11; and mass_stiffness for a random a ~ 1e4: measured 1e-10.
   subroutine test_flexible_body(error)
      type(error_t), allocatable, intent(out) :: error
      type(flexible_body_t) :: body
      real(dp), allocatable :: q(:), v(:), K(:, :), C(:, :), K_fd(:, :), C_fd(:, :), x(:), w(:)
      real(dp) :: delta, differences(2), w_position(3), w_axes(3, 3)
      integer :: n, j
      call synthetic_crank(body, 1.0e-3_dp, error)
      if (allocated(error)) return
      n = body%num_coordinates
      q = random_vector(n, 41)
      v = random_vector(n, 42)
      q(4:7) = euler_normalized(q(4:7))
      q(8:n) = 1.0e-2_dp * q(8:n)
      v(4:7) = 50.0_dp * v(4:7)
      v(8:n) = 10.0_dp * v(8:n)
      allocate (K(n, n), C(n, n), K_fd(n, n), C_fd(n, n))
      call body%force_tangents(q, v, K, C)
      do j = 1, n
         x = q
         delta = 1.0e-6_dp * max(abs(q(j)), 1.0_dp)
         x(j) = q(j) + delta
         K_fd(:, j) = body%quadratic_velocity(x, v) + body%elastic_force(x, v)
         x(j) = q(j) - delta
         K_fd(:, j) = -(K_fd(:, j) - body%quadratic_velocity(x, v) - body%elastic_force(x, v)) &
            / (2.0_dp * delta)
         ! f_v is quadratic in v: the central difference is exact but for round-off, so a large
         ! step keeps that small
         x = v
         delta = 1.0e-3_dp * max(abs(v(j)), 1.0_dp)
         x(j) = v(j) + delta
         C_fd(:, j) = body%quadratic_velocity(q, x) + body%elastic_force(q, x)
         x(j) = v(j) - delta
         C_fd(:, j) = -(C_fd(:, j) - body%quadratic_velocity(q, x) - body%elastic_force(q, x)) &
            / (2.0_dp * delta)
      end do
      differences(1) = maxval(abs(K - K_fd)) / maxval(abs(K_fd))
      differences(2) = maxval(abs(C - C_fd)) / maxval(abs(C_fd))
      call report('flexible body: -df/dq ' // to_str(differences(1), 3) // ' (scale ' // &
         to_str(maxval(abs(K_fd)), 3) // '), -df/dv ' // to_str(differences(2), 3) // &
         ' (scale ' // to_str(maxval(abs(C_fd)), 3) // ')')
      call check(error, 'flexible body force tangents within ' // to_str(tangent_rtol) // &
         ' of central differences: ' // to_str(differences(1), 3) // ', ' // &
         to_str(differences(2), 3), maxval(differences) <= tangent_rtol)
      if (allocated(error)) return
      ! Marker Hessian (joints' constraint stiffness) at marker B2 with random weights, against
      ! central differences (step 1e-6) of the exact marker Jacobians
      w_position = random_vector(3, 43)
      w_axes = reshape(random_vector(9, 44), [3, 3])
      call body%marker_hessian(q, 2, w_position, w_axes, K)
      do j = 1, n
         x = q
         delta = 1.0e-6_dp * max(abs(q(j)), 1.0_dp)
         x(j) = q(j) + delta
         K_fd(:, j) = weighted_gradient(x)
         x(j) = q(j) - delta
         K_fd(:, j) = (K_fd(:, j) - weighted_gradient(x)) / (2.0_dp * delta)
      end do
      differences(1) = maxval(abs(K - K_fd)) / maxval(abs(K_fd))
      call report('flexible body: marker Hessian ' // to_str(differences(1), 3) // ' (scale ' // &
         to_str(maxval(abs(K_fd)), 3) // ')')
      call check(error, 'flexible marker Hessian within ' // to_str(tangent_rtol) // &
         ' of central differences: ' // to_str(differences(1), 3), differences(1) <= tangent_rtol)
      if (allocated(error)) return
      ! Generalized force of a fixed force and moment at marker B2: its derivative against
      ! central differences (step 1e-6)
      call body%marker_force_tangent(q, 2, 100.0_dp * w_position, 10.0_dp * w_axes(:, 1), K)
      do j = 1, n
         x = q
         delta = 1.0e-6_dp * max(abs(q(j)), 1.0_dp)
         x(j) = q(j) + delta
         K_fd(:, j) = body%marker_generalized_force(x, 2, 100.0_dp * w_position, &
            10.0_dp * w_axes(:, 1))
         x(j) = q(j) - delta
         K_fd(:, j) = (K_fd(:, j) - body%marker_generalized_force(x, 2, 100.0_dp * w_position, &
            10.0_dp * w_axes(:, 1))) / (2.0_dp * delta)
      end do
      differences(1) = maxval(abs(K - K_fd)) / maxval(abs(K_fd))
      call report('flexible body: marker force tangent ' // to_str(differences(1), 3) // &
         ' (scale ' // to_str(maxval(abs(K_fd)), 3) // ')')
      call check(error, 'flexible marker force tangent within ' // to_str(tangent_rtol) // &
         ' of central differences: ' // to_str(differences(1), 3), differences(1) <= tangent_rtol)
      if (allocated(error)) return
      ! Mass stiffness d(M a)/dq for a random a ~ 1e4, against central differences of M(q) a
      x = 1.0e4_dp * random_vector(n, 45)
      call body%mass_stiffness(q, x, K)
      do j = 1, n
         w = q
         delta = 1.0e-6_dp * max(abs(q(j)), 1.0_dp)
         w(j) = q(j) + delta
         K_fd(:, j) = matmul(body%mass_matrix(w), x)
         w(j) = q(j) - delta
         K_fd(:, j) = (K_fd(:, j) - matmul(body%mass_matrix(w), x)) / (2.0_dp * delta)
      end do
      differences(1) = maxval(abs(K - K_fd)) / maxval(abs(K_fd))
      call report('flexible body: mass stiffness ' // to_str(differences(1), 3) // &
         ' (scale ' // to_str(maxval(abs(K_fd)), 3) // ')')
      call check(error, 'flexible mass stiffness within ' // to_str(tangent_rtol) // &
         ' of central differences: ' // to_str(differences(1), 3), differences(1) <= tangent_rtol)
   contains
      function weighted_gradient(y) result(g)
         real(dp), intent(in) :: y(:)
         real(dp) :: g(size(y))
         real(dp) :: unit(3)
         integer :: i
         g = matmul(w_position, body%marker_position_jacobian(y, 2))
         do i = 1, 3
            unit = 0.0_dp
            unit(i) = 1.0_dp
            g = g + matmul(w_axes(:, i), body%marker_axis_jacobian(y, 2, unit))
         end do
      end function weighted_gradient
   end subroutine test_flexible_body

   !> Two rigid bodies, the first on a spherical joint to ground, the second on a universal
   !> joint to the first (the joint kinds the engine does not have).
   subroutine test_universal(error)
      type(error_t), allocatable, intent(out) :: error
      type(ground_t) :: ground
      type(rigid_body_t) :: shaft, yoke
      type(mechanism_t) :: mech
      real(dp) :: frames(3, 3, 2)
      integer :: ig, i1, i2
      frames(:, :, 1) = identity3()
      frames(:, :, 2) = reshape([0.0_dp, 1.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         0.0_dp, 1.0_dp], [3, 3])
      call ground%init(reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), frames(:, :, [1]), error)
      if (allocated(error)) return
      call shaft%init(1.2_dp, [0.01_dp, 0.02_dp, 0.1_dp], diagonal([2.0e-3_dp, 2.5e-3_dp, &
         1.0e-3_dp]), reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.2_dp], [3, 2]), &
         frames, error)
      if (allocated(error)) return
      call yoke%init(0.7_dp, [0.0_dp, -0.01_dp, 0.05_dp], diagonal([1.0e-3_dp, 1.2e-3_dp, &
         0.6e-3_dp]), reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), frames(:, :, [2]), error)
      if (allocated(error)) return
      call mech%add_body(ground, 'ground', ig, error)
      if (.not. allocated(error)) call mech%add_body(shaft, 'shaft', i1, error)
      if (.not. allocated(error)) call mech%add_body(yoke, 'yoke', i2, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_SPHERICAL, 'ball', ig, 1, i1, 1, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_UNIVERSAL, 'cardan', i1, 2, i2, 1, &
         error)
      if (allocated(error)) return
      call compare_tangents(mech, 'universal/spherical', 31, error)
   end subroutine test_universal

   !> Geometric stiffening on (module header): the synthetic crank (frequencies / 1000) with six
   !> random symmetric K_G^(c) (entries in [-1, 1]); at a random state with zeta ~ 1e-2 and
   !> omega ~ 100 rad/s (as test_flexible_body) force_tangents against central differences of
   !> quadratic_velocity + elastic_force (steps 1e-6 in q, 1e-3 in v: f_v stays quadratic in
   !> v), then the engine with this crank by compare_tangents.
   subroutine test_geometric_stiffness(error)
      type(error_t), allocatable, intent(out) :: error
      type(flexible_body_t) :: body
      type(mechanism_t) :: mech
      real(dp), allocatable :: q(:), v(:), K(:, :), C(:, :), K_fd(:, :), C_fd(:, :), x(:)
      real(dp) :: K_G(3, 3, 6), B(3, 3), delta, differences(2)
      integer :: n, j, load_case
      call synthetic_crank(body, 1.0e-3_dp, error)
      if (allocated(error)) return
      do load_case = 1, 6
         B = reshape(random_vector(9, 60 + load_case), [3, 3])
         K_G(:, :, load_case) = 0.5_dp * (B + transpose(B))
      end do
      call body%set_geometric_stiffness(K_G, error)
      if (allocated(error)) return
      n = body%num_coordinates
      q = random_vector(n, 41)
      v = random_vector(n, 42)
      q(4:7) = euler_normalized(q(4:7))
      q(8:n) = 1.0e-2_dp * q(8:n)
      v(4:7) = 50.0_dp * v(4:7)
      v(8:n) = 10.0_dp * v(8:n)
      allocate (K(n, n), C(n, n), K_fd(n, n), C_fd(n, n))
      call body%force_tangents(q, v, K, C)
      do j = 1, n
         x = q
         delta = 1.0e-6_dp * max(abs(q(j)), 1.0_dp)
         x(j) = q(j) + delta
         K_fd(:, j) = body%quadratic_velocity(x, v) + body%elastic_force(x, v)
         x(j) = q(j) - delta
         K_fd(:, j) = -(K_fd(:, j) - body%quadratic_velocity(x, v) - body%elastic_force(x, v)) &
            / (2.0_dp * delta)
         x = v
         delta = 1.0e-3_dp * max(abs(v(j)), 1.0_dp)
         x(j) = v(j) + delta
         C_fd(:, j) = body%quadratic_velocity(q, x) + body%elastic_force(q, x)
         x(j) = v(j) - delta
         C_fd(:, j) = -(C_fd(:, j) - body%quadratic_velocity(q, x) - body%elastic_force(q, x)) &
            / (2.0_dp * delta)
      end do
      differences(1) = maxval(abs(K - K_fd)) / maxval(abs(K_fd))
      differences(2) = maxval(abs(C - C_fd)) / maxval(abs(C_fd))
      call report('geometric stiffness, flexible body: -df/dq ' // to_str(differences(1), 3) // &
         ' (scale ' // to_str(maxval(abs(K_fd)), 3) // '), -df/dv ' // &
         to_str(differences(2), 3) // ' (scale ' // to_str(maxval(abs(C_fd)), 3) // ')')
      call check(error, 'force tangents with geometric stiffness within ' // &
         to_str(tangent_rtol) // ' of central differences: ' // to_str(differences(1), 3) // &
         ', ' // to_str(differences(2), 3), maxval(differences) <= tangent_rtol)
      if (allocated(error)) return
      call build_engine(mech, body, error)
      if (allocated(error)) return
      call compare_tangents(mech, 'flexible crank with geometric stiffness', 21, error)
   end subroutine test_geometric_stiffness

   !> The rigid-crank engine started at rest at top dead centre with newton_atol = 1e-12,
   !> newton_rtol = 1e-10, h = 1e-4 s: 0.05 s (500 steps, starter run-up) with the central
   !> differences, 0.15 s (1500 steps, through the first firings) with the analytic tangents and
   !> the default Jacobian policy (factorised at each predictor, tangents kept up to
   !> tangent_reuse factorisations, no residual evaluation after a converged last increment),
   !> and 0.05 s with full Newton (fresh analytic tangents and factors at every iteration).
   !> References: (a) at t = 0.05 s the runs agree (the tangents and the policy only change the
   !> Newton path, all converge to the same tolerances): crank speeds within 1e-12 relative of the
   !> central-difference run (measured: equal to all printed digits) and of the full-Newton run
   !> (measured 1.3e-13); (b) the default run
   !> kept tangents (fewer tangent evaluations than factorisations) and skipped evaluations
   !> (fewer residual evaluations than iterations plus steps); (c) no rejected step (before the
   !> change of the Jacobian-reuse policy in ffrf_mbs_generalized_alpha, stale iteration matrices
   !> with contraction rates 0.1-0.2 ran out of iterations: 54 rejected steps in 3000 on
   !> test_mbs_flexible_engine's rigid engine).
   subroutine test_engine_run(error)
      type(error_t), allocatable, intent(out) :: error
      type(rigid_body_t) :: crank
      type(mechanism_t) :: mech
      type(galpha_settings_t) :: settings
      type(galpha_integrator_t) :: integrator
      real(dp), allocatable :: q(:), v(:)
      real(dp) :: frames(3, 3, 3), speeds(3)
      character(len=*), parameter :: names(3) = ['analytic', 'FD      ', 'full    ']
      integer :: run, i, k
      frames = spread(identity3(), 3, 3)
      call crank%init(2.92_dp, [0.0_dp, 0.0175_dp, 0.0_dp], diagonal([4.0e-3_dp, 1.5e-3_dp, &
         3.5e-3_dp]), reshape([0.0_dp, 0.0_dp, -0.03_dp, 0.0_dp, crank_radius, 0.0_dp, 0.0_dp, &
         0.0_dp, 0.03_dp], [3, 3]), frames, error)
      if (allocated(error)) return
      settings%h = 1.0e-4_dp
      settings%rho_inf = 0.8_dp
      settings%newton_atol = 1.0e-12_dp
      settings%newton_rtol = 1.0e-10_dp
      do run = 1, 3
         call build_engine(mech, crank, error)
         if (allocated(error)) return
         mech%analytic_tangents = run /= 2
         settings%t_end = merge(0.15_dp, 0.05_dp, run == 1)
         if (run == 3) then
            settings%jacobian = GALPHA_NEWTON_FULL
            settings%tangent_reuse = 0
         end if
         allocate (q(mech%num_coordinates()), v(mech%num_coordinates()))
         q = 0.0_dp
         do k = 1, 4
            q(7 * (k - 1) + 4) = 1.0_dp
         end do
         q(15:17) = [0.0_dp, crank_radius, 0.0_dp]
         q(22:24) = [0.0_dp, crank_radius + rod_length, 0.0_dp]
         call mech%assemble(q, 0.0_dp, error, rotor_angle=0.0_dp)
         if (.not. allocated(error)) call mech%initial_velocities(q, 0.0_dp, v, error, &
            rotor_speed=0.0_dp)
         if (.not. allocated(error)) call integrator%init(mech, settings, q, v, error)
         if (allocated(error)) return
         do i = 1, merge(1500, 500, run == 1)
            call integrator%step(mech, error)
            if (allocated(error)) return
            if (i == 500) speeds(run) = mech%rotor_speed(integrator%q, integrator%v)
         end do
         call report(names(run) // ' tangents: crank speed ' // &
            to_str(speeds(run), 14) // ' rad/s at 0.05 s; ' // to_str(integrator%stats%steps) // &
            ' steps, ' // to_str(integrator%stats%rejected_steps) // ' rejected, ' // &
            to_str(integrator%stats%newton_iterations) // ' iterations, ' // &
            to_str(integrator%stats%factorizations) // ' factorisations, ' // &
            to_str(integrator%stats%tangents) // ' tangents, ' // &
            to_str(integrator%stats%residual_evaluations) // ' residual evaluations, ' // &
            to_str(integrator%stats%wall_seconds, 3) // ' s')
         if (run == 1) then
            call check(error, 'default policy kept tangents: ' // &
               to_str(integrator%stats%tangents) // ' tangents < ' // &
               to_str(integrator%stats%factorizations) // ' factorisations', &
               integrator%stats%tangents < integrator%stats%factorizations)
            if (allocated(error)) return
            call check(error, 'default policy skipped evaluations: ' // &
               to_str(integrator%stats%residual_evaluations) // ' < iterations + steps = ' // &
               to_str(integrator%stats%newton_iterations + integrator%stats%steps), &
               integrator%stats%residual_evaluations < integrator%stats%newton_iterations + &
               integrator%stats%steps)
            if (allocated(error)) return
         end if
         call check(error, 'no rejected step (' // to_str(integrator%stats%rejected_steps) // &
            ')', integrator%stats%rejected_steps == 0)
         if (allocated(error)) return
         deallocate (q, v)
      end do
      call check(error, 'crank speed with analytic tangents ' // to_str(speeds(1), 14) // &
         ' vs differences ' // to_str(speeds(2), 14), abs(speeds(1) - speeds(2)) <= &
         1.0e-12_dp * abs(speeds(2)) .and. speeds(2) > 0.0_dp)
      if (allocated(error)) return
      call check(error, 'crank speed with the default policy ' // to_str(speeds(1), 14) // &
         ' vs full Newton ' // to_str(speeds(3), 14), abs(speeds(1) - speeds(3)) <= &
         1.0e-12_dp * abs(speeds(3)))
   end subroutine test_engine_run

   !> Three spring-dampers between the ground, a rigid body and the synthetic flexible crank
   !> (module header, system 4): K and C of the springs against central differences.
   subroutine test_springs(error)
      type(error_t), allocatable, intent(out) :: error
      type(mechanism_t) :: mech
      integer :: ig, ib, ic
      call three_bodies(mech, identity3(), ig, ib, ic, error)
      if (.not. allocated(error)) call mech%add_spring(spring_of('s1', ig, 1, ib, 1, 2.0e3_dp, &
         15.0_dp, 0.2_dp), error)
      if (.not. allocated(error)) call mech%add_spring(spring_of('s2', ib, 2, ic, 2, 5.0e4_dp, &
         3.0_dp, 0.05_dp), error)
      if (.not. allocated(error)) call mech%add_spring(spring_of('s3', ic, 3, ig, 2, 1.0e4_dp, &
         40.0_dp, 0.3_dp), error)
      if (allocated(error)) return
      call compare_tangents(mech, 'springs', 41, error)
   end subroutine test_springs

   !> add_spring refuses both ends on one body, an unknown marker, a negative stiffness or
   !> damping; set_spring_free_lengths refuses coinciding markers without a free length.
   subroutine test_spring_refusals(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: refused
      type(ground_t) :: ground
      type(rigid_body_t) :: block
      type(mechanism_t) :: mech
      real(dp) :: frames(3, 3, 2), q(7)
      integer :: ig, ib
      frames(:, :, 1) = identity3()
      frames(:, :, 2) = identity3()
      call ground%init(reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), frames(:, :, [1]), error)
      if (allocated(error)) return
      call block%init(1.0_dp, [0.0_dp, 0.0_dp, 0.0_dp], identity3(), &
         reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.1_dp, 0.0_dp, 0.0_dp], [3, 2]), frames, error)
      if (.not. allocated(error)) call mech%add_body(ground, 'ground', ig, error)
      if (.not. allocated(error)) call mech%add_body(block, 'block', ib, error)
      if (allocated(error)) return
      call mech%add_spring(spring_of('same', ib, 1, ib, 2, 1.0_dp, 0.0_dp, 0.1_dp), refused)
      call check(error, 'a spring with both ends on one body is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_spring(spring_of('marker', ig, 2, ib, 1, 1.0_dp, 0.0_dp, 0.1_dp), refused)
      call check(error, 'a spring at an unknown marker is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_spring(spring_of('k', ig, 1, ib, 1, -1.0_dp, 0.0_dp, 0.1_dp), refused)
      call check(error, 'a negative stiffness is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_spring(spring_of('c', ig, 1, ib, 1, 1.0_dp, -1.0_dp, 0.1_dp), refused)
      call check(error, 'a negative damping is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_spring(spring_of('zero', ig, 1, ib, 1, 1.0_dp, 0.0_dp, -1.0_dp), error)
      if (allocated(error)) return
      q = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      call mech%set_spring_free_lengths(q, refused)
      call check(error, 'a zero starting length without free_length is refused', &
         allocated(refused))
      if (allocated(error)) return
      q(1) = 0.25_dp
      call mech%set_spring_free_lengths(q, error)
      if (allocated(error)) return
      call check(error, 'the free length defaults to the starting distance 0.25 m, got ' // &
         to_str(mech%springs(1)%free_length), abs(mech%springs(1)%free_length - 0.25_dp) <= &
         1.0e-15_dp)
   end subroutine test_spring_refusals

   !> Two revolute joints with torsion spring-dampers (module header, system 5): K and C against
   !> central differences; then the refusals of add_torsion_spring.
   subroutine test_torsion_springs(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: refused
      type(mechanism_t) :: mech
      integer :: ig, ib, ic
      call three_bodies(mech, reshape([0.0_dp, 1.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, &
         0.0_dp, 0.0_dp, 1.0_dp], [3, 3]), ig, ib, ic, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_REVOLUTE, 'hinge', ig, 1, ib, 1, &
         error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_REVOLUTE, 'pin', ib, 2, ic, 2, error)
      if (.not. allocated(error)) call mech%add_joint(JOINT_PRISMATIC, 'slide', ig, 2, ic, 3, &
         error)
      if (.not. allocated(error)) call mech%add_torsion_spring(torsion_of('t1', 1, 40.0_dp, &
         0.7_dp, 0.3_dp), error)
      if (.not. allocated(error)) call mech%add_torsion_spring(torsion_of('t2', 2, 300.0_dp, &
         0.2_dp, -0.2_dp), error)
      if (allocated(error)) return
      call compare_tangents(mech, 'torsion springs', 53, error)
      if (allocated(error)) return
      call mech%add_torsion_spring(torsion_of('slide', 3, 1.0_dp, 0.0_dp, 0.0_dp), refused)
      call check(error, 'a torsion spring on a prismatic joint is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_torsion_spring(torsion_of('none', 4, 1.0_dp, 0.0_dp, 0.0_dp), refused)
      call check(error, 'a torsion spring on an unknown joint is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_torsion_spring(torsion_of('k', 1, -1.0_dp, 0.0_dp, 0.0_dp), refused)
      call check(error, 'a negative torsional stiffness is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_torsion_spring(torsion_of('c', 1, 1.0_dp, -1.0_dp, 0.0_dp), refused)
      call check(error, 'a negative torsional damping is refused', allocated(refused))
   end subroutine test_torsion_springs

   !> Three damped bushings (module header, system 6): K and C against central differences,
   !> the power of the undamped bushings against -dU/dt, and the refusals of add_bushing.
   subroutine test_bushings(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: refused
      type(mechanism_t) :: mech
      real(dp) :: power, rate, s, scale
      real(dp), allocatable :: q(:), v(:), lambda(:), a(:), f(:), stiffness(:, :)
      integer :: ig, ib, ic, k, j
      call three_bodies(mech, reshape([0.0_dp, 0.6_dp, 0.8_dp, 0.0_dp, -0.8_dp, 0.6_dp, &
         1.0_dp, 0.0_dp, 0.0_dp], [3, 3]), ig, ib, ic, error)
      if (.not. allocated(error)) call mech%add_bushing(bushing_of('b1', ig, 2, ib, 1, &
         [2.0e3_dp, 3.0e3_dp, 5.0e3_dp, 40.0_dp, 60.0_dp, 90.0_dp], [5.0_dp, 7.0_dp, 3.0_dp, &
         0.2_dp, 0.3_dp, 0.1_dp]), error)
      if (.not. allocated(error)) call mech%add_bushing(bushing_of('b2', ib, 2, ic, 2, &
         [1.0e4_dp, 2.0e4_dp, 1.5e4_dp, 300.0_dp, 200.0_dp, 100.0_dp], [2.0_dp, 1.0_dp, &
         4.0_dp, 0.5_dp, 0.4_dp, 0.3_dp]), error)
      if (.not. allocated(error)) call mech%add_bushing(bushing_of('b3', ic, 3, ig, 1, &
         [8.0e3_dp, 6.0e3_dp, 4.0e3_dp, 80.0_dp, 70.0_dp, 50.0_dp], [1.0_dp, 2.0_dp, 3.0_dp, &
         0.1_dp, 0.1_dp, 0.1_dp]), error)
      if (allocated(error)) return
      call compare_tangents(mech, 'bushings', 61, error)
      if (allocated(error)) return
      ! Conservative part: Q . v = -dU/dt with the damping off and no other applied force
      do k = 1, size(mech%bushings)
         mech%bushings(k)%damping = 0.0_dp
      end do
      call random_state(mech, 67, q, v, lambda, a)
      do k = 1, size(mech%bodies)
         associate (i => mech%bodies(k)%offset)
            if (mech%bodies(k)%body%num_coordinates == 0) cycle
            ! on the manifold of the Euler parameters: |theta| = 1, theta . theta' = 0
            q(i + 4:i + 7) = euler_normalized(q(i + 4:i + 7))
            v(i + 4:i + 7) = v(i + 4:i + 7) - dot_product(q(i + 4:i + 7), v(i + 4:i + 7)) * &
               q(i + 4:i + 7)
         end associate
      end do
      allocate (f(size(q)), stiffness(6, size(mech%bushings)))
      stiffness = reshape([(mech%bushings(k)%stiffness, k = 1, size(mech%bushings))], &
         shape(stiffness))
      do j = 1, size(mech%bushings)
         do k = 1, size(mech%bushings)
            mech%bushings(k)%stiffness = 0.0_dp
         end do
         mech%bushings(j)%stiffness = stiffness(:, j)
         call mech%applied_force(q, v, 0.0_dp, f, error)
         if (allocated(error)) return
         power = dot_product(f, v)
         s = 1.0e-7_dp
         rate = (mech%bushing_energy(q + s * v) - mech%bushing_energy(q - s * v)) / (2.0_dp * s)
         scale = max(abs(power), abs(rate))
         call report('bushing ' // to_str(j) // ': Q . v = ' // to_str(power, 12) // &
            ' W, -dU/dt = ' // to_str(-rate, 12) // ' W')
         call check(error, 'bushing ' // to_str(j) // ': Q . v equals -dU/dt to 1e-8, got ' &
            // to_str(abs(power + rate) / scale, 3), abs(power + rate) <= 1.0e-8_dp * scale)
         if (allocated(error)) return
      end do
      call mech%add_bushing(bushing_of('same', ib, 1, ib, 2, [(1.0_dp, k = 1, 6)], &
         [(0.0_dp, k = 1, 6)]), refused)
      call check(error, 'a bushing with both ends on one body is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_bushing(bushing_of('marker', ig, 3, ib, 1, [(1.0_dp, k = 1, 6)], &
         [(0.0_dp, k = 1, 6)]), refused)
      call check(error, 'a bushing at an unknown marker is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_bushing(bushing_of('k', ig, 1, ib, 1, [1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, &
         -1.0_dp, 1.0_dp], [(0.0_dp, k = 1, 6)]), refused)
      call check(error, 'a negative bushing stiffness entry is refused', allocated(refused))
      if (allocated(error)) return
      call mech%add_bushing(bushing_of('c', ig, 1, ib, 1, [(1.0_dp, k = 1, 6)], [0.0_dp, &
         0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]), refused)
      call check(error, 'a negative bushing damping entry is refused', allocated(refused))
   end subroutine test_bushings

   !> The ground (markers 1, 2), a rigid block (markers 1, 2) and the synthetic flexible crank
   !> (frequencies / 1000) of the force element tests (module header, systems 4 to 6); the
   !> second marker of the ground and of the block has the frame `frame`.
   subroutine three_bodies(mech, frame, ig, ib, ic, error)
      type(mechanism_t), intent(out) :: mech
      real(dp), intent(in) :: frame(3, 3)
      integer, intent(out) :: ig, ib, ic
      type(error_t), allocatable, intent(out) :: error
      type(ground_t) :: ground
      type(rigid_body_t) :: block
      type(flexible_body_t) :: crank
      real(dp) :: frames(3, 3, 2)
      frames(:, :, 1) = identity3()
      frames(:, :, 2) = frame
      call ground%init(reshape([0.3_dp, 0.0_dp, 0.1_dp, -0.2_dp, 0.1_dp, 0.0_dp], [3, 2]), &
         frames, error)
      if (allocated(error)) return
      call block%init(1.3_dp, [0.01_dp, 0.02_dp, 0.03_dp], diagonal([2.0e-3_dp, 2.5e-3_dp, &
         1.0e-3_dp]), reshape([0.05_dp, 0.0_dp, 0.0_dp, 0.0_dp, -0.04_dp, 0.1_dp], [3, 2]), &
         frames, error)
      if (allocated(error)) return
      call synthetic_crank(crank, 1.0e-3_dp, error)
      if (allocated(error)) return
      call mech%add_body(ground, 'ground', ig, error)
      if (.not. allocated(error)) call mech%add_body(block, 'block', ib, error)
      if (.not. allocated(error)) call mech%add_body(crank, 'crank', ic, error)
   end subroutine three_bodies

   !> A bushing record.
   pure function bushing_of(name, body_a, marker_a, body_b, marker_b, stiffness, damping) &
      result(bushing)
      character(len=*), intent(in) :: name
      integer, intent(in) :: body_a, marker_a, body_b, marker_b
      real(dp), intent(in) :: stiffness(6), damping(6)
      type(bushing_t) :: bushing
      bushing%name = name
      bushing%body_a = body_a
      bushing%marker_a = marker_a
      bushing%body_b = body_b
      bushing%marker_b = marker_b
      bushing%stiffness = stiffness
      bushing%damping = damping
   end function bushing_of

   !> A torsion spring-damper record about joint `joint` with a given free angle.
   pure function torsion_of(name, joint, stiffness, damping, free_angle) result(spring)
      character(len=*), intent(in) :: name
      integer, intent(in) :: joint
      real(dp), intent(in) :: stiffness, damping, free_angle
      type(torsion_spring_t) :: spring
      spring%name = name
      spring%joint = joint
      spring%stiffness = stiffness
      spring%damping = damping
      spring%free_angle = free_angle
      spring%free_angle_given = .true.
   end function torsion_of

   !> A spring-damper record.
   pure function spring_of(name, body_a, marker_a, body_b, marker_b, stiffness, damping, &
      free_length) result(spring)
      character(len=*), intent(in) :: name
      integer, intent(in) :: body_a, marker_a, body_b, marker_b
      real(dp), intent(in) :: stiffness, damping, free_length
      type(spring_damper_t) :: spring
      spring%name = name
      spring%body_a = body_a
      spring%marker_a = marker_a
      spring%body_b = body_b
      spring%marker_b = marker_b
      spring%stiffness = stiffness
      spring%damping = damping
      spring%free_length = free_length
   end function spring_of

   !> (7) body_t's default tangents called on a rigid body against its exact ones at a random
   !> state (theta normalised), at marker 2, off the reference point with a turned frame.
   subroutine test_body_defaults(error)
      type(error_t), allocatable, intent(out) :: error
      type(rigid_body_t) :: rigid
      real(dp) :: q(7), v(7), a(7), frames(3, 3, 2), w_axes(3, 3), differences(5)
      real(dp), dimension(7, 7) :: K, C, K_fd, C_fd, M_q, M_q_fd, H, H_fd, T, T_fd
      character(len=*), parameter :: names(5) = [character(len=20) :: '-df/dq', '-df/dv', &
         'd(M a)/dq', 'marker Hessian', 'marker force tangent']
      integer :: i
      frames(:, :, 1) = identity3()
      frames(:, :, 2) = reshape([0.0_dp, 1.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         0.0_dp, 1.0_dp], [3, 3])
      call rigid%init(1.3_dp, [0.02_dp, -0.01_dp, 0.03_dp], reshape([2.0e-3_dp, 1.0e-4_dp, &
         0.0_dp, 1.0e-4_dp, 3.0e-3_dp, 2.0e-4_dp, 0.0_dp, 2.0e-4_dp, 4.0e-3_dp], [3, 3]), &
         reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.1_dp, -0.05_dp, 0.02_dp], [3, 2]), frames, error)
      if (allocated(error)) return
      q = random_vector(7, 71)
      q(4:7) = euler_normalized(q(4:7))
      v = 5.0_dp * random_vector(7, 72)
      a = 30.0_dp * random_vector(7, 73)
      w_axes = reshape(random_vector(9, 74), [3, 3])
      call rigid%force_tangents(q, v, K, C)
      call body_force_tangents_fd(rigid, q, v, K_fd, C_fd)
      call rigid%mass_stiffness(q, a, M_q)
      call body_mass_stiffness_fd(rigid, q, a, M_q_fd)
      call rigid%marker_hessian(q, 2, random_vector(3, 75), w_axes, H)
      call body_marker_hessian_fd(rigid, q, 2, random_vector(3, 75), w_axes, H_fd)
      call rigid%marker_force_tangent(q, 2, random_vector(3, 76), random_vector(3, 77), T)
      call body_marker_force_tangent_fd(rigid, q, 2, random_vector(3, 76), &
         random_vector(3, 77), T_fd)
      differences = [maxval(abs(K_fd - K)) / maxval(abs(K)), &
         maxval(abs(C_fd - C)) / maxval(abs(C)), maxval(abs(M_q_fd - M_q)) / maxval(abs(M_q)), &
         maxval(abs(H_fd - H)) / maxval(abs(H)), maxval(abs(T_fd - T)) / maxval(abs(T))]
      do i = 1, size(differences)
         call report('body_t default ' // trim(names(i)) // ' vs rigid exact: ' // &
            to_str(differences(i), 3) // ' relative')
         call check(error, 'body_t default ' // trim(names(i)) // ' within ' // &
            to_str(tangent_rtol) // ' of the rigid body''s exact one, got ' // &
            to_str(differences(i), 3), differences(i) <= tangent_rtol)
         if (allocated(error)) return
      end do
   end subroutine test_body_defaults

end module test_mbs_tangents

program main_mbs_tangents
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_tangents, only: collect_mbs_tangents
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_tangents(tests)
   call run_suite('mbs_tangents', tests)
end program main_mbs_tangents
