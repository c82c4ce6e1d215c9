!> In-cylinder pressure model (ffrf_app_engine_pressure) and slider-crank kinematics
!> (ffrf_app_engine_slider_crank) against independent references: closed forms of the slider-crank
!> and of the motored polytropic p V^n = const, central differences, the exact work of the linear
!> single-zone ODE W = integral of (1 - (V/V_1)^(n-1)) dQ (derived below), its Otto limit, a
!> separate fine RK4 integration written here, a trapezoidal p dV sum, and the error bounds of the
!> periodic spline.
module test_mbs_pressure
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_app_engine_slider_crank, only: piston_position, piston_dy_dtheta, piston_d2y_dtheta2, &
      cylinder_volume, cylinder_dvolume, swept_volume, clearance_volume
   use ffrf_app_engine_pressure, only: pressure_input_t, pressure_model_t
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_mbs_pressure

   !> Reference engine (scene.md)
   real(dp), parameter :: BORE = 0.080_dp, STROKE = 0.090_dp, ROD = 0.150_dp, RC = 10.0_dp
   real(dp), parameter :: RADIUS = 0.5_dp * STROKE, EXPONENT = 1.32_dp
   real(dp), parameter :: P_IN = 1.0e5_dp, P_EX = 1.05e5_dp
   real(dp), parameter :: DEG = pi / 180.0_dp

contains

   subroutine collect_mbs_pressure(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('volume_closed_form', test_volume_closed_form), &
         new_unittest('kinematics_central_differences', test_kinematics_differences), &
         new_unittest('motored_polytropic', test_motored_polytropic), &
         new_unittest('work_of_heat_release', test_work_of_heat_release), &
         new_unittest('otto_limit', test_otto_limit), &
         new_unittest('tuned_peak', test_tuned_peak), &
         new_unittest('interpolant_vs_fine_rk4', test_interpolant_vs_fine_rk4), &
         new_unittest('dpressure_central_differences', test_dpressure_differences), &
         new_unittest('periodicity_and_jumps', test_periodicity), &
         new_unittest('piston_force_sign', test_piston_force), &
         new_unittest('cycle_work_trapezoid', test_cycle_work_trapezoid), &
         new_unittest('table_interpolation', test_table_interpolation), &
         new_unittest('table_errors', test_table_errors), &
         new_unittest('input_errors', test_input_errors)]
   end subroutine collect_mbs_pressure

   ! ---------------------------------------------------------------------------------------------
   ! Kinematics

   !> V(0) = V_c, V(pi) = V_c + V_d with V_d = pi B^2 S / 4 and V_c = V_d / (r_c - 1); y(0) = r + l,
   !> y(pi) = l - r. Closed forms, round-off tolerance 1e-14.
   subroutine test_volume_closed_form(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: vd, vc
      vd = pi * BORE**2 * STROKE / 4.0_dp
      vc = vd / (RC - 1.0_dp)
      call check_close(error, 'V_d', swept_volume(BORE, STROKE), vd, rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'V_c', clearance_volume(BORE, STROKE, RC), vc, rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'V(0)', cylinder_volume(0.0_dp, BORE, RADIUS, ROD, vc), vc, &
         rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'V(pi)', cylinder_volume(pi, BORE, RADIUS, ROD, vc), vc + vd, &
         rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'V(4 pi)', cylinder_volume(4.0_dp * pi, BORE, RADIUS, ROD, vc), vc, &
         rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'y(0)', piston_position(0.0_dp, RADIUS, ROD), RADIUS + ROD, &
         rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'y(pi)', piston_position(pi, RADIUS, ROD), ROD - RADIUS, &
         rtol=1.0e-14_dp)
      if (allocated(error)) return
      ! V = V_c + A (l + r - y) at a general angle (the volume is written without y)
      call check_close(error, 'V(1.1) = V_c + A (l + r - y)', &
         cylinder_volume(1.1_dp, BORE, RADIUS, ROD, vc), &
         vc + pi * BORE**2 / 4.0_dp * (ROD + RADIUS - piston_position(1.1_dp, RADIUS, ROD)), &
         rtol=1.0e-14_dp)
   end subroutine test_volume_closed_form

   !> dV/dtheta, dy/dtheta and d2y/dtheta2 against central differences, h = 1e-5: truncation
   !> h^2/6 |f'''| ~ 2e-11 and round-off eps |f| / h ~ 2e-11 relative to the scale of the
   !> derivative (its largest magnitude), so 1e-8 of that scale.
   subroutine test_kinematics_differences(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: h = 1.0e-5_dp
      real(dp) :: theta, vc, fd, dv_scale, dy_scale, d2y_scale
      integer :: i
      vc = clearance_volume(BORE, STROKE, RC)
      dv_scale = pi * BORE**2 / 4.0_dp * RADIUS * (1.0_dp + RADIUS / ROD)
      dy_scale = RADIUS * (1.0_dp + RADIUS / ROD)
      d2y_scale = RADIUS * (1.0_dp + RADIUS / ROD)
      do i = 0, 12
         theta = -1.0_dp + 0.61_dp * i
         fd = (cylinder_volume(theta + h, BORE, RADIUS, ROD, vc) &
            - cylinder_volume(theta - h, BORE, RADIUS, ROD, vc)) / (2.0_dp * h)
         call check_close(error, 'dV/dtheta at ' // to_str(theta), &
            cylinder_dvolume(theta, BORE, RADIUS, ROD), fd, atol=1.0e-8_dp * dv_scale)
         if (allocated(error)) return
         fd = (piston_position(theta + h, RADIUS, ROD) - piston_position(theta - h, RADIUS, ROD)) &
            / (2.0_dp * h)
         call check_close(error, 'dy/dtheta at ' // to_str(theta), &
            piston_dy_dtheta(theta, RADIUS, ROD), fd, atol=1.0e-8_dp * dy_scale)
         if (allocated(error)) return
         fd = (piston_dy_dtheta(theta + h, RADIUS, ROD) &
            - piston_dy_dtheta(theta - h, RADIUS, ROD)) / (2.0_dp * h)
         call check_close(error, 'd2y/dtheta2 at ' // to_str(theta), &
            piston_d2y_dtheta2(theta, RADIUS, ROD), fd, atol=1.0e-8_dp * d2y_scale)
         if (allocated(error)) return
      end do
      ! closed form at TDC: y'' = -r - r^2 / l
      call check_close(error, 'd2y/dtheta2 at TDC', piston_d2y_dtheta2(0.0_dp, RADIUS, ROD), &
         -RADIUS - RADIUS**2 / ROD, rtol=1.0e-14_dp)
   end subroutine test_kinematics_differences

   ! ---------------------------------------------------------------------------------------------
   ! Single-zone model

   !> Without heat (Q = 0) the closed part is p V^n = p_in V_1^n (closed form): p and dp/dtheta =
   !> -n p V'/V at off-grid angles to 1e-8 relative (RK4 at 0.05 deg: ~1e-11). The closed-part
   !> work is then zero (p dV exact differential) to 1e-8 of the compression work
   !> (p_2 V_2 - p_1 V_1)/(1 - n), and the cycle work is the pumping loop (p_in - p_ex) V_d.
   subroutine test_motored_polytropic(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp) :: theta, v1, v, p_exact, w_compression, max_error
      integer :: i
      input%heat_per_cycle = 0.0_dp
      call model%init(input, error)
      if (allocated(error)) return
      v1 = model%volume(pi)
      max_error = 0.0_dp
      do i = 0, 40
         theta = (180.0_dp + 0.3_dp + 8.9873_dp * i) * DEG
         v = model%volume(theta)
         p_exact = P_IN * (v1 / v)**EXPONENT
         max_error = max(max_error, abs(model%pressure(theta) / p_exact - 1.0_dp))
         call check_close(error, 'motored p at ' // to_str(theta / DEG) // ' deg', &
            model%pressure(theta), p_exact, rtol=1.0e-8_dp)
         if (allocated(error)) return
         call check_close(error, 'motored dp at ' // to_str(theta / DEG) // ' deg', &
            model%dpressure(theta), -EXPONENT * p_exact * model%dvolume(theta) / v, &
            atol=1.0e-8_dp * EXPONENT * P_IN * RC**EXPONENT)
         if (allocated(error)) return
      end do
      call report('motored p: largest relative error ' // to_str(max_error, 3))
      w_compression = (P_IN * RC**EXPONENT * model%volume(0.0_dp) - P_IN * v1) / &
         (1.0_dp - EXPONENT)
      call report('compression work ' // to_str(w_compression, 8) // ' J, closed-part work ' // &
         to_str(model%closed_work(), 3) // ' J')
      call check_close(error, 'motored closed-part work', model%closed_work(), 0.0_dp, &
         atol=1.0e-8_dp * abs(w_compression))
      if (allocated(error)) return
      call check_close(error, 'motored cycle work = pumping', model%cycle_work(), &
         (P_IN - P_EX) * swept_volume(BORE, STROKE), rtol=1.0e-10_dp)
      if (allocated(error)) return
      call check_close(error, 'motored peak at TDC', model%peak_pressure(), P_IN * RC**EXPONENT, &
         rtol=1.0e-10_dp)
   end subroutine test_motored_polytropic

   !> Exact closed-part work of the single-zone model. From V dp + n p dV = (n - 1) dQ the ODE is
   !> linear; heat dQ released at volume V' adds dp = (n - 1) dQ / V' (V'/V)^n afterwards, whose
   !> work to the end of expansion (V_1 = V(540 deg) = V(180 deg)) is
   !>     (n - 1) dQ V'^(n-1) integral_{V'}^{V_1} V^-n dV = dQ (1 - (V'/V_1)^(n-1)),
   !> and the motored part does no net work. Hence W_closed = integral (1 - (V/V_1)^(n-1)) dQ,
   !> computed here by composite Simpson at 0.01 deg with the Wiebe rate written here (quadrature
   !> error ~1e-12), for the tuned reference model: 1e-8 relative (RK4 and interpolation errors).
   subroutine test_work_of_heat_release(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp) :: expected
      call model%init(input, error)
      if (allocated(error)) return
      expected = heat_work(model, input)
      call report('Q = ' // to_str(model%heat_per_cycle(), 10) // ' J, closed-part work ' // &
         to_str(model%closed_work(), 10) // ' J, integral (1 - (V/V1)^(n-1)) dQ = ' // &
         to_str(expected, 10) // ' J')
      call check_close(error, 'closed-part work', model%closed_work(), expected, rtol=1.0e-8_dp)
      if (allocated(error)) return
      call check_close(error, 'cycle work = closed + pumping', model%cycle_work(), &
         expected + (P_IN - P_EX) * swept_volume(BORE, STROKE), rtol=1.0e-8_dp)
   end subroutine test_work_of_heat_release

   !> Otto limit: heat released at TDC (V = V_c = V_1 / r_c) gives, by the formula above,
   !> W = Q (1 - r_c^(1-n)). A burn of duration D centred near TDC releases heat at
   !> V - V_c = O(D^2), so the error is O(D^2): measured at D = 0.5 and 0.25 deg (start at
   !> 360 - D/2), the first below 1e-4 relative and the ratio of the two errors in [3.5, 4.5].
   subroutine test_otto_limit(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp) :: otto, errors(2), duration
      integer :: i
      input%heat_per_cycle = 600.0_dp
      otto = input%heat_per_cycle * (1.0_dp - RC**(1.0_dp - EXPONENT))
      do i = 1, 2
         duration = 0.5_dp / 2**(i - 1)
         input%combustion_duration_deg = duration
         input%combustion_start_deg = 360.0_dp - 0.5_dp * duration
         call model%init(input, error)
         if (allocated(error)) return
         errors(i) = abs(model%closed_work() - otto) / otto
         call report('duration ' // to_str(duration) // ' deg: closed-part work ' // &
            to_str(model%closed_work(), 10) // ' J, Otto ' // to_str(otto, 10) // &
            ' J, relative error ' // to_str(errors(i), 3))
      end do
      call check(error, 'Otto error at 0.5 deg = ' // to_str(errors(1), 3) // ' above 1e-4', &
         errors(1) < 1.0e-4_dp)
      if (allocated(error)) return
      ! second order in the duration (measured 4 - 2.7e-5)
      call check_close(error, 'Otto error ratio for halved duration', errors(1) / errors(2), &
         4.0_dp, atol=5.0e-4_dp)
   end subroutine test_otto_limit

   !> The tuned reference model peaks at 55 bar: the model's own peak to 1e-6 relative, a
   !> brute-force sampling of `pressure` every 0.001 deg (sampling error p'' dtheta^2 / 8 ~ 1e-9
   !> relative) and the peak of the fine RK4 of this file with the tuned Q (its own integration,
   !> peak by sampling at 0.005 deg) to 1e-6; the peak lies after the firing TDC (360 deg).
   subroutine test_tuned_peak(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp) :: sampled, at, theta, p, p_fine, fine_peak
      integer :: i
      call model%init(input, error)
      if (allocated(error)) return
      call check_close(error, 'peak pressure', model%peak_pressure(), 55.0e5_dp, rtol=1.0e-6_dp)
      if (allocated(error)) return
      sampled = 0.0_dp
      at = 0.0_dp
      do i = 0, 60000
         theta = (355.0_dp + 0.001_dp * i) * DEG
         p = model%pressure(theta)
         if (p > sampled) then
            sampled = p
            at = theta
         end if
      end do
      call check_close(error, 'sampled peak pressure', sampled, 55.0e5_dp, rtol=1.0e-6_dp)
      if (allocated(error)) return
      ! the sampling grid is 0.001 deg: the sampled angle is within half of it (measured 9.5e-5)
      call check_close(error, 'peak angle against sampling (deg)', model%peak_angle() / DEG, &
         at / DEG, atol=0.0005_dp)
      if (allocated(error)) return
      fine_peak = 0.0_dp
      p_fine = P_IN
      theta = 180.0_dp
      ! fine RK4 march at 0.005 deg up to 420 deg, peak among the steps
      do i = 1, 48000
         call rk4_march(input, model%heat_per_cycle(), theta, theta + 0.005_dp, 1, p_fine)
         theta = theta + 0.005_dp
         fine_peak = max(fine_peak, p_fine)
      end do
      call report('Q = ' // to_str(model%heat_per_cycle(), 10) // ' J, peak ' // &
         to_str(model%peak_pressure(), 10) // ' Pa at ' // to_str(model%peak_angle() / DEG, 8) // &
         ' deg; relative deviations from 55 bar: model ' // &
         to_str(model%peak_pressure() / 55.0e5_dp - 1.0_dp, 3) // ', sampled ' // &
         to_str(sampled / 55.0e5_dp - 1.0_dp, 3) // ', fine RK4 ' // &
         to_str(fine_peak / 55.0e5_dp - 1.0_dp, 3))
      call check_close(error, 'fine RK4 peak pressure', fine_peak, 55.0e5_dp, rtol=1.0e-6_dp)
      if (allocated(error)) return
      call check(error, 'peak angle ' // to_str(model%peak_angle() / DEG) // &
         ' deg not after the firing TDC', model%peak_angle() > 2.0_dp * pi)
   end subroutine test_tuned_peak

   !> p and dp/dtheta of the tuned model at off-grid angles against the RK4 of this file run to
   !> each angle with steps of at most 0.01 deg (error ~1e-12): 1e-8 relative for p; dp/dtheta
   !> against the ODE right-hand side at the fine solution to 1e-8 of max |dp/dtheta|.
   subroutine test_interpolant_vs_fine_rk4(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp), parameter :: angles(9) = [181.2345_dp, 250.0123_dp, 340.037_dp, 352.5555_dp, &
         359.9871_dp, 361.2345_dp, 377.4321_dp, 420.987_dp, 539.91_dp]
      real(dp) :: p_fine, dp_fine, dp_scale, max_p, max_dp
      integer :: i, num_steps
      call model%init(input, error)
      if (allocated(error)) return
      dp_scale = 0.0_dp
      do i = 0, 7200
         dp_scale = max(dp_scale, abs(model%dpressure((180.0_dp + 0.05_dp * i) * DEG)))
      end do
      max_p = 0.0_dp
      max_dp = 0.0_dp
      do i = 1, size(angles)
         p_fine = P_IN
         num_steps = ceiling((angles(i) - 180.0_dp) / 0.01_dp)
         call rk4_march(input, model%heat_per_cycle(), 180.0_dp, angles(i), num_steps, p_fine)
         dp_fine = single_zone_rhs(input, model%heat_per_cycle(), angles(i) * DEG, p_fine)
         max_p = max(max_p, abs(model%pressure(angles(i) * DEG) / p_fine - 1.0_dp))
         max_dp = max(max_dp, abs(model%dpressure(angles(i) * DEG) - dp_fine) / dp_scale)
         call check_close(error, 'p at ' // to_str(angles(i)) // ' deg', &
            model%pressure(angles(i) * DEG), p_fine, rtol=1.0e-8_dp)
         if (allocated(error)) return
         call check_close(error, 'dp/dtheta at ' // to_str(angles(i)) // ' deg', &
            model%dpressure(angles(i) * DEG), dp_fine, atol=1.0e-8_dp * dp_scale)
         if (allocated(error)) return
      end do
      call report('largest relative error of p ' // to_str(max_p, 3) // ', of dp/dtheta ' // &
         to_str(max_dp, 3) // ' of max |dp/dtheta| = ' // to_str(dp_scale, 6) // ' Pa/rad')
   end subroutine test_interpolant_vs_fine_rk4

   !> dpressure against central differences of pressure (h = 1e-6 rad: truncation h^2 p'''/6 and
   !> round-off eps p / h are both below 1e-8 of max |dp/dtheta|), over the cycle away from the
   !> jumps at 540 and 720 deg, unwrapped angles of several cycles included.
   subroutine test_dpressure_differences(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp), parameter :: h = 1.0e-6_dp
      real(dp) :: theta, fd, dp_scale
      integer :: i
      call model%init(input, error)
      if (allocated(error)) return
      dp_scale = abs(model%dpressure(355.0_dp * DEG))
      do i = 0, 7200
         dp_scale = max(dp_scale, abs(model%dpressure((180.0_dp + 0.05_dp * i) * DEG)))
      end do
      do i = 0, 713
         theta = (3.0_dp + 0.9997_dp * i) * DEG + 4.0_dp * pi * (modulo(i, 5) - 2)
         fd = (model%pressure(theta + h) - model%pressure(theta - h)) / (2.0_dp * h)
         call check_close(error, 'dp/dtheta at ' // to_str(theta / DEG) // ' deg', &
            model%dpressure(theta), fd, atol=1.0e-8_dp * dp_scale)
         if (allocated(error)) return
      end do
   end subroutine test_dpressure_differences

   !> p(theta + 4 pi k) = p(theta) (to the rounding of theta + 4 pi k: 1e-10 relative); the
   !> phases: p = p_in on intake, p_ex on exhaust, the blow-down jump at 540 deg and the
   !> exhaust-to-intake jump at 720 deg (right-continuous values, exact).
   subroutine test_periodicity(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp) :: theta
      integer :: i, k
      call model%init(input, error)
      if (allocated(error)) return
      do i = 0, 35
         theta = (7.0_dp + 20.0_dp * i) * DEG
         do k = -3, 3
            call check_close(error, 'p(theta + 4 pi k), k = ' // to_str(k), &
               model%pressure(theta + 4.0_dp * pi * k), model%pressure(theta), rtol=1.0e-10_dp)
            if (allocated(error)) return
         end do
      end do
      call check_close(error, 'p(0)', model%pressure(0.0_dp), P_IN, rtol=1.0e-15_dp)
      if (allocated(error)) return
      call check_close(error, 'p(100 deg)', model%pressure(100.0_dp * DEG), P_IN, rtol=1.0e-15_dp)
      if (allocated(error)) return
      call check_close(error, 'p(540 deg)', model%pressure(3.0_dp * pi), P_EX, rtol=1.0e-15_dp)
      if (allocated(error)) return
      call check_close(error, 'p(600 deg)', model%pressure(600.0_dp * DEG), P_EX, rtol=1.0e-15_dp)
      if (allocated(error)) return
      call check_close(error, 'p(-1 deg)', model%pressure(-1.0_dp * DEG), P_EX, rtol=1.0e-15_dp)
      if (allocated(error)) return
      call check_close(error, 'p(720 deg)', model%pressure(4.0_dp * pi), P_IN, rtol=1.0e-15_dp)
      if (allocated(error)) return
      call check(error, 'expansion pressure before blow-down ' // &
         to_str(model%pressure(539.99_dp * DEG)) // ' not above p_ex', &
         model%pressure(539.99_dp * DEG) > 2.0_dp * P_EX)
   end subroutine test_periodicity

   !> Gas force along +y is -(p - p_ref) pi B^2 / 4 (scene.md: (p - 1e5) A along -y): negative at
   !> the firing TDC, zero on intake (p_in = p_ref), exact to round-off.
   subroutine test_piston_force(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp) :: area
      call model%init(input, error)
      if (allocated(error)) return
      area = pi * BORE**2 / 4.0_dp
      call check_close(error, 'force at firing TDC', model%piston_force(2.0_dp * pi), &
         -(model%pressure(2.0_dp * pi) - 1.0e5_dp) * area, rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check(error, 'force at firing TDC is not towards the crank (-y)', &
         model%piston_force(2.0_dp * pi) < -1.0e4_dp)
      if (allocated(error)) return
      call check_close(error, 'force on intake', model%piston_force(1.0_dp), 0.0_dp, &
         atol=1.0e-9_dp)
      if (allocated(error)) return
      call check_close(error, 'force on exhaust', model%piston_force(11.0_dp), &
         -(P_EX - 1.0e5_dp) * area, rtol=1.0e-14_dp)
   end subroutine test_piston_force

   !> cycle_work against an independent trapezoidal sum of p dV at 0.01 deg over the cycle
   !> (error O(h^2) ~ 1e-8 relative; the jumps sit at dV = 0), 1e-6 relative;
   !> mean_indicated_torque = cycle_work / (4 pi) to round-off.
   subroutine test_cycle_work_trapezoid(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp) :: work, theta_a, theta_b
      integer :: i
      call model%init(input, error)
      if (allocated(error)) return
      work = 0.0_dp
      do i = 0, 71999
         theta_a = 0.01_dp * i * DEG
         theta_b = 0.01_dp * (i + 1) * DEG
         work = work + 0.5_dp * (model%pressure(theta_a) + model%pressure(theta_b)) * &
            (model%volume(theta_b) - model%volume(theta_a))
      end do
      call report('W = ' // to_str(model%cycle_work(), 10) // ' J (trapezoid ' // &
         to_str(work, 10) // ' J), T_mean = ' // to_str(model%mean_indicated_torque(), 10) // &
         ' N m, Q = ' // to_str(model%heat_per_cycle(), 10) // ' J, peak ' // &
         to_str(model%peak_pressure(), 10) // ' Pa at ' // &
         to_str(model%peak_angle() / DEG, 8) // ' deg')
      ! trapezoid at 0.01 deg, O(dtheta^2) at the kinks of p: measured 6.8e-9
      call check_close(error, 'cycle work', model%cycle_work(), work, rtol=1.0e-7_dp)
      if (allocated(error)) return
      call check_close(error, 'mean indicated torque', model%mean_indicated_torque(), &
         model%cycle_work() / (4.0_dp * pi), rtol=1.0e-15_dp)
   end subroutine test_cycle_work_trapezoid

   ! ---------------------------------------------------------------------------------------------
   ! User table

   !> Periodic cubic spline through a table of f = a + b cos(theta/2) + c sin(theta): the knots
   !> exactly (1e-12); between them the error bounds of the periodic spline for uniform knots,
   !> |s - f| <= 5/384 h^4 max|f''''| and |s' - f'| <= 1/24 h^3 max|f''''| (Hall and Meyer 1976);
   !> fourth order (error ratio ~16 in [12, 20]) when the spacing halves; the table's work against
   !> the closed-form integral of f dV by the model's own quadrature, 1e-6.
   subroutine test_table_interpolation(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(pressure_input_t) :: input
      real(dp), allocatable :: angles(:), pressures(:)
      real(dp) :: h, f4, errors(2), err_slope, theta, bound
      integer :: i, level, n
      do level = 1, 2
         n = 72 * level
         h = 720.0_dp / n
         if (allocated(angles)) deallocate (angles, pressures)
         allocate (angles(n), pressures(n))
         do i = 1, n
            angles(i) = 0.37_dp * h + h * (i - 1)
            pressures(i) = smooth(angles(i) * DEG)
         end do
         call model%init_from_table(input, angles, pressures, error)
         if (allocated(error)) return
         do i = 1, n
            call check_close(error, 'table point ' // to_str(i), model%pressure(angles(i) * DEG), &
               pressures(i), rtol=1.0e-12_dp)
            if (allocated(error)) return
         end do
         errors(level) = 0.0_dp
         err_slope = 0.0_dp
         do i = 0, 7199
            theta = (0.1_dp * i + 0.0137_dp) * DEG
            errors(level) = max(errors(level), abs(model%pressure(theta) - smooth(theta)))
            err_slope = max(err_slope, abs(model%dpressure(theta) - dsmooth(theta)))
         end do
         ! |f''''| <= b / 16 + c
         f4 = 20.0e5_dp / 16.0_dp + 3.0e5_dp
         bound = 5.0_dp / 384.0_dp * (h * DEG)**4 * f4
         call report('table spacing ' // to_str(h) // ' deg: max |s - f| = ' // &
            to_str(errors(level), 3) // ' Pa (bound ' // to_str(bound, 3) // &
            '), max |s'' - f''| = ' // to_str(err_slope, 3) // ' Pa/rad (bound ' // &
            to_str((h * DEG)**3 * f4 / 24.0_dp, 3) // ')')
         call check(error, 'spline error above the bound', errors(level) <= bound)
         if (allocated(error)) return
         call check(error, 'spline slope error above the bound', &
            err_slope <= (h * DEG)**3 * f4 / 24.0_dp)
         if (allocated(error)) return
      end do
      ! fourth order (measured 16 - 0.085)
      call check_close(error, 'spline error ratio for halved spacing', errors(1) / errors(2), &
         16.0_dp, atol=1.0_dp)
      if (allocated(error)) return
      ! |W_s - W_f| <= max|s - f| * (total variation of V = 4 V_d), plus quadrature round-off
      call check_close(error, 'table work', model%cycle_work(), table_work_reference(model), &
         atol=errors(2) * 4.0_dp * swept_volume(BORE, STROKE) + 1.0e-9_dp)
      if (allocated(error)) return
      call check_close(error, 'table model heat', model%heat_per_cycle(), 0.0_dp, atol=0.0_dp)
   contains
      pure function smooth(angle) result(f)
         real(dp), intent(in) :: angle
         real(dp) :: f
         f = 22.0e5_dp + 20.0e5_dp * cos(0.5_dp * angle) + 3.0e5_dp * sin(angle)
      end function smooth
      pure function dsmooth(angle) result(f)
         real(dp), intent(in) :: angle
         real(dp) :: f
         f = -10.0e5_dp * sin(0.5_dp * angle) + 3.0e5_dp * cos(angle)
      end function dsmooth
      !> Simpson at 0.01 deg of f dV over the cycle
      function table_work_reference(table) result(work)
         type(pressure_model_t), intent(in) :: table
         real(dp) :: work
         real(dp) :: step, angle
         integer :: j
         step = 0.01_dp * DEG
         work = 0.0_dp
         do j = 0, 72000
            angle = j * step
            if (j == 0 .or. j == 72000) then
               work = work + smooth(angle) * table%dvolume(angle)
            else
               work = work + (2 + 2 * modulo(j, 2)) * smooth(angle) * table%dvolume(angle)
            end if
         end do
         work = work * step / 3.0_dp
      end function table_work_reference
   end subroutine test_table_interpolation

   !> Bad tables are refused with FFRF_INPUT_ERROR and a message naming the fault.
   subroutine test_table_errors(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_input_t) :: input
      real(dp), parameter :: good(5) = [0.0_dp, 100.0_dp, 300.0_dp, 400.0_dp, 600.0_dp]
      real(dp), parameter :: p(5) = [1.0e5_dp, 2.0e5_dp, 3.0e5_dp, 4.0e5_dp, 5.0e5_dp]
      call expect_table_error(input, good(1:3), p(1:3), 'at least 4', error)
      if (allocated(error)) return
      call expect_table_error(input, good, p(1:4), 'one pressure per angle', error)
      if (allocated(error)) return
      call expect_table_error(input, [0.0_dp, 100.0_dp, 100.0_dp, 400.0_dp, 600.0_dp], p, &
         'strictly increasing', error)
      if (allocated(error)) return
      call expect_table_error(input, [0.0_dp, 100.0_dp, 300.0_dp, 200.0_dp, 600.0_dp], p, &
         'angle 4 = 200 deg does not exceed', error)
      if (allocated(error)) return
      call expect_table_error(input, [0.0_dp, 100.0_dp, 300.0_dp, 400.0_dp, 720.0_dp], p, &
         'angle 5 = 720 deg, must lie in [0, 720)', error)
      if (allocated(error)) return
      call expect_table_error(input, [-1.0_dp, 100.0_dp, 300.0_dp, 400.0_dp, 600.0_dp], p, &
         'must lie in [0, 720)', error)
      if (allocated(error)) return
      call expect_table_error(input, good, [1.0e5_dp, -2.0e5_dp, 3.0e5_dp, 4.0e5_dp, 5.0e5_dp], &
         'pressure 2 = ', error)
      if (allocated(error)) return
      input%bore = 0.0_dp
      call expect_table_error(input, good, p, 'bore = 0', error)
   end subroutine test_table_errors

   !> Bad engine data are refused with FFRF_INPUT_ERROR naming the key and its value.
   subroutine test_input_errors(error)
      type(error_t), allocatable, intent(out) :: error
      type(pressure_input_t) :: input
      input = pressure_input_t()
      input%bore = -0.08_dp
      call expect_input_error(input, 'bore = -0.08', error)
      if (allocated(error)) return
      input = pressure_input_t()
      input%compression_ratio = 1.0_dp
      call expect_input_error(input, 'compression_ratio = 1,', error)
      if (allocated(error)) return
      input = pressure_input_t()
      input%conrod_length = 0.045_dp
      call expect_input_error(input, 'conrod_length = 0.045', error)
      if (allocated(error)) return
      input = pressure_input_t()
      input%combustion_duration_deg = 0.0_dp
      call expect_input_error(input, 'combustion_duration_deg = 0', error)
      if (allocated(error)) return
      input = pressure_input_t()
      input%polytropic_exponent = 1.0_dp
      call expect_input_error(input, 'polytropic_exponent = 1,', error)
      if (allocated(error)) return
      input = pressure_input_t()
      input%target_peak_pressure = 20.0e5_dp
      call expect_input_error(input, 'target_peak_pressure = 2E+06 Pa, must exceed', error)
      if (allocated(error)) return
      input = pressure_input_t()
      input%combustion_start_deg = 500.0_dp
      call expect_input_error(input, 'must not pass the exhaust opening', error)
      if (allocated(error)) return
      input = pressure_input_t()
      input%combustion_start_deg = 100.0_dp
      call expect_input_error(input, 'combustion_start_deg = 100', error)
      if (allocated(error)) return
      input = pressure_input_t()
      input%intake_pressure = 0.0_dp
      call expect_input_error(input, 'intake_pressure = 0', error)
      if (allocated(error)) return
      input = pressure_input_t()
      input%step_deg = 2.0_dp
      call expect_input_error(input, 'step_deg = 2', error)
   end subroutine test_input_errors

   ! ---------------------------------------------------------------------------------------------
   ! Helpers: an independent single-zone integrator and the expected errors

   !> dp/dtheta of the single-zone model written out here (theory.md section 6): Wiebe rate
   !> Q a (m+1)/D x^m exp(-a x^(m+1)).
   pure function single_zone_rhs(input, q, theta, p) result(rate)
      type(pressure_input_t), intent(in) :: input
      real(dp), intent(in) :: q, theta, p
      real(dp) :: rate
      rate = ((input%polytropic_exponent - 1.0_dp) * q * wiebe(input, theta) &
         - input%polytropic_exponent * p * cylinder_dvolume(theta, input%bore, &
         0.5_dp * input%stroke, input%conrod_length)) / cylinder_volume(theta, input%bore, &
         0.5_dp * input%stroke, input%conrod_length, &
         clearance_volume(input%bore, input%stroke, input%compression_ratio))
   end function single_zone_rhs

   pure function wiebe(input, theta) result(rate)
      type(pressure_input_t), intent(in) :: input
      real(dp), intent(in) :: theta
      real(dp) :: rate
      real(dp) :: x, duration
      duration = input%combustion_duration_deg * DEG
      x = (theta - input%combustion_start_deg * DEG) / duration
      rate = 0.0_dp
      if (x > 0.0_dp .and. x < 4.0_dp) rate = input%wiebe_a * (input%wiebe_m + 1.0_dp) / duration &
         * x**input%wiebe_m * exp(-input%wiebe_a * x**(input%wiebe_m + 1.0_dp))
   end function wiebe

   !> Classical RK4 of the single-zone ODE from angle_a to angle_b (deg) in num_steps steps.
   subroutine rk4_march(input, q, angle_a, angle_b, num_steps, p)
      type(pressure_input_t), intent(in) :: input
      real(dp), intent(in) :: q, angle_a, angle_b
      integer, intent(in) :: num_steps
      real(dp), intent(inout) :: p
      real(dp) :: h, theta, k1, k2, k3, k4
      integer :: i
      h = (angle_b - angle_a) * DEG / num_steps
      do i = 0, num_steps - 1
         theta = angle_a * DEG + i * h
         k1 = single_zone_rhs(input, q, theta, p)
         k2 = single_zone_rhs(input, q, theta + 0.5_dp * h, p + 0.5_dp * h * k1)
         k3 = single_zone_rhs(input, q, theta + 0.5_dp * h, p + 0.5_dp * h * k2)
         k4 = single_zone_rhs(input, q, theta + h, p + h * k3)
         p = p + h / 6.0_dp * (k1 + 2.0_dp * k2 + 2.0_dp * k3 + k4)
      end do
   end subroutine rk4_march

   !> integral over the closed part of (1 - (V/V_1)^(n-1)) dQ, composite Simpson at 0.01 deg.
   function heat_work(model, input) result(work)
      type(pressure_model_t), intent(in) :: model
      type(pressure_input_t), intent(in) :: input
      real(dp) :: work
      real(dp) :: step, theta, v1, f, weight
      integer :: j, n
      n = 36000
      step = 360.0_dp / n * DEG
      v1 = model%volume(pi)
      work = 0.0_dp
      do j = 0, n
         theta = pi + j * step
         f = (1.0_dp - (model%volume(theta) / v1)**(input%polytropic_exponent - 1.0_dp)) * &
            model%heat_per_cycle() * wiebe(input, theta)
         weight = 2.0_dp + 2.0_dp * modulo(j, 2)
         if (j == 0 .or. j == n) weight = 1.0_dp
         work = work + weight * f
      end do
      work = work * step / 3.0_dp
   end function heat_work

   subroutine expect_table_error(input, angles, pressures, text, error)
      type(pressure_input_t), intent(in) :: input
      real(dp), intent(in) :: angles(:), pressures(:)
      character(len=*), intent(in) :: text
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(error_t), allocatable :: got
      call model%init_from_table(input, angles, pressures, got)
      call expect_message(got, text, error)
   end subroutine expect_table_error

   subroutine expect_input_error(input, text, error)
      type(pressure_input_t), intent(in) :: input
      character(len=*), intent(in) :: text
      type(error_t), allocatable, intent(out) :: error
      type(pressure_model_t) :: model
      type(error_t), allocatable :: got
      call model%init(input, got)
      call expect_message(got, text, error)
   end subroutine expect_input_error

   subroutine expect_message(got, text, error)
      type(error_t), allocatable, intent(in) :: got
      character(len=*), intent(in) :: text
      type(error_t), allocatable, intent(out) :: error
      if (.not. allocated(got)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'no error, expected "' // text // '"')
      else if (got%code /= FFRF_INPUT_ERROR .or. index(got%message, text) == 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'error "' // got%message // &
            '" (code ' // to_str(got%code) // '), expected input error with "' // text // '"')
      end if
   end subroutine expect_message

end module test_mbs_pressure

program main_mbs_pressure
   use ffrf_testing, only: unittest_t, run_suite
   use test_mbs_pressure, only: collect_mbs_pressure
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mbs_pressure(tests)
   call run_suite('mbs_pressure', tests)
end program main_mbs_pressure
