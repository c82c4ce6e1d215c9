!> Geometric (initial-stress) stiffness of Tet4 and Tet10 elements, and the centrifugal load
!> cases of a body spinning about its frame origin: the stress stiffening that linear elasticity
!> leaves out (the "stress stiffening from inertia loads" of a rotating flexible body).
!>
!> Geometric stiffness. With the Green-Lagrange strain E = (H + H^T + H^T H)/2, H = grad u, a body
!> carrying the (Cauchy = second Piola-Kirchhoff, to first order) stress sigma has the strain
!> energy of that stress W = int sigma : E dV; its part quadratic in u,
!>     W_G(u) = 1/2 int sigma_kl u_i,k u_i,l dV,
!> is the geometric stiffness u^T K_G u / 2 (Bathe, Finite Element Procedures, 1996, sec. 6.3,
!> the nonlinear strain matrix K_NL = int B_NL^T S B_NL dV; Zienkiewicz & Taylor vol. 2, the
!> initial-stress matrix). Node blocks, with the physical gradients g_a = J^-T dN_a/dxi:
!>     K_G(3(a-1)+i, 3(b-1)+j) = delta_ij int g_a . sigma g_b dV                          (G1)
!> For a stress field from a displacement u^s of the same element, sigma = lambda tr(eps) I +
!> 2 mu eps, eps = sym(grad u^s) (ffrf_fe_material), the integrand has degree 3 in a straight
!> Tet10 (g linear, sigma linear): the 14-point degree-5 rule integrates it exactly; Tet4 has
!> constant g and sigma, one point is exact.
!>
!> Centrifugal load cases. A point at x (frame coordinates, from the frame origin) of a frame
!> spinning with angular velocity omega (frame components) has the centrifugal acceleration
!>     a(x) = -omega x (omega x x) = |omega|^2 x - omega (omega . x) = sum_c p_c(omega) C_c x, (G2)
!> linear in the six products p = [w1^2, w2^2, w3^2, w1 w2, w2 w3, w1 w3] (the order of the
!> inertia keys Jxx Jyy Jzz Jxy Jyz Jxz) with C_1 = diag(0, 1, 1), C_2 = diag(1, 0, 1),
!> C_3 = diag(1, 1, 0), C_4 = -(e1 e2^T + e2 e1^T), C_5 = -(e2 e3^T + e3 e2^T),
!> C_6 = -(e1 e3^T + e3 e1^T). The consistent nodal load of case c is M (C_c x) (x is
!> interpolated exactly by isoparametric elements).
module ffrf_fe_geometric_stiffness
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t
   use ffrf_fe_material, only: material_t, lame_parameters
   use ffrf_fe_quadrature, only: TET1_POINTS, TET1_WEIGHTS, TET14_POINTS, TET14_WEIGHTS
   use ffrf_fe_tet, only: tet_shape, physical_gradients, tet_check_jacobian
   implicit none
   private
   public :: tet_geometric_stiffness, geometric_stiffness_kernel, tet_point_stress
   public :: centrifugal_products, centrifugal_product_jacobian, centrifugal_case_matrix
   public :: NUM_CENTRIFUGAL_CASES

   !> Number of centrifugal load cases: the six products w_a w_b (G2)
   integer, parameter :: NUM_CENTRIFUGAL_CASES = 6

contains

   !> The six products p(omega) = [w1^2, w2^2, w3^2, w1 w2, w2 w3, w1 w3] of (G2) (1/s^2).
   pure function centrifugal_products(omega) result(p)
      !> Angular velocity, frame components (rad/s)
      real(dp), intent(in) :: omega(3)
      real(dp) :: p(NUM_CENTRIFUGAL_CASES)
      p = [omega(1)**2, omega(2)**2, omega(3)**2, omega(1) * omega(2), omega(2) * omega(3), &
         omega(1) * omega(3)]
   end function centrifugal_products

   !> dp/domega (6 x 3) of centrifugal_products (1/s).
   pure function centrifugal_product_jacobian(omega) result(dp_domega)
      !> Angular velocity, frame components (rad/s)
      real(dp), intent(in) :: omega(3)
      real(dp) :: dp_domega(NUM_CENTRIFUGAL_CASES, 3)
      dp_domega = 0.0_dp
      dp_domega(1, 1) = 2.0_dp * omega(1)
      dp_domega(2, 2) = 2.0_dp * omega(2)
      dp_domega(3, 3) = 2.0_dp * omega(3)
      dp_domega(4, :) = [omega(2), omega(1), 0.0_dp]
      dp_domega(5, :) = [0.0_dp, omega(3), omega(2)]
      dp_domega(6, :) = [omega(3), 0.0_dp, omega(1)]
   end function centrifugal_product_jacobian

   !> C_c of (G2): the centrifugal acceleration of load case c is C_c x per unit p_c (1/s^2).
   pure function centrifugal_case_matrix(load_case) result(C)
      !> Load case, 1..NUM_CENTRIFUGAL_CASES
      integer, intent(in) :: load_case
      real(dp) :: C(3, 3)
      C = 0.0_dp
      select case (load_case)
      case (1:3)
         C(1, 1) = 1.0_dp
         C(2, 2) = 1.0_dp
         C(3, 3) = 1.0_dp
         C(load_case, load_case) = 0.0_dp
      case (4)
         C(1, 2) = -1.0_dp
         C(2, 1) = -1.0_dp
      case (5)
         C(2, 3) = -1.0_dp
         C(3, 2) = -1.0_dp
      case (6)
         C(1, 3) = -1.0_dp
         C(3, 1) = -1.0_dp
      case default
         C = 0.0_dp                 ! not a load case: no acceleration
      end select
   end function centrifugal_case_matrix

   !> Cauchy stress sigma = lambda tr(eps) I + 2 mu eps, eps = sym(grad u), of the element
   !> displacement ue at reference point xi (Pa). Linear elasticity, small strains.
   pure subroutine tet_point_stress(xe, ue, lambda, mu, xi, sigma)
      !> Node coordinates (3, nen), nen = 4 or 10, Gmsh order (m)
      real(dp), intent(in) :: xe(:, :)
      !> Node displacements (3, nen) (m)
      real(dp), intent(in) :: ue(:, :)
      !> Lame constants (Pa)
      real(dp), intent(in) :: lambda, mu
      !> Reference coordinates (u, v, w) of the point
      real(dp), intent(in) :: xi(3)
      !> Stress (3, 3) (Pa)
      real(dp), intent(out) :: sigma(3, 3)
      real(dp) :: N(size(xe, 2)), dN(3, size(xe, 2)), g(3, size(xe, 2)), detj, H(3, 3)
      real(dp) :: eps(3, 3), trace
      call tet_shape(size(xe, 2), xi, N, dN)
      call physical_gradients(xe, dN, g, detj)
      H = matmul(ue, transpose(g))          ! H(i, k) = du_i/dx_k
      eps = 0.5_dp * (H + transpose(H))
      trace = eps(1, 1) + eps(2, 2) + eps(3, 3)
      sigma = 2.0_dp * mu * eps
      sigma(1, 1) = sigma(1, 1) + lambda * trace
      sigma(2, 2) = sigma(2, 2) + lambda * trace
      sigma(3, 3) = sigma(3, 3) + lambda * trace
   end subroutine tet_point_stress

   !> K_G (G1) of one element for a given stress at each point of the rule (points, weights):
   !> kg(3 nen, 3 nen), exactly symmetric when every stress is.
   pure subroutine geometric_stiffness_kernel(xe, stress, points, weights, kg)
      !> Node coordinates (3, nen), nen = 4 or 10, Gmsh order (m)
      real(dp), intent(in) :: xe(:, :)
      !> Stress (3, 3, num_points) at the rule's points (Pa)
      real(dp), intent(in) :: stress(:, :, :)
      !> Reference coordinates (3, num_points) and weights (num_points) of the rule
      real(dp), intent(in) :: points(:, :), weights(:)
      !> Geometric stiffness (N/m), 3 nen square
      real(dp), intent(out) :: kg(:, :)
      real(dp) :: N(size(xe, 2)), dN(3, size(xe, 2)), g(3, size(xe, 2)), sg(3, size(xe, 2))
      real(dp) :: detj, value
      integer :: nen, q, a, b, i
      nen = size(xe, 2)
      kg = 0.0_dp
      do q = 1, size(weights)
         call tet_shape(nen, points(:, q), N, dN)
         call physical_gradients(xe, dN, g, detj)
         sg = matmul(stress(:, :, q), g)
         do b = 1, nen
            do a = 1, nen
               value = weights(q) * detj * dot_product(g(:, a), sg(:, b))
               do i = 1, 3
                  kg(3 * (a - 1) + i, 3 * (b - 1) + i) = kg(3 * (a - 1) + i, 3 * (b - 1) + i) &
                     + value
               end do
            end do
         end do
      end do
   end subroutine geometric_stiffness_kernel

   !> K_G (G1) of one Tet4 or Tet10 element stressed by its own displacement ue (a static
   !> solution), kg(3 nen, 3 nen): Tet4 one point, Tet10 the 14-point degree-5 rule (exact for
   !> straight elements, module header). Checks det J first.
   subroutine tet_geometric_stiffness(xe, ue, material, tag, kg, error)
      !> Node coordinates (3, nen), nen = 4 or 10, Gmsh order (m)
      real(dp), intent(in) :: xe(:, :)
      !> Node displacements of the stressing state (3, nen) (m)
      real(dp), intent(in) :: ue(:, :)
      !> Material (E, nu)
      type(material_t), intent(in) :: material
      !> Gmsh element tag (for messages)
      integer(i8), intent(in) :: tag
      !> Geometric stiffness (N/m), 3 nen square
      real(dp), intent(out) :: kg(:, :)
      !> Inverted or degenerate element, unsupported nen
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: lambda, mu
      real(dp), allocatable :: stress(:, :, :)
      integer :: q
      call tet_check_jacobian(xe, tag, error)
      if (allocated(error)) return
      call lame_parameters(material, lambda, mu)
      if (size(xe, 2) == 4) then
         allocate (stress(3, 3, size(TET1_WEIGHTS)))
         call tet_point_stress(xe, ue, lambda, mu, TET1_POINTS(:, 1), stress(:, :, 1))
         call geometric_stiffness_kernel(xe, stress, TET1_POINTS, TET1_WEIGHTS, kg)
      else
         allocate (stress(3, 3, size(TET14_WEIGHTS)))
         do q = 1, size(TET14_WEIGHTS)
            call tet_point_stress(xe, ue, lambda, mu, TET14_POINTS(:, q), stress(:, :, q))
         end do
         call geometric_stiffness_kernel(xe, stress, TET14_POINTS, TET14_WEIGHTS, kg)
      end if
   end subroutine tet_geometric_stiffness

end module ffrf_fe_geometric_stiffness
