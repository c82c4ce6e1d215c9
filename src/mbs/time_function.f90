!> Functions of time g(t) with their first two derivatives and their integral from 0, for the
!> drivers of joints (ffrf_mbs_joint_driver) and the loads over time (ffrf_mbs_mechanism_loads);
!> docs/mechanisms.md "Laws over time". One table lists the kinds (the words a user writes):
!>
!> | word           | g(t)                                                                    |
!> |----------------|-------------------------------------------------------------------------|
!> | constant       | initial                                                                 |
!> | constant_speed | initial + speed t                                                       |
!> | ramp           | initial + (final - initial) s(tau), s(tau) = tau                        |
!> | smooth_step    | initial + (final - initial) s(tau), s(tau) = tau - sin(2 pi tau)/(2 pi)  |
!> | table          | interpolation of points (t_i, y_i), i = 1..n, linear or cubic spline     |
!>
!> with tau = (t - t_start)/duration clipped to [0, 1] (g is held before t_start and after
!> t_start + duration). The smooth step is the cycloidal step of Kane's spin-up law (Kane, Ryan
!> and Banerjee 1987; tests/unit/spin_beam_reference.f90): s' = 1 - cos(2 pi tau) and
!> s'' = 2 pi sin(2 pi tau) vanish at both ends, so g, g' and g'' are continuous; a ramp's g' jumps
!> at its ends.
!>
!> Table. Between the points g is the spline S(t) with second derivatives M_i at the points
!> (de Boor, A Practical Guide to Splines, 2001, ch. IV):
!>     S = M_i a^3/(6h) + M_i+1 b^3/(6h) + (y_i/h - M_i h/6) a + (y_i+1/h - M_i+1 h/6) b,
!> a = t_i+1 - t, b = t - t_i, h = t_i+1 - t_i. interpolation = 'linear': M = 0 (the polygon);
!> 'cubic': the cubic spline through the points, C2, with end conditions
!>   - beyond = 'hold': not-a-knot (the third derivative continuous at t_2 and t_n-1; n = 3: the
!>     parabola through the points; n = 2: the line), so a cubic is reproduced exactly;
!>   - beyond = 'periodic': periodic (y_n = y_1 required, S' and S'' equal at t_1 and t_n).
!> The M_i solve one n x n linear system once (Gaussian elimination with partial pivoting;
!> n <= max_table_points). Beyond the points: 'hold' keeps g = y_1 before t_1 and g = y_n after
!> t_n (g' and g'' are 0 there: a cubic table's g' jumps at its ends unless the data are flat);
!> 'periodic' repeats the table with period t_n - t_1 for every t.
!>
!> Integral G(t) = int_0^t g (driver prescribing a rate, ffrf_mbs_joint_driver): closed forms per
!> kind; for a table the exact integral of each spline piece,
!>     int_t_i^t S = M_i (h^4 - a^4)/(24h) + M_i+1 b^4/(24h) + (y_i/h - M_i h/6)(h^2 - a^2)/2
!>                   + (y_i+1/h - M_i+1 h/6) b^2/2,
!> summed from t_1, whole periods counted for a periodic table.
module ffrf_mbs_time_function
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_choices, only: choice_kind_of, choice_words, time_law_choices, TIME_CONSTANT, &
      TIME_CONSTANT_SPEED, TIME_RAMP, TIME_SMOOTH_STEP, TIME_TABLE, interpolation_choices, &
      INTERPOLATION_LINEAR, INTERPOLATION_CUBIC, beyond_choices, BEYOND_HOLD, BEYOND_PERIODIC
   implicit none
   private
   public :: time_function_t, time_function_kind_of, time_law_choices, new_time_function
   public :: TIME_CONSTANT, TIME_CONSTANT_SPEED, TIME_RAMP, TIME_SMOOTH_STEP, TIME_TABLE
   public :: max_table_points

   !> Largest number of table points
   integer, parameter :: max_table_points = 1000
   real(dp), parameter :: pi = acos(-1.0_dp)

   !> g(t) of one kind (module header); built by new_time_function.
   type :: time_function_t
      !> TIME_*
      integer :: kind = TIME_CONSTANT
      !> constant, constant_speed: g(0); ramp, smooth_step: g before t_start
      real(dp) :: initial = 0.0_dp
      !> ramp, smooth_step: g after t_start + duration
      real(dp) :: final = 0.0_dp
      !> constant_speed: dg/dt
      real(dp) :: speed = 0.0_dp
      !> ramp, smooth_step: start (s) and duration (s, > 0)
      real(dp) :: t_start = 0.0_dp, duration = 1.0_dp
      !> table: times (strictly increasing), values, second derivatives M_i, and the integral
      !> of g from t_1 to each t_i
      real(dp), allocatable :: times(:), values(:), curvatures(:), cumulative(:)
      !> table: repeated with period t_n - t_1 (else held)
      logical :: periodic = .false.
   contains
      !> [g, g', g''] at t
      procedure :: evaluate => time_function_evaluate
      !> int_0^t g
      procedure :: integral => time_function_integral
   end type time_function_t

contains

   !> The kind of a law word (any case; 0 if none).
   pure integer function time_function_kind_of(word) result(kind)
      character(len=*), intent(in) :: word
      kind = choice_kind_of(time_law_choices, word)
   end function time_function_kind_of

   !> A time function of `word` with its parameters, checked; `where` names the place in
   !> messages (e.g. 'case.nml:12: &driver "motor"'). Tables: times, values (same size, >= 2),
   !> interpolation 'linear' or 'cubic', beyond 'hold' or 'periodic'.
   subroutine new_time_function(word, where, fun, error, initial, final, speed, t_start, &
         duration, times, values, interpolation, beyond)
      character(len=*), intent(in) :: word, where
      type(time_function_t), intent(out) :: fun
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: initial, final, speed, t_start, duration
      real(dp), intent(in), optional :: times(:), values(:)
      character(len=*), intent(in), optional :: interpolation, beyond
      integer :: n, i
      fun%kind = time_function_kind_of(word)
      if (fun%kind == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': law = ''' // trim(word) // &
            ''', must be one of ' // choice_words(time_law_choices))
         return
      end if
      if (present(initial)) fun%initial = initial
      if (present(final)) fun%final = final
      if (present(speed)) fun%speed = speed
      if (present(t_start)) fun%t_start = t_start
      if (present(duration)) fun%duration = duration
      if ((fun%kind == TIME_RAMP .or. fun%kind == TIME_SMOOTH_STEP) .and. &
         .not. (fun%duration > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': duration = ' // &
            to_str(fun%duration) // ' s, must be > 0 for a ' // trim(word))
         return
      end if
      if (fun%kind /= TIME_TABLE) return
      if (.not. (present(times) .and. present(values))) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': a table needs table_time and ' &
            // 'table_value')
         return
      end if
      n = size(times)
      if (size(values) /= n) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': table_time has ' // to_str(n) // &
            ' values, table_value ' // to_str(size(values)) // '; give one value per time')
         return
      end if
      if (n < 2 .or. n > max_table_points) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': a table of ' // to_str(n) // &
            ' points; give 2 to ' // to_str(max_table_points))
         return
      end if
      do i = 2, n
         if (.not. (times(i) > times(i - 1))) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': table_time(' // to_str(i) // &
               ') = ' // to_str(times(i)) // ' s is not after table_time(' // to_str(i - 1) // &
               ') = ' // to_str(times(i - 1)) // ' s; the times must increase strictly')
            return
         end if
      end do
      fun%times = times
      fun%values = values
      fun%periodic = .false.
      if (present(beyond)) then
         select case (choice_kind_of(beyond_choices, beyond))
         case (BEYOND_HOLD)
         case (BEYOND_PERIODIC)
            fun%periodic = .true.
         case default
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': beyond = ''' // trim(beyond) &
               // ''', must be one of ' // choice_words(beyond_choices))
            return
         end select
      end if
      if (fun%periodic .and. values(n) /= values(1)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': a periodic table must end at ' &
            // 'its first value: table_value(' // to_str(n) // ') = ' // to_str(values(n)) // &
            ', table_value(1) = ' // to_str(values(1)))
         return
      end if
      allocate (fun%curvatures(n), source=0.0_dp)
      if (present(interpolation)) then
         select case (choice_kind_of(interpolation_choices, interpolation))
         case (INTERPOLATION_LINEAR)
         case (INTERPOLATION_CUBIC)
            call spline_curvatures(fun%times, fun%values, fun%periodic, fun%curvatures, where, &
               error)
            if (allocated(error)) return
         case default
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': interpolation = ''' // &
               trim(interpolation) // ''', must be one of ' // &
               choice_words(interpolation_choices))
            return
         end select
      end if
      allocate (fun%cumulative(n), source=0.0_dp)
      do i = 2, n
         fun%cumulative(i) = fun%cumulative(i - 1) + piece_integral(fun, i - 1, fun%times(i))
      end do
   end subroutine new_time_function

   !> Second derivatives of the cubic spline (module header: not-a-knot or periodic).
   subroutine spline_curvatures(t, y, periodic, m, where, error)
      real(dp), intent(in) :: t(:), y(:)
      logical, intent(in) :: periodic
      real(dp), intent(out) :: m(:)
      character(len=*), intent(in) :: where
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: a(:, :), rhs(:)
      real(dp) :: h(size(t) - 1)
      integer :: n, i
      n = size(t)
      m = 0.0_dp
      if (n == 2) return
      h = t(2:) - t(:n - 1)
      allocate (a(n, n), rhs(n), source=0.0_dp)
      do i = 2, n - 1
         a(i, i - 1) = h(i - 1)
         a(i, i) = 2.0_dp * (h(i - 1) + h(i))
         a(i, i + 1) = h(i)
         rhs(i) = 6.0_dp * ((y(i + 1) - y(i)) / h(i) - (y(i) - y(i - 1)) / h(i - 1))
      end do
      if (periodic) then
         ! M_1 = M_n; S'(t_1+) = S'(t_n-)
         a(1, 1) = 1.0_dp
         a(1, n) = -1.0_dp
         a(n, 1) = -h(1) / 3.0_dp
         a(n, 2) = -h(1) / 6.0_dp
         a(n, n - 1) = -h(n - 1) / 6.0_dp
         a(n, n) = -h(n - 1) / 3.0_dp
         rhs(n) = (y(n) - y(n - 1)) / h(n - 1) - (y(2) - y(1)) / h(1)
      else if (n == 3) then
         ! one parabola: M_1 = M_2 = M_3
         a(1, 1:2) = [1.0_dp, -1.0_dp]
         a(3, 2:3) = [1.0_dp, -1.0_dp]
      else
         ! not-a-knot: (M_2 - M_1)/h_1 = (M_3 - M_2)/h_2, likewise at t_n-1
         a(1, 1:3) = [h(2), -(h(1) + h(2)), h(1)]
         a(n, n - 2:n) = [h(n - 1), -(h(n - 2) + h(n - 1)), h(n - 2)]
      end if
      call solve_dense(a, rhs, m)
      if (.not. all(abs(m) <= huge(1.0_dp))) call fatal_error(error, FFRF_INPUT_ERROR, where // &
         ': the cubic spline through the table is singular; check table_time')
   end subroutine spline_curvatures

   !> x = a \ b by Gaussian elimination with partial pivoting (a, b overwritten).
   pure subroutine solve_dense(a, b, x)
      real(dp), intent(inout) :: a(:, :), b(:)
      real(dp), intent(out) :: x(:)
      real(dp) :: row(size(a, 2)), factor, swap
      integer :: n, k, p, i
      n = size(b)
      do k = 1, n - 1
         p = k - 1 + maxloc(abs(a(k:, k)), dim=1)
         if (p /= k) then
            row = a(k, :)
            a(k, :) = a(p, :)
            a(p, :) = row
            swap = b(k)
            b(k) = b(p)
            b(p) = swap
         end if
         do i = k + 1, n
            if (a(i, k) == 0.0_dp) cycle
            factor = a(i, k) / a(k, k)
            a(i, k:) = a(i, k:) - factor * a(k, k:)
            b(i) = b(i) - factor * b(k)
         end do
      end do
      do k = n, 1, -1
         x(k) = (b(k) - dot_product(a(k, k + 1:), x(k + 1:))) / a(k, k)
      end do
   end subroutine solve_dense

   !> [g, g', g''] at t (module header).
   pure function time_function_evaluate(self, t) result(g)
      class(time_function_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      real(dp) :: g(3)
      real(dp) :: tau, jump
      select case (self%kind)
      case (TIME_CONSTANT)
         g = [self%initial, 0.0_dp, 0.0_dp]
      case (TIME_CONSTANT_SPEED)
         g = [self%initial + self%speed * t, self%speed, 0.0_dp]
      case (TIME_RAMP, TIME_SMOOTH_STEP)
         jump = self%final - self%initial
         tau = (t - self%t_start) / self%duration
         if (tau <= 0.0_dp) then
            g = [self%initial, 0.0_dp, 0.0_dp]
         else if (tau >= 1.0_dp) then
            g = [self%final, 0.0_dp, 0.0_dp]
         else if (self%kind == TIME_RAMP) then
            g = [self%initial + jump * tau, jump / self%duration, 0.0_dp]
         else
            g = [self%initial + jump * (tau - sin(2.0_dp * pi * tau) / (2.0_dp * pi)), &
               jump / self%duration * (1.0_dp - cos(2.0_dp * pi * tau)), &
               jump / self%duration**2 * 2.0_dp * pi * sin(2.0_dp * pi * tau)]
         end if
      case default
         g = table_evaluate(self, t)
      end select
   end function time_function_evaluate

   !> Table: [S, S', S''] at t (held or wrapped beyond the points).
   pure function table_evaluate(self, t) result(g)
      class(time_function_t), intent(in) :: self
      real(dp), intent(in) :: t
      real(dp) :: g(3)
      real(dp) :: s
      integer :: n
      n = size(self%times)
      s = local_time(self, t)
      if (.not. self%periodic .and. s <= self%times(1)) then
         g = [self%values(1), 0.0_dp, 0.0_dp]
      else if (.not. self%periodic .and. s >= self%times(n)) then
         g = [self%values(n), 0.0_dp, 0.0_dp]
      else
         g = piece_evaluate(self, segment(self, s), s)
      end if
   end function table_evaluate

   !> [S, S', S''] of piece i at s (module header).
   pure function piece_evaluate(self, i, s) result(g)
      class(time_function_t), intent(in) :: self
      integer, intent(in) :: i
      real(dp), intent(in) :: s
      real(dp) :: g(3)
      real(dp) :: w
      call piece_terms(self, i, s, g, w)
   end function piece_evaluate

   !> Piece i at s: g = [S, S', S''] and w = int_t_i^s S (module header).
   pure subroutine piece_terms(self, i, s, g, w)
      class(time_function_t), intent(in) :: self
      integer, intent(in) :: i
      real(dp), intent(in) :: s
      real(dp), intent(out) :: g(3), w
      real(dp) :: a, b, h
      h = self%times(i + 1) - self%times(i)
      a = self%times(i + 1) - s
      b = s - self%times(i)
      associate (m0 => self%curvatures(i), m1 => self%curvatures(i + 1), &
            y0 => self%values(i), y1 => self%values(i + 1))
         g(1) = m0 * a**3 / (6.0_dp * h) + m1 * b**3 / (6.0_dp * h) + &
            (y0 / h - m0 * h / 6.0_dp) * a + (y1 / h - m1 * h / 6.0_dp) * b
         g(2) = -m0 * a**2 / (2.0_dp * h) + m1 * b**2 / (2.0_dp * h) + (y1 - y0) / h - &
            (m1 - m0) * h / 6.0_dp
         g(3) = (m0 * a + m1 * b) / h
         w = m0 * (h**4 - a**4) / (24.0_dp * h) + m1 * b**4 / (24.0_dp * h) + &
            (y0 / h - m0 * h / 6.0_dp) * (h**2 - a**2) / 2.0_dp + &
            (y1 / h - m1 * h / 6.0_dp) * b**2 / 2.0_dp
      end associate
   end subroutine piece_terms

   !> t wrapped into [t_1, t_n) for a periodic table; t itself otherwise.
   pure real(dp) function local_time(self, t) result(s)
      class(time_function_t), intent(in) :: self
      real(dp), intent(in) :: t
      real(dp) :: period
      s = t
      if (.not. self%periodic) return
      period = self%times(size(self%times)) - self%times(1)
      s = self%times(1) + modulo(t - self%times(1), period)
   end function local_time

   !> Number of whole periods between t_1 and t (periodic table; 0 otherwise).
   pure real(dp) function periods_before(self, t) result(k)
      class(time_function_t), intent(in) :: self
      real(dp), intent(in) :: t
      real(dp) :: period
      k = 0.0_dp
      if (.not. self%periodic) return
      period = self%times(size(self%times)) - self%times(1)
      k = floor((t - self%times(1)) / period)
   end function periods_before

   !> The piece i with t_i <= s < t_i+1 (t_1 < s < t_n), by bisection.
   pure integer function segment(self, s) result(i)
      class(time_function_t), intent(in) :: self
      real(dp), intent(in) :: s
      integer :: lo, hi, mid
      lo = 1
      hi = size(self%times)
      do while (hi - lo > 1)
         mid = (lo + hi) / 2
         if (self%times(mid) <= s) then
            lo = mid
         else
            hi = mid
         end if
      end do
      i = lo
   end function segment

   !> int_t_i^s S for t_i <= s <= t_i+1 (module header).
   pure real(dp) function piece_integral(self, i, s) result(w)
      class(time_function_t), intent(in) :: self
      integer, intent(in) :: i
      real(dp), intent(in) :: s
      real(dp) :: g(3)
      call piece_terms(self, i, s, g, w)
   end function piece_integral

   !> int_0^t g (module header).
   pure real(dp) function time_function_integral(self, t) result(w)
      class(time_function_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      real(dp) :: jump
      select case (self%kind)
      case (TIME_CONSTANT)
         w = self%initial * t
      case (TIME_CONSTANT_SPEED)
         w = self%initial * t + 0.5_dp * self%speed * t**2
      case (TIME_RAMP, TIME_SMOOTH_STEP)
         jump = self%final - self%initial
         w = self%initial * t + jump * (step_integral(self, t) - step_integral(self, 0.0_dp))
      case default
         w = table_antiderivative(self, t) - table_antiderivative(self, 0.0_dp)
      end select
   end function time_function_integral

   !> int_-inf^t s(tau(t')) dt' of the ramp or smooth step (0 before t_start).
   pure real(dp) function step_integral(self, t) result(w)
      class(time_function_t), intent(in) :: self
      real(dp), intent(in) :: t
      real(dp) :: tau
      tau = (t - self%t_start) / self%duration
      if (tau <= 0.0_dp) then
         w = 0.0_dp
      else if (tau >= 1.0_dp) then
         w = self%duration * (unit_step_integral(self%kind, 1.0_dp) + (tau - 1.0_dp))
      else
         w = self%duration * unit_step_integral(self%kind, tau)
      end if
   end function step_integral

   !> int_0^tau s: tau^2/2 (ramp), tau^2/2 + (cos(2 pi tau) - 1)/(4 pi^2) (smooth step).
   pure real(dp) function unit_step_integral(kind, tau) result(w)
      integer, intent(in) :: kind
      real(dp), intent(in) :: tau
      w = 0.5_dp * tau**2
      if (kind == TIME_SMOOTH_STEP) w = w + (cos(2.0_dp * pi * tau) - 1.0_dp) / (4.0_dp * pi**2)
   end function unit_step_integral

   !> An antiderivative of a table's g: int_t_1^t g (negative before t_1; whole periods counted).
   pure real(dp) function table_antiderivative(self, t) result(w)
      class(time_function_t), intent(in) :: self
      real(dp), intent(in) :: t
      real(dp) :: s
      integer :: n, i
      n = size(self%times)
      s = local_time(self, t)
      w = periods_before(self, t) * self%cumulative(n)
      if (s <= self%times(1)) then
         w = w + self%values(1) * (s - self%times(1))
      else if (s >= self%times(n)) then
         w = w + self%cumulative(n) + self%values(n) * (s - self%times(n))
      else
         i = segment(self, s)
         w = w + self%cumulative(i) + piece_integral(self, i, s)
      end if
   end function table_antiderivative

end module ffrf_mbs_time_function
