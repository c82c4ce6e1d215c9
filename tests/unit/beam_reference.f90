!> Independent reference frequencies of a uniform straight beam, for the accuracy test of the
!> pipeline on input/beam.geo (a solid circular steel cylinder): bending by the exact Timoshenko
!> frequency equation, torsion of a circular shaft in closed form, and Cowper's shear coefficient.
!>
!> Bending (Timoshenko 1921; Han, Benaroya & Wei, J. Sound Vib. 225(5), 1999, 935-988):
!>   kappa G A (w'' - psi') + rho A omega^2 w = 0,
!>   E I psi'' + kappa G A (w' - psi) + rho I omega^2 psi = 0.
!> With xi = x/L, lambda^4 = rho A omega^2 L^4/(E I) (the Euler-Bernoulli frequency parameter),
!> r2 = I/(A L^2) and s2 = E I/(kappa G A L^2), a solution w ~ exp(k xi) needs
!>   k^4 + lambda^4 (r2 + s2) k^2 - lambda^4 (1 - lambda^4 r2 s2) = 0,                  (1)
!> so below the cut-off lambda^4 r2 s2 < 1 (omega^2 < kappa G A/(rho I), the low branch) the wave
!> numbers are k = +-alpha (real) and k = +-i beta with
!>   alpha^2 = -p + sqrt(p^2 + q),  beta^2 = p + sqrt(p^2 + q),
!>   p = lambda^4 (r2 + s2)/2,  q = lambda^4 (1 - lambda^4 r2 s2).                           (2)
!> From the first equation psi' = w'' + a w with a = lambda^4 s2, so every term of
!>   w = C1 exp(-alpha xi) + C2 exp(-alpha (1 - xi)) + C3 cos(beta xi) + C4 sin(beta xi)
!> carries its own psi (the decaying exponentials keep every entry of the boundary matrix O(1)).
!> The boundary conditions give a 4 x 4 matrix whose determinant vanishes at a natural frequency:
!>   clamped: w = 0, psi = 0;   free: moment E I psi' = 0, shear kappa G A (w' - psi) = 0.   (3)
!> Its roots in lambda are bracketed by a sign scan (step 0.01, far below the root spacing, which
!> is about pi) and refined by bisection to 1e-14 relative, so the frequency (proportional to
!> lambda^2) is good to ~1e-13. Only the low branch is searched; above the cut-off frequency the
!> functions return NaN rather than a second-spectrum root.
module ffrf_test_beam_reference
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use ffrf_core_kinds, only: dp
   implicit none
   private
   public :: timoshenko_free_free_hz, timoshenko_clamped_free_hz
   public :: torsion_free_free_hz, torsion_clamped_free_hz
   public :: shear_coefficient_circle, euler_bernoulli_hz

   real(dp), parameter :: pi = acos(-1.0_dp)
   integer, parameter :: bc_free_free = 1, bc_clamped_free = 2
   !> First lambda of the scan, far below the first root (clamped-free, L/r = 1: lambda = 1.26;
   !> free-free beams shorter than L/r ~ 3 have no low-branch root at all and give NaN)
   real(dp), parameter :: lambda_start = 0.05_dp
   !> Scan step in lambda (the roots are about pi apart)
   real(dp), parameter :: lambda_step = 0.01_dp

contains

   !> n-th bending frequency [Hz] of a free-free uniform Timoshenko beam, root of eq. (3) with
   !> both ends free. NaN if n < 1 or the n-th root lies above the cut-off (second spectrum).
   pure function timoshenko_free_free_hz(n, E, G, rho, A, I, kappa, L) result(f)
      !> Mode number, 1 = lowest elastic bending mode (the two rigid modes are not counted)
      integer, intent(in) :: n
      !> Young's modulus [Pa]
      real(dp), intent(in) :: E
      !> Shear modulus [Pa], E/(2(1 + nu)) for an isotropic material
      real(dp), intent(in) :: G
      !> Density [kg/m^3]
      real(dp), intent(in) :: rho
      !> Cross-section area [m^2]
      real(dp), intent(in) :: A
      !> Second moment of area about the bending axis [m^4]
      real(dp), intent(in) :: I
      !> Shear coefficient [-] (see shear_coefficient_circle)
      real(dp), intent(in) :: kappa
      !> Length [m]
      real(dp), intent(in) :: L
      real(dp) :: f
      f = timoshenko_hz(bc_free_free, n, E, G, rho, A, I, kappa, L)
   end function timoshenko_free_free_hz

   !> n-th bending frequency [Hz] of a clamped-free uniform Timoshenko beam (cantilever), root of
   !> eq. (3) with x = 0 clamped and x = L free. NaN if n < 1 or above the cut-off.
   pure function timoshenko_clamped_free_hz(n, E, G, rho, A, I, kappa, L) result(f)
      !> Mode number, 1 = lowest bending mode
      integer, intent(in) :: n
      !> Young's modulus [Pa]
      real(dp), intent(in) :: E
      !> Shear modulus [Pa]
      real(dp), intent(in) :: G
      !> Density [kg/m^3]
      real(dp), intent(in) :: rho
      !> Cross-section area [m^2]
      real(dp), intent(in) :: A
      !> Second moment of area about the bending axis [m^4]
      real(dp), intent(in) :: I
      !> Shear coefficient [-]
      real(dp), intent(in) :: kappa
      !> Length [m]
      real(dp), intent(in) :: L
      real(dp) :: f
      f = timoshenko_hz(bc_clamped_free, n, E, G, rho, A, I, kappa, L)
   end function timoshenko_clamped_free_hz

   !> n-th torsion frequency [Hz] of a free-free circular shaft (torsion constant J = polar
   !> moment Ip, so the wave speed is sqrt(G/rho)): f = n/(2L) sqrt(G/rho).
   pure function torsion_free_free_hz(n, G, rho, L) result(f)
      !> Mode number, 1 = lowest elastic torsion mode
      integer, intent(in) :: n
      !> Shear modulus [Pa]
      real(dp), intent(in) :: G
      !> Density [kg/m^3]
      real(dp), intent(in) :: rho
      !> Length [m]
      real(dp), intent(in) :: L
      real(dp) :: f
      f = real(n, dp) / (2.0_dp * L) * sqrt(G / rho)
   end function torsion_free_free_hz

   !> n-th torsion frequency [Hz] of a clamped-free circular shaft: f = (2n - 1)/(4L) sqrt(G/rho).
   pure function torsion_clamped_free_hz(n, G, rho, L) result(f)
      !> Mode number, 1 = lowest torsion mode
      integer, intent(in) :: n
      !> Shear modulus [Pa]
      real(dp), intent(in) :: G
      !> Density [kg/m^3]
      real(dp), intent(in) :: rho
      !> Length [m]
      real(dp), intent(in) :: L
      real(dp) :: f
      f = real(2 * n - 1, dp) / (4.0_dp * L) * sqrt(G / rho)
   end function torsion_clamped_free_hz

   !> Shear coefficient of a solid circular section, kappa = 6(1 + nu)/(7 + 6 nu)
   !> (Cowper, "The shear coefficient in Timoshenko's beam theory", J. Appl. Mech. 33(2), 1966,
   !> 335-340, Table 1). 0.886 for nu = 0.3.
   pure function shear_coefficient_circle(nu) result(kappa)
      !> Poisson's ratio [-]
      real(dp), intent(in) :: nu
      real(dp) :: kappa
      kappa = 6.0_dp * (1.0_dp + nu) / (7.0_dp + 6.0_dp * nu)
   end function shear_coefficient_circle

   !> Euler-Bernoulli bending frequency [Hz] for a frequency parameter beta L:
   !> f = (beta L)^2/(2 pi L^2) sqrt(E I/(rho A)).
   pure function euler_bernoulli_hz(beta_l, E, rho, A, I, L) result(f)
      !> Root beta L of the Euler-Bernoulli frequency equation (4.730040744862704 free-free,
      !> 1.875104068711961 clamped-free, first mode)
      real(dp), intent(in) :: beta_l
      !> Young's modulus [Pa]
      real(dp), intent(in) :: E
      !> Density [kg/m^3]
      real(dp), intent(in) :: rho
      !> Cross-section area [m^2]
      real(dp), intent(in) :: A
      !> Second moment of area [m^4]
      real(dp), intent(in) :: I
      !> Length [m]
      real(dp), intent(in) :: L
      real(dp) :: f
      f = beta_l**2 / (2.0_dp * pi * L**2) * sqrt(E * I / (rho * A))
   end function euler_bernoulli_hz

   !> n-th low-branch root of eq. (3) for the boundary conditions `bc`, as a frequency in Hz.
   pure function timoshenko_hz(bc, n, E, G, rho, A, I, kappa, L) result(f)
      integer, intent(in) :: bc, n
      real(dp), intent(in) :: E, G, rho, A, I, kappa, L
      real(dp) :: f
      real(dp) :: r2, s2, lambda_cut, lo, hi, mid, d_lo, d_hi, d_mid
      integer :: found, it
      f = ieee_value(f, ieee_quiet_nan)
      if (n < 1) return
      r2 = I / (A * L**2)
      s2 = E * I / (kappa * G * A * L**2)
      lambda_cut = (1.0_dp / (r2 * s2))**0.25_dp     ! lambda^4 r2 s2 = 1: cut-off, eq. (2)
      found = 0
      lo = lambda_start
      d_lo = boundary_determinant(bc, lo, r2, s2)
      do
         hi = lo + lambda_step
         if (hi >= lambda_cut) return                 ! the n-th root is not on the low branch
         d_hi = boundary_determinant(bc, hi, r2, s2)
         if (sign(1.0_dp, d_lo) /= sign(1.0_dp, d_hi)) then
            found = found + 1
            if (found == n) exit
         end if
         lo = hi
         d_lo = d_hi
      end do
      do it = 1, 200                                  ! bisection on [lo, hi]
         mid = 0.5_dp * (lo + hi)
         if (hi - lo <= 1.0e-14_dp * hi) exit
         d_mid = boundary_determinant(bc, mid, r2, s2)
         if (d_mid == 0.0_dp) then
            lo = mid
            hi = mid
            exit
         end if
         if (sign(1.0_dp, d_mid) == sign(1.0_dp, d_lo)) then
            lo = mid
            d_lo = d_mid
         else
            hi = mid
         end if
      end do
      mid = 0.5_dp * (lo + hi)
      ! lambda^4 = rho A omega^2 L^4/(E I)  =>  omega = lambda^2/L^2 sqrt(E I/(rho A))
      f = mid**2 / (2.0_dp * pi * L**2) * sqrt(E * I / (rho * A))
   end function timoshenko_hz

   !> Determinant of the boundary matrix of eq. (3) at the frequency parameter lambda, with the
   !> basis exp(-alpha xi), exp(-alpha (1 - xi)), cos(beta xi), sin(beta xi); rows scaled by
   !> positive factors only, so its sign changes exactly at the roots.
   pure function boundary_determinant(bc, lambda, r2, s2) result(d)
      integer, intent(in) :: bc
      real(dp), intent(in) :: lambda, r2, s2
      real(dp) :: d
      real(dp) :: lam4, p, q, alpha, beta, a, ca, cb, m(4, 4)
      lam4 = lambda**4
      p = 0.5_dp * lam4 * (r2 + s2)
      q = lam4 * (1.0_dp - lam4 * r2 * s2)
      alpha = sqrt(-p + sqrt(p**2 + q))
      beta = sqrt(p + sqrt(p**2 + q))
      a = lam4 * s2
      ! psi of each basis function, from psi' = w'' + a w: exp(-+alpha xi) -> -+ca, cos -> cb sin,
      ! sin -> -cb cos (eq. 2 ff.)
      ca = alpha + a / alpha
      cb = (a - beta**2) / beta
      select case (bc)
      case (bc_free_free)
         m(1, :) = moment_row(0.0_dp)
         m(2, :) = shear_row(0.0_dp)
         m(3, :) = moment_row(1.0_dp)
         m(4, :) = shear_row(1.0_dp)
      case default
         m(1, :) = deflection_row(0.0_dp)
         m(2, :) = rotation_row(0.0_dp)
         m(3, :) = moment_row(1.0_dp)
         m(4, :) = shear_row(1.0_dp)
      end select
      d = det4(m)

   contains

      pure function basis(xi) result(b)
         real(dp), intent(in) :: xi
         real(dp) :: b(4)
         b = [exp(-alpha * xi), exp(-alpha * (1.0_dp - xi)), cos(beta * xi), sin(beta * xi)]
      end function basis

      !> w
      pure function deflection_row(xi) result(row)
         real(dp), intent(in) :: xi
         real(dp) :: row(4)
         row = basis(xi)
      end function deflection_row

      !> psi, divided by beta
      pure function rotation_row(xi) result(row)
         real(dp), intent(in) :: xi
         real(dp) :: row(4), b(4)
         b = basis(xi)
         row = [-ca * b(1), ca * b(2), cb * b(4), -cb * b(3)] / beta
      end function rotation_row

      !> psi' (bending moment / (E I)), divided by beta^2
      pure function moment_row(xi) result(row)
         real(dp), intent(in) :: xi
         real(dp) :: row(4), b(4)
         b = basis(xi)
         row = [alpha * ca * b(1), alpha * ca * b(2), cb * beta * b(3), cb * beta * b(4)] &
            / beta**2
      end function moment_row

      !> w' - psi (shear force / (kappa G A)), divided by a and multiplied by beta
      pure function shear_row(xi) result(row)
         real(dp), intent(in) :: xi
         real(dp) :: row(4), b(4)
         b = basis(xi)
         row = [b(1) / alpha, -b(2) / alpha, -b(4) / beta, b(3) / beta] * beta
      end function shear_row

   end function boundary_determinant

   !> Determinant of a 4 x 4 matrix by Gaussian elimination with partial pivoting.
   pure function det4(m_in) result(d)
      real(dp), intent(in) :: m_in(4, 4)
      real(dp) :: d
      real(dp) :: m(4, 4), row(4)
      integer :: k, j, piv
      m = m_in
      d = 1.0_dp
      do k = 1, 4
         piv = k - 1 + maxloc(abs(m(k:4, k)), dim=1)
         if (m(piv, k) == 0.0_dp) then
            d = 0.0_dp
            return
         end if
         if (piv /= k) then
            row = m(k, :)
            m(k, :) = m(piv, :)
            m(piv, :) = row
            d = -d
         end if
         d = d * m(k, k)
         do j = k + 1, 4
            m(j, k:4) = m(j, k:4) - m(j, k) / m(k, k) * m(k, k:4)
         end do
      end do
   end function det4

end module ffrf_test_beam_reference
