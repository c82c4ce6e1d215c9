!> The single-zone cycle of ffrf_app_engine_pressure (a submodule): the inputs checked, the
!> closed part integrated, the heat release tuned to the wanted peak, the evaluators.
submodule (ffrf_app_engine_pressure) ffrf_app_engine_pressure_cycle
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_app_engine_slider_crank, only: cylinder_volume, cylinder_dvolume, clearance_volume
   implicit none

contains

   module procedure pressure_model_init
      real(dp), allocatable :: p_0(:), p_1(:), s_0(:), s_1(:), y(:), s(:)
      real(dp) :: h, phi, q
      integer :: num_steps, i
      call check_geometry(input, error)
      if (allocated(error)) return
      call check_combustion(input, error)
      if (allocated(error)) return
      call set_geometry(self, input)
      ! Uniform grid of the closed part [pi, 3 pi], fine enough for the Wiebe rise.
      h = min(input%step_deg, input%combustion_duration_deg / 200.0_dp) * deg
      num_steps = ceiling(2.0_dp * pi / h)
      h = 2.0_dp * pi / num_steps
      allocate (p_0(0:num_steps), p_1(0:num_steps), s_0(0:num_steps), s_1(0:num_steps))
      call integrate_closed_part(self, h, p_0, p_1)
      do i = 0, num_steps
         phi = grid_angle(i, h, num_steps)
         s_0(i) = closed_rhs(self, phi, p_0(i), 0.0_dp)
         s_1(i) = closed_rhs(self, phi, p_1(i), 1.0_dp)
      end do
      if (.not. all(ieee_is_finite(p_0) .and. ieee_is_finite(p_1))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'pressure model: the closed-part ' // &
            'integration gave a non-finite pressure; check the engine data')
         return
      end if
      if (input%heat_per_cycle >= 0.0_dp) then
         q = input%heat_per_cycle
      else
         call tune_heat(self, h, p_0, p_1, s_0, s_1, q, error)
         if (allocated(error)) return
      end if
      self%heat = q
      allocate (y(0:num_steps), s(0:num_steps))
      y(:) = p_0 + q * p_1
      do i = 0, num_steps
         s(i) = closed_rhs(self, grid_angle(i, h, num_steps), y(i), q)
      end do
      ! One period: intake [0, pi], closed [pi, 3 pi], blow-down (a repeated knot), exhaust
      ! [3 pi, 4 pi].
      allocate (self%knots(0:num_steps + 4), self%values(0:num_steps + 4), &
         self%slopes(0:num_steps + 4))
      self%knots(:) = [0.0_dp, pi, [(grid_angle(i, h, num_steps), i=0, num_steps)], &
         3.0_dp * pi, cycle_period]
      self%values(:) = [input%intake_pressure, input%intake_pressure, y, &
         input%exhaust_pressure, input%exhaust_pressure]
      self%slopes(:) = [0.0_dp, 0.0_dp, s, 0.0_dp, 0.0_dp]
      call finish(self, error)
   end procedure pressure_model_init

   module procedure pressure_model_init_from_table
      integer :: n, i
      n = size(angles_deg)
      if (size(pressures_pa) /= n) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure table: ' // to_str(n) // &
            ' angles but ' // to_str(size(pressures_pa)) // &
            ' pressures; give one pressure per angle')
         return
      end if
      if (n < 4) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure table: ' // to_str(n) // &
            ' points, at least 4 are needed for the periodic cubic spline')
         return
      end if
      do i = 1, n
         if (.not. (angles_deg(i) >= 0.0_dp .and. angles_deg(i) < 720.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'pressure table: angle ' // to_str(i) // &
               ' = ' // to_str(angles_deg(i)) // ' deg, must lie in [0, 720)')
            return
         end if
         if (.not. (pressures_pa(i) >= 0.0_dp .and. ieee_is_finite(pressures_pa(i)))) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'pressure table: pressure ' // to_str(i) &
               // ' = ' // to_str(pressures_pa(i)) // ' Pa, must be finite and >= 0 (absolute)')
            return
         end if
      end do
      do i = 2, n
         if (.not. angles_deg(i) > angles_deg(i - 1)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'pressure table: angle ' // to_str(i) // &
               ' = ' // to_str(angles_deg(i)) // ' deg does not exceed angle ' // &
               to_str(i - 1) // ' = ' // to_str(angles_deg(i - 1)) // &
               ' deg; angles must be strictly increasing')
            return
         end if
      end do
      call check_geometry(input, error)
      if (allocated(error)) then
         error%message = 'pressure table: ' // error%message
         return
      end if
      call set_geometry(self, input)
      self%from_table = .true.
      allocate (self%knots(0:n), self%values(0:n), self%slopes(0:n))
      self%knots(:) = [angles_deg * deg, angles_deg(1) * deg + cycle_period]
      self%values(:) = [pressures_pa, pressures_pa(1)]
      call periodic_spline_slopes(self%knots, self%values, self%slopes)
      call finish(self, error)
   end procedure pressure_model_init_from_table

   module procedure pressure_model_pressure
      real(dp) :: dp_dtheta
      call evaluate(self, theta_rad, p, dp_dtheta)
   end procedure pressure_model_pressure

   module procedure pressure_model_dpressure
      real(dp) :: p
      call evaluate(self, theta_rad, p, dp_dtheta)
   end procedure pressure_model_dpressure

   module procedure pressure_model_piston_force
      force = -(self%pressure(theta_rad) - self%input%reference_pressure) * self%area
   end procedure pressure_model_piston_force

   module procedure pressure_model_volume
      v = cylinder_volume(theta_rad, self%input%bore, self%crank_radius, &
         self%input%conrod_length, self%v_clearance)
   end procedure pressure_model_volume

   module procedure pressure_model_dvolume
      dv = cylinder_dvolume(theta_rad, self%input%bore, self%crank_radius, &
         self%input%conrod_length)
   end procedure pressure_model_dvolume

   module procedure pressure_model_cycle_work
      work = self%work
   end procedure pressure_model_cycle_work

   module procedure pressure_model_closed_work
      work = self%work_closed
   end procedure pressure_model_closed_work

   module procedure pressure_model_mean_indicated_torque
      torque = self%work / cycle_period
   end procedure pressure_model_mean_indicated_torque

   module procedure pressure_model_peak_pressure
      p = self%peak
   end procedure pressure_model_peak_pressure

   module procedure pressure_model_peak_angle
      theta = self%peak_at
   end procedure pressure_model_peak_angle

   module procedure pressure_model_heat_per_cycle
      q = self%heat
   end procedure pressure_model_heat_per_cycle

   module procedure wiebe_rate
      real(dp) :: x, burned
      x = (theta - start) / duration
      rate = 0.0_dp
      if (x <= 0.0_dp) return
      burned = a * x**(m + 1.0_dp)
      ! past exp(-600) the rate is below 1e-250: zero, without underflow
      if (burned < 600.0_dp) rate = a * (m + 1.0_dp) / duration * x**m * exp(-burned)
   end procedure wiebe_rate

   ! ---------------------------------------------------------------------------------------------
   ! Checks and set-up

   !> Geometry and the pressures every model needs.
   subroutine check_geometry(input, error)
      type(pressure_input_t), intent(in) :: input
      type(error_t), allocatable, intent(out) :: error
      call require_positive('bore', input%bore, 'm', error)
      if (allocated(error)) return
      call require_positive('stroke', input%stroke, 'm', error)
      if (allocated(error)) return
      if (.not. (input%conrod_length > 0.5_dp * input%stroke .and. &
         ieee_is_finite(input%conrod_length))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: conrod_length = ' // &
            to_str(input%conrod_length) // ' m, must exceed the crank radius stroke/2 = ' // &
            to_str(0.5_dp * input%stroke) // ' m')
         return
      end if
      if (.not. (input%compression_ratio > 1.0_dp .and. ieee_is_finite(input%compression_ratio))) &
         then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: compression_ratio = ' // &
            to_str(input%compression_ratio) // ', must be > 1')
         return
      end if
      if (.not. (input%reference_pressure >= 0.0_dp .and. &
         ieee_is_finite(input%reference_pressure))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: reference_pressure = ' // &
            to_str(input%reference_pressure) // ' Pa, must be finite and >= 0')
      end if
   end subroutine check_geometry

   !> The cycle and combustion data of the single-zone model.
   subroutine check_combustion(input, error)
      type(pressure_input_t), intent(in) :: input
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: finish_deg
      call require_positive('intake_pressure', input%intake_pressure, 'Pa', error)
      if (allocated(error)) return
      call require_positive('exhaust_pressure', input%exhaust_pressure, 'Pa', error)
      if (allocated(error)) return
      if (.not. (input%polytropic_exponent > 1.0_dp .and. &
         ieee_is_finite(input%polytropic_exponent))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: polytropic_exponent = ' // &
            to_str(input%polytropic_exponent) // ', must be > 1')
         return
      end if
      call require_positive('wiebe_a', input%wiebe_a, '', error)
      if (allocated(error)) return
      if (.not. (input%wiebe_m >= 0.0_dp .and. ieee_is_finite(input%wiebe_m))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: wiebe_m = ' // &
            to_str(input%wiebe_m) // ', must be finite and >= 0')
         return
      end if
      if (.not. (input%combustion_start_deg >= 180.0_dp .and. &
         input%combustion_start_deg < 540.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: combustion_start_deg = ' // &
            to_str(input%combustion_start_deg) // ', must lie in the closed part [180, 540) deg')
         return
      end if
      call require_positive('combustion_duration_deg', input%combustion_duration_deg, 'deg', &
         error)
      if (allocated(error)) return
      finish_deg = input%combustion_start_deg + input%combustion_duration_deg
      if (finish_deg > 540.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: combustion_start_deg + ' // &
            'combustion_duration_deg = ' // to_str(finish_deg) // ' deg, must not pass the ' // &
            'exhaust opening at 540 deg')
         return
      end if
      if (.not. (input%step_deg > 0.0_dp .and. input%step_deg <= 1.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: step_deg = ' // &
            to_str(input%step_deg) // ', must lie in (0, 1] deg')
         return
      end if
      if (.not. ieee_is_finite(input%heat_per_cycle)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: heat_per_cycle = ' // &
            to_str(input%heat_per_cycle) // ' J, must be finite (negative: tune it)')
         return
      end if
      if (input%heat_per_cycle < 0.0_dp) then
         call require_positive('target_peak_pressure', input%target_peak_pressure, 'Pa', error)
         if (allocated(error)) return
      end if
   end subroutine check_combustion

   !> Error unless value is finite and > 0.
   subroutine require_positive(key, value, unit, error)
      character(len=*), intent(in) :: key
      real(dp), intent(in) :: value
      character(len=*), intent(in) :: unit
      type(error_t), allocatable, intent(out) :: error
      if (.not. (value > 0.0_dp .and. ieee_is_finite(value))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: ' // key // ' = ' // &
            to_str(value) // ' ' // unit // ', must be finite and > 0')
      end if
   end subroutine require_positive

   !> Derived geometry: area, crank radius, clearance volume.
   subroutine set_geometry(self, input)
      type(pressure_model_t), intent(inout) :: self
      type(pressure_input_t), intent(in) :: input
      self%input = input
      self%area = 0.25_dp * pi * input%bore**2
      self%crank_radius = 0.5_dp * input%stroke
      self%v_clearance = clearance_volume(input%bore, input%stroke, input%compression_ratio)
   end subroutine set_geometry

   !> Knot i of the closed-part grid, pi + i h, exactly 3 pi at the end.
   pure function grid_angle(i, h, num_steps) result(phi)
      integer, intent(in) :: i, num_steps
      real(dp), intent(in) :: h
      real(dp) :: phi
      if (i == num_steps) then
         phi = 3.0_dp * pi
      else
         phi = pi + i * h
      end if
   end function grid_angle

   ! ---------------------------------------------------------------------------------------------
   ! Single-zone ODE

   !> dp/dtheta = [(n - 1) Q dx_b/dtheta - n p dV/dtheta] / V (theory.md section 6).
   pure function closed_rhs(self, phi, p, q) result(rate)
      !> Model with geometry and combustion data set
      type(pressure_model_t), intent(in) :: self
      !> Cycle angle (rad)
      real(dp), intent(in) :: phi
      !> Pressure (Pa)
      real(dp), intent(in) :: p
      !> Heat per cycle Q (J)
      real(dp), intent(in) :: q
      real(dp) :: rate
      real(dp) :: n
      n = self%input%polytropic_exponent
      rate = ((n - 1.0_dp) * q * wiebe_rate(phi, self%input%combustion_start_deg * deg, &
         self%input%combustion_duration_deg * deg, self%input%wiebe_a, self%input%wiebe_m) &
         - n * p * self%dvolume(phi)) / self%volume(phi)
   end function closed_rhs

   !> RK4 over [pi, 3 pi] of the motored pressure p_0 (Q = 0, p_0(pi) = p_in) and of the unit-heat
   !> response p_1 (Q = 1, p_1(pi) = 0); p = p_0 + Q p_1 by linearity.
   subroutine integrate_closed_part(self, h, p_0, p_1)
      !> Model with geometry and combustion data set
      type(pressure_model_t), intent(in) :: self
      !> Step (rad); ubound(p_0) steps span [pi, 3 pi]
      real(dp), intent(in) :: h
      !> Motored pressure at the grid angles (Pa)
      real(dp), intent(out) :: p_0(0:)
      !> Pressure per unit heat at the grid angles (Pa/J)
      real(dp), intent(out) :: p_1(0:)
      real(dp) :: y(2), k1(2), k2(2), k3(2), k4(2), phi
      integer :: i
      y = [self%input%intake_pressure, 0.0_dp]
      p_0(0) = y(1)
      p_1(0) = y(2)
      do i = 1, ubound(p_0, 1)
         phi = pi + (i - 1) * h
         k1 = pair_rhs(phi, y)
         k2 = pair_rhs(phi + 0.5_dp * h, y + 0.5_dp * h * k1)
         k3 = pair_rhs(phi + 0.5_dp * h, y + 0.5_dp * h * k2)
         k4 = pair_rhs(phi + h, y + h * k3)
         y = y + h / 6.0_dp * (k1 + 2.0_dp * k2 + 2.0_dp * k3 + k4)
         p_0(i) = y(1)
         p_1(i) = y(2)
      end do
   contains
      pure function pair_rhs(angle, state) result(rate)
         real(dp), intent(in) :: angle, state(2)
         real(dp) :: rate(2)
         rate = [closed_rhs(self, angle, state(1), 0.0_dp), &
            closed_rhs(self, angle, state(2), 1.0_dp)]
      end function pair_rhs
   end subroutine integrate_closed_part

   !> Heat Q >= 0 whose interpolated peak equals input%target_peak_pressure: safeguarded Newton on
   !> f(Q) = max(p_0 + Q p_1) - target, f'(Q) = p_1 at the peak (convex, increasing).
   subroutine tune_heat(self, h, p_0, p_1, s_0, s_1, q, error)
      !> Model with geometry and combustion data set
      type(pressure_model_t), intent(in) :: self
      !> Grid step (rad)
      real(dp), intent(in) :: h
      !> Motored pressure p_0 and unit-heat response p_1 at the grid angles (Pa, Pa/J)
      real(dp), intent(in) :: p_0(0:), p_1(0:)
      !> Their slopes d/dtheta from the ODE (Pa/rad, Pa/(J rad))
      real(dp), intent(in) :: s_0(0:), s_1(0:)
      !> Heat per cycle found (J)
      real(dp), intent(out) :: q
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: x(:)
      real(dp) :: target, peak, at, t, f, slope, q_lo, q_hi, q_new
      integer :: num_steps, i, cell, iteration
      target = self%input%target_peak_pressure
      num_steps = ubound(p_0, 1)
      allocate (x(0:num_steps))
      x(:) = [(grid_angle(i, h, num_steps), i=0, num_steps)]
      call hermite_peak(x, p_0, s_0, peak, at, cell, t)
      if (.not. target > peak) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pressure model: target_peak_pressure = ' // &
            to_str(target) // ' Pa, must exceed the motored (compression) peak ' // &
            to_str(peak) // ' Pa; raise it or give heat_per_cycle')
         return
      end if
      ! peak(Q) <= peak(0) + Q max(p_1): this Q lies at or below the root.
      q_lo = 0.0_dp
      q_hi = huge(1.0_dp)
      q = (target - peak) / maxval(p_1)
      do iteration = 1, 200
         call hermite_peak(x, p_0 + q * p_1, s_0 + q * s_1, peak, at, cell, t)
         f = peak - target
         if (abs(f) <= 1.0e-13_dp * target) return
         if (f < 0.0_dp) then
            q_lo = max(q_lo, q)
         else
            q_hi = min(q_hi, q)
         end if
         slope = hermite_value(p_1(cell - 1), p_1(cell), s_1(cell - 1), s_1(cell), &
            x(cell) - x(cell - 1), t)
         q_new = q - f / max(slope, tiny(1.0_dp))
         if (.not. (q_new > q_lo .and. q_new < q_hi)) then
            if (q_hi < huge(1.0_dp)) then
               q_new = 0.5_dp * (q_lo + q_hi)
            else
               q_new = 2.0_dp * max(q, q_lo) + 1.0_dp
            end if
         end if
         if (abs(q_new - q) <= 4.0_dp * epsilon(1.0_dp) * abs(q)) return
         q = q_new
      end do
      call fatal_error(error, FFRF_NUMERIC_ERROR, 'pressure model: no heat per cycle found ' // &
         'for target_peak_pressure = ' // to_str(target) // ' Pa after 200 iterations (last Q = ' &
         // to_str(q) // ' J, peak ' // to_str(peak) // ' Pa); give heat_per_cycle instead')
   end subroutine tune_heat

   !> Peak, its angle and the works, once knots, values and slopes are set; rejects NaN/Inf.
   subroutine finish(self, error)
      type(pressure_model_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
      integer :: cell
      real(dp) :: t
      if (.not. all(ieee_is_finite(self%values) .and. ieee_is_finite(self%slopes))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'pressure model: non-finite pressure or ' // &
            'slope in the table; check the input')
         return
      end if
      call hermite_peak(self%knots, self%values, self%slopes, self%peak, self%peak_at, cell, t)
      self%peak_at = modulo(self%peak_at, cycle_period)
      self%work = work_between(self, self%knots(0), self%knots(0) + cycle_period)
      self%work_closed = work_between(self, pi, 3.0_dp * pi)
      if (.not. (ieee_is_finite(self%work) .and. ieee_is_finite(self%work_closed))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'pressure model: non-finite cycle work')
      end if
   end subroutine finish

end submodule ffrf_app_engine_pressure_cycle
