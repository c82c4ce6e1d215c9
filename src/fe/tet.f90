!> Isoparametric Tet4 and Tet10 solid elements in Gmsh's node order: shape functions, element
!> stiffness for isotropic linear elasticity and the consistent scalar mass.
!>
!> Reference tetrahedron and node numbering (1-based; Gmsh's own figure is 0-based; checked by
!> meshing one tetrahedron with gmsh 4.8.4 -order 2 and reading back the edge-node coordinates):
!>```
!>                    v (y)
!>                  .
!>                ,/
!>               /
!>            3                          corners  1 (0,0,0)  2 (1,0,0)  3 (0,1,0)  4 (0,0,1)
!>          ,/|`\                        edges    5:(1,2)  6:(2,3)  7:(1,3)
!>        ,/  |  `\                               8:(1,4)  9:(3,4) 10:(2,4)
!>      ,7    '.   `6
!>    ,/       9     `\                  Abaqus/CalculiX C3D10 has 9:(2,4) and 10:(3,4):
!>  ,/         |       `\                c3d10(k) = gmsh(GMSH_TO_C3D10(k)), 9 and 10 swapped
!> 1--------5--'.--------2 --> u (x)
!>  `\.         |      ,/
!>     `\.      |    ,10
!>        `8.   '. ,/
!>           `\. |/
!>              `4
!>                 `\.
!>                    ` w (z)
!>```
!> With barycentric L1 = 1 - u - v - w, L2 = u, L3 = v, L4 = w: corner c has N_c = L_c (2 L_c - 1),
!> edge (i, j) has N = 4 L_i L_j (Tet10); Tet4 has N_c = L_c.
!>
!> Stiffness (Zienkiewicz & Taylor vol. 1, ch. 6): with the physical gradients g_a = J^-T dN_a/dxi
!> at a quadrature point, the 3x3 block of nodes a, b is
!>     K_ab(i, j) = sum_q w_q det J_q [lambda g_a,i g_b,j + mu g_a,j g_b,i + mu delta_ij g_a.g_b],
!> dofs ordered (x, y, z) per node. Tet4 takes the 1-point rule (exact), Tet10 the 4-point degree-2
!> rule ("full integration", exact for straight edges; what CalculiX and Abaqus use for C3D10).
!> Consistent scalar mass me_ab = rho int N_a N_b dV with the 14-point degree-5 rule (exact for
!> straight elements); the 3D mass is me (x) I3.
module ffrf_fe_tet
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_fe_material, only: material_t, lame_parameters
   use ffrf_fe_quadrature, only: TET1_POINTS, TET1_WEIGHTS, TET4_POINTS, TET4_WEIGHTS, &
      TET14_POINTS, TET14_WEIGHTS
   implicit none
   private
   public :: tet_shape, tet_stiffness, tet_mass, tet_stiffness_mass, tet_volume, tet_check_jacobian
   public :: physical_gradients, simplex_shape
   public :: TET10_EDGES, TET_REFERENCE_NODES, GMSH_TO_C3D10, DEGENERATE_RATIO

   !> Corner pair of each Tet10 edge node 5..10 (Gmsh order)
   integer(ip), parameter :: TET10_EDGES(2, 6) = reshape([1, 2, 2, 3, 1, 3, 1, 4, 3, 4, 2, 4], &
      [2, 6])
   !> Reference coordinates (u, v, w) of the ten nodes (the first four for Tet4)
   real(dp), parameter :: TET_REFERENCE_NODES(3, 10) = reshape([ &
      0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, &
      0.0_dp, 0.0_dp, 1.0_dp, 0.5_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 0.0_dp, &
      0.0_dp, 0.5_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.0_dp, 0.5_dp, 0.5_dp, &
      0.5_dp, 0.0_dp, 0.5_dp], [3, 10])
   !> Gmsh Tet10 -> Abaqus/CalculiX C3D10: node k of C3D10 is node GMSH_TO_C3D10(k) of Gmsh
   integer(ip), parameter :: GMSH_TO_C3D10(10) = [1, 2, 3, 4, 5, 6, 7, 8, 10, 9]
   !> det J below DEGENERATE_RATIO * h^3 (h the longest corner-to-corner edge) counts as
   !> degenerate; a regular tetrahedron has det J = h^3 / sqrt(2)
   real(dp), parameter :: DEGENERATE_RATIO = 1.0e-10_dp

contains

   !> Shape functions N(nen) and their reference derivatives dN(3, nen) (dN(k, a) = dN_a/dxi_k)
   !> at reference point xi = (u, v, w); nen = 4 or 10 (any other nen returns zeros).
   pure subroutine tet_shape(nen, xi, N, dN)
      !> Nodes per element, 4 or 10
      integer, intent(in) :: nen
      !> Reference coordinates (u, v, w)
      real(dp), intent(in) :: xi(3)
      !> Shape functions
      real(dp), intent(out) :: N(nen)
      !> Derivatives with respect to (u, v, w)
      real(dp), intent(out) :: dN(3, nen)
      real(dp) :: L(4), dL(3, 4)
      L = [1.0_dp - xi(1) - xi(2) - xi(3), xi(1), xi(2), xi(3)]
      dL = reshape([-1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, &
         0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [3, 4])
      call simplex_shape(L, dL, TET10_EDGES, N, dN)
   end subroutine tet_shape

   !> Shape functions of a simplex (tetrahedron, triangle) from its barycentric coordinates L(m)
   !> and their reference derivatives dL(:, m), by the number of nodes size(N): linear N = L
   !> (m nodes), or quadratic (m + size(edges, 2) nodes: m corners L (2 L - 1), then one
   !> mid-side node 4 L_i L_j per edge (i, j) = edges(:, e)); zeros for any other count.
   pure subroutine simplex_shape(L, dL, edges, N, dN)
      !> Barycentric coordinates
      real(dp), intent(in) :: L(:)
      !> Their reference derivatives
      real(dp), intent(in) :: dL(:, :)
      !> Corners of each edge, in mid-side node order
      integer(ip), intent(in) :: edges(:, :)
      !> Shape functions: m (linear), or m + size(edges, 2) (quadratic)
      real(dp), intent(out) :: N(:)
      !> Their reference derivatives
      real(dp), intent(out) :: dN(:, :)
      integer :: c, e, i, j, m
      m = size(L)
      if (size(N) == m) then
         N = L
         dN = dL
         return
      else if (size(N) /= m + size(edges, 2)) then
         N = 0.0_dp
         dN = 0.0_dp
         return
      end if
      do c = 1, m
         N(c) = L(c)*(2.0_dp*L(c) - 1.0_dp)
         dN(:, c) = (4.0_dp*L(c) - 1.0_dp)*dL(:, c)
      end do
      do e = 1, size(edges, 2)
         i = edges(1, e)
         j = edges(2, e)
         N(m + e) = 4.0_dp*L(i)*L(j)
         dN(:, m + e) = 4.0_dp*(L(i)*dL(:, j) + L(j)*dL(:, i))
      end do
   end subroutine simplex_shape

   !> Jacobian determinant and physical gradients g(3, nen) = J^-T dN at one point.
   pure subroutine physical_gradients(xe, dN, g, detj)
      real(dp), intent(in) :: xe(:, :), dN(:, :)
      real(dp), intent(out) :: g(:, :), detj
      real(dp) :: J(3, 3), C(3, 3)
      integer :: a
      J = matmul(xe, transpose(dN))        ! J(i, k) = dx_i / dxi_k
      ! cofactors: inv(J) = transpose(C) / det J, so J^-T = C / det J
      C(1, 1) = J(2, 2)*J(3, 3) - J(2, 3)*J(3, 2)
      C(1, 2) = J(2, 3)*J(3, 1) - J(2, 1)*J(3, 3)
      C(1, 3) = J(2, 1)*J(3, 2) - J(2, 2)*J(3, 1)
      C(2, 1) = J(1, 3)*J(3, 2) - J(1, 2)*J(3, 3)
      C(2, 2) = J(1, 1)*J(3, 3) - J(1, 3)*J(3, 1)
      C(2, 3) = J(1, 2)*J(3, 1) - J(1, 1)*J(3, 2)
      C(3, 1) = J(1, 2)*J(2, 3) - J(1, 3)*J(2, 2)
      C(3, 2) = J(1, 3)*J(2, 1) - J(1, 1)*J(2, 3)
      C(3, 3) = J(1, 1)*J(2, 2) - J(1, 2)*J(2, 1)
      detj = J(1, 1)*C(1, 1) + J(1, 2)*C(1, 2) + J(1, 3)*C(1, 3)
      if (detj == 0.0_dp) then
         g = 0.0_dp
         return
      end if
      do a = 1, size(dN, 2)
         g(:, a) = matmul(C, dN(:, a))/detj
      end do
   end subroutine physical_gradients

   !> det J of the element at reference point xi.
   pure function jacobian_determinant(xe, xi) result(detj)
      real(dp), intent(in) :: xe(:, :), xi(3)
      real(dp) :: detj
      real(dp) :: N(size(xe, 2)), dN(3, size(xe, 2)), J(3, 3)
      call tet_shape(size(xe, 2), xi, N, dN)
      J = matmul(xe, transpose(dN))
      detj = J(1, 1)*(J(2, 2)*J(3, 3) - J(2, 3)*J(3, 2)) &
         - J(1, 2)*(J(2, 1)*J(3, 3) - J(2, 3)*J(3, 1)) &
         + J(1, 3)*(J(2, 1)*J(3, 2) - J(2, 2)*J(3, 1))
   end function jacobian_determinant

   !> Check the element is neither inverted nor degenerate: det J > DEGENERATE_RATIO h^3 at the
   !> four corners and at every point of the 4- and 14-point rules (all points the element
   !> routines use). h is the longest corner-to-corner distance.
   subroutine tet_check_jacobian(xe, tag, error)
      !> Node coordinates (3, nen), nen = 4 or 10, Gmsh order
      real(dp), intent(in) :: xe(:, :)
      !> Gmsh element tag (for the message)
      integer(i8), intent(in) :: tag
      !> Inverted or degenerate element: tag, det J, where, and what to do
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: h, detj
      integer :: a, b
      call check_nodes_per_element(size(xe, 2), tag, error)
      if (allocated(error)) return
      h = 0.0_dp
      do a = 1, 4
         do b = a + 1, 4
            h = max(h, norm2(xe(:, a) - xe(:, b)))
         end do
      end do
      call check_points(TET_REFERENCE_NODES(:, 1:4), 'corner ')
      if (allocated(error) .or. size(xe, 2) == 4) return     ! Tet4: constant det J
      call check_points(TET4_POINTS, 'stiffness quadrature point ')
      if (allocated(error)) return
      call check_points(TET14_POINTS, 'mass quadrature point ')
   contains
      !> det J at each column of `points` (reference coordinates), the first failure reported.
      subroutine check_points(points, what)
         real(dp), intent(in) :: points(:, :)
         character(len=*), intent(in) :: what
         integer :: q
         do q = 1, size(points, 2)
            detj = jacobian_determinant(xe, points(:, q))
            if (.not. (detj > DEGENERATE_RATIO*h**3)) then
               call bad_jacobian(what // to_str(q))
               return
            end if
         end do
      end subroutine check_points

      subroutine bad_jacobian(where)
         character(len=*), intent(in) :: where
         character(len=:), allocatable :: kind
         if (detj <= 0.0_dp) then
            kind = 'inverted'
         else
            kind = 'degenerate'
         end if
         call fatal_error(error, FFRF_INPUT_ERROR, 'tetrahedron ' // to_str(tag) // ' is ' // &
            kind // ': det J = ' // to_str(detj) // ' at ' // where // ' (longest edge ' // &
            to_str(h) // ' m, det J must exceed ' // to_str(DEGENERATE_RATIO) // &
            ' * edge^3); re-mesh or check the .geo orientation')
      end subroutine bad_jacobian
   end subroutine tet_check_jacobian

   subroutine check_nodes_per_element(nen, tag, error)
      integer, intent(in) :: nen
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      if (nen /= 4 .and. nen /= 10) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'tetrahedron ' // to_str(tag) // ' has ' // &
            to_str(nen) // ' nodes; only Tet4 and Tet10 are supported')
      end if
   end subroutine check_nodes_per_element

   !> Element stiffness ke(3 nen, 3 nen) of an isotropic linear-elastic tetrahedron, dofs (x, y, z)
   !> per node; exactly symmetric (upper blocks computed, lower mirrored). Checks det J first.
   subroutine tet_stiffness(xe, material, tag, ke, error)
      !> Node coordinates (3, nen), nen = 4 or 10, Gmsh order (m)
      real(dp), intent(in) :: xe(:, :)
      !> Material (E, nu used)
      type(material_t), intent(in) :: material
      !> Gmsh element tag (for messages)
      integer(i8), intent(in) :: tag
      !> Element stiffness (N/m)
      real(dp), intent(out) :: ke(:, :)
      !> Inverted or degenerate element, unsupported nen
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: lambda, mu
      call tet_check_jacobian(xe, tag, error)
      if (allocated(error)) return
      call lame_parameters(material, lambda, mu)
      if (size(xe, 2) == 4) then
         call stiffness_kernel(xe, lambda, mu, TET1_POINTS, TET1_WEIGHTS, ke)
      else
         call stiffness_kernel(xe, lambda, mu, TET4_POINTS, TET4_WEIGHTS, ke)
      end if
   end subroutine tet_stiffness

   !> Stiffness and scalar mass of one element with a single det J check (what the assembly
   !> calls): same results as tet_stiffness and tet_mass.
   subroutine tet_stiffness_mass(xe, material, tag, ke, me, error)
      !> Node coordinates (3, nen), nen = 4 or 10, Gmsh order (m)
      real(dp), intent(in) :: xe(:, :)
      !> Material (E, nu, rho)
      type(material_t), intent(in) :: material
      !> Gmsh element tag (for messages)
      integer(i8), intent(in) :: tag
      !> Element stiffness (N/m), 3 nen square
      real(dp), intent(out) :: ke(:, :)
      !> Scalar element mass (kg), nen square
      real(dp), intent(out) :: me(:, :)
      !> Inverted or degenerate element, unsupported nen
      type(error_t), allocatable, intent(out) :: error
      call tet_stiffness(xe, material, tag, ke, error)
      if (allocated(error)) return
      call mass_kernel(xe, material%density, me)
   end subroutine tet_stiffness_mass

   !> ke = sum_q w_q det J_q B^T D B, block by block (see the module header).
   pure subroutine stiffness_kernel(xe, lambda, mu, points, weights, ke)
      real(dp), intent(in) :: xe(:, :), lambda, mu, points(:, :), weights(:)
      real(dp), intent(out) :: ke(:, :)
      real(dp) :: N(size(xe, 2)), dN(3, size(xe, 2)), g(3, size(xe, 2))
      real(dp) :: detj, f, fl, fm, gg
      integer :: nen, q, a, b, i, j, ra, rb
      nen = size(xe, 2)
      ke = 0.0_dp
      do q = 1, size(weights)
         call tet_shape(nen, points(:, q), N, dN)
         call physical_gradients(xe, dN, g, detj)
         f = weights(q)*detj
         fl = f*lambda
         fm = f*mu
         do b = 1, nen
            rb = 3*(b - 1)
            do a = 1, b
               ra = 3*(a - 1)
               gg = fm*(g(1, a)*g(1, b) + g(2, a)*g(2, b) + g(3, a)*g(3, b))
               do j = 1, 3
                  do i = 1, 3
                     ke(ra + i, rb + j) = ke(ra + i, rb + j) + fl*(g(i, a)*g(j, b)) &
                        + fm*(g(j, a)*g(i, b))
                  end do
                  ke(ra + j, rb + j) = ke(ra + j, rb + j) + gg
               end do
            end do
         end do
      end do
      ! mirror the upper blocks (a < b) and the upper part of the diagonal blocks
      do j = 1, 3*nen
         do i = j + 1, 3*nen
            ke(i, j) = ke(j, i)
         end do
      end do
   end subroutine stiffness_kernel

   !> Consistent scalar mass me(nen, nen) = rho int N_a N_b dV (14-point degree-5 rule, exact for
   !> straight elements); the 3D element mass is me (x) I3. Checks det J first.
   subroutine tet_mass(xe, density, tag, me, error)
      !> Node coordinates (3, nen), nen = 4 or 10, Gmsh order (m)
      real(dp), intent(in) :: xe(:, :)
      !> Density rho (kg/m^3)
      real(dp), intent(in) :: density
      !> Gmsh element tag (for messages)
      integer(i8), intent(in) :: tag
      !> Scalar element mass (kg)
      real(dp), intent(out) :: me(:, :)
      !> Inverted or degenerate element, unsupported nen
      type(error_t), allocatable, intent(out) :: error
      call tet_check_jacobian(xe, tag, error)
      if (allocated(error)) return
      call mass_kernel(xe, density, me)
   end subroutine tet_mass

   pure subroutine mass_kernel(xe, density, me)
      real(dp), intent(in) :: xe(:, :), density
      real(dp), intent(out) :: me(:, :)
      real(dp) :: N(size(xe, 2)), dN(3, size(xe, 2)), f
      integer :: nen, q, a, b
      nen = size(xe, 2)
      me = 0.0_dp
      do q = 1, size(TET14_WEIGHTS)
         call tet_shape(nen, TET14_POINTS(:, q), N, dN)
         f = density*TET14_WEIGHTS(q)*jacobian_from_dn(xe, dN)
         do b = 1, nen
            do a = 1, b
               me(a, b) = me(a, b) + f*(N(a)*N(b))
            end do
         end do
      end do
      do b = 1, nen
         do a = b + 1, nen
            me(a, b) = me(b, a)
         end do
      end do
   end subroutine mass_kernel

   pure function jacobian_from_dn(xe, dN) result(detj)
      real(dp), intent(in) :: xe(:, :), dN(:, :)
      real(dp) :: detj, J(3, 3)
      J = matmul(xe, transpose(dN))
      detj = J(1, 1)*(J(2, 2)*J(3, 3) - J(2, 3)*J(3, 2)) &
         - J(1, 2)*(J(2, 1)*J(3, 3) - J(2, 3)*J(3, 1)) &
         + J(1, 3)*(J(2, 1)*J(3, 2) - J(2, 2)*J(3, 1))
   end function jacobian_from_dn

   !> Element volume int det J dxi (14-point degree-5 rule: exact also for curved Tet10, whose
   !> det J is a cubic). Checks det J first.
   subroutine tet_volume(xe, tag, volume, error)
      !> Node coordinates (3, nen), nen = 4 or 10, Gmsh order (m)
      real(dp), intent(in) :: xe(:, :)
      !> Gmsh element tag (for messages)
      integer(i8), intent(in) :: tag
      !> Volume (m^3)
      real(dp), intent(out) :: volume
      !> Inverted or degenerate element, unsupported nen
      type(error_t), allocatable, intent(out) :: error
      integer :: q
      volume = 0.0_dp
      call tet_check_jacobian(xe, tag, error)
      if (allocated(error)) return
      do q = 1, size(TET14_WEIGHTS)
         volume = volume + TET14_WEIGHTS(q)*jacobian_determinant(xe, TET14_POINTS(:, q))
      end do
   end subroutine tet_volume

end module ffrf_fe_tet
