!> The piecewise cubic Hermite and periodic spline tables of ffrf_app_engine_pressure (a
!> submodule): evaluation, peak, the work integral p dV, the spline's knot slopes.
submodule (ffrf_app_engine_pressure) ffrf_app_engine_pressure_tables
   implicit none

contains

   module procedure evaluate
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
   end procedure evaluate

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

   module procedure hermite_value
      y = (1.0_dp + 2.0_dp * t) * (1.0_dp - t)**2 * y0 + t * (1.0_dp - t)**2 * w * s0 &
         + t**2 * (3.0_dp - 2.0_dp * t) * y1 + t**2 * (t - 1.0_dp) * w * s1
   end procedure hermite_value

   !> d/dx of hermite_value.
   pure function hermite_slope(y0, y1, s0, s1, w, t) result(s)
      real(dp), intent(in) :: y0, y1, s0, s1, w, t
      real(dp) :: s
      s = 6.0_dp * t * (t - 1.0_dp) * (y0 - y1) / w + (1.0_dp - 4.0_dp * t + 3.0_dp * t**2) * s0 &
         + (3.0_dp * t**2 - 2.0_dp * t) * s1
   end function hermite_slope

   module procedure hermite_peak
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
   end procedure hermite_peak

   module procedure work_between
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
   end procedure work_between

   module procedure periodic_spline_slopes
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
   end procedure periodic_spline_slopes

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

end submodule ffrf_app_engine_pressure_tables
