!> Stability of ffrf's generalized-alpha integrator (ffrf_mbs_generalized_alpha) where time steps
!> outrun the dynamics (issue 4, part 2), on unconstrained linear systems with closed-form answers:
!>
!> - spectral_radius_sweep: the numerical amplification measured from the integrator's own steps
!>   against the spectral radius of the closed-form characteristic polynomial of the
!>   Chung-Hulbert scheme, for rho_inf = 0, 0.5, 0.8, 1 and Omega = omega h from 1e-2 to 1e6
!>   (test_mbs_generalized_alpha checks the limit at Omega = 1e8 only, test_mbs_energy the
!>   decay of one resolved mode).
!> - stiff_mode: a resolved mode (Omega = 6.3e-3) and a stiff one (Omega = 10 .. 1e4) integrated
!>   together: generalized-alpha follows its closed-form recurrence, stays bounded (first-step
!>   overshoot in closed form) and damps the stiff mode by its spectral radius per step, which
!>   tends to rho_inf; the explicit central-difference scheme (written here) grows by its
!>   closed-form amplification |z| ~ Omega^2 per step for Omega > 2 and stays bounded below; the
!>   trapezoidal rule (rho_inf = 1, allowed without constraints) keeps the stiff mode's energy.
!>
!> The characteristic polynomial (z-transform of the scheme of theory.md 4.1 on x'' + w^2 x = 0,
!> Omega = w h; with the Chung-Hulbert parameters beta z^2 + (gamma + 1/2 - 2 beta) z + (1/2 +
!> beta - gamma) = beta (z + rho_inf)^2):
!>     c(z) = [(1 - am) z + am] (z - 1)^2 + Omega^2 beta (1 - af) (z + rho_inf)^3,
!> so that all three roots meet at -rho_inf as Omega -> infinity and x_{n+1}, x_n, x_{n-1},
!> x_{n-2} of any solution satisfy the recurrence with the expanded coefficients of c.
module test_stability_integrator
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_dae_system, only: dae_system_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   use ffrf_test_galpha_reference, only: parameters => galpha_parameters, &
      characteristic => galpha_characteristic
   implicit none
   private
   public :: collect_stability_integrator

   !> Step (s) and number of steps of the stiff-mode runs
   real(dp), parameter :: h = 1.0e-3_dp
   integer, parameter :: steps = 400

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

   !> Decoupled unit-mass modal oscillators q_k'' + omega_k^2 q_k = 0, no constraints.
   type, extends(dae_system_t) :: modal_oscillator_t
      !> Angular frequencies (rad/s)
      real(dp), allocatable :: omega(:)
   contains
      procedure :: num_coordinates => modal_n
      procedure :: num_constraints => modal_nc
      procedure :: mass => modal_mass
      procedure :: force => modal_force
      procedure :: constraints => modal_phi
      procedure :: constraint_jacobian => modal_jac
      procedure :: stiffness => modal_stiffness
   end type modal_oscillator_t

contains

   !> The suite.
   subroutine collect_stability_integrator(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('spectral_radius_sweep', test_spectral_sweep), &
         new_unittest('stiff_mode_generalized_alpha', test_stiff_galpha), &
         new_unittest('stiff_mode_central_difference', test_stiff_central), &
         new_unittest('stiff_mode_trapezoidal', test_stiff_trapezoidal)]
   end subroutine collect_stability_integrator

   !> The characteristic polynomial in factored form, accurate near its root cluster at -rho_inf:
   !> with the Chung-Hulbert parameters beta z^2 + (gamma + 1/2 - 2 beta) z + (1/2 + beta -
   !> gamma) = beta (z + rho_inf)^2 (beta = 1/(1 + rho_inf)^2, gamma + 1/2 = 2/(1 + rho_inf)), so
   !>   c(z) = [(1 - am) z + am] (z - 1)^2 + Omega^2 beta (1 - af) (z + rho_inf)^3.
   pure complex(dp) function characteristic_at(rho_inf, omega_h, z)
      real(dp), intent(in) :: rho_inf, omega_h
      complex(dp), intent(in) :: z
      real(dp) :: am, af, gamma, beta
      call parameters(rho_inf, am, af, gamma, beta)
      characteristic_at = ((1.0_dp - am) * z + am) * (z - 1.0_dp)**2 + &
         omega_h**2 * beta * (1.0_dp - af) * (z + rho_inf)**3
   end function characteristic_at

   !> Roots of the characteristic cubic: Cardano on the expanded coefficients, then
   !> Durand-Kerner (simultaneous Newton) iterations on the factored form, which converge for the
   !> near-triple root at large Omega where the expanded coefficients lose the splitting.
   pure function characteristic_roots(rho_inf, omega_h) result(z)
      real(dp), intent(in) :: rho_inf, omega_h
      complex(dp) :: z(3)
      complex(dp) :: s, w, u, rot, correction(3)
      real(dp) :: c(0:3), a, b, d, p, q
      integer :: k, it
      c = characteristic(rho_inf, omega_h)
      a = c(2) / c(3)
      b = c(1) / c(3)
      d = c(0) / c(3)
      p = b - a**2 / 3.0_dp
      q = 2.0_dp * a**3 / 27.0_dp - a * b / 3.0_dp + d
      s = sqrt(cmplx(0.25_dp * q**2 + p**3 / 27.0_dp, 0.0_dp, dp))
      w = -0.5_dp * q + s
      if (abs(-0.5_dp * q - s) > abs(w)) w = -0.5_dp * q - s
      rot = exp(cmplx(0.0_dp, 2.0_dp * pi / 3.0_dp, dp))
      if (abs(w) == 0.0_dp) then
         ! triple root: spread the start so the simultaneous iteration can separate them
         z = -a / 3.0_dp + 1.0e-3_dp * [cmplx(1.0_dp, 0.0_dp, dp), rot, rot**2]
      else
         u = w**(1.0_dp / 3.0_dp)
         do k = 1, 3
            z(k) = u - p / (3.0_dp * u) - a / 3.0_dp
            u = u * rot
         end do
      end if
      do it = 1, 50
         do k = 1, 3
            correction(k) = characteristic_at(rho_inf, omega_h, z(k)) / (c(3) * &
               product(z(k) - z(pack([1, 2, 3], [1, 2, 3] /= k))))
         end do
         z = z - correction
         if (maxval(abs(correction)) <= 4.0_dp * epsilon(1.0_dp) * maxval(abs(z))) exit
      end do
   end function characteristic_roots

   !> Spectral radius of generalized-alpha at Omega from the closed-form characteristic cubic.
   real(dp) function closed_form_radius(rho_inf, omega_h)
      real(dp), intent(in) :: rho_inf, omega_h
      closed_form_radius = maxval(abs(characteristic_roots(rho_inf, omega_h)))
   end function closed_form_radius

   !> Amplification matrix of ffrf's integrator measured column by column: three single steps
   !> of galpha_integrator_t%step on x'' + Omega^2 x = 0 (h = 1 s) from the unit states of
   !> y = (x, h v, h^2 a) (q'' = -Omega^2 x consistent with x).
   subroutine measured_amplification(rho_inf, omega_h, amp, error)
      real(dp), intent(in) :: rho_inf, omega_h
      real(dp), intent(out) :: amp(3, 3)
      type(error_t), allocatable, intent(out) :: error
      type(modal_oscillator_t) :: osc
      type(galpha_settings_t) :: settings
      type(galpha_integrator_t) :: integ
      integer :: j
      allocate (osc%omega(1))
      osc%omega(1) = omega_h
      settings%h = 1.0_dp
      settings%t_end = 1.0e3_dp
      settings%rho_inf = rho_inf
      call integ%init(osc, settings, [1.0_dp], [0.0_dp], error)
      if (allocated(error)) return
      do j = 1, 3
         integ%t = 0.0_dp
         integ%q = merge(1.0_dp, 0.0_dp, j == 1)
         integ%qdd = -omega_h**2 * integ%q
         integ%v = merge(1.0_dp, 0.0_dp, j == 2)
         integ%a = merge(1.0_dp, 0.0_dp, j == 3)
         call integ%step(osc, error)
         if (allocated(error)) return
         amp(:, j) = [integ%q(1), integ%v(1), integ%a(1)]
      end do
   end subroutine measured_amplification

   !> Largest eigenvalue modulus of a 3 x 3 matrix (LAPACK dgeev).
   real(dp) function radius_of(amp)
      real(dp), intent(in) :: amp(3, 3)
      real(dp) :: a(3, 3), wr(3), wi(3), vl(1, 3), vr(1, 3), work(64)
      integer(ip) :: info
      a = amp
      call dgeev('N', 'N', 3_ip, a, 3_ip, wr, wi, vl, 1_ip, vr, 1_ip, work, 64_ip, info)
      radius_of = huge(1.0_dp)
      if (info == 0) radius_of = maxval(hypot(wr, wi))
   end function radius_of

   !> Spectral radius of ffrf's generalized-alpha, measured: the 3 x 3 amplification matrix of
   !> the state (x, h v, h^2 a) from three single steps of galpha_integrator_t%step
   !> (measured_amplification), its eigenvalues by LAPACK dgeev. Reference: the largest root
   !> modulus of the closed-form characteristic cubic (module header; Cardano, then Durand-Kerner
   !> on the factored form, which keeps the splitting of the near-triple root at large Omega).
   !> rho_inf = 0, 0.5, 0.8, 1 and Omega = 10^(k/4), k = -8 .. 24 (1e-2 .. 1e6), 132 points.
   !> Tolerance: the roots of a near-triple cluster with separation s move by ~ delta / s^2 for a
   !> perturbation delta of the matrix, so |measured - closed| <= 16 eps / s^2 + 4 eps, s the
   !> smallest distance between the closed-form roots (measured at most 2.7 eps / s^2: 1e-15
   !> for Omega <= 100, 6e-10 at Omega = 1e6 where s = 2.7e-4). Also asserted: the measured
   !> radius never exceeds 1 (unconditional stability) and does not grow with Omega (within the
   !> same tolerance), and rho_inf = 1 (trapezoidal rule, allowed without constraints) gives
   !> exactly 1 at every Omega (measured 1 to the last bit; its spurious root is -1 exactly).
   !> Measured radii at Omega = 1, 10, 1e2, 1e4, 1e6: rho_inf = 0.8: 0.99947, 0.92979, 0.83464,
   !> 0.80167, 0.80008; rho_inf = 0: 0.93, 0.24, 0.048, 0.0022, 1.0e-4.
   subroutine test_spectral_sweep(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: rhos(4) = [0.0_dp, 0.5_dp, 0.8_dp, 1.0_dp]
      real(dp) :: amp(3, 3), omega_h, measured, closed, separation, tolerance, previous, worst
      complex(dp) :: roots(3)
      integer :: i, k
      do i = 1, size(rhos)
         worst = 0.0_dp
         previous = huge(1.0_dp)
         do k = -8, 24
            omega_h = 10.0_dp**(0.25_dp * k)
            call measured_amplification(rhos(i), omega_h, amp, error)
            if (allocated(error)) return
            measured = radius_of(amp)
            roots = characteristic_roots(rhos(i), omega_h)
            closed = maxval(abs(roots))
            separation = min(abs(roots(1) - roots(2)), abs(roots(1) - roots(3)), &
               abs(roots(2) - roots(3)))
            tolerance = 16.0_dp * epsilon(1.0_dp) / separation**2 + 4.0_dp * epsilon(1.0_dp)
            worst = max(worst, abs(measured - closed) / tolerance)
            call check_close(error, 'rho_inf = ' // to_str(rhos(i)) // ', Omega = ' // &
               to_str(omega_h, 4) // ': measured spectral radius', measured, closed, &
               atol=tolerance)
            if (allocated(error)) return
            call check(error, 'rho_inf = ' // to_str(rhos(i)) // ', Omega = ' // &
               to_str(omega_h, 4) // ': spectral radius ' // to_str(measured, 16) // &
               ' above 1 or above ' // to_str(previous, 16) // ' at the smaller Omega', &
               measured <= 1.0_dp + tolerance .and. measured <= previous + tolerance)
            if (allocated(error)) return
            if (rhos(i) == 1.0_dp) then
               call check_close(error, 'trapezoidal rule: spectral radius at Omega = ' // &
                  to_str(omega_h, 4), measured, 1.0_dp, atol=4.0_dp * epsilon(1.0_dp))
               if (allocated(error)) return
            end if
            previous = measured
         end do
         call report('rho_inf = ' // to_str(rhos(i)) // ': radius ' // to_str(measured, 6) // &
            ' at Omega = 1e6; largest |measured - closed| / tolerance ' // to_str(worst, 3))
      end do
   end subroutine test_spectral_sweep

   !> A resolved mode (1 Hz, Omega = 6.3e-3) and a stiff one (Omega_s = omega_s h = 10, 1e2, 1e3,
   !> 1e4) of the modal oscillator, both displaced by 1 at rest, h = 1e-3 s, 400 steps,
   !> rho_inf = 0.8, 0.5, 0. References (closed form) and tolerances, per run:
   !> - the stiff coordinate follows the characteristic recurrence: |sum c_k x_{n-3+k}| <= tol
   !>   sum |c_k| (|x| + |h^2 q''| + |h v| + |h^2 a|)_{n-3+k}, tol = 1e-12 (round-off; measured
   !>   1e-24 .. 6e-18). For rho_inf = 0, tol = eps Omega_s^2: x_{n+1} is the predictor, which
   !>   carries h^2 q''_n = -Omega^2 x_n, plus the Newton correction, so it is known to eps
   !>   Omega^2 |x_n| while c_2 = 3 am - 2 is O(1) (gamma + 1/2 - 2 beta = 0): measured 8.7e-17,
   !>   1.0e-15, 3.9e-14, 1.5e-11 for Omega_s = 10 .. 1e4; a second Newton iteration, with
   !>   tighter tolerances, brings it to 1e-17). Checked until the state reaches 1e-280, before
   !>   the subnormal range;
   !> - bounded: the first step's energy E_1 / E_0 = (V_1^2 + Omega^2 X_1^2) / Omega^2 of the
   !>   closed-form first step from the consistent start (X_0 = 1, V_0 = 0, h^2 a_0 = -Omega^2):
   !>   h^2 a_1 = Omega^2 (am - 1 + Omega^2 (1 - af)(1/2 - beta)) / ((1 - am) + Omega^2 (1 - af)
   !>   beta), V_1 = -(1 - gamma) Omega^2 + gamma h^2 a_1, X_1 from Newmark: the displacement
   !>   overshoot is O(1), the velocity's O(Omega) (Chung & Hulbert 1993), so E_1 / E_0 ~
   !>   k^2 Omega^2, k = gamma (1/2 - beta)/beta - (1 - gamma) (-0.010, -0.0625, -0.25 for
   !>   rho_inf = 0.8, 0.5, 0: E_1 / E_0 = 1.0e4, 3.9e5, 6.25e6 at Omega_s = 1e4), rtol 1e-9;
   !>   and no displacement above the start: max |x_n| <= |x_0| (measured max |x_n| = 1);
   !> - damping per step: the envelope max |x| over steps 181..200 and 381..400 gives the rate
   !>   (A_400 / A_200)^(1/200), against the closed-form spectral radius rho(Omega_s) within 1 %
   !>   (rho_inf = 0.8, 0.5; rho_inf = 0 annihilates the mode to round-off in a few steps,
   !>   below the smallest double after ~100): near the triple root -rho_inf the solution carries a
   !>   factor ~ n^2, which biases the rate by 2 ln 2 / 200 = 0.7 % at most (measured 0.05 ..
   !>   0.55 %); rho(Omega_s) -> rho_inf like Omega_s^(-2/3) (0.8077, 0.8017 at Omega_s = 1e3,
   !>   1e4; 0.5078, 0.5017 for rho_inf = 0.5), so at Omega_s = 1e4 the measured rate is also
   !>   asserted within 0.01 of rho_inf (the 0.7 % bias plus 0.0017; measured 0.8058, 0.5031);
   !> - the resolved mode stays accurate: |x(t) - cos(w t)| <= w t (w h)^2 = 9.9e-5 at t = 0.4 s
   !>   (second order; measured 5.1e-6, 7.3e-6, 2.7e-5 for rho_inf = 0.8, 0.5, 0).
   subroutine test_stiff_galpha(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: rhos(3) = [0.8_dp, 0.5_dp, 0.0_dp]
      real(dp), parameter :: stiff(4) = [10.0_dp, 1.0e2_dp, 1.0e3_dp, 1.0e4_dp]
      real(dp) :: x(0:steps), v(0:steps), a(0:steps), c(0:3), residual, rate, slow_error, radius
      real(dp) :: am, af, gamma, beta, a1, v1, x1, first_energy, energy_1, bound
      integer :: i, k, n
      do k = 1, size(stiff)
         do i = 1, size(rhos)
            call stiff_run(rhos(i), stiff(k), x, v, a, slow_error, error)
            if (allocated(error)) return
            ! closed-form recurrence
            c = characteristic(rhos(i), stiff(k))
            residual = 0.0_dp
            do n = 3, steps
               ! rho_inf = 0 reaches the subnormal range (1e-308) within the run
               if (size_of(n) < 1.0e-280_dp) exit
               residual = max(residual, abs(c(3) * x(n) + c(2) * x(n - 1) + c(1) * x(n - 2) + &
                  c(0) * x(n - 3)) / (abs(c(3)) * size_of(n) + abs(c(2)) * size_of(n - 1) + &
                  abs(c(1)) * size_of(n - 2) + abs(c(0)) * size_of(n - 3)))
            end do
            ! closed-form first step
            call parameters(rhos(i), am, af, gamma, beta)
            a1 = stiff(k)**2 * (am - 1.0_dp + stiff(k)**2 * (1.0_dp - af) * (0.5_dp - beta)) / &
               ((1.0_dp - am) + stiff(k)**2 * (1.0_dp - af) * beta)
            v1 = -(1.0_dp - gamma) * stiff(k)**2 + gamma * a1
            x1 = 1.0_dp + (0.5_dp - beta) * (-stiff(k)**2) + beta * a1
            first_energy = (v1**2 + stiff(k)**2 * x1**2) / stiff(k)**2
            energy_1 = ((h * v(1))**2 + stiff(k)**2 * x(1)**2) / (stiff(k)**2 * x(0)**2)
            radius = closed_form_radius(rhos(i), stiff(k))
            rate = 0.0_dp
            if (rhos(i) > 0.0_dp) rate = (maxval(abs(x(381:400))) / &
               maxval(abs(x(181:200))))**(1.0_dp / 200.0_dp)
            bound = 2.0_dp * pi * 0.4_dp * (2.0_dp * pi * h)**2
            call report('Omega_s = ' // to_str(stiff(k)) // ', rho_inf = ' // to_str(rhos(i)) // &
               ': recurrence ' // to_str(residual, 2) // ', E_1/E_0 ' // &
               to_str(energy_1, 6) // ' (closed form ' // to_str(first_energy, 6) // &
               '), max |x| ' // to_str(maxval(abs(x)), 6) // ', rate ' // to_str(rate, 6) // &
               ' (rho(Omega) ' // to_str(radius, 6) // '), slow mode error ' // &
               to_str(slow_error, 2))
            call check_close(error, 'recurrence residual', residual, 0.0_dp, &
               atol=merge(1.0e-12_dp, epsilon(1.0_dp) * stiff(k)**2, rhos(i) > 0.0_dp))
            if (allocated(error)) return
            call check_close(error, 'E_1 / E_0 vs the closed-form first step', energy_1, &
               first_energy, rtol=1.0e-9_dp)
            if (allocated(error)) return
            call check(error, 'max |x_n| = ' // to_str(maxval(abs(x)), 16) // ' > |x_0|', &
               maxval(abs(x)) <= abs(x(0)))
            if (allocated(error)) return
            call check_close(error, 'resolved mode error', slow_error, 0.0_dp, atol=bound)
            if (allocated(error)) return
            if (rhos(i) > 0.0_dp) then
               call check_close(error, 'stiff-mode decay rate per step vs rho(Omega)', rate, &
                  radius, rtol=1.0e-2_dp)
               if (allocated(error)) return
               if (stiff(k) >= 1.0e4_dp) then
                  call check_close(error, 'stiff-mode decay rate per step vs rho_inf', rate, &
                     rhos(i), atol=1.0e-2_dp)
                  if (allocated(error)) return
               end if
            end if
         end do
      end do
   contains
      !> |x| + |h^2 q''| + |h v| + |h^2 a| of the stiff coordinate at step m (q'' = -w^2 x)
      real(dp) function size_of(m)
         integer, intent(in) :: m
         size_of = abs(x(m)) * (1.0_dp + stiff(k)**2) + h * abs(v(m)) + h**2 * abs(a(m))
      end function size_of
   end subroutine test_stiff_galpha

   !> The same start run by explicit central differences (written here as the comparison method:
   !> x_{n+1} = 2 x_n - x_{n-1} - Omega^2 x_n, x_1 = x_0 - Omega^2 x_0 / 2 from rest). Reference:
   !> its characteristic equation z^2 - (2 - Omega^2) z + 1 = 0. For Omega > 2 both roots are
   !> real and negative with product 1, |z| = ((Omega^2 - 2) + sqrt((Omega^2 - 2)^2 - 4)) / 2:
   !> the growth |x_20 / x_19| equals it to 1e-12 relative (the other root's share has decayed
   !> by |z|^-38; measured <= 2.2e-16; |z| = 98.0, 1.0e4, 1.0e6, 1.0e8 for Omega = 10 .. 1e4,
   !> so x_20 ~ 1e40 .. 1e160: it blows up). For Omega = 1.9 < 2 (the stable side) the
   !> invariant I = x_n^2 - 2 c x_n x_{n-1} + x_{n-1}^2, c = 1 - Omega^2 / 2, bounds |x_n| <=
   !> sqrt(I / (1 - c^2)) over 1000 steps (checked with 1e-12 relative slack).
   subroutine test_stiff_central(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: stiff(4) = [10.0_dp, 1.0e2_dp, 1.0e3_dp, 1.0e4_dp]
      real(dp) :: xs(0:1000), z, c, invariant
      integer :: k, n
      do k = 1, size(stiff)
         xs(0) = 1.0_dp
         xs(1) = 1.0_dp - 0.5_dp * stiff(k)**2
         do n = 1, 19
            xs(n + 1) = 2.0_dp * xs(n) - xs(n - 1) - stiff(k)**2 * xs(n)
         end do
         z = 0.5_dp * ((stiff(k)**2 - 2.0_dp) + sqrt((stiff(k)**2 - 2.0_dp)**2 - 4.0_dp))
         call report('central differences, Omega = ' // to_str(stiff(k)) // ': |x_20 / x_19| ' &
            // to_str(abs(xs(20) / xs(19)), 15) // ', closed form ' // to_str(z, 15) // &
            ', |x_20| ' // to_str(abs(xs(20)), 3))
         call check_close(error, 'central-difference growth per step at Omega = ' // &
            to_str(stiff(k)), abs(xs(20) / xs(19)), z, rtol=1.0e-12_dp)
         if (allocated(error)) return
      end do
      c = 1.0_dp - 0.5_dp * 1.9_dp**2
      xs(0) = 1.0_dp
      xs(1) = c
      do n = 1, 999
         xs(n + 1) = 2.0_dp * c * xs(n) - xs(n - 1)
      end do
      invariant = xs(1)**2 - 2.0_dp * c * xs(1) * xs(0) + xs(0)**2
      call report('central differences, Omega = 1.9: max |x_n| ' // to_str(maxval(abs(xs)), 10) &
         // ' <= ' // to_str(sqrt(invariant / (1.0_dp - c**2)), 10))
      call check(error, 'central differences bounded for Omega = 1.9', &
         maxval(abs(xs)) <= sqrt(invariant / (1.0_dp - c**2)) * (1.0_dp + 1.0e-12_dp))
   end subroutine test_stiff_central

   !> The same runs with rho_inf = 1: ffrf's generalized-alpha is then the trapezoidal rule
   !> (Newmark average acceleration; accepted without constraints). Reference: it conserves the
   !> quadratic energy E = (v^2 + omega^2 x^2) / 2 of each linear mode exactly (a_0 = q''_0 keeps
   !> the spurious root -1 unexcited), so the stiff mode is not damped at all, whatever Omega_s.
   !> Asserted: max_n |E_n / E_0 - 1| <= 1e-9 for both modes over the 400 steps (round-off eps
   !> Omega_s sqrt(n): measured 7.9e-14, 2.7e-13, 1.7e-11, 3.3e-11 for Omega_s = 10 .. 1e4).
   subroutine test_stiff_trapezoidal(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: stiff(4) = [10.0_dp, 1.0e2_dp, 1.0e3_dp, 1.0e4_dp]
      real(dp) :: x(0:steps), v(0:steps), a(0:steps), e(0:steps), slow_error, omega_s
      integer :: k
      do k = 1, size(stiff)
         call stiff_run(1.0_dp, stiff(k), x, v, a, slow_error, error)
         if (allocated(error)) return
         omega_s = stiff(k) / h
         e = 0.5_dp * (v**2 + omega_s**2 * x**2)
         call report('trapezoidal, Omega_s = ' // to_str(stiff(k)) // ': max |E_n / E_0 - 1| ' &
            // to_str(maxval(abs(e / e(0) - 1.0_dp)), 3) // ', E_400 / E_0 ' // &
            to_str(e(steps) / e(0), 15) // '; resolved mode: ' // to_str(slow_error, 2))
         call check_close(error, 'trapezoidal rule: stiff-mode energy, max |E_n / E_0 - 1|', &
            maxval(abs(e / e(0) - 1.0_dp)), 0.0_dp, atol=1.0e-9_dp)
         if (allocated(error)) return
         call check_close(error, 'trapezoidal rule: resolved-mode energy, max |E_n / E_0 - 1|', &
            slow_error, 0.0_dp, atol=1.0e-9_dp)
         if (allocated(error)) return
      end do
   end subroutine test_stiff_trapezoidal

   !> The two-mode run of the stiff-mode tests: history of the stiff coordinate (x, v, a) over
   !> `steps` steps of h, and the error of the resolved mode at the end against cos(w t).
   subroutine stiff_run(rho_inf, omega_h, x, v, a, slow_error, error)
      real(dp), intent(in) :: rho_inf, omega_h
      real(dp), intent(out) :: x(0:steps), v(0:steps), a(0:steps), slow_error
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: omega_slow = 2.0_dp * pi
      type(modal_oscillator_t) :: osc
      type(galpha_settings_t) :: settings
      type(galpha_integrator_t) :: integ
      real(dp) :: energy
      integer :: n
      allocate (osc%omega(2))
      osc%omega = [omega_slow, omega_h / h]
      settings%h = h
      settings%t_end = (steps + 10) * h
      settings%rho_inf = rho_inf
      call integ%init(osc, settings, [1.0_dp, 1.0_dp], [0.0_dp, 0.0_dp], error)
      if (allocated(error)) return
      x(0) = integ%q(2)
      v(0) = integ%v(2)
      a(0) = integ%a(2)
      slow_error = 0.0_dp
      do n = 1, steps
         call integ%step(osc, error)
         if (allocated(error)) return
         x(n) = integ%q(2)
         v(n) = integ%v(2)
         a(n) = integ%a(2)
         if (rho_inf == 1.0_dp) then
            ! trapezoidal: the resolved mode's energy is conserved too
            energy = 0.5_dp * (integ%v(1)**2 + omega_slow**2 * integ%q(1)**2)
            slow_error = max(slow_error, abs(energy / (0.5_dp * omega_slow**2) - 1.0_dp))
         end if
      end do
      if (rho_inf < 1.0_dp) slow_error = abs(integ%q(1) - cos(omega_slow * integ%t))
   end subroutine stiff_run

   ! ----------------------------------------------------------------------------------------------
   ! Modal oscillator

   integer function modal_n(self)
      class(modal_oscillator_t), intent(in) :: self
      modal_n = size(self%omega)
   end function modal_n

   integer function modal_nc(self)
      class(modal_oscillator_t), intent(in) :: self
      modal_nc = 0 * size(self%omega)
   end function modal_nc

   subroutine modal_mass(self, q, M, error)
      class(modal_oscillator_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(out) :: M(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      M = 0.0_dp * q(1)
      do k = 1, size(self%omega)
         M(k, k) = 1.0_dp
      end do
   end subroutine modal_mass

   subroutine modal_force(self, q, v, t, f, error)
      class(modal_oscillator_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: f(:)
      type(error_t), allocatable, intent(out) :: error
      f = -self%omega**2 * q + 0.0_dp * (v + t)
   end subroutine modal_force

   subroutine modal_phi(self, q, t, phi, error)
      class(modal_oscillator_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      phi = 0.0_dp * (q(1) + t + size(self%omega))
   end subroutine modal_phi

   subroutine modal_jac(self, q, t, Phi_q, error)
      class(modal_oscillator_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: Phi_q(:, :)
      type(error_t), allocatable, intent(out) :: error
      Phi_q = 0.0_dp * (q(1) + t + size(self%omega))
   end subroutine modal_jac

   !> K_t = -df/dq = diag(omega^2), exact (the default central differences round at 1e-11).
   subroutine modal_stiffness(self, q, v, t, K_t, error)
      class(modal_oscillator_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: K_t(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      K_t = 0.0_dp * (q(1) + v(1) + t)
      do k = 1, size(self%omega)
         K_t(k, k) = self%omega(k)**2
      end do
   end subroutine modal_stiffness

end module test_stability_integrator

program main_stability_integrator
   use ffrf_testing, only: unittest_t, run_suite
   use test_stability_integrator, only: collect_stability_integrator
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_stability_integrator(tests)
   call run_suite('stability_integrator', tests)
end program main_stability_integrator
