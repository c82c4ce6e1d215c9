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
!> - the greedy mode selection drops as many modes as the budget allows, and the chosen step is the
!>   largest of the ladder within its budget.
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
         new_unittest('forced_response_and_mode_error', test_mode_error), &
         new_unittest('jointed_mass_frequency', test_jointed_mass), &
         new_unittest('harmonics_of_a_cosine', test_cosine_harmonics), &
         new_unittest('engine_mean_torque', test_engine_torque), &
         new_unittest('greedy_mode_selection', test_greedy_selection), &
         new_unittest('largest_step_within_budget', test_step_choice)]
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
      call check_close(error, 'period error order', log(abs(ratio1 - 1.0_dp) / &
         abs(ratio2 - 1.0_dp)) / log(2.0_dp), 2.0_dp, atol=0.02_dp)
      if (.not. allocated(error)) call check_close(error, 'damping order', &
         log(damping1 / damping2) / log(2.0_dp), 3.0_dp, atol=0.02_dp)
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
      real(dp) :: torque
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
         rtol=1.0e-5_dp)
      if (.not. allocated(error)) call check_close(error, 'regime speed', &
         excitation%regime_speed, sqrt(pressure%mean_indicated_torque() / 3.6e-4_dp), &
         rtol=1.0e-14_dp)
   end subroutine test_engine_torque

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

   subroutine test_step_choice(error)
      type(error_t), allocatable, intent(out) :: error
      type(excitation_t) :: excitation
      type(mode_effect_t) :: effect, larger
      real(dp) :: theta(samples), h, next
      integer :: i
      theta = [(4.0_dp * pi * real(i - 1, dp) / samples, i=1, samples)]
      call single_harmonic(excitation, cos(theta) + 0.1_dp * cos(20.0_dp * theta), theta)
      excitation%inertia = 0.5_dp * excitation%force
      excitation%cycle_hz = 30.0_dp
      excitation%regime_speed = 4.0_dp * pi * 30.0_dp
      excitation%mean_torque = 1.0_dp
      call select_time_step(excitation, [1500.0_dp], [mode_effect_t(0.01_dp, 0.0_dp, 0.0_dp)], &
         0.8_dp, 1.0e-3_dp, 1.0_dp, h, effect)
      call report('step ' // to_str(h, 3) // ' s, force error ' // to_str(effect%force, 3))
      call check(error, 'within the budget', effect%force <= 1.0e-3_dp)
      if (allocated(error)) return
      ! the next step of the ladder exceeds the budget or the turn limit
      i = minloc(abs(STEP_LADDER - h / 10.0_dp**floor(log10(h) + 1.0e-9_dp)), dim=1)
      if (i < size(STEP_LADDER)) then
         next = STEP_LADDER(i + 1) * 10.0_dp**floor(log10(h) + 1.0e-9_dp)
      else
         next = 10.0_dp**(floor(log10(h) + 1.0e-9_dp) + 1)
      end if
      larger = step_errors(excitation, [1500.0_dp], [mode_effect_t(0.01_dp, 0.0_dp, 0.0_dp)], &
         next, 0.8_dp)
      call check(error, 'the next step ' // to_str(next) // ' s is out', larger%force > &
         1.0e-3_dp .or. next * excitation%regime_speed > MAX_TURN_PER_STEP)
   end subroutine test_step_choice

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
