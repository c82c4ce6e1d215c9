!> Energy balance (ffrf_mbs_energy_balance) and conservation laws of free bodies integrated by
!> generalized-alpha (ffrf_mbs_generalized_alpha) as a mechanism (ffrf_mbs_mechanism).
!> References: conservation of linear and angular momentum (Noether: no applied forces, the
!> Lagrangian is invariant under translation and rotation), the convergence order 2 of
!> generalized-alpha, and the amplification matrix of generalized-alpha on the linear oscillator
!> built here from the Chung-Hulbert parameters (theory.md 4.1).
!>
!> Flexible body built by hand: four lumped masses (M = diag(m_i) (x) I3, so the FFRF invariants
!> are exact and the kinetic energy is exactly sum m_i |r_i'|^2 / 2) and one or two Ritz vectors
!> M-orthogonal to the six rigid motions, mass-normalised, with a chosen modal stiffness omega_j^2.
!> Momenta are the particle sums p = sum m_i r_i', L = sum m_i r_i x r_i' with
!> r_i = R + A u_i, r_i' = R' + A (w x u_i + Psi_i zeta'), u_i = x_i + Psi_i zeta, w = G_bar theta':
!> this includes the modal contribution (A Psi_i zeta' terms and the deformed arm u_i) and does
!> not use the FFRF mass matrix at all (an independent reference).
module test_mbs_energy
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: csr_t, csr_from_coo
   use ffrf_mbs_rotation, only: euler_rotation, euler_g_bar, euler_from_axis_angle, identity3, &
      skew3
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_mbs_rigid_body, only: rigid_body_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_energy_balance, only: energy_balance_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t, chung_hulbert
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_mbs_energy

   interface
      !> LAPACK: eigenvalues of a general matrix.
      subroutine dgeev(jobvl, jobvr, n, a, lda, wr, wi, vl, ldvl, vr, ldvr, work, lwork, info)
         import :: dp, ip
         implicit none
         character, intent(in) :: jobvl, jobvr
         integer(ip), intent(in) :: n, lda, ldvl, ldvr, lwork
         real(dp), intent(inout) :: a(lda, n)
         real(dp), intent(out) :: wr(n), wi(n), vl(ldvl, n), vr(ldvr, n), work(lwork)
         integer(ip), intent(out) :: info
      end subroutine dgeev
   end interface

   !> Lumped masses (kg) and their positions in the body frame (m) of the hand-made flexible body
   real(dp), parameter :: node_mass(4) = [1.0_dp, 1.5_dp, 0.8_dp, 1.2_dp]
   real(dp), parameter :: node_xyz(3, 4) = reshape([0.30_dp, 0.0_dp, 0.0_dp, &
      -0.10_dp, 0.25_dp, 0.0_dp, -0.10_dp, -0.15_dp, 0.20_dp, 0.05_dp, 0.05_dp, -0.30_dp], [3, 4])
   !> Rigid body: mass (kg) and inertia about the centre of mass, not diagonal (kg m^2)
   real(dp), parameter :: rigid_mass = 2.5_dp
   real(dp), parameter :: rigid_inertia(3, 3) = reshape([0.30_dp, 0.02_dp, -0.01_dp, 0.02_dp, &
      0.50_dp, 0.03_dp, -0.01_dp, 0.03_dp, 0.60_dp], [3, 3])

contains

   !> Node positions from the centre of mass: the body frame origin is the centre of mass, so the
   !> R block of the FFRF mass matrix decouples (m chi = 0, and M_PhitPsi = 0 for Ritz vectors
   !> M-orthogonal to the translations) and R'' = 0 exactly.
   pure function body_xyz() result(xyz)
      real(dp) :: xyz(3, 4)
      real(dp) :: com(3)
      integer :: i
      com = matmul(node_xyz, node_mass) / sum(node_mass)
      do i = 1, 4
         xyz(:, i) = node_xyz(:, i) - com
      end do
   end function body_xyz

   !> The suite.
   subroutine collect_mbs_energy(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('amplification_matrix_limits', test_amplification_limits), &
         new_unittest('rigid_body_momentum_and_energy', test_rigid_momentum), &
         new_unittest('flexible_body_momentum_and_energy', test_flexible_momentum), &
         new_unittest('modal_energy_decay_vs_amplification', test_modal_decay), &
         new_unittest('modal_damping_dissipation', test_modal_damping), &
         new_unittest('scheme_dissipation_identity', test_scheme_identity)]
   end subroutine collect_mbs_energy

   ! ----------------------------------------------------------------------------------------------
   ! Generalized-alpha on the linear oscillator (theory.md 4.1)

   !> Amplification matrix of the scheme of ffrf_mbs_generalized_alpha (Arnold-Bruls form with
   !> true and algorithmic accelerations) on x'' + omega^2 x = 0, Omega = omega h, state
   !> y = (x, h v, h^2 a):  L y_{n+1} = R y_n with
   !>     x1 - beta a1         = x0 + v0 + (1/2 - beta) a0
   !>     v1 - gamma a1        = v0 + (1 - gamma) a0
   !>     (1 - af) Omega^2 x1 + (1 - am) a1 = -af Omega^2 x0 - am a0
   !> (the third row is (1 - am) a1 + am a0 = (1 - af) x''_1 + af x''_0 with x'' = -omega^2 x).
   function amplification(rho_inf, omega_h) result(amp)
      real(dp), intent(in) :: rho_inf, omega_h
      real(dp) :: amp(3, 3)
      real(dp) :: am, af, gamma, beta, L(3, 3), R(3, 3), o2
      call chung_hulbert(rho_inf, am, af, gamma, beta)
      o2 = omega_h**2
      L = reshape([1.0_dp, 0.0_dp, (1.0_dp - af) * o2, 0.0_dp, 1.0_dp, 0.0_dp, -beta, -gamma, &
         1.0_dp - am], [3, 3])
      R = reshape([1.0_dp, 0.0_dp, -af * o2, 1.0_dp, 1.0_dp, 0.0_dp, 0.5_dp - beta, &
         1.0_dp - gamma, -am], [3, 3])
      amp = matmul(inverse3(L), R)
   end function amplification

   !> Inverse of a 3 x 3 matrix by cofactors.
   function inverse3(a) result(b)
      real(dp), intent(in) :: a(3, 3)
      real(dp) :: b(3, 3)
      integer :: i, j
      do i = 1, 3
         do j = 1, 3
            b(j, i) = a(mod(i, 3) + 1, mod(j, 3) + 1) * a(mod(i + 1, 3) + 1, mod(j + 1, 3) + 1) &
               - a(mod(i, 3) + 1, mod(j + 1, 3) + 1) * a(mod(i + 1, 3) + 1, mod(j, 3) + 1)
         end do
      end do
      b = b / dot_product(a(1, :), b(:, 1))
   end function inverse3

   !> Principal eigenvalue (the complex one with positive imaginary part; else the largest
   !> modulus) and spurious eigenvalue (the remaining largest modulus) of the amplification matrix.
   subroutine eigen_roots(amp, principal, spurious)
      real(dp), intent(in) :: amp(3, 3)
      complex(dp), intent(out) :: principal
      real(dp), intent(out) :: spurious
      real(dp) :: a(3, 3), wr(3), wi(3), vl(1, 3), vr(1, 3), work(64)
      integer(ip) :: info
      integer :: k, kp
      a = amp
      call dgeev('N', 'N', 3_ip, a, 3_ip, wr, wi, vl, 1_ip, vr, 1_ip, work, 64_ip, info)
      if (info /= 0) wr = huge(1.0_dp)
      kp = maxloc(wi, 1)
      if (wi(kp) <= 0.0_dp) kp = maxloc(hypot(wr, wi), 1)
      principal = cmplx(wr(kp), wi(kp), dp)
      spurious = 0.0_dp
      do k = 1, 3
         if (k == kp .or. (wi(kp) > 0.0_dp .and. abs(wi(k) + wi(kp)) <= 1.0e-14_dp .and. &
            abs(wr(k) - wr(kp)) <= 1.0e-14_dp)) cycle
         spurious = max(spurious, hypot(wr(k), wi(k)))
      end do
   end subroutine eigen_roots

   !> Principal part y_p = y - c_3 u_3 of a state: u_3 the right eigenvector of the real spurious
   !> root, c_3 = w_3 . y / (w_3 . u_3) with w_3 its left eigenvector (w_3 is orthogonal to the
   !> principal eigenvectors), so A^n y = A^n y_p + c_3 lambda_3^n u_3. ok = .false. if the
   !> spurious root is not real.
   subroutine principal_part(amp, y, y_p, ok)
      real(dp), intent(in) :: amp(3, 3), y(3)
      real(dp), intent(out) :: y_p(3)
      logical, intent(out) :: ok
      real(dp) :: a(3, 3), wr(3), wi(3), vl(3, 3), vr(3, 3), work(64)
      integer(ip) :: info
      integer :: k, k3
      a = amp
      y_p = y
      call dgeev('V', 'V', 3_ip, a, 3_ip, wr, wi, vl, 3_ip, vr, 3_ip, work, 64_ip, info)
      ok = info == 0 .and. count(wi == 0.0_dp) == 1
      if (.not. ok) return
      k3 = 0
      do k = 1, 3
         if (wi(k) == 0.0_dp) k3 = k
      end do
      y_p = y - dot_product(vl(:, k3), y) / dot_product(vl(:, k3), vr(:, k3)) * vr(:, k3)
   end subroutine principal_part

   !> Omega with arg lambda_1(Omega) = 2 pi / N (an exact discrete period of N steps), bisection.
   function period_omega_h(rho_inf, n) result(omega_h)
      real(dp), intent(in) :: rho_inf
      integer, intent(in) :: n
      real(dp) :: omega_h, lo, hi
      complex(dp) :: lambda
      real(dp) :: spurious
      integer :: it
      lo = 1.0e-3_dp
      hi = 2.0_dp * 2.0_dp * pi / n
      do it = 1, 200
         omega_h = 0.5_dp * (lo + hi)
         call eigen_roots(amplification(rho_inf, omega_h), lambda, spurious)
         if (atan2(aimag(lambda), real(lambda)) < 2.0_dp * pi / n) then
            lo = omega_h
         else
            hi = omega_h
         end if
      end do
   end function period_omega_h

   !> Sanity of the independent amplification matrix (references: Chung & Hulbert 1993):
   !> rho_inf = 1 is the trapezoidal rule, |lambda_1| = 1 at every Omega (checked at 0.3 and 3,
   !> to 1e-13); rho_inf < 1: spectral radius -> rho_inf as Omega -> inf. The optimal parameters
   !> make all three roots meet at -rho_inf there (a triple root), so the O(1/Omega^2) perturbation
   !> splits them by O(Omega^(-2/3)) and dgeev's round-off by O(eps^(1/3)) = 6e-6: at Omega = 1e8
   !> the radius is asserted to 1e-4 (measured 3.3e-6 and 3.6e-6 off; 3.6e-4 at Omega = 1e5),
   !> and 1 - |lambda_1| = O(Omega^4) for Omega -> 0 (second-order
   !> accuracy leaves the low modes undamped to third order): the ratio of 1 - |lambda_1| at
   !> Omega = 0.1 and 0.05 is 2^4 within 2 % (measured 15.97 and 15.92 for rho_inf = 0.8, 0.5).
   subroutine test_amplification_limits(error)
      type(error_t), allocatable, intent(out) :: error
      complex(dp) :: lambda
      real(dp) :: spurious, d1, d2, rho
      integer :: i
      real(dp), parameter :: rhos(2) = [0.8_dp, 0.5_dp]
      call eigen_roots(amplification(1.0_dp, 0.3_dp), lambda, spurious)
      call check_close(error, 'rho_inf = 1, Omega = 0.3: |lambda_1|', abs(lambda), 1.0_dp, &
         atol=1.0e-13_dp)
      if (allocated(error)) return
      call eigen_roots(amplification(1.0_dp, 3.0_dp), lambda, spurious)
      call check_close(error, 'rho_inf = 1, Omega = 3: |lambda_1|', abs(lambda), 1.0_dp, &
         atol=1.0e-13_dp)
      if (allocated(error)) return
      do i = 1, 2
         call eigen_roots(amplification(rhos(i), 1.0e8_dp), lambda, spurious)
         rho = max(abs(lambda), spurious)
         call eigen_roots(amplification(rhos(i), 0.1_dp), lambda, spurious)
         d1 = 1.0_dp - abs(lambda)
         call eigen_roots(amplification(rhos(i), 0.05_dp), lambda, spurious)
         d2 = 1.0_dp - abs(lambda)
         call report('rho_inf = ' // to_str(rhos(i)) // ': spectral radius at Omega = 1e8 ' // &
            to_str(rho, 8) // ', 1 - |lambda_1| at Omega = 0.1, 0.05: ' // to_str(d1, 4) // &
            ', ' // to_str(d2, 4) // ' (ratio ' // to_str(d1 / d2, 5) // ')')
         call check_close(error, 'spectral radius at infinity', rho, rhos(i), atol=1.0e-4_dp)
         if (allocated(error)) return
         call check_close(error, 'low-frequency damping ratio for Omega halved', d1 / d2, &
            16.0_dp, rtol=0.02_dp)
         if (allocated(error)) return
      end do
   end subroutine test_amplification_limits

   ! ----------------------------------------------------------------------------------------------
   ! Bodies

   !> Tight Newton tolerances: momentum and energy errors then come from the scheme, not from
   !> the iteration.
   function tight_settings(h, t_end, rho_inf) result(settings)
      real(dp), intent(in) :: h, t_end, rho_inf
      type(galpha_settings_t) :: settings
      settings%h = h
      settings%t_end = t_end
      settings%rho_inf = rho_inf
      settings%newton_atol = 1.0e-13_dp
      settings%newton_rtol = 1.0e-13_dp
      settings%lambda_atol = 1.0e-12_dp
      settings%force_atol = 1.0e-13_dp
   end function tight_settings

   !> Free rigid body (reference point at the centre of mass) tumbling about a non-principal
   !> axis, run to t_end with step h: largest relative change of |p| and |L| (L about the global
   !> origin, L = R x m R' + A J_c w) and the numerical dissipation D / T_0 at the end.
   subroutine rigid_run(h, t_end, rho_inf, drift_p, drift_l, dissipation, error, scheme_parts)
      real(dp), intent(in) :: h, t_end, rho_inf
      real(dp), intent(out) :: drift_p, drift_l, dissipation
      type(error_t), allocatable, intent(out) :: error
      !> D_s / T_0, D_k / T_0 and the constraint work C_m / T_0 at the end (energy_balance_t)
      real(dp), intent(out), optional :: scheme_parts(3)
      type(mechanism_t) :: mech
      type(rigid_body_t) :: body
      type(galpha_integrator_t) :: integrator
      type(energy_balance_t) :: balance
      real(dp) :: q(7), v(7), frames(3, 3, 1), p0(3), L0(3), p(3), L(3)
      integer :: index
      drift_p = huge(1.0_dp)
      drift_l = huge(1.0_dp)
      dissipation = huge(1.0_dp)
      frames(:, :, 1) = identity3()
      call body%init(rigid_mass, [0.0_dp, 0.0_dp, 0.0_dp], rigid_inertia, &
         reshape([0.0_dp, 0.0_dp, 0.0_dp], [3, 1]), frames, error)
      if (allocated(error)) return
      call mech%add_body(body, 'free rigid body', index, error)
      if (allocated(error)) return
      q(1:3) = [0.1_dp, 0.2_dp, -0.1_dp]
      q(4:7) = euler_from_axis_angle([1.0_dp, 2.0_dp, 3.0_dp], 0.4_dp)
      v(1:3) = [0.3_dp, -0.2_dp, 0.1_dp]
      v(4:7) = 0.25_dp * matmul(transpose(euler_g_bar(q(4:7))), [1.0_dp, -0.6_dp, 0.8_dp])
      call integrator%init(mech, tight_settings(h, t_end, rho_inf), q, v, error)
      if (allocated(error)) return
      call balance%init(mech, integrator%t, integrator%q, integrator%v, error, &
         scheme=integrator)
      if (allocated(error)) return
      call momenta(integrator%q, integrator%v, p0, L0)
      drift_p = 0.0_dp
      drift_l = 0.0_dp
      do while (integrator%t < t_end)
         call integrator%step(mech, error)
         if (allocated(error)) return
         call balance%update(mech, integrator%t, integrator%q, integrator%v, error, &
            scheme=integrator)
         if (allocated(error)) return
         call momenta(integrator%q, integrator%v, p, L)
         drift_p = max(drift_p, norm2(p - p0) / norm2(p0))
         drift_l = max(drift_l, norm2(L - L0) / norm2(L0))
      end do
      dissipation = balance%numerical_dissipation / balance%kinetic_start
      if (present(scheme_parts)) scheme_parts = [balance%scheme_dissipation, &
         balance%kinematic_dissipation, balance%constraint_work] / balance%kinetic_start
   contains
      subroutine momenta(qs, vs, p, L)
         real(dp), intent(in) :: qs(7), vs(7)
         real(dp), intent(out) :: p(3), L(3)
         real(dp) :: w(3), G_bar(3, 4)
         G_bar = euler_g_bar(qs(4:7))
         w = matmul(G_bar, vs(4:7))
         p = rigid_mass * vs(1:3)
         L = matmul(skew3(qs(1:3)), p) + matmul(euler_rotation(qs(4:7)), &
            matmul(rigid_inertia, w))
      end subroutine momenta
   end subroutine rigid_run

   !> (a) Free rigid body, no forces, reference point at the centre of mass, w = (1, -0.6, 0.8)
   !> rad/s about a non-principal axis of the non-diagonal J_c, for 2 s (0.45 revolution).
   !> - Linear momentum: the R block of M is m I and decoupled, R'' = 0 exactly: asserted 1e-14
   !>   relative (round-off; measured 0).
   !> - Angular momentum: generalized-alpha with Euler parameters is not momentum-conserving; the
   !>   drift is O(h^2): max relative change of |L - L_0| / |L_0| measured 1.08e-8, 2.70e-9,
   !>   6.76e-10 at h = 8e-4, 4e-4, 2e-4 s, rho_inf = 0.8 (observed order 2.00). Asserted: order
   !>   2 +- 0.05 between 4e-4 and 2e-4 s, and the issue's 1e-9 reached at h = 2e-4 s (10^4
   !>   steps; the 8e-4 run is left out of the suite for time).
   !> - Energy (W = 0, so D = T_0 - T): D / T_0 measured 7.46e-9, 1.87e-9, 4.66e-10 (order 2.00):
   !>   asserted order 2 +- 0.1 and D / T_0 < 1e-9 at h = 2e-4 s. With rho_inf = 1 - 1e-12
   !>   (trapezoidal rule; exactly 1 is refused because of the Euler row) the rotation still
   !>   loses O(h^2) energy, more than with 0.8 (nonlinear: the trapezoidal rule conserves only
   !>   quadratic invariants of linear systems) and D does not converge cleanly: D / T_0 = 9.2e-9,
   !>   3.0e-9, 1.65e-9 at h = 8e-4, 4e-4, 2e-4 s (ratios 3.1, 1.8), because with rho_inf = 1 the
   !>   spurious root is -1 (undamped): the start transient and the Euler-row multiplier keep
   !>   oscillating. Reported (the 4e-4 s run), not asserted (no clean reference).
   subroutine test_rigid_momentum(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: steps(2) = [4.0e-4_dp, 2.0e-4_dp], t_end = 2.0_dp
      real(dp) :: drift_p(2), drift_l(2), dissipation(2), order_l, order_d
      integer :: i
      do i = 1, 2
         call rigid_run(steps(i), t_end, 0.8_dp, drift_p(i), drift_l(i), dissipation(i), error)
         if (allocated(error)) return
         call report('rigid, rho_inf = 0.8, h = ' // to_str(steps(i)) // ' s: max relative ' // &
            'change of p ' // to_str(drift_p(i), 3) // ', of L ' // to_str(drift_l(i), 3) // &
            ', D / T_0 ' // to_str(dissipation(i), 4))
      end do
      order_l = log(drift_l(1) / drift_l(2)) / log(2.0_dp)
      order_d = log(dissipation(1) / dissipation(2)) / log(2.0_dp)
      call report('rigid: order of the L drift ' // to_str(order_l, 4) // ', of D ' // &
         to_str(order_d, 4))
      call check_close(error, 'rigid: linear momentum, max relative change', maxval(drift_p), &
         0.0_dp, atol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'rigid: order of the angular momentum drift', order_l, 2.0_dp, &
         atol=0.05_dp)
      if (allocated(error)) return
      call check_close(error, 'rigid: angular momentum drift at h = 2e-4 s', drift_l(2), &
         0.0_dp, atol=1.0e-9_dp)
      if (allocated(error)) return
      call check_close(error, 'rigid: order of the numerical dissipation', order_d, 2.0_dp, &
         atol=0.1_dp)
      if (allocated(error)) return
      call check_close(error, 'rigid: D / T_0 at h = 2e-4 s', dissipation(2), 0.0_dp, &
         atol=1.0e-9_dp)
      if (allocated(error)) return
      call rigid_run(steps(1), t_end, 1.0_dp - 1.0e-12_dp, drift_p(1), drift_l(1), &
         dissipation(1), error)
      if (allocated(error)) return
      call report('rigid, rho_inf = 1 - 1e-12, h = ' // to_str(steps(1)) // ' s: max ' // &
         'relative change of L ' // to_str(drift_l(1), 3) // ', D / T_0 ' // &
         to_str(dissipation(1), 4) // ' (not asserted)')
   end subroutine test_rigid_momentum

   !> The hand-made flexible body (module header) with the first num_modes of two Ritz vectors,
   !> modal stiffness omegas**2; one interface at node 1. Also returns the shapes (12, num_modes).
   subroutine make_flexible(omegas, flexible, shapes, error)
      real(dp), intent(in) :: omegas(:)
      type(flexible_body_t), intent(out) :: flexible
      real(dp), allocatable, intent(out) :: shapes(:, :)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: M
      real(dp) :: basis(12, 6 + 2), mdiag(12), start(12, 2), virtual_shapes(6, size(omegas))
      integer(ip) :: rows(12)
      real(dp) :: xyz(3, 4)
      integer :: i, j, k, c, nm, pass
      nm = size(omegas)
      xyz = body_xyz()
      do i = 1, 4
         mdiag(3 * i - 2:3 * i) = node_mass(i)
      end do
      rows = [(int(i, ip), i=1, 12)]
      call csr_from_coo(12_ip, 12_ip, rows, rows, mdiag, M, error)
      if (allocated(error)) return
      ! Rigid motions: translations and small rotations about the origin.
      basis = 0.0_dp
      do i = 1, 4
         do c = 1, 3
            basis(3 * i - 3 + c, c) = 1.0_dp
         end do
         basis(3 * i - 2:3 * i, 4:6) = -skew3(xyz(:, i))
      end do
      start(:, 1) = [0.3_dp, 0.1_dp, -0.2_dp, -0.4_dp, 0.5_dp, 0.1_dp, 0.2_dp, -0.3_dp, 0.6_dp, &
         -0.1_dp, 0.2_dp, -0.5_dp]
      start(:, 2) = [-0.2_dp, 0.4_dp, 0.3_dp, 0.1_dp, -0.2_dp, 0.5_dp, -0.6_dp, 0.1_dp, &
         -0.1_dp, 0.3_dp, 0.4_dp, 0.2_dp]
      basis(:, 7:8) = start
      ! M-orthonormalise (Gram-Schmidt twice): columns 7, 8 become mass-normalised Ritz vectors
      ! M-orthogonal to the rigid motions and to each other.
      do k = 1, 8
         do pass = 1, 2
            do j = 1, k - 1
               basis(:, k) = basis(:, k) - dot_product(basis(:, j), mdiag * basis(:, k)) * &
                  basis(:, j)
            end do
         end do
         basis(:, k) = basis(:, k) / sqrt(dot_product(basis(:, k), mdiag * basis(:, k)))
      end do
      shapes = basis(:, 7:6 + nm)
      virtual_shapes = 0.0_dp
      virtual_shapes(1:3, :) = shapes(1:3, :)
      call flexible%init(M, xyz, shapes, omegas**2, virtual_shapes, xyz(:, 1:1), error)
   end subroutine make_flexible

   !> Particle-sum momenta of the hand-made flexible body (module header).
   subroutine flexible_momenta(shapes, qs, vs, p, L)
      real(dp), intent(in) :: shapes(:, :), qs(:), vs(:)
      real(dp), intent(out) :: p(3), L(3)
      real(dp) :: A(3, 3), w(3), u(3), r(3), rdot(3), xyz(3, 4)
      integer :: i, nc
      nc = size(qs)
      xyz = body_xyz()
      A = euler_rotation(qs(4:7))
      w = matmul(euler_g_bar(qs(4:7)), vs(4:7))
      p = 0.0_dp
      L = 0.0_dp
      do i = 1, 4
         u = xyz(:, i) + matmul(shapes(3 * i - 2:3 * i, :), qs(8:nc))
         r = qs(1:3) + matmul(A, u)
         rdot = vs(1:3) + matmul(A, matmul(skew3(w), u) + &
            matmul(shapes(3 * i - 2:3 * i, :), vs(8:nc)))
         p = p + node_mass(i) * rdot
         L = L + node_mass(i) * matmul(skew3(r), rdot)
      end do
   end subroutine flexible_momenta

   !> Free flexible body (two modes, 3 and 5 Hz), spinning with w = (1, -0.6, 0.8) rad/s and
   !> vibrating (zeta' = (0.05, -0.03) m kg^1/2 /s), 2 s: largest relative change of |p|, |L|;
   !> D / (T_0 + U_0) at the end.
   subroutine flexible_run(h, t_end, rho_inf, drift_p, drift_l, dissipation, error)
      real(dp), intent(in) :: h, t_end, rho_inf
      real(dp), intent(out) :: drift_p, drift_l, dissipation
      type(error_t), allocatable, intent(out) :: error
      type(mechanism_t) :: mech
      type(flexible_body_t) :: body
      type(galpha_integrator_t) :: integrator
      type(energy_balance_t) :: balance
      real(dp), allocatable :: shapes(:, :)
      real(dp) :: q(9), v(9), p0(3), L0(3), p(3), L(3)
      integer :: index
      drift_p = huge(1.0_dp)
      drift_l = huge(1.0_dp)
      dissipation = huge(1.0_dp)
      call make_flexible(2.0_dp * pi * [3.0_dp, 5.0_dp], body, shapes, error)
      if (allocated(error)) return
      call mech%add_body(body, 'free flexible body', index, error)
      if (allocated(error)) return
      q(1:3) = [0.1_dp, 0.2_dp, -0.1_dp]
      q(4:7) = euler_from_axis_angle([1.0_dp, 2.0_dp, 3.0_dp], 0.4_dp)
      q(8:9) = 0.0_dp
      v(1:3) = [0.3_dp, -0.2_dp, 0.1_dp]
      v(4:7) = 0.25_dp * matmul(transpose(euler_g_bar(q(4:7))), [1.0_dp, -0.6_dp, 0.8_dp])
      v(8:9) = [0.05_dp, -0.03_dp]
      call integrator%init(mech, tight_settings(h, t_end, rho_inf), q, v, error)
      if (allocated(error)) return
      call balance%init(mech, integrator%t, integrator%q, integrator%v, error)
      if (allocated(error)) return
      call flexible_momenta(shapes, integrator%q, integrator%v, p0, L0)
      drift_p = 0.0_dp
      drift_l = 0.0_dp
      do while (integrator%t < t_end)
         call integrator%step(mech, error)
         if (allocated(error)) return
         call balance%update(mech, integrator%t, integrator%q, integrator%v, error)
         if (allocated(error)) return
         call flexible_momenta(shapes, integrator%q, integrator%v, p, L)
         drift_p = max(drift_p, norm2(p - p0) / norm2(p0))
         drift_l = max(drift_l, norm2(L - L0) / norm2(L0))
      end do
      dissipation = balance%numerical_dissipation / (balance%kinetic_start + &
         balance%strain_start)
   end subroutine flexible_run

   !> (b) Free flexible body (flexible_run: body frame at the centre of mass, modes at 3 and 5 Hz,
   !> w = (1, -0.6, 0.8) rad/s, zeta' = (0.05, -0.03), rho_inf = 0.8, 1 s); momenta by the
   !> particle sums of the module header (the modal part enters through A Psi_i zeta' and the
   !> deformed arms u_i).
   !> - Linear momentum: with the frame at the centre of mass and modes M-orthogonal to the
   !>   translations the R rows decouple (m_Rtheta = m_Rf = 0, f_vR = 0): asserted 1e-14
   !>   relative (measured 3.4e-16).
   !> - Angular momentum, max relative change over 1 s: 4.31e-9, 1.08e-9, 2.70e-10 at
   !>   h = 4e-4, 2e-4, 1e-4 s (order 2.00; over 2 s nearly the same, 4.48e-9, 1.12e-9, 2.80e-10:
   !>   a bounded O(h^2) oscillation more than a secular drift). Asserted: order 2 +- 0.05 between
   !>   2e-4 and 1e-4 s and below the issue's 1e-9 at h = 1e-4 s (10^4 steps). The spinning,
   !>   vibrating body needs half the step of the rigid one for 1e-9.
   !> - Energy: D / E_0 measured 6.86e-9, 1.70e-9, 4.23e-10 (order 2.01): asserted order
   !>   2 +- 0.1 and D / E_0 < 1e-9 at h = 1e-4 s.
   subroutine test_flexible_momentum(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: steps(2) = [2.0e-4_dp, 1.0e-4_dp], t_end = 1.0_dp
      real(dp) :: drift_p(2), drift_l(2), dissipation(2), order_l, order_d
      integer :: i
      do i = 1, 2
         call flexible_run(steps(i), t_end, 0.8_dp, drift_p(i), drift_l(i), dissipation(i), &
            error)
         if (allocated(error)) return
         call report('flexible, h = ' // to_str(steps(i)) // ' s: max relative change of p ' &
            // to_str(drift_p(i), 3) // ', of L ' // to_str(drift_l(i), 3) // &
            ', D / E_0 ' // to_str(dissipation(i), 4))
      end do
      order_l = log(drift_l(1) / drift_l(2)) / log(2.0_dp)
      order_d = log(dissipation(1) / dissipation(2)) / log(2.0_dp)
      call report('flexible: order of the L drift ' // to_str(order_l, 4) // ', of D ' // &
         to_str(order_d, 4))
      call check_close(error, 'flexible: linear momentum, max relative change', &
         maxval(drift_p), 0.0_dp, atol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'flexible: order of the angular momentum drift', order_l, &
         2.0_dp, atol=0.05_dp)
      if (allocated(error)) return
      call check_close(error, 'flexible: angular momentum drift at h = 1e-4 s', drift_l(2), &
         0.0_dp, atol=1.0e-9_dp)
      if (allocated(error)) return
      call check_close(error, 'flexible: order of the numerical dissipation', order_d, 2.0_dp, &
         atol=0.1_dp)
      if (allocated(error)) return
      call check_close(error, 'flexible: D / E_0 at h = 1e-4 s', dissipation(2), 0.0_dp, &
         atol=1.0e-9_dp)
   end subroutine test_flexible_momentum

   !> (c) Energy of a free flexible body that does not rotate and vibrates in its one mode
   !> (omega = 2 pi 10 rad/s, initial modal velocity only): the Euler rows and the rigid motion
   !> stay at rest exactly (M_PhitPsi = M_xPsi = 0, psi~^T M psi = 0, f_v = 0 at w = 0), so the
   !> mode is integrated exactly as the linear oscillator and its energy follows the amplification
   !> matrix A(Omega) built here (amplification). h is chosen so that the discrete period is a
   !> whole number N of steps (arg lambda_1 = 2 pi / N): after whole periods the principal
   !> component is back at its phase and scaled by |lambda_1|^n. References and tolerances:
   !> (1) E_n of the run = E of the recurrence y_n = A^n y_0 at every step, to 1e-10 E_0 (the
   !>     Newton tolerance 1e-13 per step over <= 1e4 steps; measured 3.0e-13, 5.2e-16, 9.0e-14).
   !> (2) E_n2 / E_n1 = |lambda_1|^(2 (n2 - n1)) for n1, n2 whole periods after the spurious root
   !>     has decayed below 1e-13 (|lambda_3|^n1 <= 1e-13), n2 where about 5 % is lost: rtol 1e-9
   !>     (measured 3.9e-12 with rho_inf = 0.8, Omega = 0.3169, 3880 steps; 0 with 0.5, 0.8500).
   !> (3) E_n / E_0 = kappa |lambda_1|^(2n) for such n: the asymptotic law, with the start factor
   !>     kappa = E(y_p) / E(y_0) of the principal part y_p of the start (principal_part; kappa = 1
   !>     + O(Omega^2): 0.99877 at Omega = 0.317, rho_inf = 0.8; 0.94710 at Omega = 0.850,
   !>     rho_inf = 0.5): rtol 1e-9 (measured 4.0e-12 and 3.6e-15).
   !> (4) energy_balance_t: W = 0 and D = E_0 - E_n (E from zeta, zeta' alone), rtol 1e-9
   !>     (measured equal to 14 digits; D / E_0 = 0.0520 and 0.228).
   !> (5) rho_inf = 1 (no numerical damping) is refused by the integrator for any mechanism with a
   !>     free body (its Euler row is a constraint); rho_inf = 1 - 1e-12 is the trapezoidal rule to
   !>     1e-12 and keeps the quadratic energy of the linear mode: |D| <= 1e-10 E_0 over 50 periods
   !>     (measured -7e-16 to -2e-14 between builds).
   subroutine test_modal_decay(error)
      type(error_t), allocatable, intent(out) :: error
      call modal_case(0.8_dp, 20, error)
      if (allocated(error)) return
      call modal_case(0.5_dp, 8, error)
      if (allocated(error)) return
      call modal_case(1.0_dp - 1.0e-12_dp, 20, error)
   end subroutine test_modal_decay

   !> One case of test_modal_decay: rho_inf and the discrete period N (steps).
   subroutine modal_case(rho_inf, period, error)
      real(dp), intent(in) :: rho_inf
      integer, intent(in) :: period
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: omega = 2.0_dp * pi * 10.0_dp, zeta_dot0 = 0.1_dp
      type(mechanism_t) :: mech
      type(flexible_body_t) :: body
      type(galpha_integrator_t) :: integrator
      type(energy_balance_t) :: balance
      real(dp), allocatable :: shapes(:, :)
      real(dp) :: q(8), v(8), omega_h, h, spurious, amp(3, 3), y(3), y_p(3), e0, e1, e2, en
      real(dp) :: worst_ref, kappa, decay
      complex(dp) :: lambda
      integer :: index, n, n1, n2
      logical :: ok, undamped
      undamped = rho_inf > 0.999_dp
      omega_h = period_omega_h(rho_inf, period)
      h = omega_h / omega
      amp = amplification(rho_inf, omega_h)
      call eigen_roots(amp, lambda, spurious)
      call make_flexible([omega], body, shapes, error)
      if (allocated(error)) return
      call mech%add_body(body, 'vibrating body', index, error)
      if (allocated(error)) return
      q = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      v = 0.0_dp
      v(8) = zeta_dot0
      ! n1: whole periods after which |lambda_3|^n1 <= 1e-13.
      if (undamped) then
         n1 = period
      else
         n1 = period * max(1, ceiling(log(1.0e-13_dp) / log(max(spurious, 1.0e-3_dp)) / period))
      end if
      ! n2 - n1: whole periods until the energy has lost about 5 % (50 periods if undamped).
      if (undamped) then
         n2 = n1 + 50 * period
      else
         n2 = n1 + period * max(1, nint(log(0.95_dp) / (2.0_dp * log(abs(lambda))) / period))
      end if
      call integrator%init(mech, tight_settings(h, (n2 + 10) * h, rho_inf), q, v, error)
      if (allocated(error)) return
      call balance%init(mech, integrator%t, integrator%q, integrator%v, error)
      if (allocated(error)) return
      e0 = modal_energy(integrator%q(8), integrator%v(8))
      y = [0.0_dp, h * zeta_dot0, 0.0_dp]
      call principal_part(amp, y, y_p, ok)
      call check(error, 'real spurious root at Omega = ' // to_str(omega_h), ok)
      if (allocated(error)) return
      kappa = modal_energy(y_p(1), y_p(2) / h) / modal_energy(y(1), y(2) / h)
      worst_ref = 0.0_dp
      e1 = 0.0_dp
      en = e0
      do n = 1, n2
         call integrator%step(mech, error)
         if (allocated(error)) return
         call balance%update(mech, integrator%t, integrator%q, integrator%v, error)
         if (allocated(error)) return
         y = matmul(amp, y)
         en = modal_energy(integrator%q(8), integrator%v(8))
         worst_ref = max(worst_ref, abs(en - modal_energy(y(1), y(2) / h)) / e0)
         if (n == n1) e1 = en
      end do
      e2 = en
      decay = abs(lambda)**(2 * (n2 - n1))
      call report('rho_inf = ' // to_str(rho_inf, 13) // ', Omega = ' // to_str(omega_h, 6) // &
         ' (period ' // to_str(period) // ' steps): |lambda_1| = ' // to_str(abs(lambda), 12) &
         // ', |lambda_3| = ' // to_str(spurious, 4) // ', kappa = ' // to_str(kappa, 8) // &
         '; n1 = ' // to_str(n1) // ', n2 = ' // to_str(n2))
      call report('   E_n2 / E_n1 = ' // to_str(e2 / e1, 14) // ' vs |lambda_1|^(2(n2-n1)) = ' &
         // to_str(decay, 14) // '; E_n2 / (E_0 kappa |lambda_1|^(2 n2)) - 1 = ' // &
         to_str(e2 / (e0 * kappa * abs(lambda)**(2 * n2)) - 1.0_dp, 3) // &
         '; max |E - E_recurrence| / E_0 = ' // to_str(worst_ref, 3))
      call report('   D = ' // to_str(balance%numerical_dissipation, 14) // ' J, E_0 - E_n = ' &
         // to_str(e0 - e2, 14) // ' J, D / E_0 = ' // to_str(balance%numerical_dissipation &
         / e0, 4) // ', W = ' // to_str(balance%work, 3) // ' J, D_p = ' // &
         to_str(balance%physical_dissipation, 3) // ' J')
      call check_close(error, 'energy of the run vs the recurrence A^n y_0, / E_0', worst_ref, &
         0.0_dp, atol=1.0e-10_dp)
      if (allocated(error)) return
      call check_close(error, 'W of a free body', balance%work, 0.0_dp, atol=0.0_dp)
      if (allocated(error)) return
      if (undamped) then
         call check_close(error, 'rho_inf = 1 - 1e-12: D / E_0', &
            balance%numerical_dissipation / e0, 0.0_dp, atol=1.0e-10_dp)
         return
      end if
      call check_close(error, 'E_n2 / E_n1 vs |lambda_1|^(2 (n2 - n1))', e2 / e1, decay, &
         rtol=1.0e-9_dp)
      if (allocated(error)) return
      call check_close(error, 'E_n2 / E_0 vs kappa |lambda_1|^(2 n2)', e2 / e0, &
         kappa * abs(lambda)**(2 * n2), rtol=1.0e-9_dp)
      if (allocated(error)) return
      call check_close(error, 'numerical dissipation D vs E_0 - E_n', &
         balance%numerical_dissipation, e0 - e2, rtol=1.0e-9_dp)
   contains
      !> E = (zeta'^2 + omega^2 zeta^2) / 2 of the mass-normalised mode (J).
      pure real(dp) function modal_energy(zeta, zeta_dot)
         real(dp), intent(in) :: zeta, zeta_dot
         modal_energy = 0.5_dp * (zeta_dot**2 + omega**2 * zeta**2)
      end function modal_energy
   end subroutine modal_case

   !> Physical modal damping in the balance: the non-rotating body of test_modal_decay (one mode,
   !> omega = 2 pi 10 rad/s, zeta'(0) = 0.1) with damping ratio xi = 0.05, rho_inf = 0.8, to
   !> t = 0.5 s (5 periods), h = T/100 and T/200. Reference: the closed-form damped oscillator,
   !> x = v0/omega_d exp(-xi omega t) sin(omega_d t), omega_d = omega sqrt(1 - xi^2), so the energy
   !> dissipated by the damper is E_0 - E_exact(t). Asserted: D_p (trapezoidal integral of
   !> zeta'^T D_ff zeta') converges to it with order 2 +- 0.1 (D_p = 4.78308e-3 J; errors 3.87e-6,
   !> 9.69e-7 J, order 2.00), and the numerical dissipation D = -(E - E_0) - D_p is O(h^2) (order
   !> 2 +- 0.1; measured -4.8e-6, -1.2e-6 J, order 2.00) and below 1e-3 D_p at h = T/200
   !> (measured -2.5e-4 D_p). At Omega = 0.03 the scheme's own dissipation is nil (1 - |lambda_1|
   !> ~ 1e-10), so D is the O(h^2) quadrature and integration error, here slightly negative.
   subroutine test_modal_damping(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: omega = 2.0_dp * pi * 10.0_dp, zeta_dot0 = 0.1_dp, xi = 0.05_dp
      real(dp), parameter :: t_end = 0.5_dp
      integer, parameter :: per_period(2) = [100, 200]
      type(mechanism_t) :: mech
      type(flexible_body_t) :: body
      type(galpha_integrator_t) :: integrator
      type(energy_balance_t) :: balance
      real(dp), allocatable :: shapes(:, :)
      real(dp) :: q(8), v(8), h, omega_d, x, xd, e0, e_exact, err_p(2), num_d(2), order_p, order_d
      integer :: index, k, n
      omega_d = omega * sqrt(1.0_dp - xi**2)
      x = zeta_dot0 / omega_d * exp(-xi * omega * t_end) * sin(omega_d * t_end)
      xd = zeta_dot0 / omega_d * exp(-xi * omega * t_end) * (omega_d * cos(omega_d * t_end) - &
         xi * omega * sin(omega_d * t_end))
      e0 = 0.5_dp * zeta_dot0**2
      e_exact = 0.5_dp * (xd**2 + omega**2 * x**2)
      do k = 1, 2
         h = 2.0_dp * pi / omega / per_period(k)
         call make_flexible([omega], body, shapes, error)
         if (allocated(error)) return
         call body%set_modal_damping([xi], error)
         if (allocated(error)) return
         if (allocated(mech%bodies)) deallocate (mech%bodies)
         call mech%add_body(body, 'damped body', index, error)
         if (allocated(error)) return
         q = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
         v = 0.0_dp
         v(8) = zeta_dot0
         call integrator%init(mech, tight_settings(h, t_end + 10.0_dp * h, 0.8_dp), q, v, error)
         if (allocated(error)) return
         call balance%init(mech, integrator%t, integrator%q, integrator%v, error)
         if (allocated(error)) return
         do n = 1, nint(t_end / h)
            call integrator%step(mech, error)
            if (allocated(error)) return
            call balance%update(mech, integrator%t, integrator%q, integrator%v, error)
            if (allocated(error)) return
         end do
         err_p(k) = balance%physical_dissipation - (e0 - e_exact)
         num_d(k) = balance%numerical_dissipation
         call report('xi = 0.05, h = T/' // to_str(per_period(k)) // ': D_p = ' // &
            to_str(balance%physical_dissipation, 10) // ' J (closed form ' // &
            to_str(e0 - e_exact, 10) // ' J, error ' // to_str(err_p(k), 3) // ' J), D = ' // &
            to_str(num_d(k), 3) // ' J, W = ' // to_str(balance%work, 3) // ' J')
      end do
      order_p = log(abs(err_p(1) / err_p(2))) / log(2.0_dp)
      order_d = log(abs(num_d(1) / num_d(2))) / log(2.0_dp)
      call report('order of the D_p error ' // to_str(order_p, 4) // ', of D ' // &
         to_str(order_d, 4))
      call check_close(error, 'order of the error of D_p', order_p, 2.0_dp, atol=0.1_dp)
      if (allocated(error)) return
      call check_close(error, 'order of D with modal damping', order_d, 2.0_dp, atol=0.1_dp)
      if (allocated(error)) return
      call check_close(error, 'D / D_p at h = T/200', num_d(2) / (e0 - e_exact), 0.0_dp, &
         atol=1.0e-3_dp)
   end subroutine test_modal_damping

   !> The scheme's own energy identity (energy_balance_t%scheme_dissipation, module header of
   !> ffrf_mbs_energy_balance) on the linear one-mode body of test_modal_decay (omega = 2 pi 10
   !> rad/s, zeta'(0) = 0.1, h = T/20, 0.5 s), undamped and with xi = 0.05. D_s (work of the
   !> step-mean forces over the increments minus the change of T + U) is computed from the
   !> forces and energies; D_k from the increments of q, v, a and q'' alone (its closed form for
   !> constant M): for a linear system they are equal by the scheme's equations, to round-off.
   !> Asserted, each with its measured value (identities to 100 eps E_0 = 2.2e-14 E_0, the house
   !> bound for round-off: measured up to 3.3e-15 E_0 over the 200 steps):
   !> - rho_inf = 0.8: D_s = D_k (measured 8.7e-16 and -2.6e-15 E_0), D_s > 0 (2.48e-3 E_0
   !>   undamped, 4.45e-4 E_0 damped), and undamped D_s = D (W = 0, no constraint work);
   !> - rho_inf = 1 - 1e-12 (the trapezoidal rule to 1e-12; 1 is refused for a free body because
   !>   of its Euler row, and the body stays at rest so that row carries no force): D_s = 0
   !>   undamped and damped (measured 1.6e-15, -3.5e-15 E_0), while the balance's D, whose W and
   !>   D_p are trapezoidal integrals of the powers, carries their O(h^2) quadrature error with
   !>   damping (measured D = -0.0238 E_0 at h = T/20 against D_p = 0.976 E_0; reported);
   !> - nonlinear: the tumbling rigid body of test_rigid_momentum (h = 4e-4 s, rho_inf = 0.8):
   !>   no applied work and no constraint work (C_m = 2.9e-24 T_0), so D_s = D to round-off
   !>   (measured 3e-24 T_0); the closed form D_k leaves out the change of M(q) along the step, an
   !>   O(h^2) term like the dissipation itself: D_k / D_s = 0.4749, asserted 0.475 +- 0.05.
   subroutine test_scheme_identity(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: d_s, d_k, d, d_p, e0, drift_p, drift_l, parts(3)
      real(dp), parameter :: rho(2) = [0.8_dp, 1.0_dp - 1.0e-12_dp], xi(2) = [0.0_dp, 0.05_dp]
      !> Round-off of the identities: 100 eps E_0 (house rule; measured up to 3.3e-15 E_0)
      real(dp), parameter :: identity_tolerance = 100.0_dp * epsilon(1.0_dp)
      integer :: i, j
      do i = 1, 2
         do j = 1, 2
            call scheme_run(rho(i), xi(j), d_s, d_k, d, d_p, e0, error)
            if (allocated(error)) return
            call report('rho_inf = ' // to_str(rho(i), 13) // ', xi = ' // to_str(xi(j)) // &
               ': D_s / E_0 = ' // to_str(d_s / e0, 6) // ', (D_s - D_k) / E_0 = ' // &
               to_str((d_s - d_k) / e0, 3) // ', D / E_0 = ' // to_str(d / e0, 6) // &
               ', D_p / E_0 = ' // to_str(d_p / e0, 6))
            call check_close(error, 'D_s = D_k (linear system)', (d_s - d_k) / e0, 0.0_dp, &
               atol=identity_tolerance)
            if (allocated(error)) return
            if (i == 2) then
               call check_close(error, 'rho_inf = 1: D_s / E_0', d_s / e0, 0.0_dp, &
                  atol=identity_tolerance)
            else
               call check(error, 'rho_inf = 0.8: D_s > 0, got ' // to_str(d_s), d_s > 0.0_dp)
               if (.not. allocated(error) .and. j == 1) call check_close(error, &
                  'undamped: D_s = D', (d_s - d) / e0, 0.0_dp, atol=identity_tolerance)
            end if
            if (allocated(error)) return
         end do
      end do
      call rigid_run(4.0e-4_dp, 2.0_dp, 0.8_dp, drift_p, drift_l, d, error, parts)
      if (allocated(error)) return
      call report('tumbling rigid body, h = 4e-4 s, rho_inf = 0.8: D / T_0 = ' // to_str(d, 4) &
         // ', D_s / T_0 = ' // to_str(parts(1), 4) // ', D_k / T_0 = ' // to_str(parts(2), 4) &
         // ', C_m / T_0 = ' // to_str(parts(3), 4))
      call report('   (D_s - D) / T_0 = ' // to_str(parts(1) - d, 3) // ', D_k / D_s = ' // &
         to_str(parts(2) / parts(1), 4))
      call check_close(error, 'tumbling rigid body: (D_s - D) / T_0 (W = D_p = 0, C_m = 0)', &
         parts(1) - d, 0.0_dp, atol=identity_tolerance)
      if (.not. allocated(error)) call check_close(error, 'tumbling rigid body: D_k / D_s', &
         parts(2) / parts(1), 0.475_dp, atol=0.05_dp)
   end subroutine test_scheme_identity

   !> One run of test_scheme_identity: D_s, D_k, D, D_p at the end and E_0.
   subroutine scheme_run(rho_inf, xi, d_s, d_k, d, d_p, e0, error)
      real(dp), intent(in) :: rho_inf, xi
      real(dp), intent(out) :: d_s, d_k, d, d_p, e0
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: omega = 2.0_dp * pi * 10.0_dp, zeta_dot0 = 0.1_dp, t_end = 0.5_dp
      type(mechanism_t) :: mech
      type(flexible_body_t) :: body
      type(galpha_integrator_t) :: integrator
      type(energy_balance_t) :: balance
      real(dp), allocatable :: shapes(:, :)
      real(dp) :: q(8), v(8), h
      integer :: index, n
      h = 2.0_dp * pi / omega / 20.0_dp
      e0 = 0.5_dp * zeta_dot0**2
      call make_flexible([omega], body, shapes, error)
      if (allocated(error)) return
      if (xi > 0.0_dp) call body%set_modal_damping([xi], error)
      if (allocated(error)) return
      call mech%add_body(body, 'vibrating body', index, error)
      if (allocated(error)) return
      q = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      v = 0.0_dp
      v(8) = zeta_dot0
      call integrator%init(mech, tight_settings(h, t_end + 10.0_dp * h, rho_inf), q, v, error)
      if (allocated(error)) return
      call balance%init(mech, integrator%t, integrator%q, integrator%v, error, &
         scheme=integrator)
      if (allocated(error)) return
      do n = 1, nint(t_end / h)
         call integrator%step(mech, error)
         if (allocated(error)) return
         call balance%update(mech, integrator%t, integrator%q, integrator%v, error, &
            scheme=integrator)
         if (allocated(error)) return
      end do
      d_s = balance%scheme_dissipation
      d_k = balance%kinematic_dissipation
      d = balance%numerical_dissipation
      d_p = balance%physical_dissipation
   end subroutine scheme_run

end module test_mbs_energy

program main_mbs_energy
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_energy, only: collect_mbs_energy
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_energy(tests)
   call run_suite('mbs_energy', tests)
end program main_mbs_energy
