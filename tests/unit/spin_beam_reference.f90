!> The rotating-beam spin-up benchmark (Kane, Ryan & Banerjee, "Dynamics of a cantilever beam
!> attached to a moving base", J. Guidance 10(2) (1987) 139-151) and its independent references,
!> for test_modes_geometric_stiffness and test_mbs_spin_up.
!>
!> Kane's beam: L = 10 m, E = 7e10 Pa, rho = 3000 kg/m^3, A = 4e-4 m^2, I = 2e-7 m^4, so
!> EI = 1.4e4 N m^2 and rho A = 1.2 kg/m. (A and I are not those of one square section: a
!> 0.02 x 0.02 m square has A = 4e-4 m^2 but I = 1.33e-8 m^4; I = 2e-7 m^4 belongs to a thin
!> rectangle bent about its strong axis. Only EI and rho A enter the in-plane Euler-Bernoulli
!> problem.) Spin-up about an axis through the root, perpendicular to the beam:
!>     Omega(t) = (Omega_s/T) (t - T/(2 pi) sin(2 pi t/T)) for t <= T, Omega_s after,  T = 15 s.
!> Scaled beam of input/spin_beam.geo: L = 10 m, square 0.2 x 0.2 m, rho = 3000 kg/m^3 and
!> E = 1.05e10 Pa, chosen so that EI/(rho A) = E a^2/(12 rho) = 1.1667e4 m^4/s^2 equals Kane's
!> 1.4e4/1.2: the same bending frequencies (omega_1 = 3.5160 sqrt(EI/(rho A L^4)) = 3.798
!> rad/s) and, for an inextensible Euler-Bernoulli beam, the same tip deflection (the mass scale
!> drops out). Slenderness L/a = 50 (Kane: L/r = 447) keeps the Tet10 mesh at 909 nodes.
!>
!> References:
!> - rotating_lambda: first bending frequency parameter lambda = omega / sqrt(EI/(rho A L^4)) of
!>   the uniform Euler-Bernoulli cantilever spinning at Omega_bar = Omega / sqrt(EI/(rho A L^4))
!>   about an axis through its root (hub radius 0), out of the plane of rotation (flapwise):
!>   EI w'''' - (N w')' = rho A omega^2 w, N = rho A Omega^2 (L^2 - x^2)/2. Values of a
!>   200-element Hermite-cubic FE solution (converged to 1e-8), which reproduce the table of
!>   Wright, Smith, Thresher & Wang (J. Appl. Mech. 49 (1982) 197) and Hodges & Rutkowski
!>   (AIAA J. 19 (1981) 1459) to its four decimals (3.6816, 5.5850, 11.2023). In the plane of
!>   rotation (chordwise) the same equation has the extra term -rho A Omega^2 w (the centrifugal
!>   force of the lateral displacement), which only shifts the eigenvalue for a uniform beam:
!>   omega_chord^2 = omega_flap^2 - Omega^2 exactly.
!> - southwell_coefficient: the first-order (Southwell) coefficient of omega^2 = omega_0^2 +
!>   K1 Omega^2, K1 = int_0^1 (1 - xi^2)/2 phi'^2 dxi / int_0^1 phi^2 dxi with the exact
!>   clamped-free mode phi (beta L = 1.87510407): K1 = 1.19334 (Rayleigh's quotient of the
!>   stiffening; the exact coefficient falls to (lambda^2 - lambda_0^2)/Omega_bar^2 = 1.1923,
!>   1.1770, 1.1314 at Omega_bar = 1, 4, 10 as the mode shape changes).
!> - hencky_chain_spin_up: a planar Hencky bar chain, the geometrically exact (large-rotation,
!>   inextensible) discrete model of the Euler-Bernoulli beam: n uniform rigid bars of length
!>   l = L/n, mass rho A l and inertia rho A l^3/12 about their centres, joined by rotational
!>   springs EI/l at the joints and 2 EI/l at the hub (the root joint represents half a bar;
!>   this places the springs so that the static tip deflection under a tip load is
!>   P L^3/(3 EI) (1 + 1/(2 n^2)): second order). Absolute bar angles phi_i, hub angle theta(t):
!>     sum_j m l^2 c_ij cos(phi_i - phi_j) phi_j'' + sum_j m l^2 c_ij sin(phi_i - phi_j) phi_j'^2
!>       = -k_i (phi_i - phi_(i-1)) + k_(i+1) (phi_(i+1) - phi_i),   phi_0 = theta(t),
!>   c_ij = n - max(i, j) + 1/2 (i /= j), c_ii = n - i + 1/3 (Lagrange's equations of the chain;
!>   Kane's equations give the same). Integrated by classical RK4 with h <= 1/omega_max (omega_max
!>   the chain's highest frequency at rest; RK4's stability limit is 2.83/omega). Tip deflection
!>   in the hub frame: l sum_i sin(phi_i - theta).
module ffrf_test_spin_beam
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_lapack, only: dsygv, dposv
   use ffrf_mbs_mechanism_loads, only: drive_law_t
   implicit none
   private
   public :: spin_up_drive_t, rotating_lambda, southwell_coefficient, reference_frequency
   public :: hencky_chain_lowest_frequency, hencky_chain_spin_up
   public :: BEAM_LENGTH, BEAM_SIDE, BEAM_YOUNG, BEAM_POISSON, BEAM_DENSITY, SPIN_UP_TIME
   public :: BENDING_STIFFNESS, MASS_PER_LENGTH

   !> Scaled beam (module header): length, side of the square section (m), E (Pa), nu, rho
   real(dp), parameter :: BEAM_LENGTH = 10.0_dp, BEAM_SIDE = 0.2_dp, BEAM_YOUNG = 1.05e10_dp
   real(dp), parameter :: BEAM_POISSON = 0.3_dp, BEAM_DENSITY = 3000.0_dp
   !> EI (N m^2) and rho A (kg/m) of the scaled beam
   real(dp), parameter :: BENDING_STIFFNESS = BEAM_YOUNG * BEAM_SIDE**4 / 12.0_dp
   real(dp), parameter :: MASS_PER_LENGTH = BEAM_DENSITY * BEAM_SIDE**2
   !> Spin-up time T (s)
   real(dp), parameter :: SPIN_UP_TIME = 15.0_dp

   !> Kane's spin-up law as a driving constraint of the hub rotation (module header).
   type, extends(drive_law_t) :: spin_up_drive_t
      !> Final speed Omega_s (rad/s)
      real(dp) :: final_speed = 4.0_dp
      !> Spin-up time T (s)
      real(dp) :: ramp_time = SPIN_UP_TIME
   contains
      procedure :: evaluate => spin_up_evaluate
   end type spin_up_drive_t

contains

   !> sqrt(EI/(rho A L^4)) (rad/s): 1.0801 for Kane's beam and the scaled one.
   pure real(dp) function reference_frequency()
      reference_frequency = sqrt(BENDING_STIFFNESS / (MASS_PER_LENGTH * BEAM_LENGTH**4))
   end function reference_frequency

   !> [theta, Omega, Omega'] at t: theta = (Omega_s/T) (t^2/2 + (T/(2 pi))^2 (cos(2 pi t/T) - 1))
   !> for t <= T, then Omega_s T/2 + Omega_s (t - T).
   pure function spin_up_evaluate(self, t) result(f)
      class(spin_up_drive_t), intent(in) :: self
      !> Time (s)
      real(dp), intent(in) :: t
      real(dp) :: f(3)
      real(dp) :: rate, phase
      rate = self%final_speed / self%ramp_time
      if (t <= self%ramp_time) then
         phase = 2.0_dp * pi * t / self%ramp_time
         f(1) = rate * (0.5_dp * t**2 + (self%ramp_time / (2.0_dp * pi))**2 * (cos(phase) - &
            1.0_dp))
         f(2) = rate * (t - self%ramp_time / (2.0_dp * pi) * sin(phase))
         f(3) = rate * (1.0_dp - cos(phase))
      else
         f = [0.5_dp * self%final_speed * self%ramp_time + self%final_speed * (t - &
            self%ramp_time), self%final_speed, 0.0_dp]
      end if
   end function spin_up_evaluate

   !> First flapwise frequency parameter of the rotating cantilever at Omega_bar = 0, 1, 4, 10
   !> (module header); NaN for other speeds.
   real(dp) function rotating_lambda(speed_parameter)
      !> Omega_bar = Omega / sqrt(EI/(rho A L^4)), one of 0, 1, 4, 10
      real(dp), intent(in) :: speed_parameter
      real(dp), parameter :: table(2, 4) = reshape([0.0_dp, 3.51601527_dp, 1.0_dp, &
         3.68164615_dp, 4.0_dp, 5.58500184_dp, 10.0_dp, 11.20232738_dp], [2, 4])
      integer :: k
      rotating_lambda = ieee_value(1.0_dp, ieee_quiet_nan)
      do k = 1, size(table, 2)
         if (abs(speed_parameter - table(1, k)) < 1.0e-12_dp) rotating_lambda = table(2, k)
      end do
   end function rotating_lambda

   !> Southwell coefficient K1 of the first bending mode, zero hub radius (module header), by the
   !> composite Simpson rule on 2000 intervals of the closed-form mode (error ~1e-12).
   pure real(dp) function southwell_coefficient()
      real(dp), parameter :: beta = 1.8751040687119611_dp
      integer, parameter :: intervals = 2000
      real(dp) :: s, xi, phi, dphi, w, stiffening, mass
      integer :: k
      s = (cosh(beta) + cos(beta)) / (sinh(beta) + sin(beta))
      stiffening = 0.0_dp
      mass = 0.0_dp
      do k = 0, intervals
         xi = real(k, dp) / intervals
         w = merge(1.0_dp, merge(4.0_dp, 2.0_dp, mod(k, 2) == 1), k == 0 .or. k == intervals)
         phi = cosh(beta * xi) - cos(beta * xi) - s * (sinh(beta * xi) - sin(beta * xi))
         dphi = beta * (sinh(beta * xi) + sin(beta * xi) - s * (cosh(beta * xi) - &
            cos(beta * xi)))
         stiffening = stiffening + w * 0.5_dp * (1.0_dp - xi**2) * dphi**2
         mass = mass + w * phi**2
      end do
      southwell_coefficient = stiffening / mass
   end function southwell_coefficient

   !> Mass matrix M (at equal angles: m l^2 c) and stiffness K (springs) of the chain at rest.
   pure subroutine chain_matrices(n, M, K, spring)
      integer, intent(in) :: n
      real(dp), intent(out) :: M(n, n), K(n, n), spring(n + 1)
      real(dp) :: l, mass
      integer :: i, j
      l = BEAM_LENGTH / n
      mass = MASS_PER_LENGTH * l
      do j = 1, n
         do i = 1, n
            if (i == j) then
               M(i, j) = mass * l**2 * (real(n - i, dp) + 1.0_dp / 3.0_dp)
            else
               M(i, j) = mass * l**2 * (real(n - max(i, j), dp) + 0.5_dp)
            end if
         end do
      end do
      spring(1) = 2.0_dp * BENDING_STIFFNESS / l
      spring(2:n) = BENDING_STIFFNESS / l
      spring(n + 1) = 0.0_dp
      K = 0.0_dp
      do i = 1, n
         K(i, i) = spring(i) + spring(i + 1)
         if (i < n) then
            K(i, i + 1) = -spring(i + 1)
            K(i + 1, i) = -spring(i + 1)
         end if
      end do
   end subroutine chain_matrices

   !> Eigenvalues (ascending) of the chain at rest, K x = omega^2 M x (LAPACK dsygv).
   subroutine chain_eigenvalues(n, lambda, error)
      integer, intent(in) :: n
      real(dp), intent(out) :: lambda(n)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: M(n, n), K(n, n), spring(n + 1), work(64 * n)
      integer(ip) :: info
      call chain_matrices(n, M, K, spring)
      call dsygv(1_ip, 'N', 'U', int(n, ip), K, int(n, ip), M, int(n, ip), lambda, work, &
         int(size(work), ip), info)
      if (info /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, 'Hencky chain: dsygv info = ' &
         // to_str(info))
   end subroutine chain_eigenvalues

   !> Lowest bending frequency (rad/s) of the chain of n bars at rest.
   subroutine hencky_chain_lowest_frequency(n, omega, error)
      !> Number of bars
      integer, intent(in) :: n
      !> Lowest natural frequency (rad/s)
      real(dp), intent(out) :: omega
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: lambda(n)
      call chain_eigenvalues(n, lambda, error)
      omega = sqrt(lambda(1))
   end subroutine hencky_chain_lowest_frequency

   !> Tip deflection in the hub frame (m) of the chain of n bars spun up by `drive`, at the output
   !> times t_out (ascending, from t = 0 at rest; every t_out(k) / output_step an integer), by
   !> RK4 (module header). `steps` returns the number of RK4 steps.
   subroutine hencky_chain_spin_up(n, drive, output_step, t_out, tip, steps, error)
      !> Number of bars
      integer, intent(in) :: n
      !> Hub rotation
      type(spin_up_drive_t), intent(in) :: drive
      !> Spacing of the output times (s)
      real(dp), intent(in) :: output_step
      !> Output times (s), multiples of output_step
      real(dp), intent(in) :: t_out(:)
      !> Tip deflection in the hub frame at t_out (m)
      real(dp), intent(out) :: tip(:)
      !> RK4 steps taken
      integer, intent(out) :: steps
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: mass(n, n), stiffness(n, n), spring(n + 1), lambda(n), y(2 * n), k1(2 * n)
      real(dp) :: k2(2 * n), k3(2 * n), k4(2 * n), h, t, l, law(3)
      integer :: per_output, k, s, total
      call chain_eigenvalues(n, lambda, error)
      if (allocated(error)) return
      call chain_matrices(n, mass, stiffness, spring)
      l = BEAM_LENGTH / n
      per_output = ceiling(output_step * sqrt(lambda(n)))
      h = output_step / per_output
      y = 0.0_dp
      t = 0.0_dp
      steps = 0
      total = nint(t_out(size(t_out)) / output_step)
      k = 1
      do s = 0, total
         if (k <= size(t_out)) then
            if (nint(t_out(k) / output_step) == s) then
               law = drive%evaluate(t)
               tip(k) = l * sum(sin(y(1:n) - law(1)))
               k = k + 1
            end if
         end if
         if (s == total) exit
         block
            integer :: r
            do r = 1, per_output
               call rhs(t, y, k1)
               call rhs(t + 0.5_dp * h, y + 0.5_dp * h * k1, k2)
               call rhs(t + 0.5_dp * h, y + 0.5_dp * h * k2, k3)
               call rhs(t + h, y + h * k3, k4)
               y = y + h / 6.0_dp * (k1 + 2.0_dp * k2 + 2.0_dp * k3 + k4)
               t = t + h
               steps = steps + 1
            end do
         end block
         if (.not. all(abs(y) < huge(1.0_dp))) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'Hencky chain: state not finite at t = ' &
               // to_str(t) // ' s')
            return
         end if
      end do
   contains
      !> y' = [phi'; M(phi)^-1 (-sum_j a_ij sin(phi_i - phi_j) phi_j'^2 + Q)].
      subroutine rhs(time, state, rate)
         real(dp), intent(in) :: time, state(2 * n)
         real(dp), intent(out) :: rate(2 * n)
         real(dp) :: a(n, n), b(n, 1), c(n), sn(n), hub(3), relative(n + 1)
         integer :: i, j
         integer(ip) :: info
         hub = drive%evaluate(time)
         c = cos(state(1:n))
         sn = sin(state(1:n))
         do j = 1, n
            do i = 1, n
               a(i, j) = mass(i, j) * (c(i) * c(j) + sn(i) * sn(j))
            end do
         end do
         relative(1) = state(1) - hub(1)
         relative(2:n) = state(2:n) - state(1:n - 1)
         relative(n + 1) = 0.0_dp
         do i = 1, n
            b(i, 1) = -spring(i) * relative(i) + spring(i + 1) * relative(i + 1)
            do j = 1, n
               b(i, 1) = b(i, 1) - mass(i, j) * (sn(i) * c(j) - c(i) * sn(j)) * &
                  state(n + j)**2
            end do
         end do
         call dposv('U', int(n, ip), 1_ip, a, int(n, ip), b, int(n, ip), info)
         if (info /= 0) b = huge(1.0_dp)
         rate(1:n) = state(n + 1:2 * n)
         rate(n + 1:2 * n) = b(:, 1)
      end subroutine rhs
   end subroutine hencky_chain_spin_up

end module ffrf_test_spin_beam
