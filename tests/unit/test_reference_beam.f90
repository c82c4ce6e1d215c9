!> Checks of the beam reference (ffrf_test_beam_reference) that the pipeline's accuracy test on
!> input/beam.geo compares with: the Euler-Bernoulli limit of the Timoshenko frequency equation,
!> a second method (a Timoshenko finite-element model, variational, no frequency equation),
!> the torsion closed forms, Cowper's shear coefficient and the cut-off guard.
module test_reference_beam
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_la_lapack, only: dsygv
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   use ffrf_test_beam_reference, only: timoshenko_free_free_hz, timoshenko_clamped_free_hz, &
      torsion_free_free_hz, torsion_clamped_free_hz, shear_coefficient_circle, euler_bernoulli_hz
   implicit none
   private
   public :: collect_reference_beam

   real(dp), parameter :: pi = acos(-1.0_dp)
   !> Steel and the cylinder of input/beam.geo (radius 0.010 m, length 0.200 m)
   real(dp), parameter :: young = 210.0e9_dp, poisson = 0.3_dp, density = 7850.0_dp
   real(dp), parameter :: radius = 0.010_dp, length = 0.200_dp
   !> Roots beta L of the Euler-Bernoulli frequency equations cos(x) cosh(x) = 1 (free-free) and
   !> cos(x) cosh(x) = -1 (clamped-free), modes 1 and 2 (Blevins, Formulas for Natural Frequency
   !> and Mode Shape, 1979, Table 8-1)
   real(dp), parameter :: beta_l_free_free(2) = [4.730040744862704_dp, 7.853204624095838_dp]
   real(dp), parameter :: beta_l_clamped_free(2) = [1.875104068711961_dp, 4.694091132974175_dp]

contains

   !> The tests of this suite.
   subroutine collect_reference_beam(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('euler_bernoulli_limit', test_euler_bernoulli_limit), &
         new_unittest('finite_element_second_method', test_finite_element_second_method), &
         new_unittest('torsion_quarter_wave_identity', test_torsion_quarter_wave_identity), &
         new_unittest('cowper_circle', test_cowper_circle), &
         new_unittest('cut_off_and_bad_mode', test_cut_off_and_bad_mode), &
         new_unittest('beam_geo_values', test_beam_geo_values)]
   end subroutine collect_reference_beam

   !> Reference: Euler-Bernoulli beta L (Blevins Table 8-1, to 16 digits). A beam with
   !> I/(A L^2) = 1e-10 (no rotary inertia to speak of) and G = 1e6 E (no shear flexibility)
   !> must give lambda = beta L: the Timoshenko correction is O(lambda^2 (r2 + s2)) ~ 1e-9 here,
   !> the root is bisected to 1e-14, so 1e-6 relative (the brief's bound) has a 1000x margin.
   !> This checks the boundary rows of eq. (3) for both end conditions, modes 1 and 2.
   subroutine test_euler_bernoulli_limit(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: A = 1.0e-4_dp, I = 1.0e-14_dp, L = 1.0_dp, G = 1.0e6_dp * young
      integer :: n
      do n = 1, 2
         call check_close(error, 'free-free mode ' // to_str(n), &
            timoshenko_free_free_hz(n, young, G, density, A, I, 1.0_dp, L), &
            euler_bernoulli_hz(beta_l_free_free(n), young, density, A, I, L), rtol=1.0e-6_dp)
         if (allocated(error)) return
         call check_close(error, 'clamped-free mode ' // to_str(n), &
            timoshenko_clamped_free_hz(n, young, G, density, A, I, 1.0_dp, L), &
            euler_bernoulli_hz(beta_l_clamped_free(n), young, density, A, I, L), rtol=1.0e-6_dp)
         if (allocated(error)) return
      end do
   end subroutine test_euler_bernoulli_limit

   !> Second method: a Timoshenko beam finite-element model (cubic Lagrange w and psi, 40
   !> elements, exact Gauss quadrature, LAPACK dsygv) of the same continuum, built from the
   !> energies U = 1/2 int(E I psi'^2 + kappa G A (w' - psi)^2),
   !> T = 1/2 int(rho A w^2 + rho I psi^2) and no frequency equation. Two-mesh study (measured):
   !> 20 -> 40 elements moves free-free mode 2 of the beam.geo cylinder by 1.9e-7 -> 3.3e-9
   !> relative (h^6 convergence), so 1e-7 bounds the finite-element error with margin. Two
   !> slenderness ratios: beam.geo (L/r = 20) and a stub (L/r = 5) where shear and rotary
   !> inertia lower free-free mode 1 by 25 % from Euler-Bernoulli.
   subroutine test_finite_element_second_method(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: G, A, I, kappa, L, fe_free(2), fe_clamped(2), worst
      integer :: k, n
      G = young / (2.0_dp * (1.0_dp + poisson))
      A = pi * radius**2
      I = pi * radius**4 / 4.0_dp
      kappa = shear_coefficient_circle(poisson)
      worst = 0.0_dp
      do k = 1, 2
         L = merge(length, 0.25_dp * length, k == 1)
         call timoshenko_fe_hz(young, G, density, A, I, kappa, L, 40, .false., fe_free, error)
         if (allocated(error)) return
         call timoshenko_fe_hz(young, G, density, A, I, kappa, L, 40, .true., fe_clamped, error)
         if (allocated(error)) return
         do n = 1, 2
            call check_close(error, 'free-free mode ' // to_str(n) // ', L = ' // to_str(L), &
               timoshenko_free_free_hz(n, young, G, density, A, I, kappa, L), fe_free(n), &
               rtol=1.0e-7_dp)
            if (allocated(error)) return
            call check_close(error, 'clamped-free mode ' // to_str(n) // ', L = ' // to_str(L), &
               timoshenko_clamped_free_hz(n, young, G, density, A, I, kappa, L), fe_clamped(n), &
               rtol=1.0e-7_dp)
            if (allocated(error)) return
            worst = max(worst, abs(timoshenko_free_free_hz(n, young, G, density, A, I, kappa, &
               L) / fe_free(n) - 1.0_dp), abs(timoshenko_clamped_free_hz(n, young, G, density, A, &
               I, kappa, L) / fe_clamped(n) - 1.0_dp))
         end do
      end do
      call report('largest relative difference to the finite-element model: ' // to_str(worst, 3))
   end subroutine test_finite_element_second_method

   !> Identity: a clamped-free shaft of length L vibrates like one half of a free-free shaft of
   !> length 2L in its odd modes (the clamp is the node of symmetry), f_cf(n, L) = f_ff(2n-1, 2L);
   !> and the first free-free mode is the half-wave c/(2L), c = sqrt(G/rho). Round-off only.
   subroutine test_torsion_quarter_wave_identity(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: G
      integer :: n
      G = young / (2.0_dp * (1.0_dp + poisson))
      do n = 1, 3
         call check_close(error, 'clamped-free torsion mode ' // to_str(n), &
            torsion_clamped_free_hz(n, G, density, length), &
            torsion_free_free_hz(2 * n - 1, G, density, 2.0_dp * length), &
            rtol=100.0_dp * epsilon(1.0_dp))
         if (allocated(error)) return
      end do
      ! wavelength 2L: f = c/lambda
      call check_close(error, 'free-free torsion mode 1', torsion_free_free_hz(1, G, density, &
         length), sqrt(G / density) / (2.0_dp * length), rtol=100.0_dp * epsilon(1.0_dp))
   end subroutine test_torsion_quarter_wave_identity

   !> Cowper (1966), Table 1, solid circle: kappa = 6(1 + nu)/(7 + 6 nu), printed 0.857 at
   !> nu = 0 (= 6/7) and 0.886 at nu = 0.3 (= 39/44); exact rationals, so round-off tolerance.
   subroutine test_cowper_circle(error)
      type(error_t), allocatable, intent(out) :: error
      call check_close(error, 'kappa(nu = 0)', shear_coefficient_circle(0.0_dp), &
         6.0_dp / 7.0_dp, rtol=10.0_dp * epsilon(1.0_dp))
      if (allocated(error)) return
      call check_close(error, 'kappa(nu = 0.3)', shear_coefficient_circle(0.3_dp), &
         39.0_dp / 44.0_dp, rtol=10.0_dp * epsilon(1.0_dp))
      if (allocated(error)) return
      call check_close(error, 'kappa(nu = 0.3) to Cowper''s printed digits', &
         shear_coefficient_circle(0.3_dp), 0.886_dp, atol=5.0e-4_dp)
   end subroutine test_cowper_circle

   !> Guards: mode 0 and a mode above the cut-off omega^2 = kappa G A/(rho I) (the second
   !> spectrum, not searched) return NaN, not a wrong root. A stub with L/r = 2 has
   !> r2 = 1/16, s2 = 0.183, so its cut-off lambda = (r2 s2)^(-1/4) = 3.06 lies far below a
   !> 30th bending root (lambda ~ 90), while its first root (< 1.875) lies below it.
   subroutine test_cut_off_and_bad_mode(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: G, A, I, kappa
      G = young / (2.0_dp * (1.0_dp + poisson))
      A = pi * radius**2
      I = pi * radius**4 / 4.0_dp
      kappa = shear_coefficient_circle(poisson)
      call check(error, 'mode 0 gives NaN', ieee_is_nan(timoshenko_free_free_hz(0, young, G, &
         density, A, I, kappa, length)))
      if (allocated(error)) return
      call check(error, 'mode 30 of a stub (L/r = 2) is above the cut-off and gives NaN', &
         ieee_is_nan(timoshenko_clamped_free_hz(30, young, G, density, A, I, kappa, &
         2.0_dp * radius)))
      if (allocated(error)) return
      call check(error, 'mode 1 of the same stub is found', .not. ieee_is_nan( &
         timoshenko_clamped_free_hz(1, young, G, density, A, I, kappa, 2.0_dp * radius)))
   end subroutine test_cut_off_and_bad_mode

   !> The reference values of input/beam.geo, reported for the accuracy test and checked against
   !> the values computed when this suite was written (with the finite-element check above as
   !> their independent confirmation), 1e-9 relative: a change in them is a change of reference.
   subroutine test_beam_geo_values(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: G, A, I, kappa, f(6)
      G = young / (2.0_dp * (1.0_dp + poisson))
      A = pi * radius**2
      I = pi * radius**4 / 4.0_dp
      kappa = shear_coefficient_circle(poisson)
      f(1) = timoshenko_free_free_hz(1, young, G, density, A, I, kappa, length)
      f(2) = torsion_free_free_hz(1, G, density, length)
      f(3) = timoshenko_clamped_free_hz(1, young, G, density, A, I, kappa, length)
      f(4) = torsion_clamped_free_hz(1, G, density, length)
      f(5) = euler_bernoulli_hz(beta_l_free_free(1), young, density, A, I, length)
      f(6) = euler_bernoulli_hz(beta_l_clamped_free(1), young, density, A, I, length)
      call report('beam.geo (steel, r = 0.010 m, L = 0.200 m, kappa = ' // to_str(kappa, 6) // ')')
      call report('free-free:    bending 1 = ' // to_str(f(1), 10) // ' Hz (Euler-Bernoulli ' // &
         to_str(f(5), 10) // '), torsion 1 = ' // to_str(f(2), 10) // ' Hz')
      call report('clamped-free: bending 1 = ' // to_str(f(3), 10) // ' Hz (Euler-Bernoulli ' // &
         to_str(f(6), 10) // '), torsion 1 = ' // to_str(f(4), 10) // ' Hz')
      call check_close(error, 'free-free bending 1', f(1), 2243.636616552_dp, rtol=1.0e-9_dp)
      if (allocated(error)) return
      call check_close(error, 'clamped-free bending 1', f(3), 359.7434151822_dp, rtol=1.0e-9_dp)
   end subroutine test_beam_geo_values

   !> Lowest two elastic bending frequencies [Hz] of a uniform Timoshenko beam by finite elements:
   !> cubic Lagrange interpolation of w and psi on num_elements equal elements, 4-point Gauss
   !> (exact for the degree-6 integrands), dense K q = omega^2 M q by dsygv. Free-free: the two
   !> rigid modes (omega ~ 0) are skipped; clamped: w = psi = 0 at x = 0 removed.
   subroutine timoshenko_fe_hz(E, G, rho, A, I, kappa, L, num_elements, clamped, f, error)
      real(dp), intent(in) :: E, G, rho, A, I, kappa, L
      integer, intent(in) :: num_elements
      logical, intent(in) :: clamped
      real(dp), intent(out) :: f(2)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: gauss_x(4) = [-0.8611363115940526_dp, -0.3399810435848563_dp, &
         0.3399810435848563_dp, 0.8611363115940526_dp]
      real(dp), parameter :: gauss_w(4) = [0.3478548451374538_dp, 0.6521451548625461_dp, &
         0.6521451548625461_dp, 0.3478548451374538_dp]
      real(dp), allocatable :: K(:, :), M(:, :), K_free(:, :), M_free(:, :), lambda(:), work(:)
      real(dp) :: h, phi(4), dphi(4), jac
      integer :: elem, qp, ia, ib, num_nodes, n_dof, first, skip, node_a, node_b
      integer(ip) :: n_solve, lwork, info
      num_nodes = 3 * num_elements + 1
      n_dof = 2 * num_nodes                     ! dof 2j-1 = w, 2j = psi of node j
      allocate (K(n_dof, n_dof), M(n_dof, n_dof), source=0.0_dp)
      h = L / num_elements
      jac = 0.5_dp * h
      do elem = 1, num_elements
         first = 3 * (elem - 1)
         do qp = 1, 4
            call cubic_lagrange(gauss_x(qp), phi, dphi)
            dphi = dphi / jac
            do ia = 1, 4
               node_a = first + ia
               do ib = 1, 4
                  node_b = first + ib
                  ! bending E I psi'^2 and shear kappa G A (w' - psi)^2
                  K(2*node_a, 2*node_b) = K(2*node_a, 2*node_b) + gauss_w(qp) * jac * &
                     (E * I * dphi(ia) * dphi(ib) + kappa * G * A * phi(ia) * phi(ib))
                  K(2*node_a - 1, 2*node_b - 1) = K(2*node_a - 1, 2*node_b - 1) + &
                     gauss_w(qp) * jac * kappa * G * A * dphi(ia) * dphi(ib)
                  K(2*node_a - 1, 2*node_b) = K(2*node_a - 1, 2*node_b) - &
                     gauss_w(qp) * jac * kappa * G * A * dphi(ia) * phi(ib)
                  K(2*node_a, 2*node_b - 1) = K(2*node_a, 2*node_b - 1) - &
                     gauss_w(qp) * jac * kappa * G * A * phi(ia) * dphi(ib)
                  M(2*node_a - 1, 2*node_b - 1) = M(2*node_a - 1, 2*node_b - 1) + &
                     gauss_w(qp) * jac * rho * A * phi(ia) * phi(ib)
                  M(2*node_a, 2*node_b) = M(2*node_a, 2*node_b) + &
                     gauss_w(qp) * jac * rho * I * phi(ia) * phi(ib)
               end do
            end do
         end do
      end do
      first = merge(3, 1, clamped)              ! clamped: drop w and psi of node 1
      n_solve = int(n_dof - first + 1, ip)
      lwork = 64_ip * n_solve
      allocate (lambda(n_solve), work(lwork), K_free(n_solve, n_solve), M_free(n_solve, n_solve))
      K_free = K(first:, first:)
      M_free = M(first:, first:)
      call dsygv(1_ip, 'N', 'U', n_solve, K_free, n_solve, M_free, n_solve, lambda, work, lwork, &
         info)
      if (info /= 0) then
         call check(error, 'dsygv info = ' // to_str(int(info)), .false.)
         return
      end if
      skip = merge(0, 2, clamped)               ! free-free: two rigid modes first
      f = sqrt(max(lambda(skip + 1:skip + 2), 0.0_dp)) / (2.0_dp * pi)
   end subroutine timoshenko_fe_hz

   !> Cubic Lagrange shape functions on [-1, 1] with nodes -1, -1/3, 1/3, 1, and derivatives.
   pure subroutine cubic_lagrange(s, N, dN)
      real(dp), intent(in) :: s
      real(dp), intent(out) :: N(4), dN(4)
      real(dp), parameter :: nodes(4) = [-1.0_dp, -1.0_dp / 3.0_dp, 1.0_dp / 3.0_dp, 1.0_dp]
      real(dp) :: term
      integer :: a, b, c
      do a = 1, 4
         N(a) = 1.0_dp
         dN(a) = 0.0_dp
         do b = 1, 4
            if (b == a) cycle
            N(a) = N(a) * (s - nodes(b)) / (nodes(a) - nodes(b))
            term = 1.0_dp / (nodes(a) - nodes(b))
            do c = 1, 4
               if (c == a .or. c == b) cycle
               term = term * (s - nodes(c)) / (nodes(a) - nodes(c))
            end do
            dN(a) = dN(a) + term
         end do
      end do
   end subroutine cubic_lagrange

end module test_reference_beam

program main_reference_beam
   use ffrf_testing, only: unittest_t, run_suite
   use test_reference_beam, only: collect_reference_beam
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_reference_beam(tests)
   call run_suite('test_reference_beam', tests)
end program main_reference_beam
