!> The rigid reference engine of scene.md (test_mbs_mechanism's builder, crank and flywheel as one
!> rigid body): observed order of convergence in time of the generalized-alpha solution, and the
!> regime speed against the closed-form energy balance of the pressure model and the load torque.
!> Bodies, joints and loads as test_mbs_mechanism's test_engine_start (inertias of the crank and
!> conrod from box and cylinder models of the scene geometry, documented there); started at rest
!> at crank angle 0 (TDC) from the exact closed-form pose.
module test_mbs_engine_convergence
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_app_engine_pressure_load, only: pressure_force_t
   use ffrf_test_rigid_engine, only: build_engine, crank_properties, crank_radius, rod_length, &
      load_coefficient, crank_pin, piston_pin
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t, galpha_stats_t
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_mbs_engine_convergence

   !> Statistics of one 720 deg cycle of the regime run.
   type :: cycle_t
      !> Cycle number k: crank angle from 4 pi (k - 1) to 4 pi k
      integer :: number = 0
      !> Times of the cycle boundaries (s)
      real(dp) :: t0 = 0.0_dp, t1 = 0.0_dp
      !> Crank-angle mean of omega^2 ((rad/s)^2)
      real(dp) :: w2_angle = 0.0_dp
      !> Time mean int omega dt / (t1 - t0) of the integrator's omega (rad/s), variance and third
      !> central moment over time of omega
      real(dp) :: mean = 0.0_dp, variance = 0.0_dp, third = 0.0_dp
      !> Largest and smallest omega (rad/s)
      real(dp) :: w_max = 0.0_dp, w_min = 0.0_dp
      !> Kinetic energy at the end minus at the start (J)
      real(dp) :: delta_energy = 0.0_dp
      !> Integral of omega over the cycle (rad), 4 pi up to the interpolation
      real(dp) :: angle = 0.0_dp
   end type cycle_t

   !> History of a regime run, one entry per accepted step, 0:n.
   type :: history_t
      !> Number of accepted steps
      integer :: n = 0
      !> Time (s), unwrapped crank angle (rad), crank speed (rad/s) and acceleration (rad/s^2),
      !> kinetic energy (J), power of the loads (W)
      real(dp), allocatable :: t(:), phi(:), w(:), wdot(:), energy(:), power(:)
   end type history_t

contains

   !> The suite.
   subroutine collect_mbs_engine_convergence(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('observed_order_in_time', test_order), &
         new_unittest('regime_speed_energy_balance', test_regime)]
   end subroutine collect_mbs_engine_convergence

   !> Settings of the runs: rho_inf = 0.8 and Newton tolerances well below the differences
   !> measured between steps.
   function tight_settings(h, t_end) result(settings)
      real(dp), intent(in) :: h, t_end
      type(galpha_settings_t) :: settings
      settings%h = h
      settings%t_end = t_end
      settings%rho_inf = 0.8_dp
      settings%newton_atol = 1.0e-13_dp
      settings%newton_rtol = 1.0e-12_dp
      settings%lambda_atol = 1.0e-9_dp
      settings%force_atol = 1.0e-9_dp
   end function tight_settings

   ! ----------------------------------------------------------------------------------------------
   ! Tests

   !> Observed order of convergence in time (issue 3: "observed order of convergence in time of
   !> the engine's crank angle and of the Lagrange multipliers in [1.8, 2.2] under step halving").
   !> The rigid engine from rest (starter, pressure, load) to t_end = 0.15 s with h = 4e-4, 2e-4
   !> and 1e-4 s, rho_inf = 0.8, Newton tolerances 1e-13 (positions) and 1e-12 relative, far
   !> below the differences. Reference: generalized-alpha is second order (Chung & Hulbert 1993;
   !> for index-3 constraints, Arnold & Bruls 2007), p = log2(|x_h - x_h/2| / |x_h/2 - x_h/4|).
   !> - Interval: at 0.15 s the crank has turned 8.64 rad = 495 deg: intake, compression, firing
   !>   (Wiebe 350..410 deg, 55 bar peak; piston pin force 4.3 kN at t_end) and most of the
   !>   expansion, but not the blow-down at 540 deg. On [0, 540) deg the pressure is C1 in the
   !>   crank angle (Hermite table; at 180 deg dV/dtheta = 0 joins the intake and closed parts
   !>   with matching slopes); the starter torque 40 (1 - omega/157) N m reaches 0 at 157 rad/s
   !>   inside the interval and stays 0 (a kink, the torque is continuous, so the acceleration is
   !>   too and the local error stays O(h^3)); the switch-off at 0.5 s is outside. Measured when
   !>   choosing the interval (not run here): to 0.2 s, through the 540 deg pressure jump, the
   !>   orders from the same steps are 1.85..1.88, and 2.04 one level finer: the jump falls at a
   !>   different place inside a step for each h and adds an O(h^2) error with an erratic
   !>   constant; to 0.1 s (intake and early compression only) they are 2.000 and 1.999.
   !> - Multipliers: the dropped redundant rows carry lambda = 0 by the integrator's split, so
   !>   the compared quantities are physically unique: the in-plane (x, y) force of the piston pin
   !>   on the piston and of the crank pin on the conrod (mechanism%reaction; planar equilibrium
   !>   of conrod and piston determines them), differences as vector norms. The O(h) start-up
   !>   error of generalized-alpha in accelerations and multipliers decays like 0.5**n (spurious
   !>   root alpha_m/(1 - alpha_m) at rho_inf = 0.8) and is gone after the 375 steps of the
   !>   coarsest run.
   !> Measured: differences 5.4e-4 / 1.34e-4 rad (angle), 1.0 / 0.25 N (piston pin); orders
   !> 2.005 (crank angle), 2.006 (piston pin), 2.002 (crank pin), 2.004 (speed, reported).
   !> Asserted: each order within 0.05 of 2 (about 10 times the measured deviations; the issue's
   !> band was [1.8, 2.2]).
   subroutine test_order(error)
      type(error_t), allocatable, intent(out) :: error
      integer, parameter :: levels = 3
      real(dp), parameter :: t_end = 0.15_dp, h_coarse = 4.0e-4_dp
      real(dp) :: angle(levels), speed(levels), pin(2, levels), crankpin(2, levels), h
      real(dp), allocatable :: lambda(:, :)
      real(dp) :: p_angle, p_speed, p_pin, p_crank, p_lambda
      integer :: k, rejected
      h = h_coarse
      do k = 1, levels
         call run_short(h, t_end, angle(k), speed(k), pin(:, k), crankpin(:, k), lambda, &
            rejected, error)
         if (allocated(error)) return
         call report('h = ' // to_str(h, 4) // ' s: crank angle ' // to_str(angle(k), 14) // &
            ' rad, speed ' // to_str(speed(k), 12) // ' rad/s, piston pin (' // &
            to_str(pin(1, k), 10) // ', ' // to_str(pin(2, k), 10) // ') N, crank pin (' // &
            to_str(crankpin(1, k), 10) // ', ' // to_str(crankpin(2, k), 10) // ') N; ' // &
            to_str(rejected) // ' rejected attempts')
         h = 0.5_dp * h
      end do
      p_angle = order(abs(angle(1) - angle(2)), abs(angle(2) - angle(3)))
      p_speed = order(abs(speed(1) - speed(2)), abs(speed(2) - speed(3)))
      p_pin = order(norm2(pin(:, 1) - pin(:, 2)), norm2(pin(:, 2) - pin(:, 3)))
      p_crank = order(norm2(crankpin(:, 1) - crankpin(:, 2)), norm2(crankpin(:, 2) - &
         crankpin(:, 3)))
      p_lambda = order(norm2(lambda(:, 1) - lambda(:, 2)), norm2(lambda(:, 2) - lambda(:, 3)))
      call report('observed orders: crank angle ' // to_str(p_angle, 4) // ', crank speed ' // &
         to_str(p_speed, 4) // ', piston pin force ' // to_str(p_pin, 4) // &
         ', crank pin force ' // to_str(p_crank, 4) // ', all multipliers (kept rows) ' // &
         to_str(p_lambda, 4))
      call check_close(error, 'observed order of the crank angle', p_angle, 2.0_dp, &
         atol=0.05_dp)
      if (allocated(error)) return
      call check_close(error, 'observed order of the piston pin force', p_pin, 2.0_dp, &
         atol=0.05_dp)
      if (allocated(error)) return
      call check_close(error, 'observed order of the crank pin force', p_crank, 2.0_dp, &
         atol=0.05_dp)
   contains
      pure real(dp) function order(coarse, fine)
         real(dp), intent(in) :: coarse, fine
         order = log(coarse / fine) / log(2.0_dp)
      end function order
   end subroutine test_order

   !> Rigid engine from rest to t_end with step h: crank angle and speed, the in-plane force of
   !> the piston pin on the piston and of the crank pin on the conrod at t_end (N), and all
   !> multipliers (appended as a column of lambdas).
   subroutine run_short(h, t_end, angle, speed, pin, crankpin, lambdas, rejected, error)
      real(dp), intent(in) :: h, t_end
      real(dp), intent(out) :: angle, speed, pin(2), crankpin(2)
      real(dp), allocatable, intent(inout) :: lambdas(:, :)
      integer, intent(out) :: rejected
      type(error_t), allocatable, intent(out) :: error
      type(mechanism_t) :: mech
      type(galpha_integrator_t) :: integrator
      real(dp) :: q(21), v(21), force(3, 2), moment(3, 2)
      real(dp), allocatable :: grown(:, :)
      call build_engine(mech, q, v, error)
      if (allocated(error)) return
      call integrator%init(mech, tight_settings(h, t_end + 10.0_dp * h), q, v, error)
      if (allocated(error)) return
      call step_to(mech, integrator, t_end, error)
      if (allocated(error)) return
      angle = mech%rotor_angle(integrator%q)
      speed = mech%rotor_speed(integrator%q, integrator%v)
      call mech%reaction(piston_pin, integrator%q, integrator%lambda, force, moment)
      pin = force(1:2, 2)
      call mech%reaction(crank_pin, integrator%q, integrator%lambda, force, moment)
      crankpin = force(1:2, 2)
      if (.not. allocated(lambdas)) allocate (lambdas(size(integrator%lambda), 0))
      allocate (grown(size(lambdas, 1), size(lambdas, 2) + 1))
      grown(:, :size(lambdas, 2)) = lambdas
      grown(:, size(grown, 2)) = integrator%lambda
      call move_alloc(grown, lambdas)
      rejected = int(integrator%stats%rejected_steps)
   end subroutine run_short

   !> Step to t_end (within rounding). The integrator runs with settings%t_end beyond it: with
   !> settings%t_end = t_end, the time accumulated by t = t + h drifts by ~1e-12 s over 2e4
   !> steps, above the 1e-9 h margin of its last-step test, so a spurious last step of ~1e-13 s
   !> was attempted and failed (Newton on beta h^2 ~ 1e-27; reported to the lead).
   subroutine step_to(mech, integrator, t_end, error)
      type(mechanism_t), intent(inout) :: mech
      type(galpha_integrator_t), intent(inout) :: integrator
      real(dp), intent(in) :: t_end
      type(error_t), allocatable, intent(out) :: error
      do while (integrator%t < t_end - 0.5_dp * integrator%settings%h)
         call integrator%step(mech, error)
         if (allocated(error)) return
      end do
   end subroutine step_to

   !> Regime speed against the closed-form energy balance (issue 3: "the engine's cycle-mean
   !> regime speed agrees with the closed-form balance of the mean indicated torque of the
   !> pressure model against the load torque, within the bias that the speed fluctuation
   !> explains"). The rigid engine 0 .. 2 s, h = 1e-4 s, rho_inf = 0.8.
   !> Reference. No friction, ideal joints, gravity off, starter off (its torque is 0 above 157
   !> rad/s, reached at 0.14 s, and it is cut at 0.5 s): over one 720 deg cycle, from crank angle
   !> 4 pi (k - 1) to 4 pi k, the gas work is the cycle work W of the pressure model (the force
   !> depends on the angle only; the p_ref A part integrates to zero) and the piston and conrod
   !> inertia forces do no net work, so in a periodic regime W = int c omega^2 dphi, i.e.
   !>     <omega^2>_phi = T_mean / c,   T_mean = W / (4 pi) = mean_indicated_torque()
   !> (64.917 N m: T_mean / c = 180325.6 (rad/s)^2, sqrt = 424.648 rad/s). The speed fluctuates
   !> over the cycle and the closed form holds for the crank-ANGLE mean of omega^2, whereas the
   !> regime speed is the TIME mean m = 4 pi / T_cycle. With dphi = omega dt and the time moments
   !> var = <(omega - m)^2>_t, mu3 = <(omega - m)^3>_t, exactly
   !>     <omega^2>_phi = <omega^3>_t / <omega>_t = m^2 + 3 var + mu3 / m,
   !> so the fluctuation predicts m = sqrt(T_mean / c - 3 var - mu3 / m), about
   !> sqrt(T_mean / c) - 3 var / (2 sqrt(T_mean / c)). (m = sqrt(<omega^2>_t - var) holds too,
   !> but <omega^2>_t is not the angle mean the balance gives: it would explain a bias of only
   !> var / (2 m), a third of the measured one.)
   !> Measured on the last full cycle (60, t = 1.958 .. 1.988 s): <omega^2>_phi is 3.7e-6 below
   !> T_mean / c; m = 423.8719 rad/s, 0.7757 rad/s below sqrt(T_mean / c); the fluctuation
   !> (std 14.650 rad/s, mu3 = -158.6 (rad/s)^3, max - min = 49.71 rad/s) explains 0.7584 of
   !> it; of the 0.0173 rad/s left, 0.0008 is the balance error above and 0.0165 the index-3
   !> velocities: int omega dt over a cycle exceeds 4 pi by 4.9e-4 rad at h = 1e-4 s (1.96e-3
   !> at 2e-4 s, O(h^2)), so the integrator's omega is 3.9e-5 relative above dphi/dt.
   !> Transient: the excess of <omega^2>_phi over its final value decays by 0.778 per cycle
   !> (cycles 35 .. 40), as exp(-T_cycle / tau) = 0.779 with tau = J / (2 c m) = 0.119 s (J =
   !> 0.0363 kg m^2, the cycle mean of 2 E_kin / omega^2: crank and flywheel 0.0344 plus the
   !> conrod and piston share); the relative error of <omega^2>_phi is -6.2e-4 at cycle 30
   !> (1.07 s), -5.4e-5 at cycle 40 (1.37 s), -5.2e-6 at cycle 50 (1.66 s), then -2.6e-6 ..
   !> -4.8e-6 over cycles 51 .. 60: the transient left at the last cycle is ~1e-7 (0.779**10 of
   !> the 1.5e-6 excess of cycle 50), and the rest is discretisation error (-0.8e-5 .. -1.9e-5 at
   !> h = 2e-4 s, O(h^2)) scattered by +/-1e-6 from cycle to cycle. The kinetic-energy change
   !> over the last cycle (+/-0.01 J, alternating in sign from cycle to cycle: the O(h^2) error
   !> of the index-3 velocities, not a trend) is reported, not used.
   !> Asserted: <omega^2>_phi = T_mean / c to 1.5e-5 relative (4 x the measured 3.7e-6), and the
   !> time mean m against the fluctuation's prediction to 0.05 rad/s (3 x the 0.017 measured, 7 %
   !> of the 0.76 rad/s bias it explains); the amplitude is reported.
   subroutine test_regime(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-4_dp, t_end = 2.0_dp
      type(history_t) :: history
      type(galpha_stats_t) :: stats
      type(cycle_t) :: c, earlier, early(2)
      real(dp) :: closed, torque, m_pred, m_time, j_mean, decay, tau
      integer :: last, i, count
      call run_regime(h, t_end, torque, history, stats, error)
      if (allocated(error)) return
      closed = torque / load_coefficient
      call report('closed form: T_mean = ' // to_str(torque, 10) // ' N m, T_mean / c = ' // &
         to_str(closed, 10) // ' (rad/s)^2, sqrt = ' // to_str(sqrt(closed), 10) // ' rad/s')
      call report(to_str(stats%steps) // ' steps, ' // to_str(stats%rejected_steps) // &
         ' rejected attempts, smallest step ' // to_str(stats%h_min, 4) // ' s, ' // &
         to_str(stats%factorizations) // ' factorisations, ' // &
         to_str(stats%newton_iterations) // ' Newton iterations, ' // &
         to_str(stats%wall_seconds, 3) // ' s')
      last = floor(history%phi(history%n) / (4.0_dp * pi))
      earlier = cycle_of(history, last - 10)
      c = cycle_of(history, last)
      m_time = 4.0_dp * pi / (c%t1 - c%t0)
      m_pred = sqrt(closed - 3.0_dp * c%variance - c%third / m_time)
      call report('cycle ' // to_str(earlier%number) // ' (t = ' // to_str(earlier%t0, 6) // &
         ' s): <omega^2>_phi / (T_mean / c) - 1 = ' // &
         to_str(earlier%w2_angle / closed - 1.0_dp, 4) // ' (transient)')
      call report('last cycle ' // to_str(c%number) // ', t = ' // to_str(c%t0, 6) // ' .. ' // &
         to_str(c%t1, 6) // ' s: <omega^2>_phi = ' // to_str(c%w2_angle, 10) // &
         ' (rad/s)^2, relative ' // to_str(c%w2_angle / closed - 1.0_dp, 4) // &
         '; kinetic energy change ' // to_str(c%delta_energy, 3) // ' J')
      call report('time mean 4 pi / T_cycle = ' // to_str(m_time, 10) // ' rad/s (int omega dt' &
         // ' / T_cycle ' // to_str(c%mean, 10) // '; int omega dt - 4 pi = ' // &
         to_str(c%angle - 4.0_dp * pi, 3) // ' rad); fluctuation: std ' // &
         to_str(sqrt(c%variance), 6) // ' rad/s, mu3 ' // to_str(c%third, 5) // &
         ' (rad/s)^3, amplitude max - min ' // to_str(c%w_max - c%w_min, 6) // ' rad/s')
      call report('bias sqrt(T_mean / c) - m = ' // to_str(sqrt(closed) - m_time, 5) // &
         ' rad/s; explained by the fluctuation ' // to_str(sqrt(closed) - m_pred, 5) // &
         ' (3 var / (2 m) = ' // to_str(1.5_dp * c%variance / m_time, 5) // '; var / (2 m) = ' &
         // to_str(0.5_dp * c%variance / m_time, 5) // '); left ' // to_str(m_time - m_pred, 3) &
         // ' rad/s')
      ! Transient: decay per cycle of the excess of <omega^2>_phi over the last cycle's, against
      ! exp(-T_cycle / tau), tau = J / (2 c m), J the cycle mean of 2 E / omega^2
      early(1) = cycle_of(history, last - 25)
      early(2) = cycle_of(history, last - 20)
      j_mean = 0.0_dp
      count = 0
      do i = 1, history%n
         if (history%t(i) >= c%t0 .and. history%t(i) < c%t1) then
            j_mean = j_mean + 2.0_dp * history%energy(i) / history%w(i)**2
            count = count + 1
         end if
      end do
      j_mean = j_mean / count
      decay = ((early(2)%w2_angle - c%w2_angle) / (early(1)%w2_angle - c%w2_angle))**0.2_dp
      tau = j_mean / (2.0_dp * load_coefficient * m_time)
      ! first sample at or above the starter's no-load speed (history is 0-based)
      i = findloc(history%w(0:history%n) >= 157.0_dp, .true., dim=1) - 1
      call report('transient: excess of <omega^2>_phi decays by ' // to_str(decay, 4) // &
         ' per cycle (cycles ' // to_str(early(1)%number) // ' .. ' // &
         to_str(early(2)%number) // '); J = ' // to_str(j_mean, 4) // ' kg m^2, tau = J / ' // &
         '(2 c m) = ' // to_str(tau, 4) // ' s: exp(-T_cycle / tau) = ' // &
         to_str(exp(-(c%t1 - c%t0) / tau), 4) // '; starter torque 0 from t = ' // &
         to_str(history%t(i), 4) // ' s')
      call check_close(error, 'angle mean of omega^2 over the last cycle', c%w2_angle, closed, &
         rtol=1.5e-5_dp)
      if (allocated(error)) return
      call check_close(error, 'time-mean speed vs closed form less the fluctuation bias', &
         m_time, m_pred, atol=0.05_dp)
   end subroutine test_regime

   !> Rigid engine from rest with step h to t_end: the history of each accepted step (time,
   !> unwrapped crank angle, crank speed and acceleration, kinetic energy, power of the loads).
   subroutine run_regime(h, t_end, torque, history, stats, error)
      real(dp), intent(in) :: h, t_end
      real(dp), intent(out) :: torque
      type(history_t), intent(out) :: history
      type(galpha_stats_t), intent(out) :: stats
      type(error_t), allocatable, intent(out) :: error
      type(mechanism_t) :: mech
      type(galpha_integrator_t) :: integrator
      real(dp) :: q(21), v(21)
      integer :: n, steps
      call build_engine(mech, q, v, error)
      if (allocated(error)) return
      torque = 0.0_dp
      select type (load => mech%loads(1)%load)
      type is (pressure_force_t)
         torque = load%model%mean_indicated_torque()
      end select
      ! t_end + 10 h for the integrator: see step_to
      call integrator%init(mech, tight_settings(h, t_end + 10.0_dp * h), q, v, error)
      if (allocated(error)) return
      steps = ceiling(t_end / h) + 100
      allocate (history%t(0:steps), history%phi(0:steps), history%w(0:steps), &
         history%wdot(0:steps), history%energy(0:steps), history%power(0:steps))
      n = 0
      call sample(error)
      if (allocated(error)) return
      do while (integrator%t < t_end - 0.5_dp * h)
         call integrator%step(mech, error)
         if (allocated(error)) return
         n = n + 1
         if (n > steps) then
            call check(error, 'regime run: more steps than ' // to_str(steps), .false.)
            return
         end if
         call sample(error)
         if (allocated(error)) return
      end do
      history%n = n
      stats = integrator%stats
   contains
      subroutine sample(error)
         type(error_t), allocatable, intent(out) :: error
         history%t(n) = integrator%t
         history%phi(n) = mech%rotor_angle(integrator%q)
         history%w(n) = mech%rotor_speed(integrator%q, integrator%v)
         ! d/dt (G theta_dot) = G theta_ddot, since G(theta_dot) theta_dot = 0
         history%wdot(n) = mech%rotor_speed(integrator%q, integrator%qdd)
         history%energy(n) = mech%kinetic_energy(integrator%q, integrator%v)
         call mech%applied_power(integrator%q, integrator%v, integrator%t, history%power(n), &
            error)
      end subroutine sample
   end subroutine run_regime

   !> Statistics of the 720 deg cycle k (crank angle from 4 pi (k - 1) to 4 pi k). Between two
   !> steps the crank angle, speed and kinetic energy are the cubic Hermite interpolants of their
   !> values and rates (omega, omega_dot, power); the cycle boundaries are the roots of the angle
   !> interpolant; the moments of omega are integrated over time by 5-point Gauss-Legendre on
   !> the speed interpolant, one rule for all of them, so that <w^2>_phi = int w^3 dt / int w dt
   !> = m^2 + 3 var + mu3 / m holds to round-off (m = int w dt / int dt).
   function cycle_of(history, k) result(c)
      type(history_t), intent(in) :: history
      integer, intent(in) :: k
      type(cycle_t) :: c
      real(dp), parameter :: gauss_x(5) = [-0.9061798459386640_dp, -0.5384693101056831_dp, &
         0.0_dp, 0.5384693101056831_dp, 0.9061798459386640_dp]
      real(dp), parameter :: gauss_w(5) = [0.2369268850561891_dp, 0.4786286704993665_dp, &
         0.5688888888888889_dp, 0.4786286704993665_dp, 0.2369268850561891_dp]
      real(dp) :: a0, a1, s0, s1, sa, sb, x, wx, moments(0:3), e0, e1
      integer :: i0, i1, i, g
      a0 = 4.0_dp * pi * (k - 1)
      a1 = 4.0_dp * pi * k
      c%number = k
      associate (t => history%t, phi => history%phi, w => history%w, wd => history%wdot)
         ! intervals (i0 - 1, i0) and (i1 - 1, i1) hold the boundaries
         i0 = 1
         do while (phi(i0) <= a0)
            i0 = i0 + 1
         end do
         i1 = i0
         do while (phi(i1) < a1)
            i1 = i1 + 1
         end do
         s0 = hermite_root(i0, a0)
         s1 = hermite_root(i1, a1)
         c%t0 = t(i0 - 1) + s0 * (t(i0) - t(i0 - 1))
         c%t1 = t(i1 - 1) + s1 * (t(i1) - t(i1 - 1))
         e0 = hermite(history%energy(i0 - 1), history%energy(i0), history%power(i0 - 1), &
            history%power(i0), t(i0) - t(i0 - 1), s0)
         e1 = hermite(history%energy(i1 - 1), history%energy(i1), history%power(i1 - 1), &
            history%power(i1), t(i1) - t(i1 - 1), s1)
         c%delta_energy = e1 - e0
         moments = 0.0_dp
         c%w_max = -huge(1.0_dp)
         c%w_min = huge(1.0_dp)
         do i = i0, i1
            sa = 0.0_dp
            sb = 1.0_dp
            if (i == i0) sa = s0
            if (i == i1) sb = s1
            do g = 1, 5
               x = sa + 0.5_dp * (sb - sa) * (gauss_x(g) + 1.0_dp)
               wx = hermite(w(i - 1), w(i), wd(i - 1), wd(i), t(i) - t(i - 1), x)
               moments = moments + 0.5_dp * (sb - sa) * (t(i) - t(i - 1)) * gauss_w(g) * &
                  [1.0_dp, wx, wx**2, wx**3]
            end do
            if (i < i1) then
               c%w_max = max(c%w_max, w(i))
               c%w_min = min(c%w_min, w(i))
            end if
         end do
      end associate
      c%angle = moments(1)
      c%w2_angle = moments(3) / moments(1)
      c%mean = moments(1) / moments(0)
      c%variance = moments(2) / moments(0) - c%mean**2
      c%third = moments(3) / moments(0) - 3.0_dp * c%mean * moments(2) / moments(0) + &
         2.0_dp * c%mean**3
   contains
      !> s in [0, 1] where the angle interpolant on step (i - 1, i) equals a (Newton).
      function hermite_root(i, a) result(s)
         integer, intent(in) :: i
         real(dp), intent(in) :: a
         real(dp) :: s, dt
         integer :: it
         associate (t => history%t, phi => history%phi, w => history%w)
            dt = t(i) - t(i - 1)
            s = (a - phi(i - 1)) / (phi(i) - phi(i - 1))
            do it = 1, 20
               s = s - (hermite(phi(i - 1), phi(i), w(i - 1), w(i), dt, s) - a) / &
                  (dt * hermite_rate(phi(i - 1), phi(i), w(i - 1), w(i), dt, s))
            end do
         end associate
      end function hermite_root
   end function cycle_of

   !> Cubic Hermite interpolant at s in [0, 1] of values y0, y1 and time rates r0, r1 over dt.
   pure real(dp) function hermite(y0, y1, r0, r1, dt, s)
      real(dp), intent(in) :: y0, y1, r0, r1, dt, s
      hermite = (2.0_dp * s**3 - 3.0_dp * s**2 + 1.0_dp) * y0 + (s**3 - 2.0_dp * s**2 + s) * &
         dt * r0 + (-2.0_dp * s**3 + 3.0_dp * s**2) * y1 + (s**3 - s**2) * dt * r1
   end function hermite

   !> Time rate of the interpolant (per second).
   pure real(dp) function hermite_rate(y0, y1, r0, r1, dt, s)
      real(dp), intent(in) :: y0, y1, r0, r1, dt, s
      hermite_rate = ((6.0_dp * s**2 - 6.0_dp * s) * y0 + (-6.0_dp * s**2 + 6.0_dp * s) * y1) / &
         dt + (3.0_dp * s**2 - 4.0_dp * s + 1.0_dp) * r0 + (3.0_dp * s**2 - 2.0_dp * s) * r1
   end function hermite_rate

end module test_mbs_engine_convergence

program main_mbs_engine_convergence
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_engine_convergence, only: collect_mbs_engine_convergence
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_engine_convergence(tests)
   call run_suite('mbs_engine_convergence', tests)
end program main_mbs_engine_convergence
