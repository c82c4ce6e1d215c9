!> Error estimates and rules of the automatic engine model (issue 4, part 3; the choices are made
!> by ffrf_app_engine_auto_model). Everything is predicted before the integration, in the periodic
!> regime of the rigid engine:
!>
!> 1. Excitation. Regime speed from the balance of the mean indicated torque and the drag load,
!>    T_i = c omega_r^2. Over one 720 deg cycle at omega_r, the conrod axial force of the rigid
!>    slider-crank, gas force plus the inertia of the reciprocating mass m,
!>       F(theta) = F_in - F_gas l / s,  F_in = m y''(theta) omega_r^2 l / s,
!>       y = r cos(theta) + s,  s = sqrt(l^2 - r^2 sin^2 theta)    (piston from the crank axis),
!>    and its lever on the crank L(theta) = -y'(theta) s / l (crank torque T = F L). Complex
!>    harmonics F_k at f_k = k omega_r / (4 pi), k = 1..NUM_HARMONICS (F(theta) = Re sum F_k
!>    e^(i k theta / 2) + mean).
!> 2. A mode j of a flexible body, frequency f~_j with the masses m_i jointed at its interfaces
!>    (Rayleigh quotient with point masses; u_ji the translation of virtual node i relative to
!>    the interfaces the bearings hold, ffrf_app_engine_auto_model):
!>       f~_j = f_j / sqrt(1 + A_j),  A_j = sum_i m_i |u_ji|^2,  mu_j = A_j / (1 + A_j).
!>    In a statically determinate chain the quasi-static deflection of the mode does not change
!>    the joint forces; its dynamic excess does, through the inertia of the jointed masses, a
!>    share mu_j of the modal mass:
!>       dF_j(theta) = mu_j Re sum_k F_k (H(f_k / f~_j) - 1) e^(i k theta / 2),
!>       H(r) = 1 / (1 - r^2 + 2 i max(zeta, 0.05) r)     (zeta: the body's modal damping):
!>    at least 5 % damping, which caps a resonance at |H| = 10, for the engine's speed that
!>    varies by about +-6 % over a cycle and whose regime value is an estimate. The mode's force
!>    error if dropped is e_j = |dF_j(theta_peak)| / max |F| at the angle of the peak force; its
!>    regime-speed error (delta omega / omega = delta T / (2 T) from T_i = c omega^2) is
!>    s_j = |mean(dF_j L)| / (2 T_i) plus what its static compliance c_j = sum_i |u_ji|^2 /
!>    (2 pi f~_j)^2 at the loaded interfaces takes from the cycle work: along the conrod it
!>    shortens the stroke under the gas load, c |mean(G F')| (G = F - F_in), across the crank arm
!>    it turns the pin against the frame whose angle drives p(theta), c |mean(y' T F_gas')| / r^2.
!>    Modes are dropped in increasing e_j while the dropped e_j and s_j stay within their
!>    budgets; a body that keeps none moves rigidly (with its mesh's inertia).
!> 3. Mesh: a mode's frequency error delta_j (first-order Richardson from two meshes, element
!>    size ~ nodes^(-1/3); the rates measured on the crank lie between 1 and 2.5, so order 1
!>    overestimates) moves dF_j to its value at f~_j (1 - delta_j) (Tet10 frequencies converge
!>    from above) and c_j by 2 delta_j; the change is the mesh error.
!> 4. Step: the rigid chain's error from generalized-alpha's periodic response of a free mass to
!>    each harmonic of F_in (the steady state S of its recurrence s_(n+1) = A s_n + b f_(n+1) +
!>    c f_n, (z I - A) S = z b + c, z = e^(i Omega h)), plus each kept mode's dynamic errors
!>    (e_j, s_j without the static part) times eps_j = |w~/w - 1| + xi~, the method's relative
!>    period error plus algorithmic damping ratio at w_j h (from the eigenvalues of its
!>    amplification matrix). The peak force read from the steps adds (1/2) |F''| (omega_r h /
!>    2)^2 / max|F| (the steps fall up to half a step from the peak). The largest step of the
!>    ladder {1, 1.25, 1.6, 2, 2.5, 3.2, 4, 5, 6.4, 8} 10^n within the budgets and a crank turn of
!>    at most 10 deg per step is taken.
module ffrf_app_engine_model_selection
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_app_model_estimates, only: STEP_LADDER, galpha_response, galpha_mode, &
      jointed_mass_share
   use ffrf_app_engine_pressure, only: pressure_model_t
   implicit none
   private
   public :: excitation_t, engine_excitation, set_harmonics, mode_effect_t, mode_effect
   public :: galpha_mode, effective_frequencies, jointed_mass_share, exact_response
   public :: galpha_response
   public :: mode_errors, body_selection_t, select_modes, mesh_frequency_error, static_speed_error
   public :: step_errors, select_time_step
   public :: STEP_LADDER, MAX_TURN_PER_STEP, RESONANCE_FLOOR, NUM_HARMONICS

   !> Largest crank turn per step (rad): 10 deg
   real(dp), parameter :: MAX_TURN_PER_STEP = 10.0_dp * pi / 180.0_dp
   !> Least 2 zeta in a mode's response (module header, 2): resonances capped at 1/0.1
   real(dp), parameter :: RESONANCE_FLOOR = 0.1_dp
   !> Harmonics of the 720 deg cycle kept (f up to 360 times the crank speed)
   integer, parameter :: NUM_HARMONICS = 720
   !> Samples of the cycle for the harmonics and for the maxima over theta
   integer, parameter :: CYCLE_SAMPLES = 2880

   !> The engine's excitation at its estimated regime speed.
   type :: excitation_t
      !> Regime speed omega_r (rad/s), cycle frequency omega_r / (4 pi) (Hz), T_i (N m)
      real(dp) :: regime_speed = 0.0_dp, cycle_hz = 0.0_dp, mean_torque = 0.0_dp
      !> Largest |F| over the cycle (N)
      real(dp) :: peak_force = 0.0_dp
      !> |F''(theta)| / max|F| at the peak (1/rad^2)
      real(dp) :: peak_curvature = 0.0_dp
      !> Floor of |1 - r^2| in a mode's response (module header, 2)
      real(dp) :: resonance_floor = RESONANCE_FLOOR
      !> Complex harmonics k = 1..NUM_HARMONICS of F, of its inertia part F_in and of the lever L
      complex(dp), allocatable :: force(:), inertia(:), lever(:)
      !> Means of F (N) and of the lever (m): mean(F L) = T_i at constant speed
      real(dp) :: mean_force = 0.0_dp, mean_lever = 0.0_dp
      !> mean(G dF/dtheta) (N^2), G = F - F_in the gas part: the cycle work lost per unit
      !> compliance of the crank pin along the conrod, divided by 4 pi (module header, 2)
      real(dp) :: work_per_compliance = 0.0_dp
      !> mean(y' T dF_gas/dtheta) / r^2 (N^2): the same for a compliance across the crank arm,
      !> which turns the pin against the crank frame whose angle drives p(theta) (header, 2)
      real(dp) :: torsion_per_compliance = 0.0_dp
      !> Cycle angle of the largest |F| (rad) and e^(i k theta_peak / 2), k = 1..NUM_HARMONICS
      real(dp) :: peak_angle = 0.0_dp
      complex(dp), allocatable :: phase(:)
   end type excitation_t

   !> Force and regime-speed errors; for a mode also the part of the speed error that comes
   !> from its static compliance (no time-step effect).
   type :: mode_effect_t
      real(dp) :: force = 0.0_dp, speed = 0.0_dp, static_speed = 0.0_dp
   end type mode_effect_t

   !> What the selection chose for one flexible body.
   type :: body_selection_t
      !> Kept modes (indices into the candidates, ascending); empty: the body stays rigid
      integer, allocatable :: kept(:)
      !> Candidate frequencies with the jointed masses (Hz) and the jointed-mass shares mu_j
      real(dp), allocatable :: loaded_hz(:), mass_share(:)
      !> Force and speed error of each candidate if dropped (e_j, s_j)
      type(mode_effect_t), allocatable :: effect(:)
      !> Static compliance of each candidate at the loaded interfaces (m/N)
      real(dp), allocatable :: compliance(:)
      !> Modal damping ratio of the body
      real(dp) :: damping = 0.0_dp
      !> Sums over the dropped candidates, and the effect of one mode just above the candidates
      !> with mu = 1 (an estimate of what the candidates leave out)
      type(mode_effect_t) :: truncation, tail
   end type body_selection_t

contains

   !> The excitation of the single-cylinder engine at the regime speed where the mean indicated
   !> torque balances the drag c omega^2 (module header, 1).
   subroutine engine_excitation(pressure, reciprocating_mass, drag_coefficient, excitation)
      type(pressure_model_t), intent(in) :: pressure
      !> Piston mass (kg)
      real(dp), intent(in) :: reciprocating_mass
      !> Drag coefficient c (N m s^2), > 0
      real(dp), intent(in) :: drag_coefficient
      type(excitation_t), intent(out) :: excitation
      real(dp) :: theta, r, l, sn, cs, s, y1, y2, omega
      real(dp) :: force(CYCLE_SAMPLES), inertia(CYCLE_SAMPLES), lever(CYCLE_SAMPLES)
      real(dp) :: piston_speed(CYCLE_SAMPLES), gas(CYCLE_SAMPLES)
      integer :: i
      excitation%mean_torque = pressure%mean_indicated_torque()
      omega = sqrt(max(excitation%mean_torque, 0.0_dp) / drag_coefficient)
      r = pressure%crank_radius
      l = pressure%input%conrod_length
      do i = 1, CYCLE_SAMPLES
         theta = 4.0_dp * pi * real(i - 1, dp) / real(CYCLE_SAMPLES, dp)
         sn = sin(theta)
         cs = cos(theta)
         s = sqrt(l**2 - (r * sn)**2)
         ! y'(theta), y''(theta) of y = r cos(theta) + s
         y1 = -r * sn - r**2 * sn * cs / s
         y2 = -r * cs - r**2 * (cs**2 - sn**2) / s - r**4 * sn**2 * cs**2 / s**3
         inertia(i) = reciprocating_mass * y2 * omega**2 * l / s
         force(i) = inertia(i) - pressure%piston_force(theta) * l / s
         lever(i) = -y1 * s / l
         piston_speed(i) = y1
      end do
      excitation%regime_speed = omega
      excitation%cycle_hz = omega / (4.0_dp * pi)
      call set_harmonics(excitation, force, inertia, lever)
      ! the pin turns by c T / r^2 against the frame: the piston runs at theta + c T / r^2 under
      ! p(theta); the cycle work changes by -c / r^2 closed integral of y' T dF_gas
      gas = -pressure%piston_force([(4.0_dp * pi * real(i - 1, dp) / real(CYCLE_SAMPLES, dp), &
         i=1, CYCLE_SAMPLES)])
      excitation%torsion_per_compliance = sum(piston_speed * force * lever * &
         (cshift(gas, 1) - cshift(gas, -1)) / (8.0_dp * pi / real(CYCLE_SAMPLES, dp))) / &
         real(CYCLE_SAMPLES, dp) / r**2
   end subroutine engine_excitation

   !> Harmonics of the sampled cycle signals (even samples over 720 deg) and the phase table.
   pure subroutine set_harmonics(excitation, force, inertia, lever)
      type(excitation_t), intent(inout) :: excitation
      real(dp), intent(in) :: force(:), inertia(:), lever(:)
      real(dp) :: angle
      integer :: k, n
      n = maxloc(abs(force), dim=1)
      excitation%peak_force = abs(force(n))
      ! central second difference on the sample grid (periodic)
      excitation%peak_curvature = abs(force(modulo(n, size(force)) + 1) - 2.0_dp * force(n) + &
         force(modulo(n - 2, size(force)) + 1)) / (4.0_dp * pi / real(size(force), dp))**2 / &
         max(excitation%peak_force, tiny(1.0_dp))
      excitation%peak_angle = 4.0_dp * pi * real(n - 1, dp) / real(size(force), dp)
      excitation%force = harmonics(force)
      excitation%inertia = harmonics(inertia)
      excitation%lever = harmonics(lever)
      excitation%mean_force = sum(force) / real(size(force), dp)
      excitation%mean_lever = sum(lever) / real(size(lever), dp)
      ! mean(G F') = (1/2) sum_k (k/2) Im(G_k conj(F_k)), G_k = F_k - F_in,k
      excitation%work_per_compliance = 0.5_dp * sum([(0.5_dp * real(k, dp) * &
         aimag((excitation%force(k) - excitation%inertia(k)) * conjg(excitation%force(k))), &
         k=1, NUM_HARMONICS)])
      allocate (excitation%phase(NUM_HARMONICS))
      do k = 1, NUM_HARMONICS
         angle = 0.5_dp * real(k, dp) * excitation%peak_angle
         excitation%phase(k) = cmplx(cos(angle), sin(angle), dp)
      end do
   contains
      !> c_k with x(theta) = mean + Re sum c_k e^(i k theta / 2): c_k = (2/N) sum x_n e^(-i ...)
      pure function harmonics(x) result(c)
         real(dp), intent(in) :: x(:)
         complex(dp) :: c(NUM_HARMONICS)
         real(dp) :: phase(size(x))
         integer :: j
         phase = 2.0_dp * pi * [(real(j, dp), j=0, size(x) - 1)] / real(size(x), dp)
         do j = 1, NUM_HARMONICS
            c(j) = 2.0_dp / real(size(x), dp) * cmplx(sum(x * cos(j * phase)), &
               -sum(x * sin(j * phase)), dp)
         end do
      end function harmonics
   end subroutine set_harmonics

   !> f~_j = f_j / sqrt(1 + A_j), A_j = sum_i m_i |u_ji|^2 (module header, 2).
   pure function effective_frequencies(frequency_hz, virtual_node_shape, attached_mass) &
         result(loaded_hz)
      real(dp), intent(in) :: frequency_hz(:)
      !> (6 num_interfaces, modes): [u; theta] per interface, mass-normalised modes
      real(dp), intent(in) :: virtual_node_shape(:, :)
      !> Mass jointed at each interface (kg)
      real(dp), intent(in) :: attached_mass(:)
      real(dp) :: loaded_hz(size(frequency_hz))
      real(dp) :: share(size(frequency_hz))
      share = jointed_mass_share(virtual_node_shape, attached_mass)
      loaded_hz = frequency_hz * sqrt(1.0_dp - share)
   end function effective_frequencies

   !> H(r) = 1 / (1 - r^2 + 2 i max(zeta, floor/2) r) (module header, 2): the damping at
   !> least floor/2, so that |H| <= 1/floor at resonance.
   pure function exact_response(r, zeta, floor) result(h)
      real(dp), intent(in) :: r, zeta
      !> Least 2 zeta (0: none)
      real(dp), intent(in) :: floor
      complex(dp) :: h
      h = 1.0_dp / cmplx(1.0_dp - r**2, 2.0_dp * max(zeta, 0.5_dp * floor) * r, dp)
   end function exact_response

   !> Errors of the peak force and of the regime speed from a force perturbation with
   !> harmonics dF_k: |Re sum dF_k e^(i k theta_peak/2)| / max|F| and |mean(dF L)| / (2 T_i).
   pure function mode_errors(excitation, perturbation) result(effect)
      type(excitation_t), intent(in) :: excitation
      complex(dp), intent(in) :: perturbation(:)
      type(mode_effect_t) :: effect
      effect%force = abs(real(sum(perturbation * excitation%phase), dp)) / &
         max(excitation%peak_force, tiny(1.0_dp))
      ! mean of the product of two signals without means: (1/2) Re sum a_k conj(b_k)
      effect%speed = abs(0.5_dp * real(sum(perturbation * conjg(excitation%lever)), dp)) / &
         (2.0_dp * max(excitation%mean_torque, tiny(1.0_dp)))
   end function mode_errors

   !> The errors a mode at f~ (Hz) with jointed-mass share mu, damping zeta and static
   !> compliance at the loaded interfaces c (m/N) causes (module header, 2): its dynamic excess,
   !> and for the speed also its quasi-static deflection, which shortens the stroke under load
   !> and so changes the cycle work by 4 pi c mean(G F').
   pure function mode_effect(excitation, loaded_hz, share, zeta, compliance) result(effect)
      type(excitation_t), intent(in) :: excitation
      real(dp), intent(in) :: loaded_hz, share, zeta, compliance
      type(mode_effect_t) :: effect
      complex(dp) :: perturbation(size(excitation%force))
      integer :: k
      do k = 1, size(perturbation)
         perturbation(k) = share * excitation%force(k) * (exact_response(k * &
            excitation%cycle_hz / loaded_hz, zeta, excitation%resonance_floor) - 1.0_dp)
      end do
      effect = mode_errors(excitation, perturbation)
      effect%static_speed = static_speed_error(excitation, compliance)
      effect%speed = effect%speed + effect%static_speed
   end function mode_effect

   !> Regime-speed error of a crank-pin compliance c (m/N), along the conrod (stroke) and across
   !> the crank arm (phase of p against the piston), each at its largest: c (|mean(G F')| +
   !> |mean(y' T F_gas')| / r^2) / (2 T_i) (module header, 2).
   pure function static_speed_error(excitation, compliance) result(error)
      type(excitation_t), intent(in) :: excitation
      real(dp), intent(in) :: compliance
      real(dp) :: error
      error = compliance * (abs(excitation%work_per_compliance) + &
         abs(excitation%torsion_per_compliance)) / (2.0_dp * &
         max(excitation%mean_torque, tiny(1.0_dp)))
   end function static_speed_error

   !> c_j = sum over the interfaces with a jointed mass of |u_ji|^2 / (2 pi f~_j)^2 (m/N): the
   !> mode's static compliance there, in the direction it moves (an upper bound along any load).
   pure function modal_compliance(loaded_hz, virtual_node_shape, attached_mass) &
         result(compliance)
      real(dp), intent(in) :: loaded_hz(:), virtual_node_shape(:, :), attached_mass(:)
      real(dp) :: compliance(size(loaded_hz))
      integer :: j, i
      compliance = 0.0_dp
      do j = 1, size(loaded_hz)
         do i = 1, size(attached_mass)
            if (attached_mass(i) <= 0.0_dp) cycle
            compliance(j) = compliance(j) + sum(virtual_node_shape(6 * i - 5:6 * i - 3, j)**2) &
               / (2.0_dp * pi * loaded_hz(j))**2
         end do
      end do
   end function modal_compliance

   !> Drop the candidates of smallest force error while the dropped force and speed errors stay
   !> within their budgets (module header, 2). Frequencies ascending.
   pure subroutine select_modes(excitation, frequency_hz, virtual_node_shape, attached_mass, &
         zeta, force_budget, speed_budget, selection)
      type(excitation_t), intent(in) :: excitation
      real(dp), intent(in) :: frequency_hz(:), virtual_node_shape(:, :), attached_mass(:)
      real(dp), intent(in) :: zeta, force_budget, speed_budget
      type(body_selection_t), intent(out) :: selection
      integer, allocatable :: order(:)
      logical, allocatable :: keep(:)
      real(dp), allocatable :: forces(:)
      integer :: j, n, i
      n = size(frequency_hz)
      selection%damping = zeta
      selection%mass_share = jointed_mass_share(virtual_node_shape, attached_mass)
      selection%loaded_hz = frequency_hz * sqrt(1.0_dp - selection%mass_share)
      selection%compliance = modal_compliance(selection%loaded_hz, virtual_node_shape, &
         attached_mass)
      allocate (selection%effect(n))
      do j = 1, n
         selection%effect(j) = mode_effect(excitation, selection%loaded_hz(j), &
            selection%mass_share(j), zeta, selection%compliance(j))
      end do
      if (n > 0) selection%tail = mode_effect(excitation, maxval(frequency_hz), 1.0_dp, zeta, &
         selection%compliance(n))
      forces = selection%effect%force
      order = sort_ascending(forces)
      allocate (keep(n), source=.true.)
      do i = 1, n
         j = order(i)
         if (selection%truncation%force + selection%effect(j)%force > force_budget .or. &
            selection%truncation%speed + selection%effect(j)%speed > speed_budget) exit
         selection%truncation%force = selection%truncation%force + selection%effect(j)%force
         selection%truncation%speed = selection%truncation%speed + selection%effect(j)%speed
         keep(j) = .false.
      end do
      selection%kept = pack([(j, j=1, n)], keep)
   end subroutine select_modes

   !> Indices that sort x ascending (insertion sort: a few tens of modes).
   pure function sort_ascending(x) result(order)
      real(dp), intent(in) :: x(:)
      integer :: order(size(x))
      integer :: i, j, t
      order = [(i, i=1, size(x))]
      do i = 2, size(x)
         t = order(i)
         j = i - 1
         do while (j >= 1)
            if (x(order(j)) <= x(t)) exit
            order(j + 1) = order(j)
            j = j - 1
         end do
         order(j + 1) = t
      end do
   end function sort_ascending

   !> Mesh error of the kept modes of a selection whose candidate frequencies have relative
   !> errors delta_j: the change of each kept mode's dF when f~_j drops by delta_j (module
   !> header, 3), summed.
   pure function mesh_frequency_error(excitation, selection, delta) result(effect)
      type(excitation_t), intent(in) :: excitation
      type(body_selection_t), intent(in) :: selection
      real(dp), intent(in) :: delta(:)
      type(mode_effect_t) :: effect
      complex(dp) :: perturbation(size(excitation%force))
      type(mode_effect_t) :: one
      real(dp) :: r_now, r_true
      integer :: i, j, k
      do i = 1, size(selection%kept)
         j = selection%kept(i)
         do k = 1, size(perturbation)
            r_now = k * excitation%cycle_hz / selection%loaded_hz(j)
            r_true = r_now / (1.0_dp - min(delta(j), 0.5_dp))
            perturbation(k) = selection%mass_share(j) * excitation%force(k) * &
               (exact_response(r_true, selection%damping, excitation%resonance_floor) - &
               exact_response(r_now, selection%damping, excitation%resonance_floor))
         end do
         one = mode_errors(excitation, perturbation)
         ! the static compliance 1/w^2 grows by about 2 delta
         effect%force = effect%force + one%force
         effect%speed = effect%speed + one%speed + static_speed_error(excitation, 2.0_dp * &
            min(delta(j), 0.5_dp) * selection%compliance(j))
      end do
   end function mesh_frequency_error

   !> Step error at step h (module header, 4): the rigid chain's, from generalized-alpha's
   !> periodic response of a free mass to each harmonic of F_in, plus each kept mode's error
   !> effect_j (e_j, s_j) times eps_j = |w~/w - 1| + xi~ (relative period error plus algorithmic
   !> damping ratio of the method at w_j h, at most 1): the share of its dynamic response the
   !> method gets wrong.
   function step_errors(excitation, mode_hz, mode_effect, h, rho_inf) result(effect)
      type(excitation_t), intent(in) :: excitation
      !> Kept modes: frequencies with the jointed masses (Hz) and their errors if dropped
      real(dp), intent(in) :: mode_hz(:)
      type(mode_effect_t), intent(in) :: mode_effect(:)
      real(dp), intent(in) :: h, rho_inf
      type(mode_effect_t) :: effect
      complex(dp) :: perturbation(size(excitation%force))
      real(dp) :: omega, frequency_ratio, added_damping, eps
      integer :: j, k
      do k = 1, size(perturbation)
         omega = 2.0_dp * pi * k * excitation%cycle_hz
         perturbation(k) = excitation%inertia(k) * (galpha_response(0.0_dp, 0.0_dp, omega, h, &
            rho_inf) - 1.0_dp)
      end do
      effect = mode_errors(excitation, perturbation)
      do j = 1, size(mode_hz)
         call galpha_mode(2.0_dp * pi * mode_hz(j) * h, rho_inf, frequency_ratio, added_damping)
         eps = min(abs(frequency_ratio - 1.0_dp) + added_damping, 1.0_dp)
         effect%force = effect%force + eps * mode_effect(j)%force
         effect%speed = effect%speed + eps * (mode_effect(j)%speed - mode_effect(j)%static_speed)
      end do
      ! the peak taken from the steps: up to half a step of crank turn from the true peak
      effect%force = effect%force + 0.5_dp * excitation%peak_curvature * (0.5_dp * &
         excitation%regime_speed * h)**2
   end function step_errors

   !> The largest step of the ladder (10^-7..10^-2 s) whose step errors stay within the budgets
   !> and whose crank turn at the regime speed is at most MAX_TURN_PER_STEP: searched downwards
   !> from the turn limit (the errors grow with h). h = 1e-7 s if none is within the budgets.
   subroutine select_time_step(excitation, mode_hz, mode_effect, rho_inf, force_budget, &
         speed_budget, h, effect)
      type(excitation_t), intent(in) :: excitation
      real(dp), intent(in) :: mode_hz(:), rho_inf, force_budget, speed_budget
      type(mode_effect_t), intent(in) :: mode_effect(:)
      real(dp), intent(out) :: h
      type(mode_effect_t), intent(out) :: effect
      integer :: decade, m
      do decade = -3, -7, -1
         do m = size(STEP_LADDER), 1, -1
            h = STEP_LADDER(m) * 10.0_dp**decade
            if (h * excitation%regime_speed > MAX_TURN_PER_STEP) cycle
            effect = step_errors(excitation, mode_hz, mode_effect, h, rho_inf)
            if (effect%force <= force_budget .and. effect%speed <= speed_budget) return
         end do
      end do
   end subroutine select_time_step

end module ffrf_app_engine_model_selection
