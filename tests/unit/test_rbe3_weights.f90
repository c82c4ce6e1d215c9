!> RBE3 weights pinned by closed forms (issue 13 item 3): asymmetric flat faces of Tri3 and Tri6
!> (Tet10) triangles of different areas, built through build_interface, whose virtual-node
!> motion q_V = G q_B under a given face displacement is known by hand for uniform, tributary
!> area ('area') and consistent area ('area_consistent') weights; the three answers differ from
!> each other and from those of the squared weights (a fit with w_i^2 fails these tests). The
!> weights themselves against their definitions (theory.md 1.3), and node-set interfaces
!> (WEIGHTING_GIVEN) against surface interfaces with the same nodes and weights.
!>
!> The hand computation (theory.md 1.2): at the weighted centroid of the nodes (sum w_i r_i = 0)
!> the fit decouples: u_V = sum w_i u_i / W and theta_V = J^-1 sum w_i r_i x u_i with
!> W = sum w_i, J = sum w_i (|r_i|^2 I - r_i r_i^T). The rotation of the fit does not depend on
!> the virtual node; moved by d, the translation becomes u_V + theta_V x d. The sums are given
!> beside each case in exact fractions; with w_i^2 instead of w_i the answers would be those in
!> the "squared" comments.
module test_rbe3_weights
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t
   use ffrf_core_strings, only: to_str
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_fe_surface, only: nodal_area_weights, nodal_consistent_weights, surface_area_centroid
   use ffrf_mpc_interface, only: interface_spec_t, interface_t, build_interface, MPC_RBE3, &
      MPC_RBE2, WEIGHTING_UNIFORM, WEIGHTING_AREA, WEIGHTING_AREA_CONSISTENT, WEIGHTING_GIVEN, &
      VIRTUAL_NODE_POSITION, VIRTUAL_NODE_CENTROID
   use ffrf_mpc_rbe3, only: rbe3_matrix
   use ffrf_la_dense, only: skew
   use ffrf_input_interface, only: interface_input_t
   use ffrf_model_specs, only: interface_spec_of
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   implicit none
   private
   public :: collect_rbe3_weights

   !> Round-off bound for O(1) results of 6 x 6 solves on O(1) data (measured <= 1.6e-15; the
   !> suite prints each deviation)
   real(dp), parameter :: tight = 1.0e-14_dp

   !> Face A, Tri3, in z = 0: triangles (1,2,3) area 1, (2,4,3) area 3, (3,4,5) area 2
   real(dp), parameter :: XYZ_A(3, 5) = reshape([0.0_dp, 0.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, &
      0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 2.0_dp, 3.0_dp, 0.0_dp, -1.0_dp, 2.0_dp, 0.0_dp], [3, 5])
   integer(ip), parameter :: TRIS_A(3, 3) = reshape([1, 2, 3, 2, 4, 3, 3, 4, 5], [3, 3])
   !> Its displacement field u_i (one column per node)
   real(dp), parameter :: U_A(3, 5) = reshape([1.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, -1.0_dp, &
      1.0_dp, 2.0_dp, 1.0_dp, 0.0_dp, -1.0_dp, 2.0_dp, 3.0_dp, 1.0_dp, 1.0_dp, -2.0_dp], [3, 5])

   !> Face B, Tri6 (Gmsh order), the corners of face A's first two triangles with straight
   !> edges: (1,2,3 | 5,6,7) area 1 and (2,4,3 | 8,9,6) area 3; mid-side nodes 5..9
   real(dp), parameter :: XYZ_B(3, 9) = reshape([0.0_dp, 0.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, &
      0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 2.0_dp, 3.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
      0.5_dp, 0.0_dp, 0.0_dp, 0.5_dp, 0.0_dp, 2.0_dp, 1.5_dp, 0.0_dp, 1.0_dp, 2.0_dp, 0.0_dp], &
      [3, 9])
   integer(ip), parameter :: TRIS_B(6, 2) = reshape([1, 2, 3, 5, 6, 7, 2, 4, 3, 8, 9, 6], [6, 2])
   real(dp), parameter :: U_B(3, 9) = reshape([1.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, -1.0_dp, &
      1.0_dp, 2.0_dp, 1.0_dp, 0.0_dp, -1.0_dp, 2.0_dp, 3.0_dp, 1.0_dp, 1.0_dp, -2.0_dp, &
      0.0_dp, 2.0_dp, 1.0_dp, -2.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, &
      1.0_dp, 1.0_dp], [3, 9])

contains

   subroutine collect_rbe3_weights(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('tri3_uniform_at_node_mean', test_tri3_uniform_mean), &
         new_unittest('tri3_uniform_at_area_centroid', test_tri3_uniform_centroid), &
         new_unittest('tri3_area', test_tri3_area), &
         new_unittest('tri3_consistent_equals_tributary', test_tri3_consistent), &
         new_unittest('tri6_weights_closed_form', test_tri6_weights), &
         new_unittest('tri6_uniform_at_node_mean', test_tri6_uniform), &
         new_unittest('tri6_area', test_tri6_area), &
         new_unittest('tri6_area_consistent', test_tri6_consistent), &
         new_unittest('curved_tri6_consistent_moments', test_curved_tri6), &
         new_unittest('node_set_equals_surface', test_node_set_equals_surface), &
         new_unittest('node_set_centroid_and_order', test_node_set_centroid), &
         new_unittest('node_set_errors', test_node_set_errors), &
         new_unittest('signed_weights', test_signed_weights), &
         new_unittest('rbe2_node_set', test_rbe2_node_set), &
         new_unittest('weighting_words', test_weighting_words)]
   end subroutine collect_rbe3_weights

   !> A mesh holding one physical surface 'face' made of `tris` (no tetrahedra: build_interface
   !> needs only nodes, triangles and the group).
   function face_mesh(xyz, tris) result(mesh)
      real(dp), intent(in) :: xyz(:, :)
      integer(ip), intent(in) :: tris(:, :)
      type(mesh_t) :: mesh
      integer :: k
      mesh%num_nodes = size(xyz, 2, kind=ip)
      mesh%xyz = xyz
      mesh%node_tags = [(int(k, i8), k=1, size(xyz, 2))]
      mesh%nodes_per_tri = size(tris, 1, kind=ip)
      mesh%tris = tris
      mesh%tri_tags = [(int(k, i8), k=1, size(tris, 2))]
      mesh%tri_entity = [(1_ip, k=1, size(tris, 2))]
      allocate (mesh%groups(1))
      mesh%groups(1)%dim = 2
      mesh%groups(1)%tag = 1
      mesh%groups(1)%name = 'face'
      mesh%groups(1)%entities = [1_ip]
      mesh%file_name = '(test face)'
   end function face_mesh

   !> q_V = G u of the RBE3 interface on 'face' with `weighting`, virtual node at the area
   !> centroid or at `position`; compared with `expected` to `tight`.
   subroutine check_motion(error, what, mesh, u, weighting, expected, position)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: what
      type(mesh_t), intent(in) :: mesh
      real(dp), intent(in) :: u(:, :)
      integer, intent(in) :: weighting
      real(dp), intent(in) :: expected(6)
      real(dp), intent(in), optional :: position(3)
      type(interface_spec_t) :: spec
      type(interface_t) :: face
      spec%name = 'face'
      spec%mpc = MPC_RBE3
      spec%weighting = weighting
      if (present(position)) then
         spec%virtual_node = VIRTUAL_NODE_POSITION
         spec%position = position
      end if
      call build_interface(mesh, spec, face, error)
      if (allocated(error)) return
      call check_vector(error, what // ': q_V', matmul(face%G, reshape(u, [size(u)])), expected, &
         tight)
   end subroutine check_motion

   !> max |actual - expected| <= tol.
   subroutine check_vector(error, what, actual, expected, tol)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: what
      real(dp), intent(in) :: actual(:), expected(:), tol
      call check(error, what // ': size', size(actual) == size(expected))
      if (allocated(error)) return
      call report(what // ': max deviation ' // to_str(maxval(abs(actual - expected)), 3))
      call check_close(error, what // ', max deviation', maxval(abs(actual - expected)), &
         0.0_dp, atol=tol)
   end subroutine check_vector

   !> Face A, w_i = 1, virtual node at the node mean (3/5, 6/5, 0): W = 5, mean u =
   !> (3/5, 3/5, 4/5); J = [34/5 -2/5 0; -2/5 36/5 0; 0 0 14], sum r_i x u_i = (1/5, -38/5, 9/5)
   !> -> theta = (-2/61, -129/122, 9/70).
   subroutine test_tri3_uniform_mean(error)
      type(error_t), allocatable, intent(out) :: error
      call check_motion(error, 'Tri3 face, uniform', face_mesh(XYZ_A, TRIS_A), U_A, &
         WEIGHTING_UNIFORM, [3.0_dp/5.0_dp, 3.0_dp/5.0_dp, 4.0_dp/5.0_dp, -2.0_dp/61.0_dp, &
         -129.0_dp/122.0_dp, 9.0_dp/70.0_dp], position=[0.6_dp, 1.2_dp, 0.0_dp])
   end subroutine test_tri3_uniform_mean

   !> Face A, w_i = 1, virtual node at the default area centroid (8/9, 25/18, 0), d = (13/45,
   !> 17/90, 0) from the node mean: same theta, u_V = (3/5, 3/5, 4/5) + theta x d =
   !> (403/700, 223/350, 1207/1098): the full 6-dof fit, not the plain mean.
   subroutine test_tri3_uniform_centroid(error)
      type(error_t), allocatable, intent(out) :: error
      call check_motion(error, 'Tri3 face, uniform, area centroid', face_mesh(XYZ_A, TRIS_A), &
         U_A, WEIGHTING_UNIFORM, [403.0_dp/700.0_dp, 223.0_dp/350.0_dp, 1207.0_dp/1098.0_dp, &
         -2.0_dp/61.0_dp, -129.0_dp/122.0_dp, 9.0_dp/70.0_dp])
   end subroutine test_tri3_uniform_centroid

   !> Face A, area weights (1/3, 4/3, 2, 5/3, 2/3): a third of each triangle per corner; their
   !> centroid is the area centroid (8/9, 25/18, 0), the default virtual node. W = 6, u_V =
   !> (5/9, 7/9, 17/18); J = [437/54 -34/27 0; -34/27 214/27 0; 0 0 865/54], sum w_i r_i x u_i
   !> = (241/54, -242/27, 94/27) -> theta = (1951/5067, -5420/5067, 188/865).
   !> Squared: (0.6543, 0.8823, 0.9405, 0.5461, -0.9959, 0.3234).
   subroutine test_tri3_area(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_spec_t) :: spec
      type(interface_t) :: face
      spec%name = 'face'
      spec%weighting = WEIGHTING_AREA
      call build_interface(face_mesh(XYZ_A, TRIS_A), spec, face, error)
      if (allocated(error)) return
      call check_vector(error, 'Tri3 tributary weights', face%weights, [1.0_dp/3.0_dp, &
         4.0_dp/3.0_dp, 2.0_dp, 5.0_dp/3.0_dp, 2.0_dp/3.0_dp], tight)
      if (allocated(error)) return
      call check_vector(error, 'area centroid', face%virtual_xyz, [8.0_dp/9.0_dp, &
         25.0_dp/18.0_dp, 0.0_dp], tight)
      if (allocated(error)) return
      call check_motion(error, 'Tri3 face, area', face_mesh(XYZ_A, TRIS_A), U_A, &
         WEIGHTING_AREA, [5.0_dp/9.0_dp, 7.0_dp/9.0_dp, 17.0_dp/18.0_dp, &
         1951.0_dp/5067.0_dp, -5420.0_dp/5067.0_dp, 188.0_dp/865.0_dp])
   end subroutine test_tri3_area

   !> Tri3: int N_a dA = A/3 per corner, the tributary third: both definitions coincide (to
   !> round-off: two quadratures of the same integral), and so do their G.
   subroutine test_tri3_consistent(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_spec_t) :: spec
      type(interface_t) :: tributary, consistent
      real(dp), allocatable :: w_area(:), w_consistent(:)
      type(mesh_t) :: mesh
      mesh = face_mesh(XYZ_A, TRIS_A)
      call nodal_area_weights(XYZ_A, TRIS_A, [1, 2, 3, 4, 5], w_area, error)
      if (allocated(error)) return
      call nodal_consistent_weights(XYZ_A, TRIS_A, [1, 2, 3, 4, 5], w_consistent, error)
      if (allocated(error)) return
      call check_vector(error, 'Tri3 consistent - tributary weights', w_consistent, w_area, &
         4.0_dp * epsilon(1.0_dp))
      if (allocated(error)) return
      spec%name = 'face'
      spec%weighting = WEIGHTING_AREA
      call build_interface(mesh, spec, tributary, error)
      if (allocated(error)) return
      spec%weighting = WEIGHTING_AREA_CONSISTENT
      call build_interface(mesh, spec, consistent, error)
      if (allocated(error)) return
      call check_vector(error, 'Tri3 G consistent - tributary', reshape(consistent%G, &
         [size(consistent%G)]), reshape(tributary%G, [size(tributary%G)]), tight)
      if (allocated(error)) return
      call check_motion(error, 'Tri3 face, area_consistent', mesh, U_A, &
         WEIGHTING_AREA_CONSISTENT, [5.0_dp/9.0_dp, 7.0_dp/9.0_dp, 17.0_dp/18.0_dp, &
         1951.0_dp/5067.0_dp, -5420.0_dp/5067.0_dp, 188.0_dp/865.0_dp])
   end subroutine test_tri3_consistent

   !> Face B (flat, straight-sided Tri6 of areas 1 and 3). Tributary: each of the four equal
   !> sub-triangles (A/4) gives its vertices a third: corners A/12, mid-side nodes A/4.
   !> Consistent: int N_corner dA = A int L(2L - 1) = 0, int N_mid dA = A int 4 L_i L_j = A/3.
   subroutine test_tri6_weights(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: w(:)
      integer(ip), parameter :: nodes(9) = [1, 2, 3, 4, 5, 6, 7, 8, 9]
      call nodal_area_weights(XYZ_B, TRIS_B, nodes, w, error)
      if (allocated(error)) return
      call check_vector(error, 'Tri6 tributary weights', w, [1.0_dp/12.0_dp, 1.0_dp/3.0_dp, &
         1.0_dp/3.0_dp, 0.25_dp, 0.25_dp, 1.0_dp, 0.25_dp, 0.75_dp, 0.75_dp], tight)
      if (allocated(error)) return
      call nodal_consistent_weights(XYZ_B, TRIS_B, nodes, w, error)
      if (allocated(error)) return
      call check_vector(error, 'Tri6 consistent weights', w, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
         1.0_dp/3.0_dp, 4.0_dp/3.0_dp, 1.0_dp/3.0_dp, 1.0_dp, 1.0_dp], tight)
      if (allocated(error)) return
      call check(error, 'flat Tri6 corners get exactly 0', all(w(1:4) == 0.0_dp))
   end subroutine test_tri6_weights

   !> Face B, w_i = 1 at the node mean (1, 17/18, 0): W = 9, u_V = (2/9, 5/9, 7/9); J =
   !> [157/18 -3 0; -3 6 0; 0 0 265/18], sum r_i x u_i = (97/18, -1, 25/18) -> theta =
   !> (44/65, 67/390, 5/53).
   subroutine test_tri6_uniform(error)
      type(error_t), allocatable, intent(out) :: error
      call check_motion(error, 'Tri6 face, uniform', face_mesh(XYZ_B, TRIS_B), U_B, &
         WEIGHTING_UNIFORM, [2.0_dp/9.0_dp, 5.0_dp/9.0_dp, 7.0_dp/9.0_dp, 44.0_dp/65.0_dp, &
         67.0_dp/390.0_dp, 5.0_dp/53.0_dp], position=[1.0_dp, 17.0_dp/18.0_dp, 0.0_dp])
   end subroutine test_tri6_uniform

   !> Face B, tributary weights at their centroid, the area centroid (7/6, 13/12, 0): W = 4,
   !> u_V = (1/4, 11/16, 11/16); J = [26/9 -25/36 0; -25/36 17/9 0; 0 0 43/9], sum w_i r_i x u_i
   !> = (67/48, -5/24, -13/12) -> theta = (2153/4298, 635/8596, -39/172).
   !> Squared: (0.2523, 0.8899, 0.7245, 0.2222, 0.2962, -0.5625).
   subroutine test_tri6_area(error)
      type(error_t), allocatable, intent(out) :: error
      call check_motion(error, 'Tri6 face, area', face_mesh(XYZ_B, TRIS_B), U_B, &
         WEIGHTING_AREA, [0.25_dp, 11.0_dp/16.0_dp, 11.0_dp/16.0_dp, 2153.0_dp/4298.0_dp, &
         635.0_dp/8596.0_dp, -39.0_dp/172.0_dp])
   end subroutine test_tri6_area

   !> Face B, consistent weights: only the mid-side nodes count (corners 0). At the area
   !> centroid (their centroid too): W = 4, u_V = (1/6, 3/4, 1/2); J = [71/36 -11/18 0;
   !> -11/18 11/9 0; 0 0 115/36], sum w_i r_i x u_i = (2/3, 2/3, -35/18) -> theta =
   !> (3/5, 93/110, -14/23). Squared: (0.1994, 0.9623, 0.7095, 0.2143, 0.8774, -0.8215).
   subroutine test_tri6_consistent(error)
      type(error_t), allocatable, intent(out) :: error
      call check_motion(error, 'Tri6 face, area_consistent', face_mesh(XYZ_B, TRIS_B), U_B, &
         WEIGHTING_AREA_CONSISTENT, [1.0_dp/6.0_dp, 0.75_dp, 0.5_dp, 0.6_dp, &
         93.0_dp/110.0_dp, -14.0_dp/23.0_dp])
   end subroutine test_tri6_consistent

   !> A curved Tri6 face (face B with its mid-side nodes moved in its plane, so that the area
   !> element is a quadratic and both quadratures are exact): the consistent weights sum to the
   !> area and their first moment is int x dA (sum N_a = 1 and x = sum N_a x_a), both from
   !> surface_area_centroid; the corners no longer get 0.
   subroutine test_curved_tri6(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: w(:)
      real(dp) :: xyz(3, 9), area, centroid(3)
      xyz = XYZ_B
      xyz(1:2, 5:9) = xyz(1:2, 5:9) + reshape([0.05_dp, 0.1_dp, 0.2_dp, -0.1_dp, -0.15_dp, &
         0.05_dp, 0.1_dp, 0.1_dp, -0.2_dp, 0.15_dp], [2, 5])
      call nodal_consistent_weights(xyz, TRIS_B, [1, 2, 3, 4, 5, 6, 7, 8, 9], w, error)
      if (allocated(error)) return
      call surface_area_centroid(xyz, TRIS_B, area, centroid, error)
      if (allocated(error)) return
      call check_close(error, 'sum of the weights / area', sum(w) / area, 1.0_dp, &
         rtol=1.0e-14_dp)
      if (allocated(error)) return
      call check_vector(error, 'first moment / area - centroid', matmul(xyz, w) / area, &
         centroid, 1.0e-14_dp)
      if (allocated(error)) return
      call check(error, 'curved Tri6 corners get non-zero weights', all(w(1:4) /= 0.0_dp))
   end subroutine test_curved_tri6

   !> A node-set interface listing face B's nodes (shuffled) gives the surface interface's G
   !> exactly for uniform weights and for given weights equal to the tributary area weights, at
   !> the same virtual node.
   subroutine test_node_set_equals_surface(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_spec_t) :: spec
      type(interface_t) :: surface, node_set
      type(mesh_t) :: mesh
      integer(ip), parameter :: order(9) = [7, 2, 9, 1, 4, 8, 3, 6, 5]
      integer :: k
      mesh = face_mesh(XYZ_B, TRIS_B)
      do k = 1, 2
         spec = interface_spec_t()
         spec%name = 'face'
         spec%weighting = merge(WEIGHTING_UNIFORM, WEIGHTING_AREA, k == 1)
         call build_interface(mesh, spec, surface, error)
         if (allocated(error)) return
         spec%name = 'set'
         spec%nodes = order
         spec%virtual_node = VIRTUAL_NODE_POSITION
         spec%position = surface%virtual_xyz
         if (k == 2) then
            spec%weighting = WEIGHTING_GIVEN
            spec%weights = surface%weights(order)
         end if
         call build_interface(mesh, spec, node_set, error)
         if (allocated(error)) return
         call check(error, 'node set sorted as the surface''s nodes', &
            all(node_set%nodes == surface%nodes))
         if (allocated(error)) return
         call check(error, 'node-set G equals the surface''s G (bitwise)', &
            all(node_set%G == surface%G))
         if (allocated(error)) return
      end do
   end subroutine test_node_set_equals_surface

   !> Node set with given weights and no position: the virtual node is the weighted centroid
   !> (face A's corners with the tributary weights: the area centroid (8/9, 25/18, 0)), and
   !> the motion is face A's area-weighted one; weights scaled by 7 change nothing.
   subroutine test_node_set_centroid(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_spec_t) :: spec
      type(interface_t) :: face
      spec%name = 'set'
      spec%nodes = [5, 3, 1, 4, 2]
      spec%weighting = WEIGHTING_GIVEN
      spec%weights = 7.0_dp * [2.0_dp/3.0_dp, 2.0_dp, 1.0_dp/3.0_dp, 5.0_dp/3.0_dp, 4.0_dp/3.0_dp]
      call build_interface(face_mesh(XYZ_A, TRIS_A), spec, face, error)
      if (allocated(error)) return
      call check_vector(error, 'weighted centroid', face%virtual_xyz, [8.0_dp/9.0_dp, &
         25.0_dp/18.0_dp, 0.0_dp], tight)
      if (allocated(error)) return
      call check_vector(error, 'node set, given weights: q_V', matmul(face%G, &
         reshape(U_A, [15])), [5.0_dp/9.0_dp, 7.0_dp/9.0_dp, 17.0_dp/18.0_dp, &
         1951.0_dp/5067.0_dp, -5420.0_dp/5067.0_dp, 188.0_dp/865.0_dp], tight)
   end subroutine test_node_set_centroid

   !> Bad node sets: each refused with a message naming the problem.
   subroutine test_node_set_errors(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(interface_spec_t) :: spec
      real(dp), parameter :: none(0) = [real(dp) ::]
      mesh = face_mesh(XYZ_A, TRIS_A)
      call expect_error(error, mesh, node_set([integer(ip) ::], WEIGHTING_UNIFORM, none), &
         'no nodes; give at least one')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([1, 2, 6], WEIGHTING_UNIFORM, none), &
         'node 3 is 6, outside the body''s nodes 1..5')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([1, 0, 2], WEIGHTING_UNIFORM, none), &
         'node 2 is 0, outside')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([1, 3, 1], WEIGHTING_UNIFORM, none), &
         'node 1 is listed twice (positions 1 and 3)')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([1, 2, 3], WEIGHTING_GIVEN, &
         [1.0_dp, 0.0_dp, 1.0_dp]), 'weight 2 (node 2) is 0')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([1, 2, 3], WEIGHTING_GIVEN, &
         [1.0_dp, 1.0_dp, -2.0_dp]), 'weight 3 (node 3) is -2')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([1, 2, 3], WEIGHTING_GIVEN, [1.0_dp, 1.0_dp]), &
         '2 weights for 3 nodes')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([1, 2, 3], WEIGHTING_GIVEN, none), &
         'WEIGHTING_GIVEN without weights')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([1, 2, 3], WEIGHTING_AREA, none), &
         'area weights need a surface')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([1, 2, 3], WEIGHTING_UNIFORM, &
         [1.0_dp, 1.0_dp, 1.0_dp]), 'weights are given but the weighting is uniform')
      if (allocated(error)) return
      call expect_error(error, mesh, node_set([3], WEIGHTING_UNIFORM, none), &
         'node(s) all sit at the virtual node')
      if (allocated(error)) return
      spec%name = 'face'
      spec%weighting = WEIGHTING_GIVEN
      call expect_error(error, mesh, spec, 'given weights need a node-set interface')
   end subroutine test_node_set_errors

   !> A node-set interface 'set' (weights given when not empty).
   function node_set(nodes, weighting, weights) result(spec)
      integer(ip), intent(in) :: nodes(:)
      integer, intent(in) :: weighting
      real(dp), intent(in) :: weights(:)
      type(interface_spec_t) :: spec
      spec%name = 'set'
      spec%nodes = nodes
      spec%weighting = weighting
      if (size(weights) > 0) spec%weights = weights
   end function node_set

   !> build_interface of `spec` must fail with a message containing `fragment`.
   subroutine expect_error(error, mesh, spec, fragment)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t), intent(in) :: mesh
      type(interface_spec_t), intent(in) :: spec
      character(len=*), intent(in) :: fragment
      type(interface_t) :: face
      type(error_t), allocatable :: got
      call build_interface(mesh, spec, face, got)
      if (.not. allocated(got)) then
         call check(error, 'refused: ' // fragment, .false.)
         return
      end if
      call check(error, 'message "' // got%message // '" contains "' // fragment // '"', &
         index(got%message, fragment) > 0)
   end subroutine expect_error

   !> The rigid fit takes weights of either sign while S^T W S stays definite (consistent
   !> weights of curved Tri6 corners): a rigid motion of face B is still reproduced with a
   !> small negative corner weight; weights whose negative part dominates are refused.
   subroutine test_signed_weights(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: got
      real(dp), allocatable :: G(:, :)
      real(dp) :: q_b(3, 9), expected(6), theta(3), t(3), x_v(3), axis(3)
      logical :: deficient
      integer :: i
      t = [0.3_dp, -0.2_dp, 0.7_dp]
      theta = [0.05_dp, -0.02_dp, 0.04_dp]
      x_v = [1.2_dp, 1.1_dp, 0.3_dp]
      call rbe3_matrix(XYZ_B, [-0.01_dp, 0.02_dp, 0.01_dp, 0.03_dp, 0.3_dp, 1.3_dp, 0.3_dp, &
         1.0_dp, 1.0_dp], x_v, 1.5_dp, G, deficient, axis, error)
      if (allocated(error)) return
      do i = 1, 9
         q_b(:, i) = t + matmul(skew(theta), XYZ_B(:, i))
      end do
      expected(1:3) = t + matmul(skew(theta), x_v)
      expected(4:6) = theta
      call check_vector(error, 'signed weights: rigid motion at the virtual node', &
         matmul(G, reshape(q_b, [27])), expected, tight)
      if (allocated(error)) return
      call rbe3_matrix(XYZ_B, [-1.0_dp, 0.1_dp, 0.1_dp, 0.1_dp, 0.1_dp, 0.1_dp, 0.1_dp, &
         0.1_dp, 0.9_dp], x_v, 1.5_dp, G, deficient, axis, got)
      if (.not. allocated(got)) then
         call check(error, 'a dominant negative weight is refused', .false.)
         return
      end if
      call check(error, 'message: ' // got%message, index(got%message, &
         'negative weights outweigh the positive ones') > 0)
   end subroutine test_signed_weights

   !> RBE2 on a node set: the virtual node at the node mean, G = F^+ (G F = I6).
   subroutine test_rbe2_node_set(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_spec_t) :: spec
      type(interface_t) :: face
      real(dp) :: gf(6, 6)
      integer :: i
      spec = node_set([1, 2, 3, 4], WEIGHTING_UNIFORM, [real(dp) ::])
      spec%mpc = MPC_RBE2
      spec%virtual_node = VIRTUAL_NODE_CENTROID
      call build_interface(face_mesh(XYZ_B, TRIS_B), spec, face, error)
      if (allocated(error)) return
      call check_vector(error, 'RBE2 node set: virtual node at the node mean', &
         face%virtual_xyz, [1.0_dp, 1.0_dp, 0.0_dp], tight)
      if (allocated(error)) return
      gf = matmul(face%G, face%F)
      do i = 1, 6
         gf(i, i) = gf(i, i) - 1.0_dp
      end do
      call check_close(error, 'RBE2 node set: max |G F - I6|', maxval(abs(gf)), 0.0_dp, &
         atol=tight)
   end subroutine test_rbe2_node_set

   !> The model's words (any case): 'area' -> WEIGHTING_AREA, 'area_consistent' ->
   !> WEIGHTING_AREA_CONSISTENT; an unknown word names the three.
   subroutine test_weighting_words(error)
      type(error_t), allocatable, intent(out) :: error
      type(interface_spec_t) :: spec
      call interface_spec_of(interface_input_t(name='face', weighting='Area_Consistent'), spec, &
         error)
      if (allocated(error)) return
      call check(error, 'Area_Consistent -> WEIGHTING_AREA_CONSISTENT', &
         spec%weighting == WEIGHTING_AREA_CONSISTENT)
      if (allocated(error)) return
      call interface_spec_of(interface_input_t(name='face', weighting='area'), spec, error)
      if (allocated(error)) return
      call check(error, 'area -> WEIGHTING_AREA', spec%weighting == WEIGHTING_AREA)
      if (allocated(error)) return
      call interface_spec_of(interface_input_t(name='face', weighting='consistent'), spec, error)
      if (.not. allocated(error)) then
         call check(error, '"consistent" is refused', .false.)
         return
      end if
      if (index(error%message, 'use one of uniform, area, area_consistent') > 0) &
         deallocate (error)
   end subroutine test_weighting_words

end module test_rbe3_weights

program main_rbe3_weights
   use ffrf_mpc_rbe3, only: rbe3_matrix
   use ffrf_la_dense, only: skew
   use ffrf_input_interface, only: interface_input_t
   use ffrf_model_specs, only: interface_spec_of
   use ffrf_testing, only: unittest_t, run_suite
   use test_rbe3_weights, only: collect_rbe3_weights
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_rbe3_weights(tests)
   call run_suite('rbe3_weights', tests)
end program main_rbe3_weights
