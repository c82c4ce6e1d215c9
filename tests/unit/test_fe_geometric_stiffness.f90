!> Element geometric (initial-stress) stiffness and centrifugal load cases
!> (ffrf_fe_geometric_stiffness) against independent references:
!> - closed forms on the reference tetrahedron (corners (0,0,0), (1,0,0), (0,1,0), (0,0,1),
!>   volume 1/6): a constant stress on Tet4, K_G(3(a-1)+i, 3(b-1)+i) = V g_a . sigma g_b with
!>   the constant gradients g = [(-1,-1,-1), e1, e2, e3]; and the linear stress of the quadratic
!>   displacement u = (c x^2/2, 0, 0) on Tet10, whose energy w^T K_G w / 2 for w = (0, x^2, 0)
!>   and w = (y z, 0, 0) follows from the simplex monomial integrals
!>   int x^a y^b z^c dV = a! b! c! / (a + b + c + 3)!;
!> - the Hessian by central second differences of the Green-Lagrange strain energy of a fixed
!>   stress, W(w) = int sigma : E(w) dV, E = (H + H^T + H^T H)/2, H = grad w, evaluated here
!>   point by point (its linear part drops out of second differences, its quadratic part is
!>   w^T K_G w / 2), on a curved Tet10 and a general Tet4 stressed by random displacements;
!> - the centrifugal identity sum_c p_c(omega) C_c x = -omega x (omega x x) and the derivative
!>   of the products p_c against central differences.
!> Tolerances: identities and closed forms 1e-12 relative (round-off of a few hundred terms);
!> second differences of an exactly quadratic-plus-linear function with step 1e-3 of the element
!> size: round-off eps * size / step ~ 1e-13 relative, asserted 1e-9.
module test_fe_geometric_stiffness
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_fe_material, only: material_t, lame_parameters
   use ffrf_fe_quadrature, only: TET1_POINTS, TET1_WEIGHTS, TET14_POINTS, TET14_WEIGHTS
   use ffrf_fe_tet, only: tet_shape, physical_gradients, TET10_EDGES, TET_REFERENCE_NODES
   use ffrf_fe_geometric_stiffness, only: tet_geometric_stiffness, geometric_stiffness_kernel, &
      tet_point_stress, centrifugal_products, centrifugal_product_jacobian, &
      centrifugal_case_matrix, NUM_CENTRIFUGAL_CASES
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_fe_geometric_stiffness

   real(dp), parameter :: YOUNG = 210.0e9_dp, POISSON = 0.3_dp, DENSITY = 7850.0_dp
   !> Element size of the general elements (m)
   real(dp), parameter :: SCALE = 0.05_dp
   !> A general straight tetrahedron, corners in Gmsh order, units of SCALE
   real(dp), parameter :: CORNERS(3, 4) = reshape([0.1_dp, 0.0_dp, -0.05_dp, &
      1.2_dp, 0.1_dp, 0.05_dp, 0.2_dp, 0.9_dp, 0.1_dp, 0.3_dp, 0.2_dp, 1.1_dp], [3, 4])
   !> Closed forms and identities (module header)
   real(dp), parameter :: closed_form_rtol = 1.0e-12_dp
   !> Second differences of the Green-Lagrange energy (module header)
   real(dp), parameter :: difference_rtol = 1.0e-9_dp

contains

   subroutine collect_fe_geometric_stiffness(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('centrifugal_cases_identity', test_centrifugal_cases), &
         new_unittest('tet4_constant_stress_closed_form', test_tet4_closed_form), &
         new_unittest('tet10_linear_stress_closed_form', test_tet10_closed_form), &
         new_unittest('tet10_curved_green_lagrange_hessian', test_tet10_green_lagrange), &
         new_unittest('tet4_green_lagrange_hessian', test_tet4_green_lagrange)]
   end subroutine collect_fe_geometric_stiffness

   !> Deterministic pseudo-random numbers in [-1, 1].
   function random_vector(n, seed) result(x)
      integer, intent(in) :: n, seed
      real(dp) :: x(n)
      integer :: i
      do i = 1, n
         x(i) = sin(12.9898_dp * real(i + 37 * seed, dp) + 78.233_dp * real(seed, dp))
         x(i) = 2.0_dp * (x(i) * 43758.5453_dp - floor(x(i) * 43758.5453_dp)) - 1.0_dp
      end do
   end function random_vector

   function factorial(n) result(f)
      integer, intent(in) :: n
      real(dp) :: f
      integer :: k
      f = 1.0_dp
      do k = 2, n
         f = f * k
      end do
   end function factorial

   !> int x^a y^b z^c dV over the reference tetrahedron.
   function monomial_integral(a, b, c) result(value)
      integer, intent(in) :: a, b, c
      real(dp) :: value
      value = factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3)
   end function monomial_integral

   function steel() result(material)
      type(material_t) :: material
      material = material_t(young=YOUNG, poisson=POISSON, density=DENSITY, name='steel')
   end function steel

   !> Reference Tet10 (straight, edge nodes at the midpoints).
   function reference_tet10() result(xe)
      real(dp) :: xe(3, 10)
      xe = TET_REFERENCE_NODES
   end function reference_tet10

   !> Curved Tet10 on CORNERS * SCALE: every edge node moved off its midpoint by up to 6 %.
   function curved_tet10() result(xe)
      real(dp) :: xe(3, 10)
      real(dp), parameter :: MOVES(3, 6) = reshape([0.00_dp, -0.06_dp, -0.05_dp, &
         0.05_dp, 0.04_dp, -0.02_dp, -0.04_dp, 0.03_dp, 0.06_dp, 0.02_dp, -0.05_dp, 0.03_dp, &
         0.05_dp, 0.05_dp, 0.04_dp, 0.06_dp, -0.02_dp, 0.05_dp], [3, 6])
      integer :: e
      xe(:, 1:4) = SCALE * CORNERS
      do e = 1, 6
         xe(:, 4 + e) = 0.5_dp * (xe(:, TET10_EDGES(1, e)) + xe(:, TET10_EDGES(2, e))) + &
            SCALE * MOVES(:, e)
      end do
   end function curved_tet10

   !> sum_c p_c(omega) C_c x = -omega x (omega x x) for random omega and x, and dp/domega
   !> against central differences (p is quadratic: exact but for round-off).
   subroutine test_centrifugal_cases(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: omega(3), x(3), expected(3), actual(3), p(NUM_CENTRIFUGAL_CASES), step
      real(dp) :: jacobian(NUM_CENTRIFUGAL_CASES, 3), differences(NUM_CENTRIFUGAL_CASES, 3)
      integer :: trial, c, j
      do trial = 1, 5
         omega = 10.0_dp * random_vector(3, 10 + trial)
         x = random_vector(3, 20 + trial)
         expected = -cross(omega, cross(omega, x))
         p = centrifugal_products(omega)
         actual = 0.0_dp
         do c = 1, NUM_CENTRIFUGAL_CASES
            actual = actual + p(c) * matmul(centrifugal_case_matrix(c), x)
         end do
         call check_close(error, 'centrifugal acceleration, trial ' // to_str(trial), &
            maxval(abs(actual - expected)), 0.0_dp, atol=closed_form_rtol * maxval(abs(expected)))
         if (allocated(error)) return
         jacobian = centrifugal_product_jacobian(omega)
         step = 1.0e-3_dp
         do j = 1, 3
            x = omega
            x(j) = omega(j) + step
            differences(:, j) = centrifugal_products(x)
            x(j) = omega(j) - step
            differences(:, j) = (differences(:, j) - centrifugal_products(x)) / (2.0_dp * step)
         end do
         call check_close(error, 'dp/domega vs central differences, trial ' // to_str(trial), &
            maxval(abs(jacobian - differences)), 0.0_dp, atol=1.0e-10_dp * maxval(abs(jacobian)))
         if (allocated(error)) return
      end do
   contains
      pure function cross(a, b) result(c)
         real(dp), intent(in) :: a(3), b(3)
         real(dp) :: c(3)
         c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
      end function cross
   end subroutine test_centrifugal_cases

   !> Reference Tet4, a full constant symmetric stress (Pa): K_G = V (g_a . sigma g_b) (x) I3.
   subroutine test_tet4_closed_form(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: gradients(3, 4) = reshape([-1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, &
         0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 4])
      real(dp) :: xe(3, 4), sigma(3, 3), stress(3, 3, 1), kg(12, 12), expected(12, 12)
      integer :: a, b, i
      xe = TET_REFERENCE_NODES(:, 1:4)
      sigma = reshape([3.0e6_dp, 0.4e6_dp, -0.7e6_dp, 0.4e6_dp, -1.5e6_dp, 0.2e6_dp, &
         -0.7e6_dp, 0.2e6_dp, 2.1e6_dp], [3, 3])
      stress(:, :, 1) = sigma
      call geometric_stiffness_kernel(xe, stress, TET1_POINTS, TET1_WEIGHTS, kg)
      expected = 0.0_dp
      do b = 1, 4
         do a = 1, 4
            do i = 1, 3
               expected(3 * (a - 1) + i, 3 * (b - 1) + i) = (1.0_dp / 6.0_dp) * &
                  dot_product(gradients(:, a), matmul(sigma, gradients(:, b)))
            end do
         end do
      end do
      call check_close(error, 'Tet4 K_G vs V g_a . sigma g_b', maxval(abs(kg - expected)), &
         0.0_dp, atol=closed_form_rtol * maxval(abs(expected)))
   end subroutine test_tet4_closed_form

   !> Reference Tet10 stressed by u = (c x^2/2, 0, 0): eps_xx = c x, sigma_xx = (lambda + 2 mu)
   !> c x, sigma_yy = sigma_zz = lambda c x. Then w = (0, x^2, 0): W = 1/2 int sigma_xx (2 x)^2
   !> = 2 (lambda + 2 mu) c int x^3 = (lambda + 2 mu) c / 60, and w = (y z, 0, 0):
   !> W = 1/2 int (sigma_yy z^2 + sigma_zz y^2) = lambda c int x y^2 = lambda c / 360.
   !> Also K_G symmetric (exactly).
   subroutine test_tet10_closed_form(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: c = 1.0e-3_dp
      real(dp) :: xe(3, 10), ue(3, 10), kg(30, 30), w(30), lambda, mu, energy, expected
      integer :: a
      xe = reference_tet10()
      ue = 0.0_dp
      ue(1, :) = 0.5_dp * c * xe(1, :)**2
      call tet_geometric_stiffness(xe, ue, steel(), 1_i8, kg, error)
      if (allocated(error)) return
      call lame_parameters(steel(), lambda, mu)
      call check_close(error, 'Tet10 K_G symmetric', maxval(abs(kg - transpose(kg))), 0.0_dp, &
         atol=closed_form_rtol * maxval(abs(kg)))
      if (allocated(error)) return
      w = 0.0_dp
      do a = 1, 10
         w(3 * (a - 1) + 2) = xe(1, a)**2
      end do
      energy = 0.5_dp * dot_product(w, matmul(kg, w))
      expected = 2.0_dp * (lambda + 2.0_dp * mu) * c * monomial_integral(3, 0, 0)
      call report('Tet10, w = (0, x^2, 0): W = ' // to_str(energy, 15) // ' J, closed form ' // &
         to_str(expected, 15) // ' = (lambda + 2 mu) c / 60')
      call check_close(error, 'Tet10 W for w = (0, x^2, 0)', energy, expected, &
         rtol=closed_form_rtol)
      if (allocated(error)) return
      w = 0.0_dp
      do a = 1, 10
         w(3 * (a - 1) + 1) = xe(2, a) * xe(3, a)
      end do
      energy = 0.5_dp * dot_product(w, matmul(kg, w))
      expected = lambda * c * monomial_integral(1, 2, 0)
      call report('Tet10, w = (y z, 0, 0): W = ' // to_str(energy, 15) // ' J, closed form ' // &
         to_str(expected, 15) // ' = lambda c / 360')
      call check_close(error, 'Tet10 W for w = (y z, 0, 0)', energy, expected, &
         rtol=closed_form_rtol)
   end subroutine test_tet10_closed_form

   !> Green-Lagrange energy of the fixed stress field of ue, W(w) = sum_q w_q det J_q
   !> sigma_q : E(w)_q with E = (H + H^T + H^T H)/2 (module header), on the element's rule.
   function green_lagrange_energy(xe, ue, w) result(energy)
      real(dp), intent(in) :: xe(:, :), ue(:, :), w(:, :)
      real(dp) :: energy
      real(dp) :: lambda, mu, sigma(3, 3), N(size(xe, 2)), dN(3, size(xe, 2))
      real(dp) :: g(3, size(xe, 2)), detj, H(3, 3), strain(3, 3)
      real(dp), allocatable :: points(:, :), weights(:)
      integer :: q
      call lame_parameters(steel(), lambda, mu)
      if (size(xe, 2) == 4) then
         points = TET1_POINTS
         weights = TET1_WEIGHTS
      else
         points = TET14_POINTS
         weights = TET14_WEIGHTS
      end if
      energy = 0.0_dp
      do q = 1, size(weights)
         call tet_point_stress(xe, ue, lambda, mu, points(:, q), sigma)
         call tet_shape(size(xe, 2), points(:, q), N, dN)
         call physical_gradients(xe, dN, g, detj)
         H = matmul(w, transpose(g))
         strain = 0.5_dp * (H + transpose(H) + matmul(transpose(H), H))
         energy = energy + weights(q) * detj * sum(sigma * strain)
      end do
   end function green_lagrange_energy

   !> K_G of a stressed element against the Hessian of green_lagrange_energy by central second
   !> differences (step 1e-3 of the element size; module header).
   subroutine check_green_lagrange(xe, ue, what, error)
      real(dp), intent(in) :: xe(:, :), ue(:, :)
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: kg(3 * size(xe, 2), 3 * size(xe, 2)), hessian(3 * size(xe, 2), 3 * size(xe, 2))
      real(dp) :: w(3, size(xe, 2)), step, difference
      integer :: i, j, n
      n = 3 * size(xe, 2)
      call tet_geometric_stiffness(xe, ue, steel(), 7_i8, kg, error)
      if (allocated(error)) return
      step = 1.0e-3_dp * SCALE
      do j = 1, n
         do i = 1, n
            hessian(i, j) = (energy_at(i, step, j, step) - energy_at(i, step, j, -step) - &
               energy_at(i, -step, j, step) + energy_at(i, -step, j, -step)) / (4.0_dp * step**2)
         end do
      end do
      difference = maxval(abs(kg - hessian)) / maxval(abs(hessian))
      call report(what // ': max |K_G - Hessian of the Green-Lagrange energy| / max |K_G| = ' // &
         to_str(difference, 3) // ' (scale ' // to_str(maxval(abs(hessian)), 3) // ' N/m)')
      call check(error, what // ': K_G equals the Hessian of the Green-Lagrange energy within ' &
         // to_str(difference_rtol, 2) // ', got ' // to_str(difference, 3), &
         difference <= difference_rtol)
   contains
      function energy_at(i, di, j, dj) result(energy)
         integer, intent(in) :: i, j
         real(dp), intent(in) :: di, dj
         real(dp) :: energy
         w = 0.0_dp
         w(mod(i - 1, 3) + 1, (i - 1) / 3 + 1) = w(mod(i - 1, 3) + 1, (i - 1) / 3 + 1) + di
         w(mod(j - 1, 3) + 1, (j - 1) / 3 + 1) = w(mod(j - 1, 3) + 1, (j - 1) / 3 + 1) + dj
         energy = green_lagrange_energy(xe, ue, w)
      end function energy_at
   end subroutine check_green_lagrange

   !> Curved Tet10 stressed by a random displacement (strains ~1e-3).
   subroutine test_tet10_green_lagrange(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: xe(3, 10), ue(3, 10)
      xe = curved_tet10()
      ue = 1.0e-3_dp * SCALE * reshape(random_vector(30, 31), [3, 10])
      call check_green_lagrange(xe, ue, 'curved Tet10', error)
   end subroutine test_tet10_green_lagrange

   !> General Tet4 stressed by a random displacement (strains ~1e-3).
   subroutine test_tet4_green_lagrange(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: xe(3, 4), ue(3, 4)
      xe = SCALE * CORNERS
      ue = 1.0e-3_dp * SCALE * reshape(random_vector(12, 32), [3, 4])
      call check_green_lagrange(xe, ue, 'Tet4', error)
   end subroutine test_tet4_green_lagrange

end module test_fe_geometric_stiffness

program main_fe_geometric_stiffness
   use ffrf_testing, only: unittest_t, run_suite
   use test_fe_geometric_stiffness, only: collect_fe_geometric_stiffness
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_fe_geometric_stiffness(tests)
   call run_suite('fe_geometric_stiffness', tests)
end program main_fe_geometric_stiffness
