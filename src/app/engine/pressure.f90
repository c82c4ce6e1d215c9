!> In-cylinder pressure of the four-stroke reference engine (scene.md "Loads", theory.md section 6)
!> as a periodic function of the unwrapped crank rotation theta (rad, period 4 pi, theta = 0 at
!> the TDC that starts the intake stroke).
!>
!> Single-zone model (`init`): intake at p_in on [0, 180) deg, closed part on [180, 540) deg with
!> the first law of a closed system at constant polytropic exponent n (theory.md section 6)
!>     dp/dtheta = [ (n - 1) dQ/dtheta - n p dV/dtheta ] / V,   p(180 deg) = p_in,
!> Wiebe heat release dQ/dtheta = Q a (m + 1)/Dtheta x^m exp(-a x^(m+1)), x = (theta -
!> theta_0)/Dtheta, instant blow-down to p_ex at 540 deg and exhaust at p_ex on [540, 720) deg. The
!> ODE is integrated once by classical RK4 on a uniform grid of the closed part and tabulated with
!> the ODE's own derivative at every node; p and dp/dtheta come from the cubic Hermite interpolant
!> of that table, which is C1 inside each of the three phases (p jumps at 540 deg and at 720 = 0
!> deg, where dV/dtheta = 0). The ODE is linear in (p, Q), so p = p_0 + Q p_1 with p_0 the motored
!> pressure and p_1 the response to unit heat: the heat per cycle that gives a target peak is found
!> by a safeguarded Newton iteration on the peak of the interpolant, whose derivative in Q is p_1 at
!> the peak (envelope theorem); the peak is convex and increasing in Q, so Newton converges
!> monotonically.
!>
!> User table (`init_from_table`): a periodic cubic spline (C2, fourth-order accurate) through the
!> points, stored in the same Hermite form.
!>
!> The piston force is -(p - p_ref) pi B^2 / 4 along +y (scene.md: the gas pushes the piston towards
!> the crank, -y, since crank angle 0 puts the pin at +y).
module ffrf_app_engine_pressure
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_input_pressure, only: pressure_input_t
   use ffrf_app_engine_slider_crank, only: cylinder_volume, cylinder_dvolume, swept_volume, &
      clearance_volume
   implicit none
   private
   !> pressure_input_t (ffrf_input_pressure) is public here too, the type init takes
   public :: pressure_input_t, pressure_model_t, wiebe_rate

   !> Period of the four-stroke cycle in crank rotation (rad)
   real(dp), parameter :: cycle_period = 4.0_dp * pi
   !> Degrees to radians
   real(dp), parameter :: deg = pi / 180.0_dp
   !> Widest piece of one Gauss-Legendre rule in the work integrals (rad): 0.5 deg
   real(dp), parameter :: max_gauss_piece = 0.5_dp * pi / 180.0_dp

   !> Cylinder pressure p(theta) as a periodic piecewise cubic Hermite function of the crank
   !> rotation (period 4 pi), from the single-zone model or from a user table.
   type :: pressure_model_t
      !> The data it was made from (geometry used by volume, work and force)
      type(pressure_input_t) :: input
      !> .true. when made by init_from_table
      logical :: from_table = .false.
      !> Piston crown area pi B^2 / 4 (m^2)
      real(dp) :: area = 0.0_dp
      !> Crank radius r = S / 2 (m)
      real(dp) :: crank_radius = 0.0_dp
      !> Clearance volume V_c (m^3)
      real(dp) :: v_clearance = 0.0_dp
      !> Heat per cycle Q (J); zero for a table
      real(dp) :: heat = 0.0_dp
      !> Largest pressure of the interpolant (Pa) and its cycle angle in [0, 4 pi) (rad)
      real(dp) :: peak = 0.0_dp, peak_at = 0.0_dp
      !> Work of one cycle, closed integral of p dV (J), and of its closed part 180..540 deg (J)
      real(dp) :: work = 0.0_dp, work_closed = 0.0_dp
      !> Knots x(0:n) of one period (rad), nondecreasing, x(n) = x(0) + 4 pi; a repeated knot
      !> is a jump
      real(dp), allocatable :: knots(:)
      !> Pressure (Pa) at the knots
      real(dp), allocatable :: values(:)
      !> dp/dtheta (Pa/rad) at the knots
      real(dp), allocatable :: slopes(:)
   contains
      !> Single-zone model from engine data
      procedure :: init => pressure_model_init
      !> Periodic spline through a user table
      procedure :: init_from_table => pressure_model_init_from_table
      !> p(theta) (Pa)
      procedure :: pressure => pressure_model_pressure
      !> dp/dtheta (Pa/rad)
      procedure :: dpressure => pressure_model_dpressure
      !> Force on the piston along +y (N)
      procedure :: piston_force => pressure_model_piston_force
      !> Cylinder volume V(theta) (m^3)
      procedure :: volume => pressure_model_volume
      !> dV/dtheta (m^3/rad)
      procedure :: dvolume => pressure_model_dvolume
      !> Closed integral of p dV over 720 deg (J)
      procedure :: cycle_work => pressure_model_cycle_work
      !> Integral of p dV from 180 to 540 deg (J)
      procedure :: closed_work => pressure_model_closed_work
      !> cycle_work / (4 pi) (N m)
      procedure :: mean_indicated_torque => pressure_model_mean_indicated_torque
      !> Largest pressure (Pa)
      procedure :: peak_pressure => pressure_model_peak_pressure
      !> Cycle angle of the largest pressure in [0, 4 pi) (rad)
      procedure :: peak_angle => pressure_model_peak_angle
      !> Heat per cycle Q (J)
      procedure :: heat_per_cycle => pressure_model_heat_per_cycle
   end type pressure_model_t

   interface
      !> Single-zone model of the engine `input` (see the module header); tunes Q when
      !> input%heat_per_cycle < 0.
      module subroutine pressure_model_init(self, input, error)
         !> Model to build
         class(pressure_model_t), intent(out) :: self
         !> Engine data
         type(pressure_input_t), intent(in) :: input
         type(error_t), allocatable, intent(out) :: error
      end subroutine pressure_model_init

      !> Periodic cubic spline (C2) through a user table p(angle) of one 720 deg cycle.
      module subroutine pressure_model_init_from_table(self, input, angles_deg, pressures_pa, error)
         !> Model to build
         class(pressure_model_t), intent(out) :: self
         !> Engine geometry and reference pressure (the combustion keys are not used)
         type(pressure_input_t), intent(in) :: input
         !> Cycle angles (deg), strictly increasing in [0, 720), at least 4
         real(dp), intent(in) :: angles_deg(:)
         !> Absolute pressures (Pa) at angles_deg, finite and >= 0
         real(dp), intent(in) :: pressures_pa(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine pressure_model_init_from_table

      !> Cylinder pressure p(theta) (Pa) at the unwrapped crank rotation theta (rad, any sign).
      elemental module function pressure_model_pressure(self, theta_rad) result(p)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         !> Crank rotation from the TDC that starts the intake (rad)
         real(dp), intent(in) :: theta_rad
         real(dp) :: p
      end function pressure_model_pressure

      !> dp/dtheta (Pa/rad) at theta (rad); the derivative of `pressure` (right limit at jumps).
      elemental module function pressure_model_dpressure(self, theta_rad) result(dp_dtheta)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         !> Crank rotation (rad)
         real(dp), intent(in) :: theta_rad
         real(dp) :: dp_dtheta
      end function pressure_model_dpressure

      !> Gas force on the piston along +y, -(p - p_ref) pi B^2 / 4 (N): negative (towards the crank)
      !> while p > p_ref.
      elemental module function pressure_model_piston_force(self, theta_rad) result(force)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         !> Crank rotation (rad)
         real(dp), intent(in) :: theta_rad
         real(dp) :: force
      end function pressure_model_piston_force

      !> Cylinder volume V(theta) (m^3), theory.md section 6.
      elemental module function pressure_model_volume(self, theta_rad) result(v)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         !> Crank rotation (rad)
         real(dp), intent(in) :: theta_rad
         real(dp) :: v
      end function pressure_model_volume

      !> dV/dtheta (m^3/rad), theory.md section 6.
      elemental module function pressure_model_dvolume(self, theta_rad) result(dv)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         !> Crank rotation (rad)
         real(dp), intent(in) :: theta_rad
         real(dp) :: dv
      end function pressure_model_dvolume

      !> Indicated work of one cycle, the closed integral of p dV over 720 deg (J), with pumping.
      pure module function pressure_model_cycle_work(self) result(work)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         real(dp) :: work
      end function pressure_model_cycle_work

      !> Work of the closed part, the integral of p dV from 180 to 540 deg (J).
      pure module function pressure_model_closed_work(self) result(work)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         real(dp) :: work
      end function pressure_model_closed_work

      !> Mean indicated torque, cycle work / (4 pi) (N m): the crank torque whose work over two
      !> revolutions equals the gas work.
      pure module function pressure_model_mean_indicated_torque(self) result(torque)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         real(dp) :: torque
      end function pressure_model_mean_indicated_torque

      !> Largest pressure of the cycle (Pa), the maximum of the interpolant.
      pure module function pressure_model_peak_pressure(self) result(p)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         real(dp) :: p
      end function pressure_model_peak_pressure

      !> Cycle angle of the peak pressure in [0, 4 pi) (rad; 2 pi is the firing TDC).
      pure module function pressure_model_peak_angle(self) result(theta)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         real(dp) :: theta
      end function pressure_model_peak_angle

      !> Heat released per cycle Q (J), given or tuned; zero for a table.
      pure module function pressure_model_heat_per_cycle(self) result(q)
         !> Initialised model
         class(pressure_model_t), intent(in) :: self
         real(dp) :: q
      end function pressure_model_heat_per_cycle

      !> Wiebe heat-release rate per unit heat, dx_b/dtheta (1/rad) (theory.md section 6).
      elemental module function wiebe_rate(theta, start, duration, a, m) result(rate)
         !> Cycle angle (rad)
         real(dp), intent(in) :: theta
         !> Start of combustion theta_0 (rad)
         real(dp), intent(in) :: start
         !> Duration Dtheta (rad), > 0
         real(dp), intent(in) :: duration
         !> Efficiency parameter a
         real(dp), intent(in) :: a
         !> Form factor m >= 0
         real(dp), intent(in) :: m
         real(dp) :: rate
      end function wiebe_rate
   end interface

end module ffrf_app_engine_pressure

!> Bodies of ffrf_app_engine_pressure (a submodule, as the house style asks of long modules): the
!> single-zone integration, the heat tuning and the piecewise cubic Hermite and spline tables.
submodule (ffrf_app_engine_pressure) ffrf_app_engine_pressure_impl
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

   ! ---------------------------------------------------------------------------------------------
   ! Piecewise cubic Hermite tables

   !> p and dp/dtheta of the table at theta (rad), wrapped into the period [x(0), x(0) + 4 pi).
   elemental subroutine evaluate(self, theta, p, dp_dtheta)
      !> Initialised model
      type(pressure_model_t), intent(in) :: self
      !> Crank rotation (rad)
      real(dp), intent(in) :: theta
      !> Pressure (Pa) and dp/dtheta (Pa/rad)
      real(dp), intent(out) :: p, dp_dtheta
      real(dp) :: phi, width, t
      integer :: cell
      phi = self%knots(0) + modulo(theta - self%knots(0), cycle_period)
      if (phi >= self%knots(0) + cycle_period) phi = self%knots(0)
      cell = find_cell(self%knots, phi)
      width = self%knots(cell) - self%knots(cell - 1)
      t = (phi - self%knots(cell - 1)) / width
      p = hermite_value(self%values(cell - 1), self%values(cell), self%slopes(cell - 1), &
         self%slopes(cell), width, t)
      dp_dtheta = hermite_slope(self%values(cell - 1), self%values(cell), &
         self%slopes(cell - 1), self%slopes(cell), width, t)
   end subroutine evaluate

   !> The cell c in 1..n with x(c-1) <= phi < x(c), the last such for repeated knots (so the
   !> value at a jump is its right limit); phi in [x(0), x(n)).
   pure function find_cell(x, phi) result(cell)
      real(dp), intent(in) :: x(0:)
      real(dp), intent(in) :: phi
      integer :: cell
      integer :: lo, hi, mid
      ! invariant: x(lo) <= phi, and x(hi) > phi or hi = n
      lo = 0
      hi = ubound(x, 1)
      do while (hi - lo > 1)
         mid = (lo + hi) / 2
         if (x(mid) <= phi) then
            lo = mid
         else
            hi = mid
         end if
      end do
      cell = lo + 1
   end function find_cell

   !> Cubic Hermite value at t in [0, 1] of a cell of width w with end values y0, y1 and slopes
   !> s0, s1 (per unit of x).
   pure function hermite_value(y0, y1, s0, s1, w, t) result(y)
      real(dp), intent(in) :: y0, y1, s0, s1, w, t
      real(dp) :: y
      y = (1.0_dp + 2.0_dp * t) * (1.0_dp - t)**2 * y0 + t * (1.0_dp - t)**2 * w * s0 &
         + t**2 * (3.0_dp - 2.0_dp * t) * y1 + t**2 * (t - 1.0_dp) * w * s1
   end function hermite_value

   !> d/dx of hermite_value.
   pure function hermite_slope(y0, y1, s0, s1, w, t) result(s)
      real(dp), intent(in) :: y0, y1, s0, s1, w, t
      real(dp) :: s
      s = 6.0_dp * t * (t - 1.0_dp) * (y0 - y1) / w + (1.0_dp - 4.0_dp * t + 3.0_dp * t**2) * s0 &
         + (3.0_dp * t**2 - 2.0_dp * t) * s1
   end function hermite_slope

   !> Maximum of a piecewise cubic Hermite function over its knots x(0:n): value, position, cell
   !> and local coordinate t. Each cell's candidates are its ends and the zeros of the quadratic
   !> derivative inside it.
   pure subroutine hermite_peak(x, y, s, peak, at, cell, t)
      !> Knots, values and slopes of the table
      real(dp), intent(in) :: x(0:), y(0:), s(0:)
      !> Largest value and its position
      real(dp), intent(out) :: peak, at
      !> Its cell c (between x(c-1) and x(c))
      integer, intent(out) :: cell
      !> Its local coordinate in [0, 1]
      real(dp), intent(out) :: t
      real(dp) :: w, a, b, c, disc, q, roots(2), value, candidates(4)
      integer :: i, j, num_roots
      peak = -huge(1.0_dp)
      cell = 1
      t = 0.0_dp
      do i = 1, ubound(x, 1)
         w = x(i) - x(i - 1)
         if (w <= 0.0_dp) cycle
         ! d/dt of the cell's cubic: a t^2 + b t + c
         a = 6.0_dp * (y(i - 1) - y(i)) + 3.0_dp * w * (s(i - 1) + s(i))
         b = -6.0_dp * (y(i - 1) - y(i)) - w * (4.0_dp * s(i - 1) + 2.0_dp * s(i))
         c = w * s(i - 1)
         num_roots = 0
         if (abs(a) > 1.0e-14_dp * (abs(b) + abs(c))) then
            disc = b * b - 4.0_dp * a * c
            if (disc >= 0.0_dp) then
               q = -0.5_dp * (b + sign(sqrt(disc), b))
               if (abs(q) > 0.0_dp) then
                  roots = [q / a, c / q]
                  num_roots = 2
               else
                  roots(1) = 0.0_dp
                  num_roots = 1
               end if
            end if
         else if (abs(b) > 0.0_dp) then
            roots(1) = -c / b
            num_roots = 1
         end if
         candidates(1:2) = [0.0_dp, 1.0_dp]
         candidates(3:2 + num_roots) = roots(1:num_roots)
         do j = 1, 2 + num_roots
            if (candidates(j) < 0.0_dp .or. candidates(j) > 1.0_dp) cycle
            value = hermite_value(y(i - 1), y(i), s(i - 1), s(i), w, candidates(j))
            if (value > peak) then
               peak = value
               cell = i
               t = candidates(j)
            end if
         end do
      end do
      at = x(cell - 1) + t * (x(cell) - x(cell - 1))
   end subroutine hermite_peak

   !> Integral of p dV = p(theta) dV/dtheta dtheta over [a, b] (rad, b - a <= 4 pi) of the
   !> periodic interpolant: cell by cell, 5-point Gauss-Legendre on pieces of at most 0.5 deg.
   function work_between(self, a, b) result(work)
      type(pressure_model_t), intent(in) :: self
      real(dp), intent(in) :: a, b
      real(dp) :: work
      real(dp), parameter :: nodes(5) = [0.0_dp, -0.5384693101056831_dp, &
         0.5384693101056831_dp, -0.9061798459386640_dp, 0.9061798459386640_dp]
      real(dp), parameter :: weights(5) = [0.5688888888888889_dp, 0.4786286704993665_dp, &
         0.4786286704993665_dp, 0.2369268850561891_dp, 0.2369268850561891_dp]
      real(dp) :: lo, hi, w, piece, centre, phi, t
      integer :: shift, i, j, k, num_pieces
      work = 0.0_dp
      do shift = -1, 1
         do i = 1, ubound(self%knots, 1)
            w = self%knots(i) - self%knots(i - 1)
            lo = max(self%knots(i - 1), a + shift * cycle_period)
            hi = min(self%knots(i), b + shift * cycle_period)
            if (w <= 0.0_dp .or. hi <= lo) cycle
            num_pieces = ceiling((hi - lo) / max_gauss_piece)
            piece = (hi - lo) / num_pieces
            do k = 1, num_pieces
               centre = lo + (k - 0.5_dp) * piece
               do j = 1, 5
                  phi = centre + 0.5_dp * piece * nodes(j)
                  t = (phi - self%knots(i - 1)) / w
                  work = work + 0.5_dp * piece * weights(j) * self%dvolume(phi) * &
                     hermite_value(self%values(i - 1), self%values(i), self%slopes(i - 1), &
                     self%slopes(i), w, t)
               end do
            end do
         end do
      end do
   end function work_between

   !> Knot slopes of the periodic cubic spline through (x(0:n), y(0:n)), y(n) = y(0): second
   !> derivatives M from the cyclic tridiagonal system
   !>    h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (d_i - d_{i-1}),
   !> d_i = (y_{i+1} - y_i)/h_i (Sherman-Morrison on the Thomas algorithm), then
   !> s_i = d_i - h_i (2 M_i + M_{i+1}) / 6.
   pure subroutine periodic_spline_slopes(x, y, s)
      !> Knots x(0:n), strictly increasing, x(n) = x(0) + period, n >= 3
      real(dp), intent(in) :: x(0:)
      !> Values, y(n) = y(0)
      real(dp), intent(in) :: y(0:)
      !> Spline slopes at the knots, s(n) = s(0)
      real(dp), intent(out) :: s(0:)
      real(dp), allocatable :: h(:), d(:), lower(:), diag(:), upper(:), rhs(:), m2(:), z(:), u(:)
      real(dp) :: gamma, corner, fact
      integer :: n, i
      n = ubound(x, 1)
      allocate (h(0:n - 1), d(0:n - 1), lower(0:n - 1), diag(0:n - 1), upper(0:n - 1), &
         rhs(0:n - 1), u(0:n - 1), m2(0:n - 1), z(0:n - 1))
      h = x(1:n) - x(0:n - 1)
      d = (y(1:n) - y(0:n - 1)) / h
      do i = 0, n - 1
         lower(i) = h(modulo(i - 1, n))
         upper(i) = h(i)
         diag(i) = 2.0_dp * (h(modulo(i - 1, n)) + h(i))
         rhs(i) = 6.0_dp * (d(i) - d(modulo(i - 1, n)))
      end do
      ! Corners A(0, n-1) = A(n-1, 0) = h_{n-1}: A = T + u v^T with u = (gamma, 0.., corner),
      ! v = (1, 0.., corner/gamma) (Numerical Recipes, cyclic).
      corner = h(n - 1)
      gamma = -diag(0)
      diag(0) = diag(0) - gamma
      diag(n - 1) = diag(n - 1) - corner * corner / gamma
      m2(:) = thomas(lower, diag, upper, rhs)
      u = 0.0_dp
      u(0) = gamma
      u(n - 1) = corner
      z(:) = thomas(lower, diag, upper, u)
      fact = (m2(0) + corner * m2(n - 1) / gamma) / (1.0_dp + z(0) + corner * z(n - 1) / gamma)
      m2 = m2 - fact * z
      do i = 0, n - 1
         s(i) = d(i) - h(i) * (2.0_dp * m2(i) + m2(modulo(i + 1, n))) / 6.0_dp
      end do
      s(n) = s(0)
   end subroutine periodic_spline_slopes

   !> Solution of the tridiagonal system lower(i) u(i-1) + diag(i) u(i) + upper(i) u(i+1) = r(i)
   !> (lower(0) and upper(n-1) ignored), no pivoting: diagonally dominant systems only.
   pure function thomas(lower, diag, upper, r) result(u)
      real(dp), intent(in) :: lower(0:), diag(0:), upper(0:), r(0:)
      real(dp) :: u(0:ubound(r, 1))
      real(dp) :: c(0:ubound(r, 1)), beta
      integer :: i, n
      n = ubound(r, 1)
      beta = diag(0)
      u(0) = r(0) / beta
      do i = 1, n
         c(i) = upper(i - 1) / beta
         beta = diag(i) - lower(i) * c(i)
         u(i) = (r(i) - lower(i) * u(i - 1)) / beta
      end do
      do i = n - 1, 0, -1
         u(i) = u(i) - c(i + 1) * u(i + 1)
      end do
   end function thomas

end submodule ffrf_app_engine_pressure_impl
