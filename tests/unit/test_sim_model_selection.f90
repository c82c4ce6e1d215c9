!> The error estimates of the automatic engine model (ffrf_app_engine_model_selection) against
!> closed forms and conservation laws:
!> - generalized-alpha with rho_inf = 1 is the trapezoidal rule: its numerical frequency
!>   2 atan(w h / 2) / h, no damping; its periodic response of a free mass to e^(i W t),
!>   (W h / 2)^2 / tan^2(W h / 2) times the exact one, and of an oscillator, 1 / (1 - (2 tan(W h /
!>   2) / (w h))^2); with rho_inf = 0.8 the period error is of order 2 and the damping of order 3
!>   in w h (ratios over a halving of w h);
!> - the forced response H(r) = 1 / (1 - r^2 + 2 i max(zeta, floor/2) r) and a mode's error at the
!>   peak of a single-harmonic force, mu |Re(H - 1)|;
!> - a point mass m on a spring with a mass M jointed: f~ = f / sqrt(1 + M/m) exactly;
!> - the harmonics of a sampled cosine, and of the engine's conrod force: the mean torque
!>   mean(F L) of the rigid slider-crank at constant speed equals the cycle work of p dV over
!>   4 pi (inertia forces do no work over a cycle), a second computation of T_i;
!> - generalized-alpha with rho_inf = 0.8 against the scheme written out for the tests
!>   (ffrf_test_galpha_reference: Chung & Hulbert 1993 parameters and characteristic cubic;
!>   here the z-transform of the steady state and the principal root by Newton): forced
!>   responses and numerical frequency and damping;
!> - the regime speed against the cycle work integrated here (p dV over a fine grid, slider-crank
!>   volume written out here);
!> - the greedy mode selection drops as many modes as the budget allows; the chosen step is the
!>   largest of the ladder whose step error, computed here from the reference scheme, is within
!>   its budget, and the step error falls as h^2 (the method's order).
module test_sim_model_selection
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_app_engine_pressure, only: pressure_model_t, pressure_input_t
   use ffrf_app_engine_model_selection, only: excitation_t, engine_excitation, set_harmonics, &
      mode_effect_t, mode_effect, galpha_mode, effective_frequencies, exact_response, &
      galpha_response, body_selection_t, select_modes, select_time_step, step_errors, &
      STEP_LADDER, MAX_TURN_PER_STEP, NUM_HARMONICS
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   use ffrf_test_galpha_reference, only: galpha_parameters, galpha_characteristic
   implicit none
   private
   public :: collect_sim_model_selection

   integer, parameter :: samples = 2880

contains

   subroutine collect_sim_model_selection(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('trapezoidal_mode', test_trapezoidal_mode), &
         new_unittest('trapezoidal_forced_response', test_trapezoidal_forced), &
         new_unittest('galpha_orders', test_galpha_orders), &
         new_unittest('galpha_forced_response_rho_0.8', test_galpha_forced), &
         new_unittest('galpha_mode_rho_0.8', test_galpha_mode_roots), &
         new_unittest('forced_response_and_mode_error', test_mode_error), &
         new_unittest('jointed_mass_frequency', test_jointed_mass), &
         new_unittest('harmonics_of_a_cosine', test_cosine_harmonics), &
         new_unittest('engine_mean_torque', test_engine_torque), &
         new_unittest('greedy_mode_selection', test_greedy_selection), &
         new_unittest('largest_step_within_budget', test_step_choice), &
         new_unittest('step_error_order', test_step_order)]
   end subroutine collect_sim_model_selection

   subroutine test_trapezoidal_mode(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: wh, ratio, damping
      integer :: i
      do i = 1, 5
         wh = 0.05_dp * 3.0_dp**(i - 1)
         call galpha_mode(wh, 1.0_dp, ratio, damping)
         call check_close(error, 'frequency ratio at w h = ' // to_str(wh), ratio, &
            2.0_dp * atan(0.5_dp * wh) / wh, rtol=1.0e-12_dp)
         if (allocated(error)) return
         call check_close(error, 'damping at w h = ' // to_str(wh), damping, 0.0_dp, &
            atol=1.0e-12_dp)
         if (allocated(error)) return
      end do
   end subroutine test_trapezoidal_mode

   subroutine test_trapezoidal_forced(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-4_dp
      real(dp) :: big_omega, w, theta
      complex(dp) :: response
      integer :: i
      do i = 1, 4
         big_omega = 2.0_dp * pi * 300.0_dp * i
         theta = big_omega * h
         response = galpha_response(0.0_dp, 0.0_dp, big_omega, h, 1.0_dp)
         call check_close(error, 'free mass at W h = ' // to_str(theta), real(response, dp), &
            (0.5_dp * theta)**2 / tan(0.5_dp * theta)**2, rtol=1.0e-10_dp)
         if (allocated(error)) return
         call check_close(error, 'free mass, imaginary part', aimag(response), 0.0_dp, &
            atol=1.0e-10_dp)
         if (allocated(error)) return
         w = 2.0_dp * pi * 2000.0_dp
         response = galpha_response(w, 0.0_dp, big_omega, h, 1.0_dp)
         call check_close(error, 'oscillator at W h = ' // to_str(theta), real(response, dp), &
            1.0_dp / (1.0_dp - (2.0_dp * tan(0.5_dp * theta) / (w * h))**2), rtol=1.0e-10_dp)
         if (allocated(error)) return
      end do
   end subroutine test_trapezoidal_forced

   !> rho_inf = 0.8: halving w h divides the period error by about 4 and the damping by 8.
   subroutine test_galpha_orders(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: ratio1, ratio2, damping1, damping2
      call galpha_mode(0.02_dp, 0.8_dp, ratio1, damping1)
      call galpha_mode(0.01_dp, 0.8_dp, ratio2, damping2)
      call report('rho_inf 0.8: period error ' // to_str(abs(ratio1 - 1.0_dp), 3) // ' -> ' // &
         to_str(abs(ratio2 - 1.0_dp), 3) // ', damping ' // to_str(damping1, 3) // ' -> ' // &
         to_str(damping2, 3))
      ! measured 2 - 6.8e-5 and 3 - 1.7e-4 (higher-order terms at w h = 0.02)
      call check_close(error, 'period error order', log(abs(ratio1 - 1.0_dp) / &
         abs(ratio2 - 1.0_dp)) / log(2.0_dp), 2.0_dp, atol=2.0e-3_dp)
      if (.not. allocated(error)) call check_close(error, 'damping order', &
         log(damping1 / damping2) / log(2.0_dp), 3.0_dp, atol=2.0e-3_dp)
   end subroutine test_galpha_orders

   !> A single harmonic F = cos(k theta / 2) (peak 1 at theta = 0): a mode's force error is
   !> mu |Re(H(r) - 1)| in closed form.
   subroutine test_mode_error(error)
      type(error_t), allocatable, intent(out) :: error
      type(excitation_t) :: excitation
      type(mode_effect_t) :: effect
      real(dp) :: theta(samples), r, zeta, expected
      integer :: i
      complex(dp) :: h
      h = exact_response(1.0_dp, 0.0_dp, 0.1_dp)
      call check_close(error, '|H(1)| with the floor 0.1', abs(h), 10.0_dp, rtol=1.0e-14_dp)
      if (allocated(error)) return
      theta = [(4.0_dp * pi * real(i - 1, dp) / samples, i=1, samples)]
      call single_harmonic(excitation, cos(6.0_dp * theta), theta)
      excitation%cycle_hz = 100.0_dp
      do i = 1, 3
         r = 0.3_dp * i
         zeta = 0.02_dp * i
         effect = mode_effect(excitation, 12.0_dp * 100.0_dp / r, 0.4_dp, zeta, 0.0_dp)
         zeta = max(zeta, 0.05_dp)
         expected = 0.4_dp * abs((1.0_dp - r**2) / ((1.0_dp - r**2)**2 + (2.0_dp * zeta * r)**2) &
            - 1.0_dp)
         call check_close(error, 'force error at r = ' // to_str(r), effect%force, expected, &
            rtol=1.0e-9_dp)
         if (allocated(error)) return
      end do
   end subroutine test_mode_error

   subroutine test_jointed_mass(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: shape(12, 1), loaded(1)
      real(dp), parameter :: m = 2.0_dp, big_m = 0.5_dp
      ! a point mass m at interface 2, mass-normalised: u = 1/sqrt(m) along y
      shape = 0.0_dp
      shape(8, 1) = 1.0_dp / sqrt(m)
      loaded = effective_frequencies([100.0_dp], shape, [3.0_dp, big_m])
      call check_close(error, 'f~', loaded(1), 100.0_dp / sqrt(1.0_dp + big_m / m), &
         rtol=1.0e-14_dp)
   end subroutine test_jointed_mass

   subroutine test_cosine_harmonics(error)
      type(error_t), allocatable, intent(out) :: error
      type(excitation_t) :: excitation
      real(dp) :: theta(samples)
      integer :: i
      theta = [(4.0_dp * pi * real(i - 1, dp) / samples, i=1, samples)]
      call single_harmonic(excitation, 3.0_dp * cos(5.0_dp * theta / 2.0_dp + 0.7_dp), theta)
      call check_close(error, 'F_5 real', real(excitation%force(5), dp), 3.0_dp * cos(0.7_dp), &
         atol=1.0e-12_dp)
      if (.not. allocated(error)) call check_close(error, 'F_5 imaginary', &
         aimag(excitation%force(5)), 3.0_dp * sin(0.7_dp), atol=1.0e-12_dp)
      if (.not. allocated(error)) call check_close(error, 'other harmonics', &
         maxval(abs(excitation%force([(i, i=1, 4), (i, i=6, NUM_HARMONICS)]))), 0.0_dp, &
         atol=1.0e-11_dp)
      if (.not. allocated(error)) call check_close(error, 'peak', excitation%peak_force, &
         3.0_dp, rtol=1.0e-5_dp)
   end subroutine test_cosine_harmonics

   !> mean(F L) = cycle work / (4 pi): the mean indicated torque by a second route.
   subroutine test_engine_torque(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: pressure
      type(pressure_input_t) :: input
      type(excitation_t) :: excitation
      real(dp) :: torque, reference
      call pressure%init(input, error)
      if (allocated(error)) return
      call engine_excitation(pressure, 0.45_dp, 3.6e-4_dp, excitation)
      torque = excitation%mean_force * excitation%mean_lever + 0.5_dp * &
         real(sum(excitation%force * conjg(excitation%lever)), dp)
      call report('regime speed ' // to_str(excitation%regime_speed, 6) // ' rad/s, T_i ' // &
         to_str(pressure%mean_indicated_torque(), 9) // ' N m, mean(F L) ' // to_str(torque, 9))
      ! 2880 samples of a pressure with a jump at 540 deg (blow-down, where the lever is ~0):
      ! measured 1.8e-7
      call check_close(error, 'mean(F L)', torque, pressure%mean_indicated_torque(), &
         rtol=2.0e-6_dp)
      if (allocated(error)) return
      ! regime speed sqrt(T_i / c) with T_i = W / (4 pi) from the cycle work integrated here
      ! (midpoint rule, 288000 points: O(dtheta^2) at the kinks of p); measured 4.6e-12
      reference = sqrt(cycle_work(pressure) / (4.0_dp * pi) / 3.6e-4_dp)
      call report('regime speed against the cycle work integrated here: relative difference ' &
         // to_str(abs(excitation%regime_speed / reference - 1.0_dp), 3))
      call check_close(error, 'regime speed', excitation%regime_speed, reference, rtol=5.0e-11_dp)
   end subroutine test_engine_torque

   !> W = closed integral of p dV = -A_p int_0^(4 pi) p(theta) y'(theta) dtheta, y = r cos(theta)
   !> + sqrt(l^2 - r^2 sin^2(theta)) (the piston from the crank axis; V = V_c + A_p (r + l - y)),
   !> midpoint rule on a fine grid: p jumps only where y' = 0 (BDC, TDC).
   function cycle_work(pressure) result(work)
      type(pressure_model_t), intent(in) :: pressure
      real(dp) :: work
      integer, parameter :: n = 288000
      real(dp) :: theta, r, l, dy
      integer :: i
      r = pressure%crank_radius
      l = pressure%input%conrod_length
      work = 0.0_dp
      do i = 1, n
         theta = 4.0_dp * pi * (real(i, dp) - 0.5_dp) / real(n, dp)
         dy = -r * sin(theta) - r**2 * sin(theta) * cos(theta) / sqrt(l**2 - (r * sin(theta))**2)
         work = work - pressure%area * pressure%pressure(theta) * dy
      end do
      work = work * 4.0_dp * pi / real(n, dp)
   end function cycle_work

   !> Five modes of one interface with shares set by their shapes: every dropped set fits the
   !> budget and dropping the smallest kept one as well would not.
   subroutine test_greedy_selection(error)
      type(error_t), allocatable, intent(out) :: error
      type(excitation_t) :: excitation
      type(body_selection_t) :: selection
      real(dp) :: theta(samples), shape(6, 5), budget, smallest_kept
      integer :: i
      theta = [(4.0_dp * pi * real(i - 1, dp) / samples, i=1, samples)]
      call single_harmonic(excitation, cos(20.0_dp * theta) + 0.3_dp * cos(3.0_dp * theta), &
         theta)
      excitation%cycle_hz = 50.0_dp
      excitation%mean_torque = 1.0_dp
      shape = 0.0_dp
      shape(2, :) = [0.8_dp, 0.5_dp, 0.3_dp, 0.6_dp, 0.1_dp]
      budget = 0.01_dp
      call select_modes(excitation, [900.0_dp, 2100.0_dp, 3500.0_dp, 5000.0_dp, 8000.0_dp], &
         shape, [1.0_dp], 0.0_dp, budget, 1.0_dp, selection)
      call report('force errors ' // to_str(selection%effect(1)%force, 3) // ' ' // &
         to_str(selection%effect(2)%force, 3) // ' ' // to_str(selection%effect(3)%force, 3) // &
         ' ' // to_str(selection%effect(4)%force, 3) // ' ' // &
         to_str(selection%effect(5)%force, 3) // '; kept ' // to_str(size(selection%kept)))
      call check(error, 'dropped within the budget', selection%truncation%force <= budget)
      if (allocated(error)) return
      call check(error, 'some modes kept, some dropped', size(selection%kept) > 0 .and. &
         size(selection%kept) < 5)
      if (allocated(error)) return
      smallest_kept = minval(selection%effect(selection%kept)%force)
      call check(error, 'no further mode fits', selection%truncation%force + smallest_kept > &
         budget)
      if (allocated(error)) return
      call check_close(error, 'dropped sum', selection%truncation%force, &
         sum(selection%effect%force) - sum(selection%effect(selection%kept)%force), &
         rtol=1.0e-12_dp)
   end subroutine test_greedy_selection

   !> The step choice against the step error computed here: the rigid chain's part from the
   !> reference scheme's free-mass response (reference_response), the mode's from its numerical
   !> frequency and damping (principal_root), the peak sampled half a step off. The chosen step
   !> must be the largest of the ladder (under the turn limit) within the budget by this error.
   subroutine test_step_choice(error)
      type(error_t), allocatable, intent(out) :: error
      type(excitation_t) :: excitation
      type(mode_effect_t) :: effect
      real(dp), parameter :: budget = 1.0e-3_dp
      real(dp) :: h, expected_h, expected_error
      integer :: decade, m
      call step_excitation(excitation)
      call select_time_step(excitation, [1500.0_dp], [mode_effect_t(0.01_dp, 0.0_dp, 0.0_dp)], &
         0.8_dp, budget, 1.0_dp, h, effect)
      expected_h = 0.0_dp
      search: do decade = -3, -7, -1
         do m = size(STEP_LADDER), 1, -1
            expected_h = STEP_LADDER(m) * 10.0_dp**decade
            if (expected_h * excitation%regime_speed > MAX_TURN_PER_STEP) cycle
            expected_error = reference_step_error(excitation, 1500.0_dp, 0.01_dp, expected_h)
            if (expected_error <= budget) exit search
         end do
      end do search
      call report('step ' // to_str(h, 3) // ' s, force error ' // to_str(effect%force, 3) // &
         ' (reference: ' // to_str(expected_h, 3) // ' s, relative difference ' // &
         to_str(abs(effect%force / expected_error - 1.0_dp), 3) // ')')
      call check_close(error, 'chosen step', h, expected_h, rtol=1.0e-12_dp)
      if (allocated(error)) return
      ! the same quantity by two routes (3x3 solve and eigenvalues against z-transform and
      ! Newton): measured 7.4e-15
      call check_close(error, 'force error at the chosen step', effect%force, expected_error, &
         rtol=1.0e-13_dp)
   end subroutine test_step_choice

   !> The step error (rigid chain and the mode) at h and h/2: ratio 4 for a second-order method
   !> once w h and the harmonics' W h are small (h = 1e-5 s: w h = 0.09 for the mode; measured
   !> 2 - 6.2e-5 and 2 - 1.2e-4).
   subroutine test_step_order(error)
      type(error_t), allocatable, intent(out) :: error
      type(excitation_t) :: excitation
      type(mode_effect_t) :: coarse, fine
      real(dp), parameter :: h = 1.0e-5_dp
      real(dp) :: order_rigid, order_mode
      call step_excitation(excitation)
      coarse = step_errors(excitation, [real(dp) ::], [mode_effect_t ::], h, 0.8_dp)
      fine = step_errors(excitation, [real(dp) ::], [mode_effect_t ::], 0.5_dp * h, 0.8_dp)
      order_rigid = log(coarse%force / fine%force) / log(2.0_dp)
      coarse = step_errors(excitation, [1500.0_dp], [mode_effect_t(0.01_dp, 0.0_dp, 0.0_dp)], &
         h, 0.8_dp)
      fine = step_errors(excitation, [1500.0_dp], [mode_effect_t(0.01_dp, 0.0_dp, 0.0_dp)], &
         0.5_dp * h, 0.8_dp)
      order_mode = log(coarse%force / fine%force) / log(2.0_dp)
      call report('orders of the step error: rigid chain 2 - ' // to_str(2.0_dp - order_rigid, &
         3) // ', with the mode 2 - ' // to_str(2.0_dp - order_mode, 3))
      call check_close(error, 'order, rigid chain', order_rigid, 2.0_dp, atol=1.0e-3_dp)
      if (.not. allocated(error)) call check_close(error, 'order with the mode', order_mode, &
         2.0_dp, atol=1.0e-3_dp)
   end subroutine test_step_order

   !> The excitation of the step tests: F = cos(theta) + 0.1 cos(20 theta), half of it inertia.
   subroutine step_excitation(excitation)
      type(excitation_t), intent(out) :: excitation
      real(dp) :: theta(samples)
      integer :: i
      theta = [(4.0_dp * pi * real(i - 1, dp) / samples, i=1, samples)]
      call single_harmonic(excitation, cos(theta) + 0.1_dp * cos(20.0_dp * theta), theta)
      excitation%inertia = 0.5_dp * excitation%force
      excitation%cycle_hz = 30.0_dp
      excitation%regime_speed = 4.0_dp * pi * 30.0_dp
      excitation%mean_torque = 1.0_dp
   end subroutine step_excitation

   !> Peak-force error at step h (rho_inf = 0.8) of the rigid chain plus one mode at mode_hz
   !> whose force error if dropped is mode_force: the inertia harmonics times (R - 1), R the
   !> reference free-mass response; the mode's error times its relative period error plus
   !> damping ratio; the peak read up to half a step of crank turn off (model_selection.f90,
   !> header 4).
   function reference_step_error(excitation, mode_hz, mode_force, h) result(force_error)
      type(excitation_t), intent(in) :: excitation
      real(dp), intent(in) :: mode_hz, mode_force, h
      real(dp) :: force_error, wh, angle
      complex(dp) :: total, root
      integer :: k
      total = (0.0_dp, 0.0_dp)
      do k = 1, size(excitation%force)
         total = total + excitation%inertia(k) * (reference_response(0.0_dp, 2.0_dp * pi * k * &
            excitation%cycle_hz, h, 0.8_dp) - 1.0_dp) * excitation%phase(k)
      end do
      force_error = abs(real(total, dp)) / excitation%peak_force
      wh = 2.0_dp * pi * mode_hz * h
      root = principal_root(wh, 0.8_dp)
      angle = atan2(aimag(root), real(root, dp))
      force_error = force_error + min(abs(angle / wh - 1.0_dp) - log(abs(root)) / angle, &
         1.0_dp) * mode_force
      force_error = force_error + 0.5_dp * excitation%peak_curvature * (0.5_dp * &
         excitation%regime_speed * h)**2
   end function reference_step_error

   !> rho_inf = 0.8 against the reference scheme: a free mass and an oscillator at 2 kHz forced
   !> at W h = 0.03 .. 0.6.
   subroutine test_galpha_forced(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-4_dp, w = 2.0_dp * pi * 2000.0_dp
      real(dp) :: big_omega, worst
      complex(dp) :: code, reference
      integer :: i, j
      worst = 0.0_dp
      do i = 1, 4
         big_omega = 2.0_dp * pi * 50.0_dp * 3.0_dp**(i - 1)
         do j = 1, 2
            code = galpha_response(merge(0.0_dp, w, j == 1), 0.0_dp, big_omega, h, 0.8_dp)
            reference = reference_response(merge(0.0_dp, w, j == 1), big_omega, h, 0.8_dp)
            worst = max(worst, abs(code - reference) / abs(reference))
            ! the same steady state by a 3x3 solve and by the z-transform: measured 4.8e-16
            call check_close(error, merge('free mass ', 'oscillator', j == 1) // ' at W h = ' // &
               to_str(big_omega * h) // ', |R - R_ref|', abs(code - reference), 0.0_dp, &
               atol=1.0e-14_dp * abs(reference))
            if (allocated(error)) return
         end do
      end do
      call report('rho_inf 0.8 forced responses: largest relative difference ' // &
         to_str(worst, 3))
   end subroutine test_galpha_forced

   !> galpha_mode's frequency ratio and damping at rho_inf = 0.8 give the principal root of the
   !> reference characteristic cubic.
   subroutine test_galpha_mode_roots(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: wh, ratio, damping, angle, worst_ratio, worst_damping
      complex(dp) :: root
      integer :: i
      worst_ratio = 0.0_dp
      worst_damping = 0.0_dp
      do i = 1, 5
         wh = 0.01_dp * 3.0_dp**(i - 1)
         call galpha_mode(wh, 0.8_dp, ratio, damping)
         root = principal_root(wh, 0.8_dp)
         angle = atan2(aimag(root), real(root, dp))
         worst_ratio = max(worst_ratio, abs(ratio - angle / wh))
         worst_damping = max(worst_damping, abs(damping + log(abs(root)) / angle))
         ! eigenvalues of the amplification matrix against Newton on the cubic: measured
         ! 5.7e-14 (ratio) and 3.3e-14 (damping)
         call check_close(error, 'frequency ratio at w h = ' // to_str(wh), ratio, angle / wh, &
            rtol=5.0e-13_dp)
         if (allocated(error)) return
         ! the damping ratio -ln|z| / arg z is O((w h)^3): compared in absolute terms
         call check_close(error, 'damping at w h = ' // to_str(wh), damping, &
            -log(abs(root)) / angle, atol=5.0e-13_dp)
         if (allocated(error)) return
      end do
      call report('rho_inf 0.8 against the cubic: frequency ratio ' // to_str(worst_ratio, 3) // &
         ', damping ' // to_str(worst_damping, 3))
   end subroutine test_galpha_mode_roots

   !> Steady state of generalized-alpha on x'' + w^2 x = w^2 e^(i W t) (w > 0; on x'' = e^(i W t)
   !> for w = 0, as a multiple of the exact -1/W^2) by the z-transform, z = e^(i W h):
   !>   Newmark: X = h^2 q(z) A,
   !>   q = ((1 - gamma) + gamma z)/(z - 1)^2 + ((1/2 - beta) + beta z)/(z - 1);
   !>   balance: A ((1 - am) z + am) = w^2 ((1 - af) z + af) (1 - X)   (free mass: A M = F).
   pure function reference_response(w, big_omega, h, rho) result(response)
      real(dp), intent(in) :: w, big_omega, h, rho
      complex(dp) :: response, z, q, f_part, m_part, a
      real(dp) :: am, af, gamma, beta
      call galpha_parameters(rho, am, af, gamma, beta)
      z = cmplx(cos(big_omega * h), sin(big_omega * h), dp)
      q = ((1.0_dp - gamma) + gamma * z) / (z - 1.0_dp)**2 + ((0.5_dp - beta) + beta * z) / &
         (z - 1.0_dp)
      f_part = (1.0_dp - af) * z + af
      m_part = (1.0_dp - am) * z + am
      if (w > 0.0_dp) then
         a = w**2 * f_part / (m_part + w**2 * h**2 * q * f_part)
         response = h**2 * q * a
      else
         response = -big_omega**2 * h**2 * q * f_part / m_part
      end if
   end function reference_response

   !> Principal root of the characteristic cubic of generalized-alpha on x'' + w^2 x = 0 (the
   !> free solutions z^n of the balance above; ffrf_test_galpha_reference), by Newton from
   !> e^(i w h).
   pure function principal_root(wh, rho) result(z)
      real(dp), intent(in) :: wh, rho
      complex(dp) :: z
      real(dp) :: c(0:3)
      integer :: iteration
      c = galpha_characteristic(rho, wh)
      z = cmplx(cos(wh), sin(wh), dp)
      do iteration = 1, 50
         z = z - (((c(3) * z + c(2)) * z + c(1)) * z + c(0)) / &
            ((3.0_dp * c(3) * z + 2.0_dp * c(2)) * z + c(1))
      end do
   end function principal_root

   !> An excitation whose F (and lever) is the sampled signal.
   subroutine single_harmonic(excitation, force, theta)
      type(excitation_t), intent(out) :: excitation
      real(dp), intent(in) :: force(:), theta(:)
      call set_harmonics(excitation, force, 0.0_dp * force, sin(theta))
   end subroutine single_harmonic

end module test_sim_model_selection

program main_sim_model_selection
   use ffrf_testing, only: unittest_t, run_suite
   use test_sim_model_selection, only: collect_sim_model_selection
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_sim_model_selection(tests)
   call run_suite('sim_model_selection', tests)
end program main_sim_model_selection
