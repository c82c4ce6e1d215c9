!> Energy balance of a mechanism run (theory.md 4.1; scene.md output: energy balance). The run loop
!> calls init once at the start and update after every accepted step; the type keeps
!>
!>     T   kinetic energy sum_b v_b^T M_b(q_b) v_b / 2 (mechanism%kinetic_energy)
!>     U   strain energy sum_b zeta_b^T K_ff,b zeta_b / 2 (mechanism%strain_energy)
!>     W   work of the applied loads and gravity, W = int P dt, P = Q_applied . v
!>         (mechanism%applied_power), plus the work of a driving constraint when the multipliers
!>         are passed (below)
!>     D_p energy dissipated by the physical modal damping of the flexible bodies,
!>         D_p = int P_d dt, P_d = sum_b zeta_dot_b^T D_ff,b zeta_dot_b >= 0
!>         (flexible_body_t%damping = diag(2 xi_j omega_j), mass-normalised modes)
!>     D   numerical dissipation, D = W - (T + U - T_0 - U_0) - D_p (the balance's residual)
!>     D_s numerical dissipation of generalized-alpha from its own per-step energy identity
!>         (theory.md 4.4), when the integrator is passed to init and update:
!>         D_s = W_m - D_p,m - C_m - (T + U - T_0 - U_0), with the work of the step-mean
!>         applied, damping and constraint forces over the step increments,
!>         W_m = sum dq . (Q_n + Q_(n+1))/2, D_p,m = sum dq . C (v_n + v_(n+1))/2,
!>         C_m = sum dq . (Phi_q^T lambda)_mean; for a linear system it equals, step by step,
!>         D_k = sum h (beta - gamma/2) da . M dv + (1 - alpha_m - gamma) dq . M da
!>               - (1/2 - alpha_f) dq . M dqdd
!>         (from the increments of q, v, a, q'' alone), which vanishes identically for rho_inf = 1
!>         (test_mbs_energy: D_s = D_k to 3e-15 E_0; D_s = 0 to 4e-15 E_0 with rho_inf = 1, also
!>         with modal damping, where the trapezoidal D is -2.4 % of E_0). For a nonlinear system
!>         D_k (with M_bar = (M_n + M_(n+1))/2) is only an estimate and D_s the scheme's
!>         quantity.
!>
!> D and D_s. D - D_s = (W - W_m) - (D_p - D_p,m) + C_m: the O(h^2) difference between the
!> trapezoidal rule on the power and the step-mean force times the increment (h/4 dv . dQ per
!> step) and the work of the constraint forces over the steps. Measured (tests/regression,
!> h = 1e-4 s, rho_inf = 0.8): the all-rigid engine, 0.3 s, D = 1.76e-4 W, D_s = 8.0e-5 W,
!> |D - D_s| <= 1.02e-4 W; the flexible RC set 1 rotating link and conrod, 0.1 s, D = 6.05e-6 W,
!> D_s = 4.0e-6 W, |D - D_s| <= 2.15e-6 W; both can dip to round-off-sized negative values at
!> the start (down to -2.4e-8 W and -4.8e-8 W).
!>
!> Exact balance. Along an exact solution of M q'' + Phi_q^T lambda = f_v + Q_e + Q_applied,
!> Phi(q, t) = 0, d(T + U)/dt = P - P_d + P_c, where P_c = -lambda^T Phi_q v = lambda^T Phi_t is
!> the power of the constraint forces: zero for the scleronomic joint and Euler-parameter rows,
!> lambda_d Phi_t,d for the rheonomic driving constraint (ffrf_mbs_mechanism) and each driver of
!> a joint (ffrf_mbs_joint_driver: tau f'), all counted in W. So D = 0 exactly
!> for the continuous problem, and D measures what the integrator loses (or gains).
!>
!> Quadrature. Each integral is advanced by the trapezoidal rule over the accepted step
!> h = t_{n+1} - t_n: W += h/2 (P_n + P_{n+1}), likewise D_p and the drive work. The rule is
!> O(h^3) per step on a smooth power, O(h^2) over a fixed interval, so D carries an O(h^2)
!> quadrature part (~ t h^2 max|P''|/12) besides the integrator's own energy error: D is not the
!> pure algorithmic dissipation when loads vary fast within a step (pressure peaks: take it as an
!> O(h^2)-accurate estimate and compare it across step sizes).
!>
!> Generalized-alpha energy behaviour (Chung & Hulbert, J. Appl. Mech. 60 (1993) 371; theory.md
!> 4.1). On the linear oscillator x'' + omega^2 x = 0 the step is y_{n+1} = A(Omega) y_n,
!> Omega = omega h, with a 3 x 3 amplification matrix; its principal (complex pair) eigenvalues
!> lambda_1,2 carry the physical oscillation, so the energy of a vibrating mode decays as
!> E_n / E_0 = kappa |lambda_1(Omega)|^(2n) over whole discrete periods once the spurious root
!> (|lambda_3| <= rho_inf) has died out; kappa = 1 + O(Omega^2) is the share of the start in the
!> principal pair. rho_inf < 1 damps high Omega (|lambda_1| -> rho_inf as Omega -> inf) and
!> leaves the low modes almost untouched (1 - |lambda_1| = O(Omega^4)). With rho_inf = 1
!> (trapezoidal rule) |lambda_1| = 1 and a linear system keeps its quadratic energy to round-off,
!> but the spurious root is -1 (undamped), and the integrator refuses rho_inf = 1 for any
!> mechanism with a free body (its Euler row is a constraint) unless its constraints are
!> stabilized index 2 (theory.md 4.6). For the nonlinear rigid rotation
!> with Euler parameters the scheme conserves neither energy nor angular momentum; both drift by
!> O(h^2) over a fixed interval (tests/unit/test_mbs_energy.f90: D / T_0 = 4.7e-10 and
!> |L - L_0| / |L_0| = 6.8e-10 for a tumbling rigid body, 2 s, h = 2e-4 s, rho_inf = 0.8).
!> D > 0 is energy removed by the scheme; D < 0 beyond the O(h^2) quadrature part (a damped mode
!> resolved by 200 steps per period: D = -2.5e-4 D_p) would signal energy created (instability);
!> D_s has no quadrature part and is >= 0 up to round-off on every case measured without a
!> prescribed motion. With a driving constraint C_m holds the drive's work as a step-mean
!> quadrature, and D_s can be negative by O(h^2): the driven, damped spin-up of
!> tests/unit/test_mbs_energy_scenes.f90 gives D_s = -7.9e-7 W at h = 2 ms, -2.0e-7 W at 1 ms.
module ffrf_mbs_energy_balance
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_NUMERIC_ERROR, &
      FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_mechanism, only: mechanism_t
   use ffrf_mbs_generalized_alpha, only: galpha_integrator_t
   implicit none
   private
   public :: energy_balance_t

   !> Running energy balance of a mechanism (module header); all energies in J, time in s.
   type :: energy_balance_t
      !> Time of the last update (s)
      real(dp) :: t = 0.0_dp
      !> Kinetic energy T and strain energy U at the last update (J)
      real(dp) :: kinetic = 0.0_dp, strain = 0.0_dp
      !> T_0 and U_0 at init (J)
      real(dp) :: kinetic_start = 0.0_dp, strain_start = 0.0_dp
      !> Work W of the applied loads and gravity (and of a driving constraint) since init (J)
      real(dp) :: work = 0.0_dp
      !> Energy D_p dissipated by the physical modal damping since init (J)
      real(dp) :: physical_dissipation = 0.0_dp
      !> Numerical dissipation D = W - (T + U - T_0 - U_0) - D_p (J): the balance's residual
      real(dp) :: numerical_dissipation = 0.0_dp
      !> Numerical dissipation of generalized-alpha from its per-step energy identity (module
      !> header), D_s = W_m - D_p,m - C_m - (T + U - T_0 - U_0) (J); zero unless the integrator
      !> is passed to init and update
      real(dp) :: scheme_dissipation = 0.0_dp
      !> Its parts: the work of the step-mean applied forces, damping forces and constraint
      !> forces over the step increments, W_m, D_p,m, C_m (J)
      real(dp) :: step_work = 0.0_dp, step_damping = 0.0_dp, constraint_work = 0.0_dp
      !> The closed form of D_s for constant M from the increments of q, v, a and q'' alone,
      !> D_k (module header; exact for linear systems, an estimate otherwise) (J)
      real(dp) :: kinematic_dissipation = 0.0_dp
      !> D_s is being accumulated (the integrator was passed to init)
      logical :: has_scheme = .false.
      !> Parameters of the scheme: alpha_m, alpha_f, gamma, beta (theory.md 4.1)
      real(dp) :: scheme(4) = 0.0_dp
      !> At the last update (n each): q, v, a, q'', the applied force Q and the constraint force
      !> Phi_q^T lambda; the mass matrix there (n x n, recomputed after import_state)
      real(dp), allocatable :: q_last(:), v_last(:), a_last(:), qdd_last(:), force_last(:)
      real(dp), allocatable :: reaction_last(:)
      real(dp), allocatable :: mass_last(:, :)
      !> Power P of the applied loads (and drive) and damping power P_d at the last update (W)
      real(dp) :: power = 0.0_dp, damping_power = 0.0_dp
      !> Number of updates after init
      integer :: steps = 0
   contains
      !> Energies at the start of the run; zero work and dissipation
      procedure :: init => energy_balance_init
      !> Advance the balance to an accepted step
      procedure :: update => energy_balance_update
      !> Total mechanical energy T + U (J)
      procedure :: total => energy_balance_total
      !> The accumulators as a flat array (checkpoint)
      procedure :: export_state => energy_balance_export_state
      !> Restore them (restart)
      procedure :: import_state => energy_balance_import_state
   end type energy_balance_t

contains

   !> Start the balance at (t, q, v): T_0, U_0 and the powers at t; W = D_p = D = D_s = 0.
   !> With `scheme` (the integrator after its init) D_s is accumulated too.
   subroutine energy_balance_init(self, mech, t, q, v, error, lambda, scheme)
      !> The balance
      class(energy_balance_t), intent(out) :: self
      !> The mechanism
      class(mechanism_t), intent(inout) :: mech
      !> Start time (s)
      real(dp), intent(in) :: t
      !> Coordinates, n
      real(dp), intent(in) :: q(:)
      !> Velocities, n
      real(dp), intent(in) :: v(:)
      type(error_t), allocatable, intent(out) :: error
      !> Multipliers, nc (optional): with them the work of a driving constraint enters W
      real(dp), intent(in), optional :: lambda(:)
      !> The integrator at (t, q, v) (optional): its parameters and algorithmic accelerations a
      !> give D_s
      type(galpha_integrator_t), intent(in), optional :: scheme
      call evaluate(mech, t, q, v, self%kinetic, self%strain, self%power, self%damping_power, &
         error, lambda)
      if (allocated(error)) then
         call add_context(error, 'energy balance at the start, t = ' // to_str(t, 12) // ' s')
         return
      end if
      self%t = t
      self%kinetic_start = self%kinetic
      self%strain_start = self%strain
      if (.not. present(scheme)) return
      if (size(scheme%a) /= mech%n) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'energy balance: the integrator has ' // &
            to_str(size(scheme%a)) // ' coordinates, the mechanism ' // to_str(mech%n) // &
            '; pass the integrator of this mechanism after its init')
         return
      end if
      self%has_scheme = .true.
      self%scheme = [scheme%alpha_m, scheme%alpha_f, scheme%gamma, scheme%beta]
      self%q_last = q
      self%v_last = v
      self%a_last = scheme%a
      self%qdd_last = scheme%qdd
      allocate (self%mass_last(mech%n, mech%n), self%force_last(mech%n), &
         self%reaction_last(mech%n))
      call mech%mass(q, self%mass_last, error)
      if (.not. allocated(error)) call step_forces(mech, t, q, v, scheme%lambda, &
         self%force_last, self%reaction_last, error)
   end subroutine energy_balance_init

   !> Advance to the accepted step (t, q, v): new T, U, powers; W and D_p by the trapezoidal rule
   !> over [t_last, t]; D from the balance; D_s from the scheme's identity when the integrator
   !> (at this step) is passed and was passed to init (module header).
   subroutine energy_balance_update(self, mech, t, q, v, error, lambda, scheme)
      !> The balance (after init)
      class(energy_balance_t), intent(inout) :: self
      !> The mechanism
      class(mechanism_t), intent(inout) :: mech
      !> Time of the accepted step (s), after the last update
      real(dp), intent(in) :: t
      !> Coordinates, n
      real(dp), intent(in) :: q(:)
      !> Velocities, n
      real(dp), intent(in) :: v(:)
      type(error_t), allocatable, intent(out) :: error
      !> Multipliers, nc (optional): with them the work of a driving constraint enters W
      real(dp), intent(in), optional :: lambda(:)
      !> The integrator at this step (optional): D_s (module header)
      type(galpha_integrator_t), intent(in), optional :: scheme
      real(dp) :: kinetic, strain, power, damping_power, h
      h = t - self%t
      if (.not. h >= 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'energy balance: update at t = ' // &
            to_str(t, 12) // ' s is before the last one at t = ' // to_str(self%t, 12) // &
            ' s; call update once per accepted step, in time order')
         return
      end if
      call evaluate(mech, t, q, v, kinetic, strain, power, damping_power, error, lambda)
      if (allocated(error)) then
         call add_context(error, 'energy balance at step ' // to_str(self%steps + 1) // &
            ', t = ' // to_str(t, 12) // ' s')
         return
      end if
      self%work = self%work + 0.5_dp * h * (self%power + power)
      self%physical_dissipation = self%physical_dissipation + 0.5_dp * h * &
         (self%damping_power + damping_power)
      self%t = t
      self%kinetic = kinetic
      self%strain = strain
      self%power = power
      self%damping_power = damping_power
      self%steps = self%steps + 1
      self%numerical_dissipation = self%work - (kinetic + strain - self%kinetic_start - &
         self%strain_start) - self%physical_dissipation
      if (self%has_scheme .and. present(scheme)) then
         call add_scheme_step(self, mech, t, h, q, v, scheme%a, scheme%qdd, scheme%lambda, &
            error)
         if (allocated(error)) return
      end if
      if (.not. (ieee_is_finite(self%work) .and. ieee_is_finite(self%numerical_dissipation) &
         .and. ieee_is_finite(self%scheme_dissipation) .and. &
         ieee_is_finite(self%kinematic_dissipation))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'energy balance: NaN or Inf in the work ' &
            // 'or the dissipation at step ' // to_str(self%steps) // ', t = ' // &
            to_str(t, 12) // ' s')
      end if
   end subroutine energy_balance_update

   !> Advance D_s and D_k over the step from the last update to (t, q, v, a, q'', lambda)
   !> (module header). With the step means x_m = (x_n + x_(n+1)) / 2:
   !>     W_m += dq . Q_m,  D_p,m += dq . C v_m,  C_m += dq . (Phi_q^T lambda)_m,
   !>     D_k += h (beta - gamma/2) da . M_bar dv + (1 - alpha_m - gamma) dq . M_bar da
   !>            - (1/2 - alpha_f) dq . M_bar dqdd,
   !> M_bar = (M(q_n) + M(q_(n+1))) / 2; the damping's quadratic form comes from the bodies'
   !> damping power, x . C y = (P_d(x + y) - P_d(x) - P_d(y)) / 2.
   subroutine add_scheme_step(self, mech, t, h, q, v, a, qdd, lambda, error)
      type(energy_balance_t), intent(inout) :: self
      class(mechanism_t), intent(inout) :: mech
      real(dp), intent(in) :: t, h, q(:), v(:), a(:), qdd(:), lambda(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: mass(:, :), m_bar(:, :), dq(:), dv(:), da(:), dqdd(:), force(:)
      real(dp), allocatable :: reaction(:), v_m(:)
      if (size(a) /= mech%n .or. size(qdd) /= mech%n .or. size(lambda) /= mech%nc) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'energy balance: integrator state of ' // &
            to_str(size(a)) // ' coordinates and ' // to_str(size(lambda)) // ' multipliers ' &
            // 'for a mechanism with ' // to_str(mech%n) // ' and ' // to_str(mech%nc) // &
            '; pass the integrator of this mechanism')
         return
      end if
      allocate (mass(mech%n, mech%n), force(mech%n), reaction(mech%n))
      if (.not. allocated(self%mass_last)) then
         allocate (self%mass_last(mech%n, mech%n))
         call mech%mass(self%q_last, self%mass_last, error)
         if (allocated(error)) return
      end if
      call mech%mass(q, mass, error)
      if (.not. allocated(error)) call step_forces(mech, t, q, v, lambda, force, reaction, &
         error)
      if (allocated(error)) return
      dq = q - self%q_last
      dv = v - self%v_last
      da = a - self%a_last
      dqdd = qdd - self%qdd_last
      v_m = 0.5_dp * (v + self%v_last)
      self%step_work = self%step_work + 0.5_dp * dot_product(dq, force + self%force_last)
      self%step_damping = self%step_damping + 0.5_dp * (damping_form(mech, dq + v_m) - &
         damping_form(mech, dq) - damping_form(mech, v_m))
      self%constraint_work = self%constraint_work + 0.5_dp * dot_product(dq, reaction + &
         self%reaction_last)
      m_bar = 0.5_dp * (self%mass_last + mass)
      associate (alpha_m => self%scheme(1), alpha_f => self%scheme(2), gamma => self%scheme(3), &
            beta => self%scheme(4))
         self%kinematic_dissipation = self%kinematic_dissipation + h * (beta - 0.5_dp * gamma) &
            * dot_product(da, matmul(m_bar, dv)) + (1.0_dp - alpha_m - gamma) * &
            dot_product(dq, matmul(m_bar, da)) - (0.5_dp - alpha_f) * &
            dot_product(dq, matmul(m_bar, dqdd))
      end associate
      self%scheme_dissipation = self%step_work - self%step_damping - self%constraint_work - &
         (self%kinetic + self%strain - self%kinetic_start - self%strain_start)
      self%q_last = q
      self%v_last = v
      self%a_last = a
      self%qdd_last = qdd
      self%force_last = force
      self%reaction_last = reaction
      self%mass_last = mass
   end subroutine add_scheme_step

   !> The applied force Q(q, v, t) (loads and gravity) and the constraint force Phi_q^T lambda.
   subroutine step_forces(mech, t, q, v, lambda, force, reaction, error)
      class(mechanism_t), intent(inout) :: mech
      real(dp), intent(in) :: t, q(:), v(:), lambda(:)
      real(dp), intent(out) :: force(:), reaction(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: phi_q(:, :)
      allocate (phi_q(mech%nc, mech%n))
      call mech%applied_force(q, v, t, force, error)
      if (allocated(error)) return
      call mech%constraint_jacobian(q, t, phi_q, error)
      if (allocated(error)) return
      reaction = matmul(lambda, phi_q)
   end subroutine step_forces

   !> x^T C x of the bodies' own damping: body_t%damping_power of the slices of x.
   real(dp) function damping_form(mech, x)
      class(mechanism_t), intent(in) :: mech
      real(dp), intent(in) :: x(:)
      integer :: b, k, nb
      damping_form = 0.0_dp
      if (.not. allocated(mech%bodies)) return
      do b = 1, size(mech%bodies)
         k = mech%bodies(b)%offset
         nb = mech%bodies(b)%body%num_coordinates
         damping_form = damping_form + mech%bodies(b)%body%damping_power(x(k + 1:k + nb))
      end do
   end function damping_form

   !> T + U at the last update (J).
   pure real(dp) function energy_balance_total(self) result(energy)
      !> The balance
      class(energy_balance_t), intent(in) :: self
      energy = self%kinetic + self%strain
   end function energy_balance_total

   !> T, U, P (applied loads, gravity, drive if lambda is given) and P_d at one state; all finite.
   subroutine evaluate(mech, t, q, v, kinetic, strain, power, damping_power, error, lambda)
      class(mechanism_t), intent(inout) :: mech
      real(dp), intent(in) :: t, q(:), v(:)
      real(dp), intent(out) :: kinetic, strain, power, damping_power
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: lambda(:)
      real(dp), allocatable :: phi_t(:)
      integer :: k
      kinetic = 0.0_dp
      strain = 0.0_dp
      power = 0.0_dp
      damping_power = 0.0_dp
      if (size(q) /= mech%n .or. size(v) /= mech%n) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'energy balance: ' // to_str(size(q)) // &
            ' coordinates and ' // to_str(size(v)) // ' velocities for a mechanism with ' // &
            to_str(mech%n) // '; pass the integrator state')
         return
      end if
      kinetic = mech%kinetic_energy(q, v)
      strain = mech%strain_energy(q)
      call mech%applied_power(q, v, t, power, error)
      if (allocated(error)) return
      ! Driving constraint: power of its reaction, -lambda_d (Phi_q v)_d = lambda_d Phi_t,d.
      if (present(lambda) .and. (mech%drive_row > 0 .or. allocated(mech%drivers))) then
         if (size(lambda) /= mech%nc) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'energy balance: ' // &
               to_str(size(lambda)) // ' multipliers for ' // to_str(mech%nc) // &
               ' constraint rows; pass the integrator lambda')
            return
         end if
         allocate (phi_t(mech%nc))
         call mech%constraint_rate(q, t, phi_t, error)
         if (allocated(error)) return
         if (mech%drive_row > 0) power = power + lambda(mech%drive_row) * &
            phi_t(mech%drive_row)
         ! Drivers of joints: lambda Phi_t = tau f' on the constraint (ffrf_mbs_joint_driver)
         if (allocated(mech%drivers)) then
            do k = 1, size(mech%drivers)
               power = power + lambda(mech%drivers(k)%row) * phi_t(mech%drivers(k)%row)
            end do
         end if
      end if
      ! Physical damping of the bodies (body_t%damping_power): the flexible bodies' modal
      ! damping P_d = zeta_dot^T D_ff zeta_dot, zero for rigid bodies and the ground.
      if (.not. allocated(mech%bodies)) return
      damping_power = damping_form(mech, v)
      if (.not. (ieee_is_finite(kinetic) .and. ieee_is_finite(strain) .and. &
         ieee_is_finite(power) .and. ieee_is_finite(damping_power))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'energy balance: NaN or Inf in T = ' // &
            to_str(kinetic) // ' J, U = ' // to_str(strain) // ' J, P = ' // to_str(power) // &
            ' W or P_d = ' // to_str(damping_power) // ' W at t = ' // to_str(t, 12) // ' s')
      end if
   end subroutine evaluate

   !> Every accumulator of the balance (checkpoint): t, T, U, T_0, U_0, W, D_p, D, P, P_d, the
   !> number of updates; D_s, W_m, D_p,m, C_m, D_k, the scheme flag and parameters (4), n; then
   !> q, v, a, q'', Q and Phi_q^T lambda of the last update (n each; n = 0 without the scheme).
   pure function energy_balance_export_state(self) result(state)
      class(energy_balance_t), intent(in) :: self
      real(dp), allocatable :: state(:)
      integer :: n
      n = 0
      if (self%has_scheme) n = size(self%q_last)
      state = [self%t, self%kinetic, self%strain, self%kinetic_start, self%strain_start, &
         self%work, self%physical_dissipation, self%numerical_dissipation, self%power, &
         self%damping_power, real(self%steps, dp), self%scheme_dissipation, &
         self%step_work, self%step_damping, self%constraint_work, &
         self%kinematic_dissipation, merge(1.0_dp, 0.0_dp, self%has_scheme), self%scheme, &
         real(n, dp)]
      if (n > 0) state = [state, self%q_last, self%v_last, self%a_last, self%qdd_last, &
         self%force_last, self%reaction_last]
   end function energy_balance_export_state

   !> Restore the accumulators of export_state; .false. when `state` has the wrong size. The mass
   !> matrix at the last q is recomputed at the next update.
   subroutine energy_balance_import_state(self, state, ok)
      class(energy_balance_t), intent(inout) :: self
      real(dp), intent(in) :: state(:)
      logical, intent(out) :: ok
      integer, parameter :: head = 22
      integer :: n
      ok = size(state) >= head
      if (.not. ok) return
      n = nint(state(head))
      ok = n >= 0 .and. size(state) == head + 6 * n
      if (.not. ok) return
      self%t = state(1)
      self%kinetic = state(2)
      self%strain = state(3)
      self%kinetic_start = state(4)
      self%strain_start = state(5)
      self%work = state(6)
      self%physical_dissipation = state(7)
      self%numerical_dissipation = state(8)
      self%power = state(9)
      self%damping_power = state(10)
      self%steps = nint(state(11))
      self%scheme_dissipation = state(12)
      self%step_work = state(13)
      self%step_damping = state(14)
      self%constraint_work = state(15)
      self%kinematic_dissipation = state(16)
      self%has_scheme = state(17) > 0.5_dp .and. n > 0
      self%scheme = state(18:21)
      if (allocated(self%mass_last)) deallocate (self%mass_last)
      if (self%has_scheme) then
         self%q_last = state(head + 1:head + n)
         self%v_last = state(head + n + 1:head + 2 * n)
         self%a_last = state(head + 2 * n + 1:head + 3 * n)
         self%qdd_last = state(head + 3 * n + 1:head + 4 * n)
         self%force_last = state(head + 4 * n + 1:head + 5 * n)
         self%reaction_last = state(head + 5 * n + 1:head + 6 * n)
      end if
   end subroutine energy_balance_import_state

end module ffrf_mbs_energy_balance
