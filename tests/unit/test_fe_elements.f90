!> Element-level tests: quadrature exactness (closed-form monomial integrals), shape functions,
!> Tet4/Tet10 stiffness (symmetry, rigid-body null space, a second Voigt B^T D B computation) and
!> consistent mass (closed forms), the det J check, material checks, and Tri3/Tri6 surface
!> integrals against closed-form areas and centroids.
module test_fe_elements
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_lapack, only: dsyev, dgesv
   use ffrf_fe_material, only: material_t, check_material, lame_parameters
   use ffrf_fe_quadrature, only: quadrature_t, tet_quadrature, tri_quadrature
   use ffrf_fe_tet, only: tet_shape, tet_stiffness, tet_mass, tet_volume, tet_check_jacobian, &
      TET10_EDGES, TET_REFERENCE_NODES, GMSH_TO_C3D10
   use ffrf_fe_surface, only: tri_shape, surface_area_centroid, nodal_area_weights, surface_nodes
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_fe_elements

   real(dp), parameter :: EPS = epsilon(1.0_dp)
   !> Steel-like material; element size ~5 cm so that ke has realistic magnitudes (~1e10 N/m)
   real(dp), parameter :: YOUNG = 210.0e9_dp, POISSON = 0.3_dp, DENSITY = 7850.0_dp
   real(dp), parameter :: SCALE = 0.05_dp
   !> A general (not right-angled) straight tetrahedron, corners in Gmsh order, units of SCALE
   real(dp), parameter :: CORNERS(3, 4) = reshape([0.1_dp, 0.0_dp, -0.05_dp, &
      1.2_dp, 0.1_dp, 0.05_dp, 0.2_dp, 0.9_dp, 0.1_dp, 0.3_dp, 0.2_dp, 1.1_dp], [3, 4])

contains

   subroutine collect_fe_elements(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('tet_quadrature_monomials', test_tet_quadrature), &
         new_unittest('tri_quadrature_monomials', test_tri_quadrature), &
         new_unittest('tet_shape_functions', test_tet_shape), &
         new_unittest('tri_shape_functions', test_tri_shape), &
         new_unittest('tet4_stiffness', test_tet4_stiffness), &
         new_unittest('tet10_straight_stiffness', test_tet10_straight_stiffness), &
         new_unittest('tet10_curved_stiffness', test_tet10_curved_stiffness), &
         new_unittest('tet4_mass_closed_form', test_tet4_mass), &
         new_unittest('tet10_mass_closed_form', test_tet10_mass), &
         new_unittest('tet10_curved_mass_volume', test_tet10_curved_mass), &
         new_unittest('inverted_element_error', test_inverted_element), &
         new_unittest('degenerate_element_error', test_degenerate_element), &
         new_unittest('material_checks', test_material_checks), &
         new_unittest('tri3_area_centroid_weights', test_tri3_surface), &
         new_unittest('tri6_straight_weights', test_tri6_straight), &
         new_unittest('tri6_curved_area_centroid', test_tri6_curved), &
         new_unittest('surface_errors', test_surface_errors)]
   end subroutine collect_fe_elements

   ! ------------------------------------------------------------------ helpers

   function factorial(n) result(f)
      integer, intent(in) :: n
      real(dp) :: f
      integer :: k
      f = 1.0_dp
      do k = 2, n
         f = f*k
      end do
   end function factorial

   function steel() result(material)
      type(material_t) :: material
      material = material_t(young=YOUNG, poisson=POISSON, density=DENSITY, name='steel')
   end function steel

   !> Straight Tet10 on CORNERS*SCALE: edge nodes at the midpoints.
   function straight_tet10() result(xe)
      real(dp) :: xe(3, 10)
      integer :: e
      xe(:, 1:4) = SCALE*CORNERS
      do e = 1, 6
         xe(:, 4 + e) = 0.5_dp*(xe(:, TET10_EDGES(1, e)) + xe(:, TET10_EDGES(2, e)))
      end do
   end function straight_tet10

   !> Curved Tet10: every edge node moved off its midpoint by up to ~8% of the element size.
   function curved_tet10() result(xe)
      real(dp) :: xe(3, 10)
      real(dp), parameter :: MOVES(3, 6) = reshape([0.00_dp, -0.06_dp, -0.05_dp, &
         0.05_dp, 0.04_dp, -0.02_dp, -0.04_dp, 0.03_dp, 0.06_dp, 0.02_dp, -0.05_dp, 0.03_dp, &
         0.05_dp, 0.05_dp, 0.04_dp, 0.06_dp, -0.02_dp, 0.05_dp], [3, 6])
      xe = straight_tet10()
      xe(:, 5:10) = xe(:, 5:10) + SCALE*MOVES
   end function curved_tet10

   function det3(A) result(d)
      real(dp), intent(in) :: A(3, 3)
      real(dp) :: d
      d = A(1, 1)*(A(2, 2)*A(3, 3) - A(2, 3)*A(3, 2)) - A(1, 2)*(A(2, 1)*A(3, 3) - &
         A(2, 3)*A(3, 1)) + A(1, 3)*(A(2, 1)*A(3, 2) - A(2, 2)*A(3, 1))
   end function det3

   !> Volume of the straight tetrahedron on the first four columns of xe.
   function corner_volume(xe) result(v)
      real(dp), intent(in) :: xe(:, :)
      real(dp) :: v, J(3, 3)
      J(:, 1) = xe(:, 2) - xe(:, 1)
      J(:, 2) = xe(:, 3) - xe(:, 1)
      J(:, 3) = xe(:, 4) - xe(:, 1)
      v = det3(J)/6.0_dp
   end function corner_volume

   !> Eigenvalues (ascending) of a symmetric matrix with LAPACK dsyev.
   subroutine eigenvalues(A, w, error)
      real(dp), intent(in) :: A(:, :)
      real(dp), allocatable, intent(out) :: w(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: work(:), B(:, :)
      real(dp) :: query(1)
      integer(ip) :: n, info
      n = size(A, 1, kind=ip)
      B = A
      allocate (w(n))
      call dsyev('N', 'U', n, B, n, w, query, -1_ip, info)
      allocate (work(int(query(1))))
      call dsyev('N', 'U', n, B, n, w, work, size(work, kind=ip), info)
      call check(error, 'dsyev info = ' // to_str(info), info == 0)
   end subroutine eigenvalues

   !> The six rigid motions of the nodes xe as columns (3 nen, 6): translations, then
   !> infinitesimal rotations omega x x about the three axes.
   function rigid_modes(xe) result(R)
      real(dp), intent(in) :: xe(:, :)
      real(dp) :: R(3*size(xe, 2), 6)
      integer :: a, k
      real(dp) :: omega(3)
      R = 0.0_dp
      do a = 1, size(xe, 2)
         do k = 1, 3
            R(3*(a - 1) + k, k) = 1.0_dp
            omega = 0.0_dp
            omega(k) = 1.0_dp
            R(3*(a - 1) + 1:3*a, 3 + k) = [omega(2)*xe(3, a) - omega(3)*xe(2, a), &
               omega(3)*xe(1, a) - omega(1)*xe(3, a), omega(1)*xe(2, a) - omega(2)*xe(1, a)]
         end do
      end do
   end function rigid_modes

   !> Second method for ke: Voigt strain-displacement B (6 x 3 nen) and isotropic D, ke =
   !> sum_q w_q det J_q B^T D B, with the given rule (engineering shear strains).
   subroutine voigt_stiffness(xe, rule, ke)
      real(dp), intent(in) :: xe(:, :)
      type(quadrature_t), intent(in) :: rule
      real(dp), intent(out) :: ke(:, :)
      real(dp) :: N(size(xe, 2)), dN(3, size(xe, 2)), J(3, 3), g(3, size(xe, 2))
      real(dp) :: B(6, 3*size(xe, 2)), D(6, 6), lambda, mu, Jt(3, 3)
      integer(ip) :: ipiv(3), info, nen
      integer :: q, a
      nen = size(xe, 2, kind=ip)
      call lame_parameters(steel(), lambda, mu)
      D = 0.0_dp
      D(1:3, 1:3) = lambda
      do a = 1, 3
         D(a, a) = lambda + 2.0_dp*mu
         D(3 + a, 3 + a) = mu
      end do
      ke = 0.0_dp
      do q = 1, rule%num_points
         call tet_shape(int(nen), rule%points(:, q), N, dN)
         J = matmul(xe, transpose(dN))
         ! g = J^-T dN by an LU solve (the library uses cofactors)
         Jt = transpose(J)
         g = dN
         call dgesv(3_ip, nen, Jt, 3_ip, ipiv, g, 3_ip, info)
         B = 0.0_dp
         do a = 1, int(nen)
            B(1, 3*a - 2) = g(1, a)
            B(2, 3*a - 1) = g(2, a)
            B(3, 3*a) = g(3, a)
            B(4, 3*a - 2) = g(2, a)
            B(4, 3*a - 1) = g(1, a)
            B(5, 3*a - 1) = g(3, a)
            B(5, 3*a) = g(2, a)
            B(6, 3*a - 2) = g(3, a)
            B(6, 3*a) = g(1, a)
         end do
         ke = ke + rule%weights(q)*det3(J)*matmul(transpose(B), matmul(D, B))
      end do
   end subroutine voigt_stiffness

   !> Symmetry, six zero eigenvalues, rigid null space, 7th eigenvalue positive, and agreement
   !> with the Voigt computation using `rule`.
   subroutine check_element_stiffness(error, what, xe, rule)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: what
      real(dp), intent(in) :: xe(:, :)
      type(quadrature_t), intent(in) :: rule
      real(dp) :: ke(3*size(xe, 2), 3*size(xe, 2)), ref(3*size(xe, 2), 3*size(xe, 2))
      real(dp) :: R(3*size(xe, 2), 6), norm_k, worst
      real(dp), allocatable :: w(:)
      integer :: k
      call tet_stiffness(xe, steel(), 1_i8, ke, error)
      if (allocated(error)) return
      norm_k = norm2(ke)
      ! identity: exact symmetry (upper blocks are mirrored); budget 100 eps ||ke||
      call check_close(error, what // ': max |ke - ke^T| / ||ke||', &
         maxval(abs(ke - transpose(ke)))/norm_k, 0.0_dp, atol=100.0_dp*EPS)
      if (allocated(error)) return
      ! identity: rigid motions are in the null space, ||ke r|| <= 100 eps ||ke|| ||r||
      R = rigid_modes(xe)
      worst = 0.0_dp
      do k = 1, 6
         worst = max(worst, norm2(matmul(ke, R(:, k)))/(norm_k*norm2(R(:, k))))
      end do
      call report(what // ': max ||ke r|| / (||ke|| ||r||) = ' // to_str(worst, 3))
      call check_close(error, what // ': rigid-motion residual', worst, 0.0_dp, atol=100.0_dp*EPS)
      if (allocated(error)) return
      ! exactly six zero eigenvalues: |lambda_1..6| <= 100 eps lambda_max (dsyev's backward
      ! error is a few eps ||ke||), and lambda_7 clearly positive
      call eigenvalues(ke, w, error)
      if (allocated(error)) return
      call report(what // ': max |lambda_1..6| / lambda_max = ' // &
         to_str(maxval(abs(w(1:6)))/w(size(w)), 3) // ', lambda_7 / lambda_max = ' // &
         to_str(w(7)/w(size(w)), 3))
      call check_close(error, what // ': max |lambda_1..6| / lambda_max', &
         maxval(abs(w(1:6)))/w(size(w)), 0.0_dp, atol=100.0_dp*EPS)
      if (allocated(error)) return
      call check(error, what // ': lambda_7 / lambda_max = ' // to_str(w(7)/w(size(w))) // &
         ' must exceed 1e-4 (no spurious zero-energy mode)', w(7) > 1.0e-4_dp*w(size(w)))
      if (allocated(error)) return
      ! second method: Voigt B^T D B with an LU-based inverse
      call voigt_stiffness(xe, rule, ref)
      call check_close(error, what // ': max |ke - B^T D B| / max |ke|', &
         maxval(abs(ke - ref))/maxval(abs(ke)), 0.0_dp, atol=1.0e-13_dp)
   end subroutine check_element_stiffness

   ! ------------------------------------------------------------------ quadrature

   !> Every monomial x^a y^b z^c of degree <= d against a! b! c! / (a+b+c+3)! (rtol 1e-14: sums
   !> of <= 14 positive terms); at least one of degree d+1 must miss (the claimed degree is
   !> sharp, so the check can fail).
   subroutine test_tet_quadrature(error)
      type(error_t), allocatable, intent(out) :: error
      type(quadrature_t) :: rule
      integer :: degree, a, b, c, expected_points(5)
      real(dp) :: exact, approx, worst, miss
      expected_points = [1, 4, 14, 14, 14]
      do degree = 1, 5
         call tet_quadrature(degree, rule, error)
         if (allocated(error)) return
         call check(error, 'tet rule for degree ' // to_str(degree) // ': ' // &
            to_str(rule%num_points) // ' points, positive weights', rule%num_points == &
            expected_points(degree) .and. all(rule%weights > 0.0_dp))
         if (allocated(error)) return
         worst = 0.0_dp
         miss = 0.0_dp
         do a = 0, rule%degree + 1
            do b = 0, rule%degree + 1 - a
               do c = 0, rule%degree + 1 - a - b
                  exact = factorial(a)*factorial(b)*factorial(c)/factorial(a + b + c + 3)
                  approx = sum(rule%weights*rule%points(1, :)**a*rule%points(2, :)**b* &
                     rule%points(3, :)**c)
                  if (a + b + c <= rule%degree) then
                     worst = max(worst, abs(approx - exact)/exact)
                  else
                     miss = max(miss, abs(approx - exact)/exact)
                  end if
               end do
            end do
         end do
         call check_close(error, 'tet degree ' // to_str(rule%degree) // &
            ': max relative monomial error', worst, 0.0_dp, atol=1.0e-14_dp)
         if (allocated(error)) return
         call check(error, 'tet degree ' // to_str(rule%degree) // ': some monomial of degree ' &
            // to_str(rule%degree + 1) // ' is not exact', miss > 1.0e-6_dp)
         if (allocated(error)) return
      end do
      call tet_quadrature(6, rule, error)
      if (allocated(error)) then
         deallocate (error)
      else
         call check(error, 'tet degree 6 must be refused', .false.)
      end if
   end subroutine test_tet_quadrature

   !> Triangle monomials x^a y^b against a! b! / (a+b+2)!.
   subroutine test_tri_quadrature(error)
      type(error_t), allocatable, intent(out) :: error
      type(quadrature_t) :: rule
      integer :: degree, a, b
      real(dp) :: exact, approx, worst, miss
      do degree = 2, 5, 3
         call tri_quadrature(degree, rule, error)
         if (allocated(error)) return
         call check(error, 'triangle rule: positive weights', all(rule%weights > 0.0_dp))
         if (allocated(error)) return
         worst = 0.0_dp
         miss = 0.0_dp
         do a = 0, rule%degree + 1
            do b = 0, rule%degree + 1 - a
               exact = factorial(a)*factorial(b)/factorial(a + b + 2)
               approx = sum(rule%weights*rule%points(1, :)**a*rule%points(2, :)**b)
               if (a + b <= rule%degree) then
                  worst = max(worst, abs(approx - exact)/exact)
               else
                  miss = max(miss, abs(approx - exact)/exact)
               end if
            end do
         end do
         call check_close(error, 'triangle degree ' // to_str(rule%degree) // &
            ': max relative monomial error', worst, 0.0_dp, atol=1.0e-14_dp)
         if (allocated(error)) return
         call check(error, 'triangle degree ' // to_str(rule%degree) // &
            ': some monomial of the next degree is not exact', miss > 1.0e-6_dp)
         if (allocated(error)) return
      end do
   end subroutine test_tri_quadrature

   ! ------------------------------------------------------------------ shape functions

   !> N_a(x_b) = delta_ab at the reference nodes; derivatives against central differences
   !> (h = 1e-6: error ~h^2 f''' + eps/h ~ 1e-10); Tet10 edge nodes at their edges' midpoints.
   subroutine test_tet_shape(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: N(10), dN(3, 10), Np(10), Nm(10), dtmp(3, 10), xi(3), worst, h
      integer :: nen, b, k, e
      real(dp) :: identity(10, 10)
      h = 1.0e-6_dp
      do nen = 4, 10, 6
         identity = 0.0_dp
         do b = 1, nen
            identity(b, b) = 1.0_dp
            call tet_shape(nen, TET_REFERENCE_NODES(:, b), N(:nen), dN(:, :nen))
            worst = maxval(abs(N(:nen) - identity(:nen, b)))
            call check_close(error, 'Tet' // to_str(nen) // ' N_a(node ' // to_str(b) // &
               ') - delta_ab', worst, 0.0_dp, atol=10.0_dp*EPS)
            if (allocated(error)) return
         end do
         xi = [0.21_dp, 0.17_dp, 0.33_dp]
         call tet_shape(nen, xi, N(:nen), dN(:, :nen))
         call check_close(error, 'Tet' // to_str(nen) // ' partition of unity', sum(N(:nen)), &
            1.0_dp, atol=10.0_dp*EPS)
         if (allocated(error)) return
         worst = 0.0_dp
         do k = 1, 3
            xi(k) = xi(k) + h
            call tet_shape(nen, xi, Np(:nen), dtmp(:, :nen))
            xi(k) = xi(k) - 2.0_dp*h
            call tet_shape(nen, xi, Nm(:nen), dtmp(:, :nen))
            xi(k) = xi(k) + h
            worst = max(worst, maxval(abs((Np(:nen) - Nm(:nen))/(2.0_dp*h) - dN(k, :nen))))
         end do
         call check_close(error, 'Tet' // to_str(nen) // ' dN against central differences', &
            worst, 0.0_dp, atol=1.0e-8_dp)
         if (allocated(error)) return
      end do
      do e = 1, 6
         worst = maxval(abs(TET_REFERENCE_NODES(:, 4 + e) - 0.5_dp*( &
            TET_REFERENCE_NODES(:, TET10_EDGES(1, e)) + TET_REFERENCE_NODES(:, TET10_EDGES(2, e)))))
         call check_close(error, 'edge node ' // to_str(4 + e) // ' at its edge midpoint', &
            worst, 0.0_dp, atol=0.0_dp)
         if (allocated(error)) return
      end do
      call check(error, 'C3D10 permutation swaps 9 and 10 only', &
         all(GMSH_TO_C3D10 == [1, 2, 3, 4, 5, 6, 7, 8, 10, 9]))
   end subroutine test_tet_shape

   subroutine test_tri_shape(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), parameter :: NODES(2, 6) = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, &
         1.0_dp, 0.5_dp, 0.0_dp, 0.5_dp, 0.5_dp, 0.0_dp, 0.5_dp], [2, 6])
      real(dp) :: N(6), dN(2, 6), Np(6), Nm(6), dtmp(2, 6), xi(2), worst, h
      integer :: nen, b, k
      h = 1.0e-6_dp
      do nen = 3, 6, 3
         worst = 0.0_dp
         do b = 1, nen
            call tri_shape(nen, NODES(:, b), N(:nen), dN(:, :nen))
            N(b) = N(b) - 1.0_dp
            worst = max(worst, maxval(abs(N(:nen))))
         end do
         call check_close(error, 'Tri' // to_str(nen) // ' N_a(node b) - delta_ab', worst, &
            0.0_dp, atol=10.0_dp*EPS)
         if (allocated(error)) return
         xi = [0.27_dp, 0.41_dp]
         call tri_shape(nen, xi, N(:nen), dN(:, :nen))
         worst = 0.0_dp
         do k = 1, 2
            xi(k) = xi(k) + h
            call tri_shape(nen, xi, Np(:nen), dtmp(:, :nen))
            xi(k) = xi(k) - 2.0_dp*h
            call tri_shape(nen, xi, Nm(:nen), dtmp(:, :nen))
            xi(k) = xi(k) + h
            worst = max(worst, maxval(abs((Np(:nen) - Nm(:nen))/(2.0_dp*h) - dN(k, :nen))))
         end do
         call check_close(error, 'Tri' // to_str(nen) // ' dN against central differences', &
            worst, 0.0_dp, atol=1.0e-8_dp)
         if (allocated(error)) return
      end do
   end subroutine test_tri_shape

   ! ------------------------------------------------------------------ stiffness

   subroutine test_tet4_stiffness(error)
      type(error_t), allocatable, intent(out) :: error
      type(quadrature_t) :: rule
      call tet_quadrature(1, rule, error)
      if (allocated(error)) return
      call check_element_stiffness(error, 'Tet4', SCALE*CORNERS, rule)
   end subroutine test_tet4_stiffness

   !> Straight Tet10: the Voigt reference uses the 14-point rule (also exact here, the
   !> integrand is quadratic), so it checks the 4-point integration as well.
   subroutine test_tet10_straight_stiffness(error)
      type(error_t), allocatable, intent(out) :: error
      type(quadrature_t) :: rule
      call tet_quadrature(5, rule, error)
      if (allocated(error)) return
      call check_element_stiffness(error, 'straight Tet10', straight_tet10(), rule)
   end subroutine test_tet10_straight_stiffness

   !> Curved Tet10 (not exactly integrable): the Voigt reference uses the same 4-point rule.
   subroutine test_tet10_curved_stiffness(error)
      type(error_t), allocatable, intent(out) :: error
      type(quadrature_t) :: rule
      call tet_quadrature(2, rule, error)
      if (allocated(error)) return
      call check_element_stiffness(error, 'curved Tet10', curved_tet10(), rule)
   end subroutine test_tet10_curved_stiffness

   ! ------------------------------------------------------------------ mass

   !> Tet4 consistent mass rho V / 20 (2 on the diagonal, 1 off it): Zienkiewicz & Taylor.
   subroutine test_tet4_mass(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: me(4, 4), ref(4, 4), v
      integer :: a
      call tet_mass(SCALE*CORNERS, DENSITY, 1_i8, me, error)
      if (allocated(error)) return
      v = corner_volume(SCALE*CORNERS)
      ref = DENSITY*v/20.0_dp
      do a = 1, 4
         ref(a, a) = 2.0_dp*DENSITY*v/20.0_dp
      end do
      call check_close(error, 'Tet4 max |me - rho V (1 + delta_ab)/20| / max |ref|', &
         maxval(abs(me - ref))/maxval(abs(ref)), 0.0_dp, atol=1.0e-14_dp)
   end subroutine test_tet4_mass

   !> Straight Tet10 consistent mass, rho V / 420 times: corner diagonal 6, corner-corner 1,
   !> corner-edge -4 if the edge touches the corner else -6, edge diagonal 32, edges sharing a
   !> corner 16, opposite edges 8 (from int L1^a L2^b L3^c L4^d dV = 6V a!b!c!d!/(a+b+c+d+3)!,
   !> checked with exact fractions; rows sum to -21 (corners) and 84 (edges), total 420).
   subroutine test_tet10_mass(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: me(10, 10), ref(10, 10), v
      integer :: a, b, shared
      call tet_mass(straight_tet10(), DENSITY, 1_i8, me, error)
      if (allocated(error)) return
      v = corner_volume(straight_tet10())
      do b = 1, 10
         do a = 1, 10
            if (a <= 4 .and. b <= 4) then
               ref(a, b) = merge(6.0_dp, 1.0_dp, a == b)
            else if (a <= 4 .or. b <= 4) then
               if (any(TET10_EDGES(:, max(a, b) - 4) == min(a, b))) then
                  ref(a, b) = -4.0_dp
               else
                  ref(a, b) = -6.0_dp
               end if
            else if (a == b) then
               ref(a, b) = 32.0_dp
            else
               shared = count(TET10_EDGES(1, a - 4) == TET10_EDGES(:, b - 4)) + &
                  count(TET10_EDGES(2, a - 4) == TET10_EDGES(:, b - 4))
               ref(a, b) = merge(16.0_dp, 8.0_dp, shared == 1)
            end if
         end do
      end do
      call check_close(error, 'closed-form table sums to 420', sum(ref), 420.0_dp, atol=0.0_dp)
      if (allocated(error)) return
      ref = ref*DENSITY*v/420.0_dp
      call check_close(error, 'Tet10 max |me - closed form| / max |ref|', &
         maxval(abs(me - ref))/maxval(abs(ref)), 0.0_dp, atol=1.0e-14_dp)
   end subroutine test_tet10_mass

   !> Curved Tet10 with one edge node (5) moved by d: det J = det J0 (1 + grad N5 . J0^-1 d)
   !> (rank-one update), int grad_xi N5 dxi = (0, -1/6, -1/6), so V = V0 + det J0 (0, -1/6,
   !> -1/6) . J0^-1 d exactly. Checks tet_volume and sum(me) = rho V (3D mass: the x-x block sums
   !> to the same) to 1e-14 (the 14-point rule integrates the cubic det J exactly).
   subroutine test_tet10_curved_mass(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: xe(3, 10), me(10, 10), J0(3, 3), y(3, 1), v, v_ref, d(3)
      integer(ip) :: ipiv(3), info
      xe = straight_tet10()
      d = SCALE*[0.04_dp, -0.07_dp, -0.05_dp]
      xe(:, 5) = xe(:, 5) + d
      J0(:, 1) = xe(:, 2) - xe(:, 1)
      J0(:, 2) = xe(:, 3) - xe(:, 1)
      J0(:, 3) = xe(:, 4) - xe(:, 1)
      y(:, 1) = d
      v_ref = det3(J0)
      call dgesv(3_ip, 1_ip, J0, 3_ip, ipiv, y, 3_ip, info)
      v_ref = v_ref/6.0_dp + v_ref*(-y(2, 1) - y(3, 1))/6.0_dp
      call tet_volume(xe, 1_i8, v, error)
      if (allocated(error)) return
      call check_close(error, 'curved Tet10 volume', v, v_ref, rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check(error, 'the moved node changes the volume (by ' // &
         to_str(v_ref/corner_volume(xe) - 1.0_dp) // ')', abs(v_ref/corner_volume(xe) - 1) > 0.01)
      if (allocated(error)) return
      call tet_mass(xe, DENSITY, 1_i8, me, error)
      if (allocated(error)) return
      call check_close(error, 'curved Tet10 sum(me)', sum(me), DENSITY*v_ref, rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'curved Tet10 me symmetric', maxval(abs(me - transpose(me))), &
         0.0_dp, atol=0.0_dp)
   end subroutine test_tet10_curved_mass

   ! ------------------------------------------------------------------ error paths

   !> Swapping corners 2 and 3 inverts the element: FFRF_INPUT_ERROR naming the tag, det J and
   !> the fix.
   subroutine test_inverted_element(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: expected
      real(dp) :: xe(3, 10), ke(30, 30)
      xe = straight_tet10()
      xe(:, [2, 3]) = xe(:, [3, 2])
      xe(:, [5, 7]) = xe(:, [7, 5])      ! edges (1,2) <-> (1,3)
      xe(:, [9, 10]) = xe(:, [10, 9])    ! edges (3,4) <-> (2,4)
      call tet_stiffness(xe, steel(), 4711_i8, ke, expected)
      call check(error, 'inverted Tet10 must be refused', allocated(expected))
      if (allocated(error)) return
      call check(error, 'message: ' // expected%message, expected%code == FFRF_INPUT_ERROR &
         .and. index(expected%message, 'tetrahedron 4711') > 0 .and. &
         index(expected%message, 'inverted') > 0 .and. index(expected%message, 'det J = -') > 0 &
         .and. index(expected%message, 're-mesh or check the .geo orientation') > 0)
      if (allocated(error)) return
      ! a Tet10 whose edge node is pulled across the element: positive volume overall but
      ! det J < 0 at a corner
      xe = straight_tet10()
      xe(:, 5) = xe(:, 1) + 0.2_dp*(xe(:, 2) - xe(:, 1))
      call tet_check_jacobian(xe, 12_i8, expected)
      call check(error, 'Tet10 with edge node 5 at 1/5 of its edge must be refused', &
         allocated(expected))
      if (allocated(error)) return
      call check(error, 'message: ' // expected%message, &
         index(expected%message, 'tetrahedron 12') > 0 .and. index(expected%message, 'corner') > 0)
   end subroutine test_inverted_element

   !> A flat tetrahedron (4th corner in the plane of the others) is degenerate.
   subroutine test_degenerate_element(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: expected
      real(dp) :: xe(3, 4), me(4, 4)
      xe = SCALE*CORNERS
      xe(:, 4) = (xe(:, 1) + xe(:, 2) + xe(:, 3))/3.0_dp
      call tet_mass(xe, DENSITY, 99_i8, me, expected)
      call check(error, 'flat Tet4 must be refused', allocated(expected))
      if (allocated(error)) return
      call check(error, 'message: ' // expected%message, &
         index(expected%message, 'tetrahedron 99') > 0 .and. &
         (index(expected%message, 'degenerate') > 0 .or. index(expected%message, 'inverted') > 0))
   end subroutine test_degenerate_element

   subroutine test_material_checks(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: expected
      type(material_t) :: bad
      call check_material(steel(), expected)
      call check(error, 'steel passes', .not. allocated(expected))
      if (allocated(error)) return
      bad = steel()
      bad%poisson = 0.5_dp
      call check_material(bad, expected)
      call check(error, 'nu = 0.5 refused', allocated(expected))
      if (allocated(error)) return
      call check(error, 'message: ' // expected%message, expected%message == &
         'material "steel": nu = 0.5, must lie in (-1, 0.5)')
      if (allocated(error)) return
      bad = steel()
      bad%young = 0.0_dp
      call check_material(bad, expected)
      call check(error, 'E = 0 refused', allocated(expected))
      if (allocated(error)) return
      bad = steel()
      bad%density = -1.0_dp
      call check_material(bad, expected)
      call check(error, 'rho < 0 refused', allocated(expected))
   end subroutine test_material_checks

   ! ------------------------------------------------------------------ surfaces

   !> A rotation that maps the xy plane into a general plane, and an offset.
   function rotation() result(R)
      real(dp) :: R(3, 3), c1, s1, c2, s2
      c1 = cos(0.7_dp)
      s1 = sin(0.7_dp)
      c2 = cos(-0.4_dp)
      s2 = sin(-0.4_dp)
      R = matmul(reshape([c1, s1, 0.0_dp, -s1, c1, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 3]), &
         reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, c2, s2, 0.0_dp, -s2, c2], [3, 3]))
   end function rotation

   !> Rectangle 0.3 x 0.2 in a rotated plane, split in two Tri3: area 0.06, centroid the
   !> rectangle centre, weights A_t/3 per corner of each triangle.
   subroutine test_tri3_surface(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: xy(3, 4), xyz(3, 5), area, centroid(3), offset(3)
      real(dp), allocatable :: weights(:)
      integer(ip), allocatable :: nodes(:)
      integer(ip) :: tris(3, 2)
      integer :: k
      offset = [0.5_dp, -1.0_dp, 2.0_dp]
      xy = reshape([0.0_dp, 0.0_dp, 0.0_dp, 0.3_dp, 0.0_dp, 0.0_dp, 0.3_dp, 0.2_dp, 0.0_dp, &
         0.0_dp, 0.2_dp, 0.0_dp], [3, 4])
      xyz(:, 1) = 99.0_dp        ! node 1 is not on the surface
      do k = 1, 4
         xyz(:, k + 1) = matmul(rotation(), xy(:, k)) + offset
      end do
      tris = reshape([2, 3, 4, 2, 4, 5], [3, 2])
      call surface_area_centroid(xyz, tris, area, centroid, error)
      if (allocated(error)) return
      call check_close(error, 'Tri3 area', area, 0.06_dp, rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'Tri3 centroid error', norm2(centroid - (matmul(rotation(), &
         [0.15_dp, 0.1_dp, 0.0_dp]) + offset)), 0.0_dp, atol=1.0e-14_dp)
      if (allocated(error)) return
      call surface_nodes(tris, nodes)
      call check(error, 'surface nodes 2..5', size(nodes) == 4 .and. all(nodes == [2, 3, 4, 5]))
      if (allocated(error)) return
      call nodal_area_weights(xyz, tris, nodes, weights, error)
      if (allocated(error)) return
      ! nodes 2 and 4 are in both triangles (0.03 each): 0.02; nodes 3 and 5: 0.01
      call check_close(error, 'Tri3 weights max error', maxval(abs(weights - &
         [0.02_dp, 0.01_dp, 0.02_dp, 0.01_dp])), 0.0_dp, atol=1.0e-15_dp)
   end subroutine test_tri3_surface

   !> Straight Tri6: corners get A/12, edge nodes A/4 (each in three sub-triangles of A/4).
   subroutine test_tri6_straight(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: xyz(3, 6), area, centroid(3), a_ref
      real(dp), allocatable :: weights(:)
      integer(ip) :: tris(6, 1)
      xyz(:, 1:3) = reshape([0.1_dp, 0.2_dp, 0.3_dp, 1.0_dp, 0.4_dp, 0.1_dp, 0.3_dp, 1.2_dp, &
         0.7_dp], [3, 3])
      xyz(:, 4) = 0.5_dp*(xyz(:, 1) + xyz(:, 2))
      xyz(:, 5) = 0.5_dp*(xyz(:, 2) + xyz(:, 3))
      xyz(:, 6) = 0.5_dp*(xyz(:, 3) + xyz(:, 1))
      tris(:, 1) = [1, 2, 3, 4, 5, 6]
      a_ref = 0.5_dp*norm2(cross(xyz(:, 2) - xyz(:, 1), xyz(:, 3) - xyz(:, 1)))
      call surface_area_centroid(xyz, tris, area, centroid, error)
      if (allocated(error)) return
      call check_close(error, 'straight Tri6 area', area, a_ref, rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'straight Tri6 centroid error', norm2(centroid - &
         sum(xyz(:, 1:3), dim=2)/3.0_dp), 0.0_dp, atol=1.0e-14_dp)
      if (allocated(error)) return
      call nodal_area_weights(xyz, tris, [1, 2, 3, 4, 5, 6], weights, error)
      if (allocated(error)) return
      call check_close(error, 'straight Tri6 weights max error / A', maxval(abs(weights - &
         a_ref*[1, 1, 1, 3, 3, 3]/12.0_dp))/a_ref, 0.0_dp, atol=1.0e-14_dp)
   end subroutine test_tri6_straight

   function cross(a, b) result(c)
      real(dp), intent(in) :: a(3), b(3)
      real(dp) :: c(3)
      c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
   end function cross

   !> Planar curved Tri6: edge node e moved by d_e along the chord's outward normal n_e bounds the
   !> region by parabolic arcs. Each arc adds (2/3) L_e d_e of area with its centroid at the
   !> chord midpoint + (2/5) d_e n_e (int_0^1 4t(1-t) dt = 2/3, int (4t(1-t))^2/2 / (2/3) = 2/5).
   !> The 7-point rule is exact here (dA quadratic, x dA quartic): 1e-14. Then rotated into 3D.
   !> Weights: positive and summing to the area.
   subroutine test_tri6_curved(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: p(2, 3), d(3), xy(3, 6), xyz(3, 6), n(2), chord(2), m(2), offset(3)
      real(dp) :: a_tri, a_ref, c_ref(2), a_seg, area, centroid(3)
      real(dp), allocatable :: weights(:)
      integer(ip) :: tris(6, 1)
      integer :: e, i, j
      integer, parameter :: EDGES(2, 3) = reshape([1, 2, 2, 3, 3, 1], [2, 3])
      p = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.3_dp, 0.8_dp], [2, 3])
      d = [0.05_dp, 0.04_dp, -0.03_dp]           ! the third edge bulges inwards
      offset = [0.2_dp, 0.3_dp, -0.1_dp]
      a_tri = 0.5_dp*((p(1, 2) - p(1, 1))*(p(2, 3) - p(2, 1)) - &
         (p(2, 2) - p(2, 1))*(p(1, 3) - p(1, 1)))
      a_ref = a_tri
      c_ref = a_tri*sum(p, dim=2)/3.0_dp
      xy = 0.0_dp
      xy(1:2, 1:3) = p
      do e = 1, 3
         i = EDGES(1, e)
         j = EDGES(2, e)
         chord = p(:, j) - p(:, i)
         n = [chord(2), -chord(1)]/norm2(chord)   ! outward for a counter-clockwise triangle
         m = 0.5_dp*(p(:, i) + p(:, j))
         xy(1:2, 3 + e) = m + d(e)*n
         a_seg = 2.0_dp/3.0_dp*norm2(chord)*d(e)
         a_ref = a_ref + a_seg
         c_ref = c_ref + a_seg*(m + 0.4_dp*d(e)*n)
      end do
      c_ref = c_ref/a_ref
      do i = 1, 6
         xyz(:, i) = matmul(rotation(), xy(:, i)) + offset
      end do
      tris(:, 1) = [1, 2, 3, 4, 5, 6]
      call surface_area_centroid(xyz, tris, area, centroid, error)
      if (allocated(error)) return
      call report('curved Tri6: area ' // to_str(area, 15) // ' (flat ' // to_str(a_tri) // ')')
      call check_close(error, 'curved Tri6 area', area, a_ref, rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_close(error, 'curved Tri6 centroid error', norm2(centroid - (matmul( &
         rotation(), [c_ref(1), c_ref(2), 0.0_dp]) + offset)), 0.0_dp, atol=1.0e-14_dp)
      if (allocated(error)) return
      call nodal_area_weights(xyz, tris, [1, 2, 3, 4, 5, 6], weights, error)
      if (allocated(error)) return
      call check(error, 'curved Tri6 weights positive', all(weights > 0.0_dp))
      if (allocated(error)) return
      call check_close(error, 'curved Tri6 weights sum', sum(weights), a_ref, rtol=1.0e-14_dp)
   end subroutine test_tri6_curved

   subroutine test_surface_errors(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: expected
      real(dp) :: xyz(3, 4)
      real(dp), allocatable :: weights(:)
      xyz = reshape([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0], [3, 4])*1.0_dp
      call nodal_area_weights(xyz, reshape([1, 2, 3, 2, 4, 3], [3, 2]), [1, 2, 3], weights, &
         expected)
      call check(error, 'node 4 missing from the list must be refused', allocated(expected))
      if (allocated(error)) return
      call check(error, 'message: ' // expected%message, &
         index(expected%message, 'node 4 of triangle 2') > 0)
      if (allocated(error)) return
      call nodal_area_weights(xyz, reshape([1, 2, 3], [3, 1]), [3, 2, 1], weights, expected)
      call check(error, 'unsorted node list must be refused', allocated(expected))
   end subroutine test_surface_errors

end module test_fe_elements

program main_fe_elements
   use ffrf_testing, only: unittest_t, run_suite
   use test_fe_elements, only: collect_fe_elements
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_fe_elements(tests)
   call run_suite('fe_elements', tests)
end program main_fe_elements
