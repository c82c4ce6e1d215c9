!> Energy watch of a mechanism run (issue 30, part 3): the energy balance (ffrf_mbs_energy_balance)
!> is watched while the run goes, and an energy the model cannot account for is a warning with
!> its time and body, or (energy_watch = 'stop') the end of the run with FFRF_NUMERIC_ERROR.
!> Two criteria, both checked after every accepted step:
!>
!> 1. Energy created. Along the exact solution W = dT + dU + D_p; generalized-alpha with
!>    rho_inf < 1 only removes energy, so its own dissipation D_s (the per-step energy identity,
!>    docs/theory.md 4.4: work of the step-mean forces minus the change of T + U) is >= 0 up to
!>    round-off, and an integration that creates energy makes it negative. The spurious energy
!>        S = -D_s   (-D, the balance's residual, when D_s is not accumulated)
!>    is watched against the energy scale of the run,
!>        S > tolerance * E_ref,   E_ref = max over the run so far of (T + U + |W| + D_p),
!>    tolerance = energy_watch_tolerance (default 1e-4). D itself is not used when D_s is there:
!>    it also holds the O(h^2) quadrature error of the trapezoidal work, which is negative at the
!>    start of the engines from rest (-D / E_ref = 1.8e-4 at the first step of the all-rigid
!>    engine, h = 1e-4 s; 1.2e-6 at h = 2.5e-5 s). Measured -D_s / E_ref: <= 1.5e-6 (all-rigid
!>    engine, second step, 2.7e-9 J), <= 7e-8 on the flexible engines (h = 2.5e-5 .. 1e-4 s,
!>    10 and 30 modes, 2 s): the default leaves a margin of about 70. Criterion 1 is checked
!>    from the end of the first window on: from rest E_ref starts at zero, and the identity's
!>    start transient (-D_s = 2.3e-10 J at the first step, h = 6.25e-6 s, rho_inf = 0.5) is then
!>    1.1e-4 of E_ref = 2.1e-6 J; after 0.1 s the engines' worst is 4.9e-7 (all rigid, at the
!>    first combustion, t = 0.136 s), the flexible ones' 7e-8.
!>
!> 2. Strain energy growing without work to pay for it. For each flexible body the largest
!>    strain energy U_b within consecutive windows of `window` seconds (energy_watch_window,
!>    default 0.1 s) is kept; a steady forced response has a bounded envelope, an instability
!>    (physical or numerical) a growing one. The watch warns when the envelope has grown in each
!>    of GROWTH_WINDOWS = 5 consecutive windows and by more than GROWTH_FACTOR = 4 over them,
!>    beyond what the forcing can pay: the strain energy of a forced response scales with the
!>    square of the force, and the inertia forces with the kinetic energy T of the mechanism,
!>        U_b,k / U_b,k-5 > 4 max(1, (T_k / T_k-5)^2)
!>    (U_b,k, T_k: the largest U_b and T in window k), once U_b,k exceeds GROWTH_FLOOR = 1e-4 of
!>    E_ref (below, a modal response at round-off level: a conrod mode left unexcited grew from
!>    5e-49 J to 3e-42 J in 0.5 s on the engine of input/engine_rigid.nml with OpenBLAS's
!>    Nehalem kernel). A run speeding up from rest (T growing) therefore does not trigger it; a
!>    rotor at a steady speed whose strain energy grows does (the undamped RC set 2 engine:
!>    1.7 J against a floor of 0.36 J at its warning).
!>
!> Each criterion warns once per body (criterion 1 names the body whose T_b + U_b grew most over
!> the current window, where the energy appears); the warnings are kept in `warnings` (text,
!> time, body) for the results file and the log. 'stop' turns the first warning into an error.
module ffrf_mbs_energy_watch
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: energy_watch_t, energy_watch_settings_t, energy_watch_kind, energy_watch_word
   public :: ENERGY_WATCH_OFF, ENERGY_WATCH_WARN, ENERGY_WATCH_STOP, ENERGY_WATCH_WORDS
   public :: GROWTH_WINDOWS, GROWTH_FACTOR, GROWTH_FLOOR

   !> What the watch does: nothing, a warning, or a stop with FFRF_NUMERIC_ERROR
   integer, parameter :: ENERGY_WATCH_OFF = 1, ENERGY_WATCH_WARN = 2, ENERGY_WATCH_STOP = 3
   !> The words of &integrator energy_watch, in the order of the kinds above (the one table)
   character(len=4), parameter :: ENERGY_WATCH_WORDS(3) = ['off ', 'warn', 'stop']
   !> Consecutive windows of growing strain energy, and the growth over them (criterion 2)
   integer, parameter :: GROWTH_WINDOWS = 5
   real(dp), parameter :: GROWTH_FACTOR = 4.0_dp
   !> Fraction of the energy scale E_ref below which a strain envelope is not watched
   real(dp), parameter :: GROWTH_FLOOR = 1.0e-4_dp

   !> Settings (&integrator energy_watch, energy_watch_tolerance, energy_watch_window).
   type :: energy_watch_settings_t
      !> ENERGY_WATCH_OFF, _WARN (default) or _STOP
      integer :: mode = ENERGY_WATCH_WARN
      !> Spurious energy S relative to the run's energy scale E_ref that warns (criterion 1)
      real(dp) :: tolerance = 1.0e-4_dp
      !> Window of the strain-energy envelope (s) (criterion 2)
      real(dp) :: window = 0.1_dp
   end type energy_watch_settings_t

   !> One warning: what, when (s) and where.
   type :: energy_warning_t
      character(len=:), allocatable :: text, body
      real(dp) :: t = 0.0_dp
   end type energy_warning_t

   !> The watch of one run (module header).
   type :: energy_watch_t
      type(energy_watch_settings_t) :: settings
      !> Body names (mechanism order) and which are flexible (criterion 2)
      character(len=64), allocatable :: names(:)
      logical, allocatable :: flexible(:)
      !> Energy scale E_ref so far (J)
      real(dp) :: scale = 0.0_dp
      !> Start of the current window (s); largest T and U_b in it; T_b + U_b at its start
      real(dp) :: window_start = 0.0_dp, kinetic_max = 0.0_dp
      !> Time from which criterion 1 is checked: the end of the first window (s)
      real(dp) :: created_from = 0.0_dp
      real(dp), allocatable :: strain_max(:), energy_at_start(:)
      !> Envelopes of the closed windows, newest last (GROWTH_WINDOWS + 1 kept): T and U_b
      real(dp), allocatable :: kinetic_envelope(:), strain_envelope(:, :)
      integer :: closed_windows = 0
      !> Consecutive growing windows of each body's strain envelope
      integer, allocatable :: growing(:)
      !> A warning was issued: energy created (criterion 1), growth of body b (criterion 2)
      logical :: created_warned = .false.
      logical, allocatable :: growth_warned(:)
      !> Largest S / E_ref seen, and when (for the log and the tests)
      real(dp) :: worst_ratio = 0.0_dp
      real(dp) :: worst_time = 0.0_dp
      type(energy_warning_t), allocatable :: warnings(:)
   contains
      !> Start at t with the bodies' names
      procedure :: init => energy_watch_init
      !> Check an accepted step (criteria 1 and 2); error with 'stop'
      procedure :: check => energy_watch_check
      !> Number of warnings
      procedure :: count => energy_watch_count
      !> Warning k: text, time, body
      procedure :: warning => energy_watch_warning
   end type energy_watch_t

contains

   !> The kind of an energy_watch word (case as given, lowered by the reader); 0 if unknown.
   pure integer function energy_watch_kind(word) result(kind)
      character(len=*), intent(in) :: word
      integer :: k
      kind = 0
      do k = 1, size(ENERGY_WATCH_WORDS)
         if (trim(word) == trim(ENERGY_WATCH_WORDS(k))) kind = k
      end do
   end function energy_watch_kind

   !> The word of an energy_watch kind.
   pure function energy_watch_word(kind) result(word)
      integer, intent(in) :: kind
      character(len=:), allocatable :: word
      word = trim(ENERGY_WATCH_WORDS(max(1, min(kind, size(ENERGY_WATCH_WORDS)))))
   end function energy_watch_word

   !> Start the watch at time t for the bodies `names` (flexible: criterion 2 applies), with
   !> their T_b + U_b at t.
   subroutine energy_watch_init(self, settings, t, names, flexible, body_energy, error)
      class(energy_watch_t), intent(out) :: self
      type(energy_watch_settings_t), intent(in) :: settings
      !> Start time (s)
      real(dp), intent(in) :: t
      !> Body names and flexibility, mechanism order
      character(len=*), intent(in) :: names(:)
      logical, intent(in) :: flexible(:)
      !> T_b + U_b of each body at t (J)
      real(dp), intent(in) :: body_energy(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: n
      if (.not. (settings%tolerance > 0.0_dp .and. settings%window > 0.0_dp) .or. &
         settings%mode < ENERGY_WATCH_OFF .or. settings%mode > ENERGY_WATCH_STOP) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'energy watch: tolerance = ' // &
            to_str(settings%tolerance) // ', window = ' // to_str(settings%window) // &
            ' s, mode ' // to_str(settings%mode) // '; need tolerance > 0, window > 0, ' // &
            'mode off, warn or stop')
         return
      end if
      n = size(names)
      if (size(flexible) /= n .or. size(body_energy) /= n) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'energy watch: ' // to_str(n) // &
            ' names, ' // to_str(size(flexible)) // ' flags, ' // to_str(size(body_energy)) &
            // ' energies; give one of each per body')
         return
      end if
      self%settings = settings
      allocate (self%names(n), self%flexible(n), self%strain_max(n), self%growing(n), &
         self%growth_warned(n), self%kinetic_envelope(GROWTH_WINDOWS + 1), &
         self%strain_envelope(n, GROWTH_WINDOWS + 1), self%warnings(0))
      self%names = names
      self%flexible = flexible
      self%energy_at_start = body_energy
      self%window_start = t
      self%created_from = t + settings%window * (1.0_dp - 1.0e-9_dp)
      self%strain_max = 0.0_dp
      self%growing = 0
      self%growth_warned = .false.
      self%kinetic_envelope = 0.0_dp
      self%strain_envelope = 0.0_dp
   end subroutine energy_watch_init

   !> Check the accepted step at t (module header). T, U, W, D_p, D, D_s: the balance after the
   !> step (J); has_scheme: D_s is accumulated; body_kinetic, body_strain: T_b and U_b (J).
   !> A new warning is appended (and `new_warning` set); with mode 'stop' it is returned as
   !> FFRF_NUMERIC_ERROR instead.
   subroutine energy_watch_check(self, t, kinetic, strain, work, physical, numerical, scheme, &
         has_scheme, body_kinetic, body_strain, new_warning, error)
      class(energy_watch_t), intent(inout) :: self
      real(dp), intent(in) :: t, kinetic, strain, work, physical, numerical, scheme
      logical, intent(in) :: has_scheme
      real(dp), intent(in) :: body_kinetic(:), body_strain(:)
      logical, intent(out) :: new_warning
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: spurious, ratio, paid, growth
      integer :: b, n
      new_warning = .false.
      if (self%settings%mode == ENERGY_WATCH_OFF .or. .not. allocated(self%names)) return
      n = size(self%names)
      ! Criterion 1: energy created
      self%scale = max(self%scale, kinetic + strain + abs(work) + physical)
      spurious = -numerical
      if (has_scheme) spurious = -scheme
      if (self%scale > 0.0_dp .and. t >= self%created_from) then
         ratio = spurious / self%scale
         if (ratio > self%worst_ratio) then
            self%worst_ratio = ratio
            self%worst_time = t
         end if
         if (ratio > self%settings%tolerance .and. .not. self%created_warned) then
            self%created_warned = .true.
            b = maxloc(body_kinetic + body_strain - self%energy_at_start, 1)
            call add_warning(self, t, b, 'energy created by the integration: ' // &
               trim(merge('-D_s', '-D  ', has_scheme)) // ' = ' // &
               to_str(spurious, 4) // ' J = ' // to_str(ratio, 3) // ' of the energy scale ' // &
               to_str(self%scale, 4) // ' J (T + U + |W| + D_p), above energy_watch_tolerance' &
               // ' = ' // to_str(self%settings%tolerance, 3) // '; body "' // &
               trim(self%names(b)) // '" gained most (T + U + ' // to_str(body_kinetic(b) + &
               body_strain(b) - self%energy_at_start(b), 4) // ' J in this window); ' // &
               'reduce h or rho_inf, or add modal damping', new_warning, error)
            if (allocated(error)) return
         end if
      end if
      ! Criterion 2: the windows' strain envelopes
      self%kinetic_max = max(self%kinetic_max, kinetic)
      self%strain_max = max(self%strain_max, body_strain)
      if (t < self%window_start + self%settings%window * (1.0_dp - 1.0e-9_dp)) return
      self%kinetic_envelope = [self%kinetic_envelope(2:), self%kinetic_max]
      self%strain_envelope = reshape([self%strain_envelope(:, 2:), self%strain_max], &
         [n, GROWTH_WINDOWS + 1])
      self%closed_windows = self%closed_windows + 1
      do b = 1, n
         if (.not. self%flexible(b)) cycle
         if (self%closed_windows >= 2 .and. self%strain_envelope(b, GROWTH_WINDOWS + 1) > &
            self%strain_envelope(b, GROWTH_WINDOWS)) then
            self%growing(b) = self%growing(b) + 1
         else
            self%growing(b) = 0
         end if
         if (self%growing(b) < GROWTH_WINDOWS .or. self%growth_warned(b)) cycle
         if (.not. (self%strain_envelope(b, 1) > 0.0_dp .and. &
            self%kinetic_envelope(1) > 0.0_dp)) cycle
         if (.not. self%strain_envelope(b, GROWTH_WINDOWS + 1) > GROWTH_FLOOR * self%scale) cycle
         growth = self%strain_envelope(b, GROWTH_WINDOWS + 1) / self%strain_envelope(b, 1)
         paid = max(1.0_dp, (self%kinetic_envelope(GROWTH_WINDOWS + 1) / &
            self%kinetic_envelope(1))**2)
         if (growth > GROWTH_FACTOR * paid) then
            self%growth_warned(b) = .true.
            call add_warning(self, t, b, 'strain energy of body "' // trim(self%names(b)) // &
               '" grows without work to pay for it: its largest value per ' // &
               to_str(self%settings%window, 3) // ' s window rose in ' // &
               to_str(GROWTH_WINDOWS) // ' consecutive windows from ' // &
               to_str(self%strain_envelope(b, 1), 4) // ' J to ' // &
               to_str(self%strain_envelope(b, GROWTH_WINDOWS + 1), 4) // ' J (x ' // &
               to_str(growth, 3) // ', more than ' // to_str(GROWTH_FACTOR, 2) // &
               ' x (T growth)^2 = ' // to_str(GROWTH_FACTOR * paid, 3) // '): an ' // &
               'instability of the undamped model or of the integration; add modal ' // &
               'damping, or check h and rho_inf', new_warning, error)
            if (allocated(error)) return
         end if
      end do
      self%window_start = t
      self%kinetic_max = kinetic
      self%strain_max = body_strain
      self%energy_at_start = body_kinetic + body_strain
   end subroutine energy_watch_check

   !> Append a warning, or return it as the error of a 'stop' watch.
   subroutine add_warning(self, t, b, text, new_warning, error)
      type(energy_watch_t), intent(inout) :: self
      real(dp), intent(in) :: t
      integer, intent(in) :: b
      character(len=*), intent(in) :: text
      logical, intent(inout) :: new_warning
      type(error_t), allocatable, intent(out) :: error
      type(energy_warning_t) :: w
      w%t = t
      w%body = trim(self%names(b))
      w%text = 't = ' // to_str(t, 6) // ' s: ' // text
      self%warnings = [self%warnings, w]
      new_warning = .true.
      if (self%settings%mode == ENERGY_WATCH_STOP) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'energy watch (energy_watch = ''stop''): ' // w%text)
   end subroutine add_warning

   !> Number of warnings so far.
   pure integer function energy_watch_count(self) result(n)
      class(energy_watch_t), intent(in) :: self
      n = 0
      if (allocated(self%warnings)) n = size(self%warnings)
   end function energy_watch_count

   !> Warning k (1-based): its text, time (s) and body.
   subroutine energy_watch_warning(self, k, text, t, body)
      class(energy_watch_t), intent(in) :: self
      integer, intent(in) :: k
      character(len=:), allocatable, intent(out) :: text, body
      real(dp), intent(out) :: t
      text = self%warnings(k)%text
      body = self%warnings(k)%body
      t = self%warnings(k)%t
   end subroutine energy_watch_warning

end module ffrf_mbs_energy_watch
