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
   use ffrf_core_kinds, only: dp, pi
   use ffrf_core_error, only: error_t
   use ffrf_input_pressure, only: pressure_input_t
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

      ! --- ffrf_app_engine_pressure_tables (pressure_tables.f90) ---------------------------------

      !> p and dp/dtheta of the table at theta (rad), wrapped into the period [x(0), x(0) + 4 pi).
      elemental module subroutine evaluate(self, theta, p, dp_dtheta)
         !> Initialised model
         type(pressure_model_t), intent(in) :: self
         !> Crank rotation (rad)
         real(dp), intent(in) :: theta
         !> Pressure (Pa) and dp/dtheta (Pa/rad)
         real(dp), intent(out) :: p, dp_dtheta
      end subroutine evaluate

      !> Cubic Hermite value at t in [0, 1] of a cell of width w with end values y0, y1 and slopes
      !> s0, s1 (per unit of x).
      pure module function hermite_value(y0, y1, s0, s1, w, t) result(y)
         real(dp), intent(in) :: y0, y1, s0, s1, w, t
         real(dp) :: y
      end function hermite_value

      !> Maximum of a piecewise cubic Hermite function over its knots x(0:n): value, position, cell
      !> and local coordinate t. Each cell's candidates are its ends and the zeros of the quadratic
      !> derivative inside it.
      pure module subroutine hermite_peak(x, y, s, peak, at, cell, t)
         !> Knots, values and slopes of the table
         real(dp), intent(in) :: x(0:), y(0:), s(0:)
         !> Largest value and its position
         real(dp), intent(out) :: peak, at
         !> Its cell c (between x(c-1) and x(c))
         integer, intent(out) :: cell
         !> Its local coordinate in [0, 1]
         real(dp), intent(out) :: t
      end subroutine hermite_peak

      !> Integral of p dV = p(theta) dV/dtheta dtheta over [a, b] (rad, b - a <= 4 pi) of the
      !> periodic interpolant: cell by cell, 5-point Gauss-Legendre on pieces of at most 0.5 deg.
      module function work_between(self, a, b) result(work)
         type(pressure_model_t), intent(in) :: self
         real(dp), intent(in) :: a, b
         real(dp) :: work
      end function work_between

      !> Knot slopes of the periodic cubic spline through (x(0:n), y(0:n)), y(n) = y(0): second
      !> derivatives M from the cyclic tridiagonal system
      !>    h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (d_i - d_{i-1}),
      !> d_i = (y_{i+1} - y_i)/h_i (Sherman-Morrison on the Thomas algorithm), then
      !> s_i = d_i - h_i (2 M_i + M_{i+1}) / 6.
      pure module subroutine periodic_spline_slopes(x, y, s)
         !> Knots x(0:n), strictly increasing, x(n) = x(0) + period, n >= 3
         real(dp), intent(in) :: x(0:)
         !> Values, y(n) = y(0)
         real(dp), intent(in) :: y(0:)
         !> Spline slopes at the knots, s(n) = s(0)
         real(dp), intent(out) :: s(0:)
      end subroutine periodic_spline_slopes

   end interface

end module ffrf_app_engine_pressure
