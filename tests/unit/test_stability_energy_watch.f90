!> The energy watch of a mechanism run (issue 30, part 3; ffrf_mbs_energy_watch) on energy
!> histories with closed-form answers, fed step by step as the run feeds them:
!>
!> - energy created at a constant rate c into body 2 of a mechanism at rest otherwise
!>   (T = T_0 + c t, W = 0, D = D_s = -c t): the warning comes at the first step past the
!>   closed-form time t* = tol T_0 / (c (1 - tol)) where c t = tol (T_0 + c t), within one step,
!>   and names body 2; with energy_watch = 'stop' the same step returns FFRF_NUMERIC_ERROR whose
!>   message names the watch and the time; D_s = -c t with D = 0 warns alike; D = -c t with
!>   D_s = 0 (the balance's quadrature part: not energy created) does not, unless D_s is not
!>   accumulated (has_scheme = .false.), where D stands in.
!> - a flexible body's strain energy growing as U_0 exp(2 sigma t) sin^2(2 pi f t) at a steady
!>   T: windows of tau = 0.1 s; the envelope grows by exp(2 sigma tau) per window, so the watch
!>   must warn at the close of window GROWTH_WINDOWS + 1 (t = 6 tau, within one oscillation
!>   period) exactly when exp(10 sigma tau) > GROWTH_FACTOR (sigma = 1.2x and 1/1.2x the
!>   threshold sigma_c = ln(4) / (10 tau): warned at 0.6 s, and never in 3 s).
!> - the same growth paid by the forcing (T = T_0 exp(sigma t), so (T ratio)^2 equals the strain
!>   ratio): no warning; a rigid body's (flexible = .false.) growth is not watched; nor a growth
!>   below GROWTH_FLOOR of the energy scale (U_0 = 1e-12 J against T = 100 J, round-off level).
!> - round-off-sized negative D, D_s (-1e-7 of the energy scale; the engines' measured worst after
!>   the first window is 4.9e-7, see ffrf_mbs_energy_watch) stays below the default tolerance
!>   1e-4, and a start transient of -1e-3 of the scale within the first window is not watched.
module test_stability_energy_watch
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_energy_watch, only: energy_watch_t, energy_watch_settings_t, &
      ENERGY_WATCH_WARN, ENERGY_WATCH_STOP, GROWTH_WINDOWS, GROWTH_FACTOR
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_stability_energy_watch

   !> Step of the fed histories (s) and the oscillation of the strain energy (Hz)
   real(dp), parameter :: h = 1.0e-4_dp, f = 250.0_dp

contains

   !> The suite.
   subroutine collect_stability_energy_watch(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [new_unittest('energy_created_at_the_closed_form_time', test_created), &
         new_unittest('energy_created_stops_the_run', test_created_stop), &
         new_unittest('scheme_dissipation_negative_alone', test_scheme_only), &
         new_unittest('balance_residual_alone_only_without_scheme', test_residual_only), &
         new_unittest('unpaid_strain_growth_at_window_six', test_growth), &
         new_unittest('growth_below_the_factor_not_flagged', test_slow_growth), &
         new_unittest('growth_paid_by_the_forcing_not_flagged', test_paid_growth), &
         new_unittest('growth_below_the_floor_not_flagged', test_tiny_growth), &
         new_unittest('round_off_not_flagged', test_round_off)]
   end subroutine collect_stability_energy_watch

   !> Feed `steps` steps of the created-energy history (module header) with rate c (J/s) into
   !> body 2; `scheme_rate`: the rate of -D_s (J/s). Returns the time of the first warning (-1:
   !> none) and the error of a 'stop' watch.
   subroutine feed_created(mode, c, scheme_rate, steps, watch, t_warn, error)
      integer, intent(in) :: mode, steps
      real(dp), intent(in) :: c, scheme_rate
      type(energy_watch_t), intent(out) :: watch
      real(dp), intent(out) :: t_warn
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_settings_t) :: settings
      real(dp), parameter :: kinetic0 = 10.0_dp
      real(dp) :: t
      logical :: new_warning
      integer :: n
      settings%mode = mode
      call watch%init(settings, 0.0_dp, ['b1', 'b2'], [.false., .false.], [kinetic0, 0.0_dp], &
         error)
      if (allocated(error)) return
      t_warn = -1.0_dp
      do n = 1, steps
         t = n * h
         call watch%check(t, kinetic0 + c * t, 0.0_dp, 0.0_dp, 0.0_dp, -c * t, &
            -scheme_rate * t, .true., [kinetic0, c * t], [0.0_dp, 0.0_dp], new_warning, error)
         if (allocated(error)) then
            t_warn = t
            return
         end if
         if (new_warning .and. t_warn < 0.0_dp) t_warn = t
      end do
   end subroutine feed_created

   !> Energy created at c = 1e-3 J/s into body 2 (T_0 = 10 J): warned within one step after
   !> t* = tol T_0 / (c (1 - tol)) = 1.0001 s, naming body 2.
   subroutine test_created(error)
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_t) :: watch
      type(energy_watch_settings_t) :: defaults
      real(dp), parameter :: c = 1.0e-3_dp
      real(dp) :: t_warn, t_star, t
      character(len=:), allocatable :: text, body
      call feed_created(ENERGY_WATCH_WARN, c, c, 20000, watch, t_warn, error)
      if (allocated(error)) return
      t_star = defaults%tolerance * 10.0_dp / (c * (1.0_dp - defaults%tolerance))
      call report('warned at t = ' // to_str(t_warn, 8) // ' s, closed form ' // &
         to_str(t_star, 8) // ' s')
      call check(error, 'one warning', watch%count() == 1)
      if (allocated(error)) return
      call check(error, 'warned after t*', t_warn >= t_star)
      if (allocated(error)) return
      call check_close(error, 'warning time', t_warn, t_star, atol=h)
      if (allocated(error)) return
      call watch%warning(1, text, t, body)
      call check(error, 'body b2 named: ' // body, body == 'b2')
      if (allocated(error)) return
      call check(error, 'text names the created energy: ' // text, &
         index(text, 'energy created') > 0)
   end subroutine test_created

   !> energy_watch = 'stop': the step of the warning returns FFRF_NUMERIC_ERROR naming the watch.
   subroutine test_created_stop(error)
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_t) :: watch
      type(error_t), allocatable :: stopped
      type(energy_watch_settings_t) :: defaults
      real(dp), parameter :: c = 1.0e-3_dp
      real(dp) :: t_warn, t_star
      call feed_created(ENERGY_WATCH_STOP, c, c, 20000, watch, t_warn, stopped)
      call check(error, 'stopped', allocated(stopped))
      if (allocated(error)) return
      call check(error, 'FFRF_NUMERIC_ERROR', stopped%code == FFRF_NUMERIC_ERROR)
      if (allocated(error)) return
      call check(error, 'message names the watch: ' // stopped%message, &
         index(stopped%message, 'energy watch') > 0 .and. &
         index(stopped%message, 'body "b2"') > 0)
      if (allocated(error)) return
      t_star = defaults%tolerance * 10.0_dp / (c * (1.0_dp - defaults%tolerance))
      call check_close(error, 'stop time', t_warn, t_star, atol=h)
   end subroutine test_created_stop

   !> D_s = -c t with D = 0 (the other quantity): warned as well, at the same closed form.
   subroutine test_scheme_only(error)
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_t) :: watch
      type(energy_watch_settings_t) :: settings
      real(dp), parameter :: c = 1.0e-3_dp, kinetic0 = 10.0_dp
      real(dp) :: t, t_warn, t_star
      logical :: new_warning
      integer :: n
      call watch%init(settings, 0.0_dp, ['b1', 'b2'], [.false., .false.], [kinetic0, 0.0_dp], &
         error)
      if (allocated(error)) return
      t_warn = -1.0_dp
      do n = 1, 20000
         t = n * h
         call watch%check(t, kinetic0, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, -c * t, .true., &
            [kinetic0, 0.0_dp], [0.0_dp, 0.0_dp], new_warning, error)
         if (allocated(error)) return
         if (new_warning .and. t_warn < 0.0_dp) t_warn = t
      end do
      t_star = settings%tolerance * kinetic0 / c
      call check_close(error, 'warning time (D_s alone)', t_warn, t_star, atol=h)
   end subroutine test_scheme_only

   !> D = -c t with D_s = 0: no warning in 2 s while D_s is accumulated (D's quadrature part is
   !> not energy created); without the scheme (has_scheme = .false.) D stands in and warns at
   !> t* = tol T_0 / c.
   subroutine test_residual_only(error)
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_t) :: watch
      type(energy_watch_settings_t) :: settings
      real(dp), parameter :: c = 1.0e-3_dp, kinetic0 = 10.0_dp
      real(dp) :: t, t_warn
      logical :: new_warning, scheme
      integer :: n, pass
      do pass = 1, 2
         scheme = pass == 1
         call watch%init(settings, 0.0_dp, ['b1', 'b2'], [.false., .false.], &
            [kinetic0, 0.0_dp], error)
         if (allocated(error)) return
         t_warn = -1.0_dp
         do n = 1, 20000
            t = n * h
            call watch%check(t, kinetic0, 0.0_dp, 0.0_dp, 0.0_dp, -c * t, 0.0_dp, scheme, &
               [kinetic0, 0.0_dp], [0.0_dp, 0.0_dp], new_warning, error)
            if (allocated(error)) return
            if (new_warning .and. t_warn < 0.0_dp) t_warn = t
         end do
         if (scheme) then
            call check(error, 'no warning with D_s accumulated', watch%count() == 0)
         else
            call check_close(error, 'warning time (D without D_s)', t_warn, &
               settings%tolerance * kinetic0 / c, atol=h)
         end if
         if (allocated(error)) return
      end do
   end subroutine test_residual_only

   !> Feed the strain-growth history (module header) for t_end: body 1 rigid (its "strain"
   !> grows too, and must be ignored), body 2 flexible; `paid`: T grows as exp(sigma t).
   subroutine feed_growth(sigma, paid, t_end, watch, t_warn, error, strain_start)
      real(dp), intent(in) :: sigma, t_end
      logical, intent(in) :: paid
      type(energy_watch_t), intent(out) :: watch
      real(dp), intent(out) :: t_warn
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_settings_t) :: settings
      !> U_0 (J; default 0.1 J)
      real(dp), intent(in), optional :: strain_start
      real(dp), parameter :: kinetic0 = 100.0_dp
      real(dp) :: t, kinetic, strain, strain0
      logical :: new_warning
      integer :: n
      strain0 = 0.1_dp
      if (present(strain_start)) strain0 = strain_start
      call watch%init(settings, 0.0_dp, ['rigid', 'flex '], [.false., .true.], &
         [kinetic0, 0.0_dp], error)
      if (allocated(error)) return
      t_warn = -1.0_dp
      do n = 1, nint(t_end / h)
         t = n * h
         kinetic = kinetic0
         if (paid) kinetic = kinetic0 * exp(sigma * t)
         strain = strain0 * exp(2.0_dp * sigma * t) * sin(2.0_dp * pi * f * t + 0.3_dp)**2
         ! energy conserved (D = D_s = 0): only criterion 2 can warn
         call watch%check(t, kinetic, strain, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, .true., &
            [kinetic, 0.0_dp], [strain, strain], new_warning, error)
         if (allocated(error)) return
         if (new_warning .and. t_warn < 0.0_dp) t_warn = t
      end do
   end subroutine feed_growth

   !> sigma = 1.2 sigma_c: warned at the close of window 6 (t = 0.6 s), naming the flexible
   !> body (the rigid one, growing alike, is not watched).
   subroutine test_growth(error)
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_t) :: watch
      type(energy_watch_settings_t) :: defaults
      real(dp) :: sigma_c, t_warn, t
      character(len=:), allocatable :: text, body
      sigma_c = log(GROWTH_FACTOR) / (2.0_dp * GROWTH_WINDOWS * defaults%window)
      call feed_growth(1.2_dp * sigma_c, .false., 3.0_dp, watch, t_warn, error)
      if (allocated(error)) return
      call report('sigma_c = ' // to_str(sigma_c, 6) // ' 1/s; warned at t = ' // &
         to_str(t_warn, 6) // ' s')
      call check(error, 'one warning', watch%count() == 1)
      if (allocated(error)) return
      call check_close(error, 'warning time', t_warn, (GROWTH_WINDOWS + 1) * defaults%window, &
         atol=h)
      if (allocated(error)) return
      call watch%warning(1, text, t, body)
      call check(error, 'flexible body named: ' // body, body == 'flex')
   end subroutine test_growth

   !> sigma = sigma_c / 1.2: the envelope grows every window, by less than GROWTH_FACTOR over
   !> five: no warning in 3 s.
   subroutine test_slow_growth(error)
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_t) :: watch
      type(energy_watch_settings_t) :: defaults
      real(dp) :: sigma_c, t_warn
      sigma_c = log(GROWTH_FACTOR) / (2.0_dp * GROWTH_WINDOWS * defaults%window)
      call feed_growth(sigma_c / 1.2_dp, .false., 3.0_dp, watch, t_warn, error)
      if (allocated(error)) return
      call check(error, 'no warning (t_warn = ' // to_str(t_warn) // ')', watch%count() == 0)
   end subroutine test_slow_growth

   !> sigma = 2 sigma_c with T = T_0 exp(sigma t): paid, no warning in 3 s.
   subroutine test_paid_growth(error)
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_t) :: watch
      type(energy_watch_settings_t) :: defaults
      real(dp) :: sigma_c, t_warn
      sigma_c = log(GROWTH_FACTOR) / (2.0_dp * GROWTH_WINDOWS * defaults%window)
      call feed_growth(2.0_dp * sigma_c, .true., 3.0_dp, watch, t_warn, error)
      if (allocated(error)) return
      call check(error, 'no warning (t_warn = ' // to_str(t_warn) // ')', watch%count() == 0)
   end subroutine test_paid_growth

   !> sigma = 1.2 sigma_c from U_0 = 1e-12 J (T = 100 J): the envelope reaches 1e-12 e^(2 sigma t)
   !> = 2e-8 J at 3 s, far below GROWTH_FLOOR x 100 J: no warning.
   subroutine test_tiny_growth(error)
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_t) :: watch
      type(energy_watch_settings_t) :: defaults
      real(dp) :: sigma_c, t_warn
      sigma_c = log(GROWTH_FACTOR) / (2.0_dp * GROWTH_WINDOWS * defaults%window)
      call feed_growth(1.2_dp * sigma_c, .false., 3.0_dp, watch, t_warn, error, &
         strain_start=1.0e-12_dp)
      if (allocated(error)) return
      call check(error, 'no warning (t_warn = ' // to_str(t_warn) // ')', watch%count() == 0)
   end subroutine test_tiny_growth

   !> D, D_s = -1e-7 of the energy scale, alternating with +1e-7 (round-off): no warning, and the
   !> largest ratio recorded is 1e-7.
   subroutine test_round_off(error)
      type(error_t), allocatable, intent(out) :: error
      type(energy_watch_t) :: watch
      type(energy_watch_settings_t) :: settings
      real(dp), parameter :: kinetic0 = 10.0_dp, noise = 1.0e-7_dp
      real(dp) :: t, d
      logical :: new_warning
      integer :: n
      call watch%init(settings, 0.0_dp, ['b1'], [.true.], [kinetic0], error)
      if (allocated(error)) return
      do n = 1, 10000
         t = n * h
         d = noise * kinetic0 * (-1.0_dp)**n
         if (t < 0.5_dp * settings%window) d = -1.0e-3_dp * kinetic0
         call watch%check(t, kinetic0, 0.0_dp, 0.0_dp, 0.0_dp, d, d, .true., [kinetic0], &
            [0.0_dp], new_warning, error)
         if (allocated(error)) return
      end do
      call check(error, 'no warning', watch%count() == 0)
      if (allocated(error)) return
      call check_close(error, 'largest ratio', watch%worst_ratio, noise, rtol=1.0e-12_dp)
   end subroutine test_round_off

end module test_stability_energy_watch

program main_stability_energy_watch
   use ffrf_testing, only: unittest_t, run_suite
   use test_stability_energy_watch, only: collect_stability_energy_watch
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_stability_energy_watch(tests)
   call run_suite('stability_energy_watch', tests)
end program main_stability_energy_watch
