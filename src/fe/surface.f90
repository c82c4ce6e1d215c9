!> Surface integrals over Tri3/Tri6 triangles of a body mesh, for interfaces (RBE2/RBE3): area,
!> area centroid int x dA / A, and nodal area weights (tributary and consistent).
!>
!> Gmsh node order (1-based), reference triangle {u, v >= 0, u + v <= 1}:
!>```
!>  v
!>  3                 corners 1 (0,0)  2 (1,0)  3 (0,1)
!>  |`\               edges   4:(1,2)  5:(2,3)  6:(3,1)   (Tri6)
!>  6  `5
!>  |    `\           Tri6 sub-triangles for the nodal weights:
!>  1--4---2 --> u    (1,4,6) (4,2,5) (6,5,3) and the middle one (4,5,6)
!>```
!> Isoparametric: x(u, v) = sum_a N_a x_a, dA = |x_u x x_v| du dv; Tri3 uses the 3-point degree-2
!> rule (exact for flat triangles, also for int x dA), Tri6 the 7-point degree-5 rule (exact for
!> planar Tri6, whose |x_u x x_v| is a quadratic; accurate for curved ones).
module ffrf_fe_surface
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: sort_indices
   use ffrf_fe_quadrature, only: TRI3_POINTS, TRI3_WEIGHTS, TRI7_POINTS, TRI7_WEIGHTS
   use ffrf_fe_tet, only: simplex_shape
   implicit none
   private
   public :: tri_shape, surface_area_centroid, nodal_area_weights, nodal_consistent_weights
   public :: surface_nodes

   !> Reference coordinates of the six Tri6 nodes (first three for Tri3)
   real(dp), parameter :: TRI_REFERENCE_NODES(2, 6) = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, &
      0.0_dp, 1.0_dp, 0.5_dp, 0.0_dp, 0.5_dp, 0.5_dp, 0.0_dp, 0.5_dp], [2, 6])
   !> The four Tri6 sub-triangles (local node numbers)
   integer, parameter :: TRI6_SUBTRIANGLES(3, 4) = reshape([1, 4, 6, 4, 2, 5, 6, 5, 3, 4, 5, 6], &
      [3, 4])

contains

   !> Shape functions N(nen) and derivatives dN(2, nen) (dN(k, a) = dN_a/du_k) of Tri3 (nen = 3)
   !> or Tri6 (nen = 6) at reference point xi = (u, v); any other nen returns zeros.
   pure subroutine tri_shape(nen, xi, N, dN)
      !> Nodes per triangle, 3 or 6
      integer, intent(in) :: nen
      !> Reference coordinates (u, v)
      real(dp), intent(in) :: xi(2)
      !> Shape functions
      real(dp), intent(out) :: N(nen)
      !> Derivatives with respect to (u, v)
      real(dp), intent(out) :: dN(2, nen)
      real(dp) :: L(3), dL(2, 3)
      integer(ip), parameter :: EDGES(2, 3) = reshape([1, 2, 2, 3, 3, 1], [2, 3])
      L = [1.0_dp - xi(1) - xi(2), xi(1), xi(2)]
      dL = reshape([-1.0_dp, -1.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 3])
      call simplex_shape(L, dL, EDGES, N, dN)
   end subroutine tri_shape

   !> Area element |x_u x x_v| and position x of triangle xe at reference point xi.
   pure subroutine area_element(xe, xi, da, x)
      real(dp), intent(in) :: xe(:, :), xi(2)
      real(dp), intent(out) :: da, x(3)
      real(dp) :: N(size(xe, 2)), dN(2, size(xe, 2)), tu(3), tv(3)
      call tri_shape(size(xe, 2), xi, N, dN)
      tu = matmul(xe, dN(1, :))
      tv = matmul(xe, dN(2, :))
      da = norm2([tu(2)*tv(3) - tu(3)*tv(2), tu(3)*tv(1) - tu(1)*tv(3), tu(1)*tv(2) - tu(2)*tv(1)])
      x = matmul(xe, N)
   end subroutine area_element

   !> Check triangle shape and node indices.
   subroutine check_triangles(num_nodes, tris, error)
      integer(ip), intent(in) :: num_nodes
      integer(ip), intent(in) :: tris(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: k, a
      if (size(tris, 1) /= 3 .and. size(tris, 1) /= 6) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'surface: triangles have ' // &
            to_str(size(tris, 1, kind=ip)) // ' nodes; only Tri3 (3) and Tri6 (6) are supported')
         return
      end if
      do k = 1, size(tris, 2, kind=ip)
         do a = 1, size(tris, 1, kind=ip)
            if (tris(a, k) < 1 .or. tris(a, k) > num_nodes) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'surface: triangle ' // to_str(k) // &
                  ' has node index ' // to_str(tris(a, k)) // ', outside 1..' // &
                  to_str(num_nodes) // '; check the mesh')
               return
            end if
         end do
      end do
   end subroutine check_triangles

   !> Total area A = sum int dA and area centroid int x dA / A of the triangles.
   subroutine surface_area_centroid(xyz, tris, area, centroid, error)
      !> Node coordinates (3, num_nodes) (m)
      real(dp), intent(in) :: xyz(:, :)
      !> Triangle node indices (3 or 6, num_tris), Gmsh order
      integer(ip), intent(in) :: tris(:, :)
      !> Area (m^2)
      real(dp), intent(out) :: area
      !> Area centroid (m)
      real(dp), intent(out) :: centroid(3)
      !> Bad triangle shape or node index, or zero total area
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: first(3), da, x(3)
      integer(ip) :: k
      integer :: q
      area = 0.0_dp
      centroid = 0.0_dp
      call check_triangles(size(xyz, 2, kind=ip), tris, error)
      if (allocated(error)) return
      first = 0.0_dp
      do k = 1, size(tris, 2, kind=ip)
         if (size(tris, 1) == 3) then
            do q = 1, size(TRI3_WEIGHTS)
               call area_element(xyz(:, tris(:, k)), TRI3_POINTS(:, q), da, x)
               area = area + TRI3_WEIGHTS(q)*da
               first = first + (TRI3_WEIGHTS(q)*da)*x
            end do
         else
            do q = 1, size(TRI7_WEIGHTS)
               call area_element(xyz(:, tris(:, k)), TRI7_POINTS(:, q), da, x)
               area = area + TRI7_WEIGHTS(q)*da
               first = first + (TRI7_WEIGHTS(q)*da)*x
            end do
         end if
      end do
      if (.not. (area > 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'surface: ' // &
            to_str(size(tris, 2, kind=ip)) // ' triangles with total area ' // to_str(area) // &
            ' m^2; the surface must not be empty or degenerate')
         return
      end if
      centroid = first/area
   end subroutine surface_area_centroid

   !> Tributary area weights of the nodes of a surface (`weighting = 'area'`), positive and
   !> summing to its area: Tri3 gives each corner a third of the triangle's area; Tri6 splits
   !> each triangle into its four sub-triangles (corner-mid-mid and the middle one, in the
   !> reference triangle) and gives each sub-triangle's vertices a third of its (isoparametric)
   !> area. For a flat straight-sided Tri6 of area A: corners A/12, mid-side nodes A/4.
   subroutine nodal_area_weights(xyz, tris, nodes, weights, error)
      !> Node coordinates (3, num_nodes) (m)
      real(dp), intent(in) :: xyz(:, :)
      !> Triangle node indices (3 or 6, num_tris), Gmsh order
      integer(ip), intent(in) :: tris(:, :)
      !> Node indices, strictly ascending, containing every node of tris
      integer(ip), intent(in) :: nodes(:)
      !> Weight of nodes(i) (m^2)
      real(dp), allocatable, intent(out) :: weights(:)
      !> Bad triangle, unsorted node list, triangle node missing from the list
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: xi(2), p(2, 3), da, x(3), sub_area, jac
      integer(ip) :: k, a
      integer :: s, q, v
      call start_node_weights(xyz, tris, nodes, 'nodal_area_weights', weights, error)
      if (allocated(error)) return
      do k = 1, size(tris, 2, kind=ip)
         if (size(tris, 1) == 3) then
            call area_element(xyz(:, tris(:, k)), TRI3_POINTS(:, 1), da, x)
            do a = 1, 3
               call add_node_weight(nodes, tris(a, k), k, 0.5_dp*da/3.0_dp, weights, error)
               if (allocated(error)) return
            end do
         else
            do s = 1, 4
               p = TRI_REFERENCE_NODES(:, TRI6_SUBTRIANGLES(:, s))
               ! |det| of the affine map from the reference triangle to the sub-triangle
               jac = abs((p(1, 2) - p(1, 1))*(p(2, 3) - p(2, 1)) - &
                  (p(2, 2) - p(2, 1))*(p(1, 3) - p(1, 1)))
               sub_area = 0.0_dp
               do q = 1, size(TRI7_WEIGHTS)
                  xi = p(:, 1) + (p(:, 2) - p(:, 1))*TRI7_POINTS(1, q) + &
                     (p(:, 3) - p(:, 1))*TRI7_POINTS(2, q)
                  call area_element(xyz(:, tris(:, k)), xi, da, x)
                  sub_area = sub_area + TRI7_WEIGHTS(q)*da*jac
               end do
               do v = 1, 3
                  call add_node_weight(nodes, tris(TRI6_SUBTRIANGLES(v, s), k), k, &
                     sub_area/3.0_dp, weights, error)
                  if (allocated(error)) return
               end do
            end do
         end if
      end do
   end subroutine nodal_area_weights

   !> Consistent area weights of the nodes of a surface (`weighting = 'area_consistent'`):
   !> w_a = int N_a dA, the integral of node a's shape function over the surface, i.e. the
   !> work-equivalent nodal forces of a unit uniform traction. They sum to the area and their
   !> first moment is the area's (sum w_a x_a = int x dA, isoparametric). Tri3: A/3 per corner,
   !> as the tributary weights. Tri6: for a flat straight-sided triangle the corners get 0 and
   !> the mid-side nodes A/3; on a curved Tri6 the corner integrals are small and of either sign.
   !> Quadrature: Tri3 3-point (degree 2, exact); Tri6 the 7-point degree-5 rule on each of the
   !> 16 triangles of a 4 x 4 subdivision of the reference triangle: exact for flat triangles,
   !> and on curved ones, where N_a |x_u x x_v| is not a polynomial, about 1e-9 of the largest
   !> weight (the 7-point rule alone errs by 1.3e-5 on the lc = 10 mm crank, whose corner weights
   !> are 1e-3 of the mid-side ones). A triangle's value below 8 eps of its area (round-off
   !> of 0) is set to 0.
   subroutine nodal_consistent_weights(xyz, tris, nodes, weights, error)
      !> Node coordinates (3, num_nodes) (m)
      real(dp), intent(in) :: xyz(:, :)
      !> Triangle node indices (3 or 6, num_tris), Gmsh order
      integer(ip), intent(in) :: tris(:, :)
      !> Node indices, strictly ascending, containing every node of tris
      integer(ip), intent(in) :: nodes(:)
      !> Weight of nodes(i) (m^2)
      real(dp), allocatable, intent(out) :: weights(:)
      !> Bad triangle, unsorted node list, triangle node missing from the list
      type(error_t), allocatable, intent(out) :: error
      integer, parameter :: n = 4
      real(dp), allocatable :: element(:)
      real(dp) :: N_a(size(tris, 1)), dN(2, size(tris, 1)), da, x(3), corner(2), xi(2), h
      integer(ip) :: k, a
      integer :: q, i, j, flip
      call start_node_weights(xyz, tris, nodes, 'nodal_consistent_weights', weights, error)
      if (allocated(error)) return
      allocate (element(size(tris, 1)))
      h = 1.0_dp/n
      do k = 1, size(tris, 2, kind=ip)
         element = 0.0_dp
         if (size(tris, 1) == 3) then
            do q = 1, size(TRI3_WEIGHTS)
               call tri_shape(3, TRI3_POINTS(:, q), N_a, dN)
               call area_element(xyz(:, tris(:, k)), TRI3_POINTS(:, q), da, x)
               element = element + (TRI3_WEIGHTS(q)*da)*N_a
            end do
         else
            ! sub-triangle (i, j): upright, corner h (i, j), legs +h u and +h v; flipped,
            ! corner h (i + 1, j + 1), legs -h u and -h v
            do flip = 0, 1
               do j = 0, n - 1 - flip
                  do i = 0, n - 1 - flip - j
                     corner = h*[real(i + flip, dp), real(j + flip, dp)]
                     do q = 1, size(TRI7_WEIGHTS)
                        xi = corner + (1 - 2*flip)*h*TRI7_POINTS(:, q)
                        call tri_shape(6, xi, N_a, dN)
                        call area_element(xyz(:, tris(:, k)), xi, da, x)
                        element = element + (TRI7_WEIGHTS(q)*da*h*h)*N_a
                     end do
                  end do
               end do
            end do
         end if
         ! round-off of an integral that is 0 (corners of a flat Tri6) is made exactly 0
         where (abs(element) <= 8.0_dp*epsilon(1.0_dp)*sum(element)) element = 0.0_dp
         do a = 1, size(tris, 1, kind=ip)
            call add_node_weight(nodes, tris(a, k), k, element(a), weights, error)
            if (allocated(error)) return
         end do
      end do
   end subroutine nodal_consistent_weights

   !> Checks shared by the nodal weights: triangles, strictly ascending node list; zero weights.
   subroutine start_node_weights(xyz, tris, nodes, what, weights, error)
      real(dp), intent(in) :: xyz(:, :)
      integer(ip), intent(in) :: tris(:, :), nodes(:)
      character(len=*), intent(in) :: what
      real(dp), allocatable, intent(out) :: weights(:)
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: k
      allocate (weights(size(nodes)))
      weights = 0.0_dp
      call check_triangles(size(xyz, 2, kind=ip), tris, error)
      if (allocated(error)) return
      do k = 2, size(nodes, kind=ip)
         if (nodes(k) <= nodes(k - 1)) then
            call fatal_error(error, FFRF_INPUT_ERROR, what // ': the node list is ' // &
               'not strictly ascending at position ' // to_str(k) // ' (' // &
               to_str(nodes(k - 1)) // ', ' // to_str(nodes(k)) // '); sort it and drop repeats')
            return
         end if
      end do
   end subroutine start_node_weights

   !> weights(i) += w where nodes(i) = node (binary search; node of triangle k).
   subroutine add_node_weight(nodes, node, k, w, weights, error)
      integer(ip), intent(in) :: nodes(:), node, k
      real(dp), intent(in) :: w
      real(dp), intent(inout) :: weights(:)
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: lo, hi, mid, pos
      pos = 0
      lo = 1
      hi = size(nodes, kind=ip)
      do while (lo <= hi)
         mid = lo + (hi - lo)/2
         if (nodes(mid) == node) then
            pos = mid
            exit
         else if (nodes(mid) < node) then
            lo = mid + 1
         else
            hi = mid - 1
         end if
      end do
      if (pos == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'nodal weights: node ' // &
            to_str(node) // ' of triangle ' // to_str(k) // ' is not in the node list; ' // &
            'pass all nodes of the surface (surface_nodes)')
         return
      end if
      weights(pos) = weights(pos) + w
   end subroutine add_node_weight

   !> The sorted, unique node indices of a set of triangles.
   subroutine surface_nodes(tris, nodes)
      !> Triangle node indices (3 or 6, num_tris)
      integer(ip), intent(in) :: tris(:, :)
      !> Their nodes, strictly ascending
      integer(ip), allocatable, intent(out) :: nodes(:)
      integer(ip), allocatable :: list(:)
      integer(ip) :: k, count
      list = reshape(tris, [size(tris)])
      call sort_indices(list)
      count = 0
      do k = 1, size(list, kind=ip)
         if (count > 0) then
            if (list(k) == list(count)) cycle
         end if
         count = count + 1
         list(count) = list(k)
      end do
      nodes = list(1:count)
   end subroutine surface_nodes

end module ffrf_fe_surface
