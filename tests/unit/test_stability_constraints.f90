!> rho_inf -> 1 with index-3 constraints (issue 4, part 2): ffrf's generalized-alpha
!> (ffrf_mbs_generalized_alpha) refuses rho_inf = 1 for a constrained system; what happens close to
!> 1 is measured on the Cartesian pendulum (x, y, rod length by a multiplier) and on the rigid
!> reference engine of scene.md (the builder of test_mbs_engine_convergence, copied: crank and
!> flywheel as one rigid body, conrod, piston; two main bearings, crank pin, piston pin, cylinder;
!> pressure, starter and load; started at rest at TDC).
!>
!> Theory (theory.md 4.1, 4.3): in a constrained direction the "stiffness" is infinite, and there
!> the three roots of generalized-alpha sit at -rho_inf (the limit Omega -> infinity of
!> test_stability_integrator). Whatever perturbs the multipliers from step to step (the start,
!> the Newton tolerance, the forcing) leaves a component that alternates in sign and decays like
!> n^2 rho_inf^n; a unit impulse peaks at about 0.27 / (1 - rho_inf)^2 after 2 / (1 - rho_inf)
!> steps. At rho_inf = 1 nothing decays (Cardona & Geradin 1989: weak instability).
!>
!> The alternating part of a multiplier history is measured by the fourth difference
!> (lambda_{n+2} - 4 lambda_{n+1} + 6 lambda_n - 4 lambda_{n-1} + lambda_{n-2}) / 16, the
!> amplitude of a (-1)^n component, which removes a smooth part up to h^4 d4lambda/dt4; the
!> second difference of the issue, |lambda_{n+1} - 2 lambda_n + lambda_{n-1}|, is reported too,
!> but at these steps it is dominated by the smooth h^2 d2lambda/dt2.
module test_stability_constraints
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_dae_system, only: dae_system_t
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_test_rigid_engine, only: build_engine
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_stability_constraints

   !> Pendulum: gravity (m/s^2), rod length (m), mass (kg), initial angle (rad, at rest)
   real(dp), parameter :: gravity = 9.81_dp, rod = 1.0_dp, bob = 1.0_dp, theta0 = 1.0_dp

   !> Point mass on a massless rod in Cartesian coordinates (x, y), index 3:
   !> Phi = (x^2 + y^2 - L^2)/2; records the multiplier of every accepted state.
   type, extends(dae_system_t) :: pendulum_t
      !> Multipliers of the accepted states, 1..count (N/m: the force is lambda (x, y))
      real(dp), allocatable :: lambda(:)
      integer :: count = 0
   contains
      procedure :: num_coordinates => pendulum_n
      procedure :: num_constraints => pendulum_nc
      procedure :: mass => pendulum_mass
      procedure :: force => pendulum_force
      procedure :: constraints => pendulum_phi
      procedure :: constraint_jacobian => pendulum_jac
      procedure :: accepted_step => pendulum_hook
   end type pendulum_t

contains

   !> The suite.
   subroutine collect_stability_constraints(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('rho_inf_1_refused_on_the_engine', test_refusal), &
         new_unittest('pendulum_multipliers_vs_rho_inf', test_pendulum_fine), &
         new_unittest('pendulum_coarse_step_instability_stopped', test_pendulum_coarse), &
         new_unittest('engine_multipliers_vs_rho_inf', test_engine)]
   end subroutine collect_stability_constraints

   !> rho_inf = 1 on the engine (28 constraint equations: 5 joints x 5 rows and 3 Euler rows):
   !> galpha_init refuses it with FFRF_INPUT_ERROR and a message that names the value, the reason
   !> and the fix ("rho_inf = 1 (no numerical damping) is unstable with index-3 constraints (28
   !> constraint equations here): ... use rho_inf < 1, typically 0.6 to 0.9"), keeping no
   !> state; the same settings with rho_inf = 0.8 start. (rho_inf = 1 - 1e-12 is accepted: only
   !> the value 1 is refused, see test_pendulum_coarse.)
   subroutine test_refusal(error)
      type(error_t), allocatable, intent(out) :: error
      type(mechanism_t) :: mech
      type(galpha_integrator_t) :: integ
      type(galpha_settings_t) :: settings
      type(error_t), allocatable :: failure
      real(dp) :: q(21), v(21)
      call build_engine(mech, q, v, error)
      if (allocated(error)) return
      settings%h = 1.0e-4_dp
      settings%t_end = 0.1_dp
      settings%rho_inf = 1.0_dp
      call integ%init(mech, settings, q, v, failure)
      call check(error, 'rho_inf = 1 with constraints is refused', allocated(failure))
      if (allocated(error)) return
      call report('refusal: ' // failure%message)
      call check(error, 'FFRF_INPUT_ERROR naming rho_inf = 1, index-3, the 28 constraint ' // &
         'equations and the fix rho_inf < 1: ' // failure%message, &
         failure%code == FFRF_INPUT_ERROR .and. index(failure%message, 'rho_inf = 1') > 0 .and. &
         index(failure%message, 'index-3') > 0 .and. &
         index(failure%message, '28 constraint equations') > 0 .and. &
         index(failure%message, 'use rho_inf < 1') > 0)
      if (allocated(error)) return
      call check(error, 'no state after the refusal', .not. allocated(integ%q))
      if (allocated(error)) return
      settings%rho_inf = 0.8_dp
      call integ%init(mech, settings, q, v, error)
   end subroutine test_refusal

   !> The pendulum (1 m, 1 kg, released at theta0 = 1 rad) over 10 s with h = 1e-3 s and the
   !> default Newton tolerances, rho_inf = 0.8, 0.9, 0.95, 0.99. Reference: the largest
   !> multiplier m g (3 - 2 cos theta0) / L = 18.8293 N/m at the bottom (energy). Measured
   !> alternating part over the second half, relative to max |lambda|: 5.4e-7, 1.3e-6, 3.9e-6,
   !> 9.0e-5 (second difference 1.6e-5 .. 3.7e-4, mostly h^2 d2lambda/dt2). It is fed by the
   !> Newton tolerance (with rtol 1e-12 it drops to 7e-9 .. 2.8e-7) and grows like
   !> (1 - rho_inf)^-2 between 0.9 and 0.99 (70x; the impulse response of the triple root
   !> predicts 100x), less below. Asserted: it grows strictly with rho_inf; at 0.8 it stays below
   !> 1e-6 (smooth: 5.4e-7 of 19 N/m); at 0.99 it is at least 30 times that of 0.8 (measured
   !> 166x); max |lambda| of every run within 1e-4 of the closed form (measured 3e-7 .. 7.4e-5,
   !> the last one the alternation).
   subroutine test_pendulum_fine(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: rhos(4) = [0.8_dp, 0.9_dp, 0.95_dp, 0.99_dp]
      type(error_t), allocatable :: failure
      real(dp) :: alternating(4), second, lambda_max, closed
      integer :: i
      closed = bob * gravity * (3.0_dp - 2.0_dp * cos(theta0)) / rod
      do i = 1, size(rhos)
         call pendulum_run(rhos(i), 1.0e-3_dp, lambda_max, alternating(i), second, failure)
         if (allocated(failure)) then
            call move_alloc(failure, error)
            return
         end if
         call report('h = 1e-3 s, rho_inf = ' // to_str(rhos(i)) // ': max lambda ' // &
            to_str(lambda_max, 8) // ' (closed form ' // to_str(closed, 8) // &
            '), alternating part ' // to_str(alternating(i), 3) // ', second difference ' // &
            to_str(second, 3) // ' of max |lambda|')
         call check_close(error, 'rho_inf = ' // to_str(rhos(i)) // ': max lambda (N/m)', &
            lambda_max, closed, rtol=1.0e-4_dp)
         if (allocated(error)) return
      end do
      call check_alternation_trend(error, rhos, alternating, 30.0_dp)
   end subroutine test_pendulum_fine

   !> The same pendulum with h = 1e-2 s (Omega = 0.03 for its ~3 rad/s swing: well resolved):
   !> - rho_inf = 0.8: max |lambda| within 1e-4 of the closed form 18.8293 (measured 18.8294);
   !> - rho_inf = 0.99 and 0.999: the weak instability of index-3 generalized-alpha near
   !>   rho_inf = 1 grows the multiplier as a step-to-step alternation (before the check in
   !>   ffrf_mbs_generalized_alpha, 0.99 completed WITHOUT an error with max |lambda| = 2.7e4,
   !>   1400 x the closed form, and 0.999 reached 6.6e18 before Newton failed at 8.19 s with a
   !>   message that did not name the cause). Now the run stops with FFRF_NUMERIC_ERROR naming
   !>   rho_inf as soon as the alternating part exceeds alternation_limit (0.25) of the largest
   !>   |lambda|. Asserted: the error, its message (alternation, rho_inf), and that the stop comes
   !>   before the multipliers are garbage: max |lambda| at the stop below 1.5 x the closed form
   !>   (measured 1.17 x and 1.16 x: an alternation of 0.25 of |lambda| held for 20 steps adds at
   !>   most that to the smooth multiplier, so 1.5 x leaves room for its growth over the window).
   subroutine test_pendulum_coarse(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: failure
      real(dp), parameter :: rhos(2) = [0.99_dp, 0.999_dp]
      real(dp) :: alternating, second, lambda_max, closed
      integer :: i
      closed = bob * gravity * (3.0_dp - 2.0_dp * cos(theta0)) / rod
      call pendulum_run(0.8_dp, 1.0e-2_dp, lambda_max, alternating, second, failure)
      if (allocated(failure)) then
         call move_alloc(failure, error)
         return
      end if
      call report('h = 1e-2 s, rho_inf = 0.8: max lambda ' // to_str(lambda_max, 8) // &
         ', alternating part ' // to_str(alternating, 3))
      call check_close(error, 'h = 1e-2 s, rho_inf = 0.8: max lambda (N/m)', lambda_max, &
         closed, rtol=1.0e-4_dp)
      if (allocated(error)) return
      do i = 1, size(rhos)
         call pendulum_run(rhos(i), 1.0e-2_dp, lambda_max, alternating, second, failure)
         call check(error, 'h = 1e-2 s, rho_inf = ' // to_str(rhos(i)) // &
            ' stops with an error', allocated(failure))
         if (allocated(error)) return
         call report('h = 1e-2 s, rho_inf = ' // to_str(rhos(i)) // ': max lambda ' // &
            to_str(lambda_max, 6) // ' (closed form ' // to_str(closed, 6) // ') at the stop: ' &
            // failure%message)
         call check(error, 'FFRF_NUMERIC_ERROR naming the alternation and rho_inf: ' // &
            failure%message, failure%code == FFRF_NUMERIC_ERROR .and. &
            index(failure%message, 'alternate') > 0 .and. index(failure%message, 'rho_inf') > 0)
         if (allocated(error)) return
         call check(error, 'stopped before garbage: max lambda ' // to_str(lambda_max, 6) // &
            ' < 1.5 x ' // to_str(closed, 6), lambda_max < 1.5_dp * closed)
         if (allocated(error)) return
      end do
   end subroutine test_pendulum_coarse

   !> Pendulum from theta0 at rest, 10 s with step h: the largest multiplier, and the largest
   !> alternating part and second difference of lambda over the second half of the accepted
   !> states, relative to max |lambda|. `failure` if the run stops (the figures then cover the
   !> states before).
   subroutine pendulum_run(rho_inf, h, lambda_max, alternating, second, failure)
      real(dp), intent(in) :: rho_inf, h
      real(dp), intent(out) :: lambda_max, alternating, second
      type(error_t), allocatable, intent(out) :: failure
      type(error_t), allocatable :: stopped
      type(pendulum_t) :: pend
      type(galpha_settings_t) :: settings
      type(galpha_integrator_t) :: integ
      settings%h = h
      settings%t_end = 10.0_dp
      settings%rho_inf = rho_inf
      allocate (pend%lambda(nint(settings%t_end / h) + 1000))
      lambda_max = 0.0_dp
      alternating = 0.0_dp
      second = 0.0_dp
      call integ%init(pend, settings, [rod * sin(theta0), -rod * cos(theta0)], [0.0_dp, 0.0_dp], &
         failure)
      if (allocated(failure)) return
      call integ%run(pend, stopped)
      lambda_max = maxval(abs(pend%lambda(1:pend%count)))
      call oscillation(pend%lambda(1:pend%count), pend%count / 2, pend%count, alternating, second)
      alternating = alternating / lambda_max
      second = second / lambda_max
      if (allocated(stopped)) call move_alloc(stopped, failure)
   end subroutine pendulum_run

   !> Largest |fourth difference| / 16 (alternating part) and |second difference| of the series
   !> x over the centres first .. last (clipped to the valid range).
   pure subroutine oscillation(x, first, last, alternating, second)
      real(dp), intent(in) :: x(:)
      integer, intent(in) :: first, last
      real(dp), intent(out) :: alternating, second
      integer :: n
      alternating = 0.0_dp
      second = 0.0_dp
      do n = max(first, 3), min(last, size(x) - 2)
         alternating = max(alternating, abs(x(n + 2) - 4.0_dp * x(n + 1) + 6.0_dp * x(n) - &
            4.0_dp * x(n - 1) + x(n - 2)) / 16.0_dp)
         second = max(second, abs(x(n + 1) - 2.0_dp * x(n) + x(n - 1)))
      end do
   end subroutine oscillation

   !> The rigid engine from rest, h = 1e-4 s (the reference step), 1000 steps (0.1 s: intake and
   !> early compression, smooth forcing), default Newton tolerances, rho_inf = 0.8, 0.9, 0.99,
   !> 0.999. Per multiplier row (rows with max |lambda_j| >= 1e-3 of the largest; the dropped
   !> redundant rows carry 0) the alternating part over steps 100 .. 800, relative to
   !> max_n |lambda_j| (the start-up transient of the first steps, 5e-6 for every rho_inf, and
   !> the kink of the pressure table at 180 deg near step 850, 1.4e-6, are outside the window).
   !> Measured: 1.4e-7, 5.3e-7, 1.05e-5, 1.45e-5 (second difference 4.3e-5 .. 7.8e-5, mostly
   !> h^2 d2lambda/dt2); with Newton rtol 1e-12: 6.7e-9, 1.9e-8, 7.8e-7, 5.3e-6, so the source is
   !> again the per-step tolerance, amplified as rho_inf -> 1; at 0.999 the response time
   !> 2 / (1 - rho_inf) = 2000 steps exceeds the window, so the growth saturates. The motion is
   !> not disturbed: the crank angles at 0.1 s differ from rho_inf = 0.8 by at most 7.3e-7 rad,
   !> rho_inf entering only the constant of the O(h^2) error (4.5e-5 rad at this step and 0.15 s,
   !> from the step halving of test_mbs_engine_convergence). Asserted: strictly growing with
   !> rho_inf; 0.8 below 1e-6 (the Newton rtol 1e-8 times the impulse peak 0.27/0.2^2 = 6.8
   !> gives 7e-8); 0.999 at least 10 x 0.8 (measured 100x); every one below 1e-4 (bounded: at
   !> the reference step the engine stays stable close to rho_inf = 1, unlike the pendulum at
   !> h = 1e-2 s); crank angles within 1e-5 rad of rho_inf = 0.8.
   subroutine test_engine(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: rhos(4) = [0.8_dp, 0.9_dp, 0.99_dp, 0.999_dp]
      integer, parameter :: steps = 1000
      type(mechanism_t) :: mech
      type(galpha_integrator_t) :: integ
      type(galpha_settings_t) :: settings
      real(dp) :: q(21), v(21), alternating(4), angle(4), second, a, s, row_max
      real(dp), allocatable :: lambda(:, :)
      integer :: i, j, n
      do i = 1, size(rhos)
         call build_engine(mech, q, v, error)
         if (allocated(error)) return
         settings%h = 1.0e-4_dp
         settings%t_end = (steps + 10) * settings%h
         settings%rho_inf = rhos(i)
         call integ%init(mech, settings, q, v, error)
         if (allocated(error)) return
         if (allocated(lambda)) deallocate (lambda)
         allocate (lambda(size(integ%lambda), 0:steps))
         lambda(:, 0) = integ%lambda
         do n = 1, steps
            call integ%step(mech, error)
            if (allocated(error)) return
            lambda(:, n) = integ%lambda
         end do
         angle(i) = mech%rotor_angle(integ%q)
         alternating(i) = 0.0_dp
         second = 0.0_dp
         do j = 1, size(lambda, 1)
            row_max = maxval(abs(lambda(j, :)))
            if (row_max < 1.0e-3_dp * maxval(abs(lambda))) cycle
            ! series index n + 1 holds step n
            call oscillation(lambda(j, :), 101, 801, a, s)
            alternating(i) = max(alternating(i), a / row_max)
            second = max(second, s / row_max)
         end do
         call report('engine, h = 1e-4 s, rho_inf = ' // to_str(rhos(i)) // &
            ': alternating part ' // to_str(alternating(i), 3) // ', second difference ' // &
            to_str(second, 3) // ' of max |lambda_j|; crank angle ' // to_str(angle(i), 12) // &
            ' rad, ' // to_str(int(integ%stats%rejected_steps)) // ' rejected attempts')
         call check_close(error, 'rho_inf = ' // to_str(rhos(i)) // ': crank angle at 0.1 s ' // &
            'vs rho_inf = 0.8 (rad)', angle(i), angle(1), atol=1.0e-5_dp)
         if (allocated(error)) return
         call check_close(error, 'rho_inf = ' // to_str(rhos(i)) // ': alternating part', &
            alternating(i), 0.0_dp, atol=1.0e-4_dp)
         if (allocated(error)) return
      end do
      call check_alternation_trend(error, rhos, alternating, 10.0_dp)
   end subroutine test_engine

   !> The alternating parts of runs at increasing rho_inf (rhos(1) = 0.8): strictly growing, the
   !> first below 1e-6 (smooth), the last at least `ratio` times the first.
   subroutine check_alternation_trend(error, rhos, alternating, ratio)
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in) :: rhos(:), alternating(:), ratio
      integer :: i, last
      last = size(rhos)
      do i = 2, last
         call check(error, 'alternating part grows with rho_inf: ' // &
            to_str(alternating(i), 3) // ' at ' // to_str(rhos(i)) // ' vs ' // &
            to_str(alternating(i - 1), 3) // ' at ' // to_str(rhos(i - 1)), &
            alternating(i) > alternating(i - 1))
         if (allocated(error)) return
      end do
      call check_close(error, 'rho_inf = ' // to_str(rhos(1)) // ': alternating part', &
         alternating(1), 0.0_dp, atol=1.0e-6_dp)
      if (allocated(error)) return
      call check(error, 'rho_inf = ' // to_str(rhos(last)) // ': alternating part ' // &
         to_str(alternating(last), 3) // ' at least ' // to_str(ratio) // ' x that of ' // &
         to_str(rhos(1)) // ' (' // to_str(alternating(1), 3) // ')', &
         alternating(last) >= ratio * alternating(1))
   end subroutine check_alternation_trend

   ! ----------------------------------------------------------------------------------------------
   ! Pendulum

   integer function pendulum_n(self)
      class(pendulum_t), intent(in) :: self
      pendulum_n = 2 + 0 * self%count
   end function pendulum_n

   integer function pendulum_nc(self)
      class(pendulum_t), intent(in) :: self
      pendulum_nc = 1 + 0 * self%count
   end function pendulum_nc

   subroutine pendulum_mass(self, q, M, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(out) :: M(:, :)
      type(error_t), allocatable, intent(out) :: error
      M = reshape([bob, 0.0_dp, 0.0_dp, bob], [2, 2]) + 0.0_dp * (q(1) + self%count)
   end subroutine pendulum_mass

   subroutine pendulum_force(self, q, v, t, f, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: f(:)
      type(error_t), allocatable, intent(out) :: error
      f = [0.0_dp, -bob * gravity] + 0.0_dp * (q + v + t + self%count)
   end subroutine pendulum_force

   subroutine pendulum_phi(self, q, t, phi, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      phi(1) = 0.5_dp * (q(1)**2 + q(2)**2 - rod**2) + 0.0_dp * (t + self%count)
   end subroutine pendulum_phi

   subroutine pendulum_jac(self, q, t, Phi_q, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: Phi_q(:, :)
      type(error_t), allocatable, intent(out) :: error
      Phi_q(1, :) = q + 0.0_dp * (t + self%count)
   end subroutine pendulum_jac

   !> Records lambda of every accepted state (and of the start).
   subroutine pendulum_hook(self, t, q, v, qdd, lambda, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: t, q(:), v(:), qdd(:), lambda(:)
      type(error_t), allocatable, intent(out) :: error
      if (self%count >= size(self%lambda)) return
      self%count = self%count + 1
      self%lambda(self%count) = lambda(1) + 0.0_dp * (t + sum(q) + sum(v) + sum(qdd))
   end subroutine pendulum_hook

end module test_stability_constraints

program main_stability_constraints
   use ffrf_testing, only: unittest_t, run_suite
   use test_stability_constraints, only: collect_stability_constraints
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_stability_constraints(tests)
   call run_suite('stability_constraints', tests)
end program main_stability_constraints
