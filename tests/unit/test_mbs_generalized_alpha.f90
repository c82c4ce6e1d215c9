!> Generalized-alpha for index-3 constrained systems (ffrf_mbs_generalized_alpha) on small
!> systems with known answers: the linear oscillator (closed form, second order, spectral radius
!> of the amplification matrix at w h -> infinity = rho_inf), the Cartesian pendulum (reference:
!> the angle ODE by RK4 at a step where its error is ~1e-15; orders of q, v and lambda), the
!> pendulum with a redundant constraint row (same motion as without), the finite-difference
!> default tangents of ffrf_mbs_dae_system against an analytic override, failure paths (NaN force,
!> system error, minimum step, rho_inf out of range) and the energy of the frictionless pendulum.
module test_mbs_generalized_alpha
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_dae_system, only: dae_system_t
   use ffrf_mbs_generalized_alpha, only: galpha_settings_t, galpha_integrator_t, &
      GALPHA_NEWTON_FULL, GALPHA_NEWTON_ADAPTIVE
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_mbs_generalized_alpha

   !> Gravity (m/s^2) and pendulum length (m), mass (kg) and initial angle (rad)
   real(dp), parameter :: gravity = 9.81_dp, length = 1.0_dp, mass = 1.0_dp, theta0 = 1.0_dp

   !> x'' + w^2 x = 0 (n = 1, no constraint); the force turns NaN (or fails) after t_fail.
   type, extends(dae_system_t) :: oscillator_t
      real(dp) :: omega = 2.0_dp * pi
      real(dp) :: t_fail = huge(1.0_dp)
      logical :: fail_with_error = .false.
   contains
      procedure :: num_coordinates => oscillator_n
      procedure :: num_constraints => oscillator_nc
      procedure :: mass => oscillator_mass
      procedure :: force => oscillator_force
      procedure :: constraints => oscillator_phi
      procedure :: constraint_jacobian => oscillator_jac
   end type oscillator_t

   !> Energy of the accepted states: first, last, largest, and largest from window_start on.
   type :: energy_record_t
      real(dp) :: first = 0.0_dp, last = 0.0_dp, max = -huge(1.0_dp), window_max = -huge(1.0_dp)
      real(dp) :: window_start = huge(1.0_dp)
      integer :: calls = 0
   end type energy_record_t

   !> The pendulum in its angle: m L^2 theta'' = -m g L sin(theta), no constraint.
   type, extends(dae_system_t) :: angle_pendulum_t
      type(energy_record_t) :: record
   contains
      procedure :: num_coordinates => angle_n
      procedure :: num_constraints => angle_nc
      procedure :: mass => angle_mass
      procedure :: force => angle_force
      procedure :: constraints => angle_phi
      procedure :: constraint_jacobian => angle_jac
      procedure :: accepted_step => angle_hook
   end type angle_pendulum_t

   !> Point mass on a rod in Cartesian coordinates, index 3: dims = 2 (x, y; Phi = (|q|^2 -
   !> L^2)/2) or 3 (x, y, z; plus Phi_2 = z, and with `redundant` Phi_3 = Phi_1 + 2 Phi_2).
   !> The output hook records the energy and the constraint violation of every accepted step.
   type, extends(dae_system_t) :: pendulum_t
      integer :: dims = 2
      logical :: redundant = .false.
      type(energy_record_t) :: record
      real(dp) :: max_violation = 0.0_dp
   contains
      procedure :: num_coordinates => pendulum_n
      procedure :: num_constraints => pendulum_nc
      procedure :: mass => pendulum_mass
      procedure :: force => pendulum_force
      procedure :: constraints => pendulum_phi
      procedure :: constraint_jacobian => pendulum_jac
      procedure :: accepted_step => pendulum_hook
   end type pendulum_t

   !> A nonlinear test system (configuration-dependent mass, nonlinear forces and constraint)
   !> with only the basic procedures: its tangents come from the finite-difference defaults.
   type, extends(dae_system_t) :: nonlinear_t
   contains
      procedure :: num_coordinates => nonlinear_n
      procedure :: num_constraints => nonlinear_nc
      procedure :: mass => nonlinear_mass
      procedure :: force => nonlinear_force
      procedure :: constraints => nonlinear_phi
      procedure :: constraint_jacobian => nonlinear_jac
   end type nonlinear_t

   !> The same system with analytic tangents (the overrides a mechanism writes).
   type, extends(nonlinear_t) :: nonlinear_exact_t
   contains
      procedure :: stiffness => exact_stiffness
      procedure :: damping => exact_damping
      procedure :: constraint_stiffness => exact_constraint_stiffness
      procedure :: mass_stiffness => exact_mass_stiffness
      procedure :: acceleration_rhs => exact_acceleration_rhs
   end type nonlinear_exact_t

   real(dp), parameter :: k1 = 3.0_dp, k2 = 5.0_dp, c1 = 0.7_dp

contains

   subroutine collect_mbs_generalized_alpha(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('parameters_chung_hulbert', test_parameters), &
         new_unittest('oscillator_second_order', test_oscillator_order), &
         new_unittest('spectral_radius_at_infinity', test_spectral_radius), &
         new_unittest('pendulum_order_q_v_lambda', test_pendulum_order), &
         new_unittest('pendulum_redundant_row', test_pendulum_redundant), &
         new_unittest('inconsistent_start_projected', test_projection), &
         new_unittest('fd_tangents_vs_analytic', test_fd_tangents), &
         new_unittest('analytic_vs_fd_run', test_tangent_runs), &
         new_unittest('nan_force_fails_with_time', test_nan_force), &
         new_unittest('system_error_propagates', test_system_error), &
         new_unittest('min_step_failure', test_min_step), &
         new_unittest('step_cut_and_regrow', test_step_control), &
         new_unittest('rho_inf_range', test_rho_range), &
         new_unittest('pendulum_energy_rho', test_energy)]
   end subroutine collect_mbs_generalized_alpha

   ! ------------------------------------------------------------------------------------------
   ! Tests
   ! ------------------------------------------------------------------------------------------

   !> theory.md 4.1: rho_inf = 0 gives alpha_m = -1, alpha_f = 0, gamma = 3/2, beta = 1 and
   !> rho_inf = 1 the trapezoidal rule (1/2, 1/2, 1/2, 1/4); exact in binary arithmetic.
   subroutine test_parameters(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integ
      type(oscillator_t) :: osc
      type(galpha_settings_t) :: settings
      settings%rho_inf = 0.0_dp
      call integ%init(osc, settings, [1.0_dp], [0.0_dp], error)
      if (allocated(error)) return
      call check_close(error, 'alpha_m(0)', integ%alpha_m, -1.0_dp, atol=1.0e-15_dp)
      if (allocated(error)) return
      call check_close(error, 'gamma(0)', integ%gamma, 1.5_dp, atol=1.0e-15_dp)
      if (allocated(error)) return
      call check_close(error, 'beta(0)', integ%beta, 1.0_dp, atol=1.0e-15_dp)
      if (allocated(error)) return
      settings%rho_inf = 1.0_dp
      call integ%init(osc, settings, [1.0_dp], [0.0_dp], error)
      if (allocated(error)) return
      call check_close(error, 'alpha_f(1)', integ%alpha_f, 0.5_dp, atol=1.0e-15_dp)
      if (allocated(error)) return
      call check_close(error, 'beta(1)', integ%beta, 0.25_dp, atol=1.0e-15_dp)
   end subroutine test_parameters

   !> Second order (Chung & Hulbert 1993): x'' + w^2 x = 0, w = 2 pi, x(0) = 1, reference
   !> x = cos(w t); observed at t = 1.25 s, a zero crossing (at a peak the phase error hides).
   !> Observed order from h = 1e-2 and 5e-3 within 0.01 of 2 (measured 2 - 7.2e-4).
   subroutine test_oscillator_order(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: e1, e2, order
      e1 = abs(oscillator_end(1.0e-2_dp, 0.8_dp, error))
      if (allocated(error)) return
      e2 = abs(oscillator_end(5.0e-3_dp, 0.8_dp, error))
      if (allocated(error)) return
      order = log(e1 / e2) / log(2.0_dp)
      call report('oscillator: |x(1.25)| = ' // to_str(e1) // ', ' // to_str(e2) // &
         ', order ' // to_str(order))
      call check_close(error, 'observed order', order, 2.0_dp, atol=0.01_dp)
   end subroutine test_oscillator_order

   !> x(1.25 s) of the oscillator for step h.
   function oscillator_end(h, rho_inf, error) result(x)
      real(dp), intent(in) :: h, rho_inf
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: x
      type(galpha_integrator_t) :: integ
      type(oscillator_t) :: osc
      type(galpha_settings_t) :: settings
      x = huge(1.0_dp)
      settings%rho_inf = rho_inf
      settings%h = h
      settings%t_end = 1.25_dp
      call integ%init(osc, settings, [1.0_dp], [0.0_dp], error)
      if (allocated(error)) return
      call integ%run(osc, error)
      if (allocated(error)) return
      x = integ%q(1)
   end function oscillator_end

   !> Spectral radius of the amplification matrix for w h -> infinity equals rho_inf (Chung &
   !> Hulbert 1993, by design of the parameters). The 3 x 3 matrix maps (h^2 x'', h v, h^2 a)
   !> over one step of the real integrator (w h = 1e8, where its deviation from the limit is
   !> O((w h)**-2)); its spectral radius is lim ||A^k||^(1/k), taken at k = 2**60 by repeated
   !> squaring (the k**2 growth of the triple eigenvalue's Jordan block then costs < 1e-16).
   !> At the limit the amplification matrix has a triple (defective) eigenvalue, which round-off
   !> moves by O(eps**(1/3)) = 6e-6 (measured 3.7e-6 for rho_inf = 0.5, 0.8; 4.8e-6 for 0):
   !> tolerance 10 eps**(1/3) = 6e-5.
   subroutine test_spectral_radius(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: rhos(3) = [0.0_dp, 0.5_dp, 0.8_dp]
      type(galpha_integrator_t) :: integ
      type(oscillator_t) :: osc
      type(galpha_settings_t) :: settings
      real(dp) :: amp(3, 3), b(3, 3), log_norm, norm, radius
      integer :: i, j, k
      osc%omega = 1.0e8_dp
      settings%h = 1.0_dp
      settings%t_end = 1.0e3_dp
      settings%jacobian = GALPHA_NEWTON_FULL
      do i = 1, size(rhos)
         settings%rho_inf = rhos(i)
         call integ%init(osc, settings, [1.0_dp], [0.0_dp], error)
         if (allocated(error)) return
         do j = 1, 3
            integ%t = 0.0_dp
            integ%qdd = merge(1.0_dp, 0.0_dp, j == 1)
            integ%q = -integ%qdd / osc%omega**2
            integ%v = merge(1.0_dp, 0.0_dp, j == 2)
            integ%a = merge(1.0_dp, 0.0_dp, j == 3)
            call integ%step(osc, error)
            if (allocated(error)) return
            amp(:, j) = [integ%qdd(1), integ%v(1), integ%a(1)]
         end do
         b = amp
         log_norm = 0.0_dp
         radius = 0.0_dp
         do k = 1, 60
            b = matmul(b, b)
            norm = maxval(abs(b))
            if (norm == 0.0_dp) exit
            b = b / norm
            log_norm = 2.0_dp * log_norm + log(norm)
            radius = exp(log_norm / 2.0_dp**k)
         end do
         if (k <= 60) radius = 0.0_dp
         call report('rho_inf = ' // to_str(rhos(i)) // ': spectral radius ' // to_str(radius, 10))
         call check_close(error, 'spectral radius for rho_inf = ' // to_str(rhos(i)), radius, &
            rhos(i), atol=10.0_dp * epsilon(1.0_dp)**(1.0_dp / 3.0_dp))
         if (allocated(error)) return
      end do
   end subroutine test_spectral_radius

   !> Index-3 pendulum (x, y, rod length 1 m, theta0 = 1 rad, at rest) against the angle ODE
   !> theta'' = -(g/L) sin(theta) by RK4 with dt = 1e-4 (error ~1e-14): x, v_x and the multiplier
   !> lambda = m theta'^2 + m g cos(theta)/L at t = 1 s. Steps 1e-2 and 5e-3 give observed orders
   !> within 0.05 of 2 (measured deviations 3.5e-3 x, 3.2e-4 v_x, 1.05e-2 lambda; the higher-order
   !> terms at these steps) (Arnold & Bruls 2007: second order in q, v and lambda from a consistent
   !> start); every step keeps |Phi| below newton_atol. The start itself is checked first
   !> (pendulum_start_check).
   subroutine test_pendulum_order(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: ref(3), e1(3), e2(3), order
      real(dp) :: theta, omega, violation
      character(len=*), parameter :: names(3) = ['x       ', 'v_x     ', 'lambda  ']
      integer :: i
      call pendulum_start_check(error)
      if (allocated(error)) return
      call angle_reference(1.0_dp, theta, omega)
      ref = [length * sin(theta), length * cos(theta) * omega, &
         mass * omega**2 + mass * gravity * cos(theta) / length]
      call pendulum_errors(1.0e-2_dp, ref, e1, violation, error)
      if (allocated(error)) return
      call check(error, 'max |Phi| over the steps = ' // to_str(violation) // &
         ' > newton_atol = 1e-10', violation <= 1.0e-10_dp)
      if (allocated(error)) return
      call pendulum_errors(5.0e-3_dp, ref, e2, violation, error)
      if (allocated(error)) return
      call check(error, 'max |Phi| over the steps = ' // to_str(violation) // &
         ' > newton_atol = 1e-10', violation <= 1.0e-10_dp)
      if (allocated(error)) return
      do i = 1, 3
         order = log(e1(i) / e2(i)) / log(2.0_dp)
         call report('pendulum ' // trim(names(i)) // ': errors ' // to_str(e1(i)) // ', ' // &
            to_str(e2(i)) // ', order ' // to_str(order))
         call check_close(error, 'observed order of ' // trim(names(i)), order, 2.0_dp, &
            atol=0.05_dp)
         if (allocated(error)) return
      end do
   end subroutine test_pendulum_order

   !> Consistent start of the pendulum at rest (theory.md 4.3), closed form: lambda_0 =
   !> m g cos(theta0)/L, q''_0 = -g sin(theta0) (cos theta0, sin theta0); round-off bound 1e-12.
   subroutine pendulum_start_check(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integ
      type(pendulum_t) :: pend
      type(galpha_settings_t) :: settings
      real(dp) :: expected(2)
      call integ%init(pend, settings, pendulum_start(2), [0.0_dp, 0.0_dp], error)
      if (allocated(error)) return
      call check_close(error, 'lambda_0', integ%lambda(1), mass * gravity * cos(theta0) / &
         length, rtol=1.0e-12_dp)
      if (allocated(error)) return
      expected = -gravity * sin(theta0) * [cos(theta0), sin(theta0)]
      call check_close(error, 'max |q''''_0 - closed form|', maxval(abs(integ%qdd - expected)), &
         0.0_dp, atol=1.0e-12_dp * gravity)
      if (allocated(error)) return
      call check_close(error, 'a_0 = q''''_0', maxval(abs(integ%a - integ%qdd)), 0.0_dp, &
         atol=0.0_dp)
   end subroutine pendulum_start_check

   !> theta(t), theta'(t) of theta'' = -(g/L) sin(theta), theta(0) = theta0, at rest, by RK4.
   subroutine angle_reference(t_end, theta, omega)
      real(dp), intent(in) :: t_end
      real(dp), intent(out) :: theta, omega
      real(dp), parameter :: dt = 1.0e-4_dp
      real(dp) :: k(2, 4), y(2)
      integer :: i, steps
      steps = nint(t_end / dt)
      y = [theta0, 0.0_dp]
      do i = 1, steps
         k(:, 1) = rate(y)
         k(:, 2) = rate(y + 0.5_dp * dt * k(:, 1))
         k(:, 3) = rate(y + 0.5_dp * dt * k(:, 2))
         k(:, 4) = rate(y + dt * k(:, 3))
         y = y + dt / 6.0_dp * (k(:, 1) + 2.0_dp * k(:, 2) + 2.0_dp * k(:, 3) + k(:, 4))
      end do
      theta = y(1)
      omega = y(2)
   contains
      pure function rate(s) result(ds)
         real(dp), intent(in) :: s(2)
         real(dp) :: ds(2)
         ds = [s(2), -gravity / length * sin(s(1))]
      end function rate
   end subroutine angle_reference

   !> Errors of x, v_x, lambda at t = 1 s for step h, and the largest |Phi| seen by the hook.
   subroutine pendulum_errors(h, ref, errors, violation, error)
      real(dp), intent(in) :: h, ref(3)
      real(dp), intent(out) :: errors(3), violation
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integ
      type(pendulum_t) :: pend
      type(galpha_settings_t) :: settings
      settings%h = h
      settings%t_end = 1.0_dp
      call integ%init(pend, settings, pendulum_start(2), [0.0_dp, 0.0_dp], error)
      if (allocated(error)) return
      call integ%run(pend, error)
      if (allocated(error)) return
      errors = abs([integ%q(1), integ%v(1), integ%lambda(1)] - ref)
      violation = max(pend%max_violation, integ%stats%max_constraint_violation)
   end subroutine pendulum_errors

   !> Pendulum at theta0: (L sin theta0, -L cos theta0 [, 0]).
   function pendulum_start(dims) result(q)
      integer, intent(in) :: dims
      real(dp), allocatable :: q(:)
      q = [length * sin(theta0), -length * cos(theta0)]
      if (dims == 3) q = [q, 0.0_dp]
   end function pendulum_start

   !> The 3D pendulum with rows (length, z) and with the dependent row length + 2 z added: the
   !> run reports one dropped row (2 or 3), its multiplier is zero, and q, v and the reaction
   !> force Phi_q^T lambda equal those of the run without it to 1e-10 (same constraint manifold;
   !> full Newton to 1e-13 so the two linear solves differ only by round-off).
   subroutine test_pendulum_redundant(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: plain, extra
      type(pendulum_t) :: pend_plain, pend_extra
      type(galpha_settings_t) :: settings
      real(dp) :: jac2(2, 3), jac3(3, 3), reaction_plain(3), reaction_extra(3)
      settings%h = 1.0e-2_dp
      settings%t_end = 1.0_dp
      settings%newton_atol = 1.0e-13_dp
      settings%newton_rtol = 1.0e-13_dp
      settings%jacobian = GALPHA_NEWTON_FULL
      pend_plain%dims = 3
      pend_extra%dims = 3
      pend_extra%redundant = .true.
      call plain%init(pend_plain, settings, pendulum_start(3), [0.0_dp, 0.0_dp, 0.0_dp], error)
      if (allocated(error)) return
      call extra%init(pend_extra, settings, pendulum_start(3), [0.0_dp, 0.0_dp, 0.0_dp], error)
      if (allocated(error)) return
      call check(error, 'no row dropped without redundancy', size(plain%dropped) == 0)
      if (allocated(error)) return
      call check(error, 'one dropped row, got ' // to_str(size(extra%dropped)), &
         size(extra%dropped) == 1)
      if (allocated(error)) return
      call check(error, 'dropped row is 2 or 3, got ' // to_str(extra%dropped(1)), &
         extra%dropped(1) == 2 .or. extra%dropped(1) == 3)
      if (allocated(error)) return
      call report('redundant pendulum: dropped row ' // to_str(extra%dropped(1)) // '; note: ' &
         // extra%notes)
      call check(error, 'the notes name the dropped row', index(extra%notes, 'rows ' // &
         to_str(extra%dropped(1))) > 0)
      if (allocated(error)) return
      call plain%run(pend_plain, error)
      if (allocated(error)) return
      call extra%run(pend_extra, error)
      if (allocated(error)) return
      call check_close(error, 'multiplier of the dropped row', &
         extra%lambda(extra%dropped(1)), 0.0_dp, atol=0.0_dp)
      if (allocated(error)) return
      call check_close(error, 'max |q - q_plain|', maxval(abs(extra%q - plain%q)), 0.0_dp, &
         atol=1.0e-10_dp)
      if (allocated(error)) return
      call check_close(error, 'max |v - v_plain|', maxval(abs(extra%v - plain%v)), 0.0_dp, &
         atol=1.0e-10_dp)
      if (allocated(error)) return
      call pend_plain%constraint_jacobian(plain%q, plain%t, jac2, error)
      if (allocated(error)) return
      call pend_extra%constraint_jacobian(extra%q, extra%t, jac3, error)
      if (allocated(error)) return
      reaction_plain = matmul(plain%lambda, jac2)
      reaction_extra = matmul(extra%lambda, jac3)
      call report('reaction force at t = 1 s: ' // to_str(reaction_plain(1)) // ', ' // &
         to_str(reaction_plain(2)) // ' N; difference ' // &
         to_str(maxval(abs(reaction_extra - reaction_plain))))
      call check_close(error, 'max |reaction - reaction_plain| (N)', &
         maxval(abs(reaction_extra - reaction_plain)), 0.0_dp, atol=1.0e-10_dp * &
         maxval(abs(reaction_plain)))
   end subroutine test_pendulum_redundant

   !> An inconsistent start (rod 1 % too long, velocity with a radial part) is projected: after
   !> init |Phi| <= newton_atol and |Phi_q v| <= newton_atol/h, and the notes say so; with
   !> project_initial = .false. init refuses with the violation in the message.
   subroutine test_projection(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integ
      type(pendulum_t) :: pend
      type(galpha_settings_t) :: settings
      type(error_t), allocatable :: failure
      real(dp) :: q0(2), v0(2), phi(1), jac(1, 2)
      q0 = 1.01_dp * pendulum_start(2)
      v0 = [0.3_dp, 0.2_dp]
      call integ%init(pend, settings, q0, v0, error)
      if (allocated(error)) return
      call pend%constraints(integ%q, integ%t, phi, error)
      if (allocated(error)) return
      call pend%constraint_jacobian(integ%q, integ%t, jac, error)
      if (allocated(error)) return
      call check_close(error, 'Phi after projection', phi(1), 0.0_dp, atol=1.0e-10_dp)
      if (allocated(error)) return
      call check_close(error, 'Phi_q v after projection', sum(jac(1, :) * integ%v), 0.0_dp, &
         atol=1.0e-10_dp / settings%h)
      if (allocated(error)) return
      call check(error, 'notes mention the projection: ' // integ%notes, &
         index(integ%notes, 'positions projected') > 0 .and. &
         index(integ%notes, 'velocities projected') > 0)
      if (allocated(error)) return
      settings%project_initial = .false.
      call integ%init(pend, settings, q0, v0, failure)
      call check(error, 'refused start without projection', allocated(failure))
      if (allocated(error)) return
      call report('refusal: ' // failure%message)
      call check(error, 'message gives the violation: ' // failure%message, &
         index(failure%message, 'max |Phi_i| = ') > 0 .and. failure%code == FFRF_INPUT_ERROR)
   end subroutine test_projection

   !> The finite-difference defaults of dae_system_t (central, eps**(1/3) scaled step) against
   !> the analytic tangents of the same nonlinear system, at a generic state: K_t, C_t,
   !> d(Phi_q^T lambda)/dq, d(M a)/dq and the acceleration right-hand side g agree to
   !> sqrt(eps) relative to each matrix's largest entry (the difference error is ~eps**(2/3)).
   subroutine test_fd_tangents(error)
      type(error_t), allocatable, intent(out) :: error
      type(nonlinear_t) :: fd
      type(nonlinear_exact_t) :: exact
      real(dp) :: q(3), v(3), acc(3), t, lambda(1), fd_mat(3, 3), ex_mat(3, 3)
      real(dp) :: fd_g(1), ex_g(1), tol
      integer :: which
      character(len=24) :: names(4)
      names = [character(len=24) :: 'K_t = -df/dq', 'C_t = -df/dv', 'd(Phi_q^T lambda)/dq', &
         'd(M a)/dq']
      q = [0.7_dp, -0.4_dp, 1.3_dp]
      v = [-1.1_dp, 0.8_dp, 0.5_dp]
      acc = [0.3_dp, -2.0_dp, 1.7_dp]
      lambda = [2.5_dp]
      t = 0.6_dp
      tol = sqrt(epsilon(1.0_dp))
      do which = 1, 4
         select case (which)
         case (1)
            call fd%stiffness(q, v, t, fd_mat, error)
            if (.not. allocated(error)) call exact%stiffness(q, v, t, ex_mat, error)
         case (2)
            call fd%damping(q, v, t, fd_mat, error)
            if (.not. allocated(error)) call exact%damping(q, v, t, ex_mat, error)
         case (3)
            call fd%constraint_stiffness(q, t, lambda, fd_mat, error)
            if (.not. allocated(error)) call exact%constraint_stiffness(q, t, lambda, ex_mat, &
               error)
         case default
            call fd%mass_stiffness(q, acc, fd_mat, error)
            if (.not. allocated(error)) call exact%mass_stiffness(q, acc, ex_mat, error)
         end select
         if (allocated(error)) return
         call report(trim(names(which)) // ': max |fd - exact| = ' // &
            to_str(maxval(abs(fd_mat - ex_mat))) // ' (scale ' // &
            to_str(maxval(abs(ex_mat))) // ')')
         call check_close(error, 'max |fd - exact| of ' // trim(names(which)), &
            maxval(abs(fd_mat - ex_mat)), 0.0_dp, atol=tol * maxval(abs(ex_mat)))
         if (allocated(error)) return
      end do
      call fd%acceleration_rhs(q, v, t, fd_g, error)
      if (allocated(error)) return
      call exact%acceleration_rhs(q, v, t, ex_g, error)
      if (allocated(error)) return
      call report('g: fd ' // to_str(fd_g(1), 12) // ', exact ' // to_str(ex_g(1), 12))
      call check_close(error, 'acceleration rhs g (fd)', fd_g(1), ex_g(1), &
         rtol=tol)
   end subroutine test_fd_tangents

   !> The nonlinear system integrated with analytic and with finite-difference tangents (full
   !> Newton, so each iteration uses the tangent): the converged motions agree to the Newton
   !> tolerance (1e-10 absolute, 1e-8 relative; asserted at 1e-7), and the analytic tangent
   !> needs no more iterations (quadratic convergence either way).
   subroutine test_tangent_runs(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: run_fd, run_exact
      type(nonlinear_t) :: fd
      type(nonlinear_exact_t) :: exact
      type(galpha_settings_t) :: settings
      real(dp) :: q0(3)
      settings%h = 1.0e-2_dp
      settings%t_end = 0.5_dp
      settings%jacobian = GALPHA_NEWTON_FULL
      ! On the constraint q1^2 + q2 q3 + sin(q3) = 1: solve for q1.
      q0 = [0.0_dp, 0.3_dp, 0.4_dp]
      q0(1) = sqrt(1.0_dp - q0(2) * q0(3) - sin(q0(3)))
      call run_fd%init(fd, settings, q0, [0.0_dp, 0.0_dp, 0.0_dp], error)
      if (allocated(error)) return
      call run_fd%run(fd, error)
      if (allocated(error)) return
      call run_exact%init(exact, settings, q0, [0.0_dp, 0.0_dp, 0.0_dp], error)
      if (allocated(error)) return
      call run_exact%run(exact, error)
      if (allocated(error)) return
      call report('nonlinear run: Newton iterations fd ' // &
         to_str(run_fd%stats%newton_iterations) // ', exact ' // &
         to_str(run_exact%stats%newton_iterations) // '; max |q_fd - q_exact| ' // &
         to_str(maxval(abs(run_fd%q - run_exact%q))))
      call check_close(error, 'max |q_fd - q_exact|', maxval(abs(run_fd%q - run_exact%q)), &
         0.0_dp, atol=1.0e-7_dp)
      if (allocated(error)) return
      call check_close(error, 'lambda fd vs exact', run_fd%lambda(1), run_exact%lambda(1), &
         rtol=1.0e-6_dp)
      if (allocated(error)) return
      call check(error, 'analytic tangent needs no more iterations than fd', &
         run_exact%stats%newton_iterations <= run_fd%stats%newton_iterations)
   end subroutine test_tangent_runs

   !> A force that turns NaN at t > 0.3 s: the step is cut down to min_step, then
   !> FFRF_NUMERIC_ERROR with the time in the message; the last converged state (t within
   !> 1e-4 s below 0.3 s, x near cos(w t)) stays available.
   subroutine test_nan_force(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integ
      type(oscillator_t) :: osc
      type(galpha_settings_t) :: settings
      type(error_t), allocatable :: failure
      osc%t_fail = 0.3_dp
      settings%h = 1.0e-2_dp
      settings%min_step = 1.0e-6_dp
      call integ%init(osc, settings, [1.0_dp], [0.0_dp], error)
      if (allocated(error)) return
      call integ%run(osc, failure)
      call check(error, 'run fails', allocated(failure))
      if (allocated(error)) return
      call report('NaN failure: ' // failure%message)
      call check(error, 'code FFRF_NUMERIC_ERROR', failure%code == FFRF_NUMERIC_ERROR)
      if (allocated(error)) return
      call check(error, 'message names the time, the step and NaN: ' // failure%message, &
         index(failure%message, 't = ' // to_str(integ%t, 12) // ' s') > 0 .and. &
         index(failure%message, 'NaN') > 0 .and. index(failure%message, 'min_step') > 0)
      if (allocated(error)) return
      call check(error, 'last converged time ' // to_str(integ%t, 12) // ' just below 0.3 s', &
         integ%t <= 0.3_dp .and. integ%t > 0.3_dp - 1.0e-4_dp)
      if (allocated(error)) return
      call check_close(error, 'last converged x vs cos(w t)', integ%q(1), &
         cos(osc%omega * integ%t), atol=1.0e-2_dp)
   end subroutine test_nan_force

   !> A system that returns its own error at t > 0.3 s: the run stops at once (no step cutting)
   !> with the system's message and the step's time added.
   subroutine test_system_error(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integ
      type(oscillator_t) :: osc
      type(galpha_settings_t) :: settings
      type(error_t), allocatable :: failure
      osc%t_fail = 0.3_dp
      osc%fail_with_error = .true.
      settings%h = 1.0e-2_dp
      call integ%init(osc, settings, [1.0_dp], [0.0_dp], error)
      if (allocated(error)) return
      call integ%run(osc, failure)
      call check(error, 'run fails', allocated(failure))
      if (allocated(error)) return
      call report('system failure: ' // failure%message)
      call check(error, 'message has the step time and the system message: ' // &
         failure%message, index(failure%message, 'step from t = 0.29 s') > 0 .and. &
         index(failure%message, 'oscillator force') > 0)
      if (allocated(error)) return
      call check(error, 'no rejected steps', integ%stats%rejected_steps == 0)
   end subroutine test_system_error

   !> One Newton iteration can never pass the increment test from a predictor (increment far
   !> above 1e-10): with max_iterations = 1 and min_step = h/4 the step is cut twice and the run
   !> fails with the min-step message; the state stays the initial one.
   subroutine test_min_step(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integ
      type(pendulum_t) :: pend
      type(galpha_settings_t) :: settings
      type(error_t), allocatable :: failure
      settings%h = 4.0e-2_dp
      settings%min_step = 1.0e-2_dp
      settings%max_iterations = 1
      call integ%init(pend, settings, pendulum_start(2), [0.0_dp, 0.0_dp], error)
      if (allocated(error)) return
      call integ%run(pend, failure)
      call check(error, 'run fails', allocated(failure))
      if (allocated(error)) return
      call report('min-step failure: ' // failure%message)
      call check(error, 'min-step message: ' // failure%message, &
         index(failure%message, 'below min_step = 0.01 s') > 0 .and. &
         index(failure%message, 'Newton did not converge in 1 iterations') > 0 .and. &
         index(failure%message, 'step h = 0.01 s') > 0)
      if (allocated(error)) return
      call check(error, 'state kept at t = 0', integ%t == 0.0_dp .and. &
         all(integ%q == pendulum_start(2)))
      if (allocated(error)) return
      call check(error, '3 rejected attempts (0.04, 0.02, 0.01), got ' // &
         to_str(int(integ%stats%rejected_steps)), integ%stats%rejected_steps == 3)
   end subroutine test_min_step

   !> Step control: with max_iterations = 2 the pendulum's 0.05 s steps fail and are cut, and
   !> after grow_after = 4 accepted steps the step grows back to 0.05 s. The run completes with
   !> rejected attempts, less than half the accepted steps of a run at the smallest step used
   !> (without regrowth: 1194 steps at 1.6e-3 s against 1280; with it 242 against 2560), x(2 s)
   !> within 1e-2 m of the angle-ODE reference (measured 5e-4 m).
   subroutine test_step_control(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integ
      type(pendulum_t) :: pend
      type(galpha_settings_t) :: settings
      real(dp) :: theta, omega
      integer :: constant_steps
      settings%h = 5.0e-2_dp
      settings%t_end = 2.0_dp
      settings%max_iterations = 2
      settings%jacobian = GALPHA_NEWTON_FULL
      call integ%init(pend, settings, pendulum_start(2), [0.0_dp, 0.0_dp], error)
      if (allocated(error)) return
      call integ%run(pend, error)
      if (allocated(error)) return
      call angle_reference(2.0_dp, theta, omega)
      constant_steps = nint(2.0_dp / integ%stats%h_min)
      call report('step control: ' // to_str(int(integ%stats%steps)) // ' steps, ' // &
         to_str(int(integ%stats%rejected_steps)) // ' rejected, smallest h ' // &
         to_str(integ%stats%h_min) // ' s, x error ' // &
         to_str(abs(integ%q(1) - length * sin(theta))))
      call check(error, 'steps were rejected', integ%stats%rejected_steps > 0)
      if (allocated(error)) return
      call check(error, 'the step grew back: ' // to_str(int(integ%stats%steps)) // &
         ' steps, at the smallest step ' // to_str(constant_steps), &
         2 * integ%stats%steps < constant_steps)
      if (allocated(error)) return
      call check_close(error, 'x(2 s)', integ%q(1), length * sin(theta), atol=1.0e-2_dp)
   end subroutine test_step_control

   !> rho_inf outside [0, 1] is refused with the value and the range; rho_inf = 1 is refused
   !> for a constrained system (the pendulum; documented choice) and accepted without
   !> constraints (the oscillator).
   subroutine test_rho_range(error)
      type(error_t), allocatable, intent(out) :: error
      type(galpha_integrator_t) :: integ
      type(oscillator_t) :: osc
      type(pendulum_t) :: pend
      type(galpha_settings_t) :: settings
      type(error_t), allocatable :: failure
      real(dp), parameter :: bad(2) = [1.2_dp, -0.1_dp]
      integer :: i
      do i = 1, 2
         settings%rho_inf = bad(i)
         call integ%init(osc, settings, [1.0_dp], [0.0_dp], failure)
         call check(error, 'rho_inf = ' // to_str(bad(i)) // ' refused', allocated(failure))
         if (allocated(error)) return
         call check(error, 'message: ' // failure%message, failure%code == FFRF_INPUT_ERROR &
            .and. index(failure%message, 'rho_inf = ' // to_str(bad(i))) > 0 .and. &
            index(failure%message, '[0, 1]') > 0)
         if (allocated(error)) return
      end do
      settings%rho_inf = 1.0_dp
      call integ%init(pend, settings, pendulum_start(2), [0.0_dp, 0.0_dp], failure)
      call check(error, 'rho_inf = 1 refused with constraints', allocated(failure))
      if (allocated(error)) return
      call report('rho_inf = 1 with constraints: ' // failure%message)
      call check(error, 'message: ' // failure%message, failure%code == FFRF_INPUT_ERROR .and. &
         index(failure%message, 'rho_inf = 1') > 0 .and. index(failure%message, 'index-3') > 0)
      if (allocated(error)) return
      call integ%init(osc, settings, [1.0_dp], [0.0_dp], error)
   end subroutine test_rho_range

   !> Frictionless pendulum (energy conserved exactly), theta0 = 1 rad, h = 0.05 s, 20 s. The
   !> drift is measured on the envelope, (E0 - max E over [17 s, 20 s]) / swing energy, since
   !> E oscillates at O(h^2) within a period even without dissipation (swing energy
   !> m g L (1 - cos theta0)). In the angle coordinate (ODE, no constraint) rho_inf = 1 conserves
   !> it (drift below 1e-6; measured ~1e-8) and rho_inf = 0.8 dissipates (drift > 0, < 1e-3;
   !> measured 2.2e-4); the index-3 Cartesian pendulum with rho_inf = 0.8 (rho_inf = 1 is
   !> refused there) also dissipates, more (drift > 0, < 5e-3; measured 1.2e-3). In no case does
   !> E rise above E0 by more than 1e-6 of the swing energy.
   subroutine test_energy(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: rhos(3) = [1.0_dp, 0.8_dp, 0.8_dp], h = 0.05_dp, t_end = 20.0_dp
      character(len=*), parameter :: names(3) = ['angle, rho_inf = 1      ', &
         'angle, rho_inf = 0.8    ', 'Cartesian, rho_inf = 0.8']
      type(galpha_integrator_t) :: integ
      type(pendulum_t) :: pend
      type(angle_pendulum_t) :: swing_pend
      type(galpha_settings_t) :: settings
      type(energy_record_t) :: record
      real(dp) :: swing, drift(3), gain
      integer :: i
      settings%h = h
      settings%t_end = t_end
      swing = mass * gravity * length * (1.0_dp - cos(theta0))
      do i = 1, 3
         settings%rho_inf = rhos(i)
         if (i < 3) then
            swing_pend = angle_pendulum_t()
            swing_pend%record%window_start = t_end - 3.0_dp
            call integ%init(swing_pend, settings, [theta0], [0.0_dp], error)
            if (allocated(error)) return
            call integ%run(swing_pend, error)
            record = swing_pend%record
         else
            pend = pendulum_t()
            pend%record%window_start = t_end - 3.0_dp
            call integ%init(pend, settings, pendulum_start(2), [0.0_dp, 0.0_dp], error)
            if (allocated(error)) return
            call integ%run(pend, error)
            record = pend%record
         end if
         if (allocated(error)) return
         drift(i) = (record%first - record%window_max) / swing
         gain = (record%max - record%first) / swing
         call report(trim(names(i)) // ': envelope drift ' // to_str(drift(i)) // &
            ' of the swing energy, largest gain ' // to_str(gain) // ', E(t_end) - E0 ' // &
            to_str((record%last - record%first) / swing))
         call check(error, trim(names(i)) // ': energy rises above E0 by ' // to_str(gain), &
            gain <= 1.0e-6_dp)
         if (allocated(error)) return
      end do
      call check(error, 'rho_inf = 1 conserves: drift ' // to_str(drift(1)), &
         abs(drift(1)) < 1.0e-6_dp)
      if (allocated(error)) return
      call check(error, 'angle, rho_inf = 0.8 dissipates within 1e-3: drift ' // &
         to_str(drift(2)), drift(2) > 0.0_dp .and. drift(2) < 1.0e-3_dp)
      if (allocated(error)) return
      call check(error, 'Cartesian, rho_inf = 0.8 dissipates within 5e-3: drift ' // &
         to_str(drift(3)), drift(3) > 0.0_dp .and. drift(3) < 5.0e-3_dp)
   end subroutine test_energy

   ! ------------------------------------------------------------------------------------------
   ! Oscillator
   ! ------------------------------------------------------------------------------------------

   integer function oscillator_n(self)
      class(oscillator_t), intent(in) :: self
      oscillator_n = 1 + 0 * int(self%omega)
   end function oscillator_n

   integer function oscillator_nc(self)
      class(oscillator_t), intent(in) :: self
      oscillator_nc = 0 * int(self%omega)
   end function oscillator_nc

   subroutine oscillator_mass(self, q, M, error)
      class(oscillator_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(out) :: M(:, :)
      type(error_t), allocatable, intent(out) :: error
      M = 1.0_dp + 0.0_dp * q(1) * self%omega
   end subroutine oscillator_mass

   subroutine oscillator_force(self, q, v, t, f, error)
      class(oscillator_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: f(:)
      type(error_t), allocatable, intent(out) :: error
      f = -self%omega**2 * q + 0.0_dp * v
      if (t > self%t_fail) then
         if (self%fail_with_error) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'oscillator force: failure at t = ' // &
               to_str(t))
         else
            f = ieee_value(1.0_dp, ieee_quiet_nan)
         end if
      end if
   end subroutine oscillator_force

   subroutine oscillator_phi(self, q, t, phi, error)
      class(oscillator_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      phi = 0.0_dp * (q(1) + t + self%omega)
   end subroutine oscillator_phi

   subroutine oscillator_jac(self, q, t, Phi_q, error)
      class(oscillator_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: Phi_q(:, :)
      type(error_t), allocatable, intent(out) :: error
      Phi_q = 0.0_dp * (q(1) + t + self%omega)
   end subroutine oscillator_jac

   ! ------------------------------------------------------------------------------------------
   ! Pendulum
   ! ------------------------------------------------------------------------------------------

   integer function pendulum_n(self)
      class(pendulum_t), intent(in) :: self
      pendulum_n = self%dims
   end function pendulum_n

   integer function pendulum_nc(self)
      class(pendulum_t), intent(in) :: self
      pendulum_nc = 1
      if (self%dims == 3) pendulum_nc = 2
      if (self%redundant) pendulum_nc = 3
   end function pendulum_nc

   subroutine pendulum_mass(self, q, M, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(out) :: M(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: i
      M = 0.0_dp * q(1)
      do i = 1, self%dims
         M(i, i) = mass
      end do
   end subroutine pendulum_mass

   subroutine pendulum_force(self, q, v, t, f, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: f(:)
      type(error_t), allocatable, intent(out) :: error
      f = 0.0_dp * (q + v + t + self%dims)
      f(2) = -mass * gravity
   end subroutine pendulum_force

   subroutine pendulum_phi(self, q, t, phi, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      phi(1) = 0.5_dp * (sum(q**2) - length**2) + 0.0_dp * t
      if (self%dims == 3) phi(2) = q(3)
      if (self%redundant) phi(3) = phi(1) + 2.0_dp * phi(2)
   end subroutine pendulum_phi

   subroutine pendulum_jac(self, q, t, Phi_q, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: Phi_q(:, :)
      type(error_t), allocatable, intent(out) :: error
      Phi_q = 0.0_dp * t
      Phi_q(1, :) = q
      if (self%dims == 3) Phi_q(2, 3) = 1.0_dp
      if (self%redundant) Phi_q(3, :) = Phi_q(1, :) + 2.0_dp * Phi_q(2, :)
   end subroutine pendulum_jac

   !> Records the energy m |v|^2/2 + m g y and |Phi| of every accepted state.
   subroutine pendulum_hook(self, t, q, v, qdd, lambda, error)
      class(pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: t, q(:), v(:), qdd(:), lambda(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: phi(3)
      call self%constraints(q, t, phi(:self%num_constraints()), error)
      if (allocated(error)) return
      self%max_violation = max(self%max_violation, maxval(abs(phi(:self%num_constraints()))))
      call record_energy(self%record, t, 0.5_dp * mass * sum(v**2) + mass * gravity * q(2) + &
         0.0_dp * sum(qdd) * sum(lambda))
   end subroutine pendulum_hook

   !> Add one accepted state's energy to the record.
   subroutine record_energy(record, t, energy)
      type(energy_record_t), intent(inout) :: record
      real(dp), intent(in) :: t, energy
      record%calls = record%calls + 1
      if (record%calls == 1) record%first = energy
      record%last = energy
      record%max = max(record%max, energy)
      if (t >= record%window_start) record%window_max = max(record%window_max, energy)
   end subroutine record_energy

   ! ------------------------------------------------------------------------------------------
   ! Pendulum in its angle
   ! ------------------------------------------------------------------------------------------

   integer function angle_n(self)
      class(angle_pendulum_t), intent(in) :: self
      angle_n = 1 + 0 * self%record%calls
   end function angle_n

   integer function angle_nc(self)
      class(angle_pendulum_t), intent(in) :: self
      angle_nc = 0 * self%record%calls
   end function angle_nc

   subroutine angle_mass(self, q, M, error)
      class(angle_pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(out) :: M(:, :)
      type(error_t), allocatable, intent(out) :: error
      M = mass * length**2 + 0.0_dp * q(1) * self%record%calls
   end subroutine angle_mass

   subroutine angle_force(self, q, v, t, f, error)
      class(angle_pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: f(:)
      type(error_t), allocatable, intent(out) :: error
      f = -mass * gravity * length * sin(q) + 0.0_dp * (v + t + self%record%calls)
   end subroutine angle_force

   subroutine angle_phi(self, q, t, phi, error)
      class(angle_pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      phi = 0.0_dp * (q(1) + t + self%record%calls)
   end subroutine angle_phi

   subroutine angle_jac(self, q, t, Phi_q, error)
      class(angle_pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: Phi_q(:, :)
      type(error_t), allocatable, intent(out) :: error
      Phi_q = 0.0_dp * (q(1) + t + self%record%calls)
   end subroutine angle_jac

   !> Records the energy m L^2 theta'^2/2 - m g L cos(theta).
   subroutine angle_hook(self, t, q, v, qdd, lambda, error)
      class(angle_pendulum_t), intent(inout) :: self
      real(dp), intent(in) :: t, q(:), v(:), qdd(:), lambda(:)
      type(error_t), allocatable, intent(out) :: error
      call record_energy(self%record, t, 0.5_dp * mass * length**2 * v(1)**2 - mass * gravity &
         * length * cos(q(1)) + 0.0_dp * sum(qdd) * sum(lambda))
   end subroutine angle_hook

   ! ------------------------------------------------------------------------------------------
   ! Nonlinear system: M(q) = [[1 + q1^2, 0.1 q3, 0], [0.1 q3, 2 + sin q2, 0], [0, 0, 1.5]],
   ! f = [-k1 q1^3 - c1 v1 |v1|, -k2 sin q2 + q1 v2^2, -q3 + cos(t) v3 q1],
   ! Phi = q1^2 + q2 q3 + sin q3 - 1.
   ! ------------------------------------------------------------------------------------------

   integer function nonlinear_n(self)
      class(nonlinear_t), intent(in) :: self
      nonlinear_n = 3 + 0 * storage_size(self)
   end function nonlinear_n

   integer function nonlinear_nc(self)
      class(nonlinear_t), intent(in) :: self
      nonlinear_nc = 1 + 0 * storage_size(self)
   end function nonlinear_nc

   subroutine nonlinear_mass(self, q, M, error)
      class(nonlinear_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      real(dp), intent(out) :: M(:, :)
      type(error_t), allocatable, intent(out) :: error
      M = 0.0_dp * storage_size(self)
      M(1, 1) = 1.0_dp + q(1)**2
      M(1, 2) = 0.1_dp * q(3)
      M(2, 1) = 0.1_dp * q(3)
      M(2, 2) = 2.0_dp + sin(q(2))
      M(3, 3) = 1.5_dp
   end subroutine nonlinear_mass

   subroutine nonlinear_force(self, q, v, t, f, error)
      class(nonlinear_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: f(:)
      type(error_t), allocatable, intent(out) :: error
      f(1) = -k1 * q(1)**3 - c1 * v(1) * abs(v(1)) + 0.0_dp * storage_size(self)
      f(2) = -k2 * sin(q(2)) + q(1) * v(2)**2
      f(3) = -q(3) + cos(t) * v(3) * q(1)
   end subroutine nonlinear_force

   subroutine nonlinear_phi(self, q, t, phi, error)
      class(nonlinear_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      phi(1) = q(1)**2 + q(2) * q(3) + sin(q(3)) - 1.0_dp + 0.0_dp * t * storage_size(self)
   end subroutine nonlinear_phi

   subroutine nonlinear_jac(self, q, t, Phi_q, error)
      class(nonlinear_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t
      real(dp), intent(out) :: Phi_q(:, :)
      type(error_t), allocatable, intent(out) :: error
      Phi_q(1, :) = [2.0_dp * q(1), q(3), q(2) + cos(q(3))] + 0.0_dp * t * storage_size(self)
   end subroutine nonlinear_jac

   subroutine exact_stiffness(self, q, v, t, K_t, error)
      class(nonlinear_exact_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: K_t(:, :)
      type(error_t), allocatable, intent(out) :: error
      K_t = 0.0_dp * storage_size(self)
      K_t(1, 1) = 3.0_dp * k1 * q(1)**2
      K_t(2, 1) = -v(2)**2
      K_t(2, 2) = k2 * cos(q(2))
      K_t(3, 1) = -cos(t) * v(3)
      K_t(3, 3) = 1.0_dp
   end subroutine exact_stiffness

   subroutine exact_damping(self, q, v, t, C_t, error)
      class(nonlinear_exact_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: C_t(:, :)
      type(error_t), allocatable, intent(out) :: error
      C_t = 0.0_dp * storage_size(self)
      C_t(1, 1) = 2.0_dp * c1 * abs(v(1))
      C_t(2, 2) = -2.0_dp * q(1) * v(2)
      C_t(3, 3) = -cos(t) * q(1)
   end subroutine exact_damping

   subroutine exact_constraint_stiffness(self, q, t, lambda, K_c, error)
      class(nonlinear_exact_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), t, lambda(:)
      real(dp), intent(out) :: K_c(:, :)
      type(error_t), allocatable, intent(out) :: error
      K_c = 0.0_dp * t * storage_size(self)
      K_c(1, 1) = 2.0_dp * lambda(1)
      K_c(2, 3) = lambda(1)
      K_c(3, 2) = lambda(1)
      K_c(3, 3) = -sin(q(3)) * lambda(1)
   end subroutine exact_constraint_stiffness

   subroutine exact_mass_stiffness(self, q, a, K_m, error)
      class(nonlinear_exact_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), a(:)
      real(dp), intent(out) :: K_m(:, :)
      type(error_t), allocatable, intent(out) :: error
      K_m = 0.0_dp * storage_size(self)
      K_m(1, 1) = 2.0_dp * q(1) * a(1)
      K_m(1, 3) = 0.1_dp * a(2)
      K_m(2, 2) = cos(q(2)) * a(2)
      K_m(2, 3) = 0.1_dp * a(1)
   end subroutine exact_mass_stiffness

   !> g = -Phi_qq(v, v) (scleronomic): -(2 v1^2 + 2 v2 v3 - sin(q3) v3^2).
   subroutine exact_acceleration_rhs(self, q, v, t, g, error)
      class(nonlinear_exact_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), v(:), t
      real(dp), intent(out) :: g(:)
      type(error_t), allocatable, intent(out) :: error
      g(1) = -(2.0_dp * v(1)**2 + 2.0_dp * v(2) * v(3) - sin(q(3)) * v(3)**2) + &
         0.0_dp * t * storage_size(self)
   end subroutine exact_acceleration_rhs

end module test_mbs_generalized_alpha

program main_mbs_generalized_alpha
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_generalized_alpha, only: collect_mbs_generalized_alpha
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_generalized_alpha(tests)
   call run_suite('test_mbs_generalized_alpha', tests)
end program main_mbs_generalized_alpha
