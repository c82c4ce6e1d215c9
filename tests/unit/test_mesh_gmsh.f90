!> Gmsh reader and mesh_t. The real gmsh meshes the .geo files of tests/data/mesh as ctest
!> fixtures (tests/unit/mesh.cmake) into $FFRF_MESH_DIR/test_mesh/; the hand-written .msh files
!> are read from $FFRF_TEST_DATA_DIR/mesh/. References: the box volume and face areas in closed
!> form (a straight-sided tetrahedral tiling is exact up to round-off), the same mesh written in
!> three formats, and hand-written files whose content is known entry by entry; the bad meshes of
!> tests/data/mesh/bad (one defect each) for the validation (issue 10).
module test_mesh_gmsh
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mesh_mesh, only: mesh_t, extract_body
   use ffrf_mesh_gmsh, only: read_gmsh
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, test_mesh_dir, report
   implicit none
   private
   public :: collect_mesh_gmsh

   !> Box of box.geo and left_block of two_blocks.geo, metres
   real(dp), parameter :: box_lx = 0.3_dp, box_ly = 0.2_dp, box_lz = 0.1_dp
   !> Sums of ~1000 element volumes or areas, each exact up to a few eps: 1e-12 relative
   real(dp), parameter :: sum_rtol = 1.0e-12_dp
   !> Gmsh prints %.16g (relative rounding <= 5e-16) and the reader rounds correctly (<= 1.1e-16)
   real(dp), parameter :: print_rtol = 1.0e-15_dp

contains

   subroutine collect_mesh_gmsh(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('formats_agree', test_formats_agree), &
         new_unittest('box_volume', test_box_volume), &
         new_unittest('face_areas', test_face_areas), &
         new_unittest('groups_by_name', test_groups_by_name), &
         new_unittest('tet10_node_order', test_tet10_node_order), &
         new_unittest('hand_written_41', test_hand_written_41), &
         new_unittest('hand_written_22', test_hand_written_22), &
         new_unittest('extract_body', test_extract_body), &
         new_unittest('error_missing_file', test_error_missing_file), &
         new_unittest('error_unknown_group', test_error_unknown_group), &
         new_unittest('error_no_tetrahedra', test_error_no_tetrahedra), &
         new_unittest('error_version', test_error_version), &
         new_unittest('error_missing_node', test_error_missing_node), &
         new_unittest('error_mixed_order', test_error_mixed_order), &
         new_unittest('error_truncated_binary', test_error_truncated_binary), &
         new_unittest('crank_lc8_counts', test_crank_lc8_counts), &
         new_unittest('valid_small_meshes', test_valid_small_meshes), &
         new_unittest('bad_meshes', test_bad_meshes), &
         new_unittest('error_not_regular', test_error_not_regular)]
   end subroutine collect_mesh_gmsh

   !> A mesh gmsh built for the tests.
   function built(name) result(path)
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: path
      path = test_mesh_dir() // '/test_mesh/' // name
   end function built

   !> A hand-written file of tests/data/mesh.
   function data_file(name) result(path)
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: path
      character(len=4096) :: dir
      integer :: length, stat
      call get_environment_variable('FFRF_TEST_DATA_DIR', dir, length, stat)
      if (stat /= 0 .or. length == 0) dir = 'tests/data'
      path = trim(dir) // '/mesh/' // name
   end function data_file

   !> Read a mesh that must read without error.
   subroutine read_ok(path, mesh, error)
      character(len=*), intent(in) :: path
      type(mesh_t), intent(out) :: mesh
      type(error_t), allocatable, intent(out) :: error
      call read_gmsh(path, mesh, error)
      if (allocated(error)) error%message = 'unexpected error: ' // error%message
   end subroutine read_ok

   !> Signed volume of the corner tetrahedron of element e: det[x2-x1, x3-x1, x4-x1] / 6.
   pure function tet_volume(mesh, e) result(volume)
      type(mesh_t), intent(in) :: mesh
      integer(ip), intent(in) :: e
      real(dp) :: volume
      real(dp) :: a(3), b(3), c(3)
      a = mesh%xyz(:, mesh%tets(2, e)) - mesh%xyz(:, mesh%tets(1, e))
      b = mesh%xyz(:, mesh%tets(3, e)) - mesh%xyz(:, mesh%tets(1, e))
      c = mesh%xyz(:, mesh%tets(4, e)) - mesh%xyz(:, mesh%tets(1, e))
      volume = (a(1) * (b(2) * c(3) - b(3) * c(2)) - a(2) * (b(1) * c(3) - b(3) * c(1)) + &
         a(3) * (b(1) * c(2) - b(2) * c(1))) / 6.0_dp
   end function tet_volume

   !> Area of the corner triangle of triangle t: |(x2-x1) x (x3-x1)| / 2.
   pure function tri_area(mesh, t) result(area)
      type(mesh_t), intent(in) :: mesh
      integer(ip), intent(in) :: t
      real(dp) :: area
      real(dp) :: a(3), b(3)
      a = mesh%xyz(:, mesh%tris(2, t)) - mesh%xyz(:, mesh%tris(1, t))
      b = mesh%xyz(:, mesh%tris(3, t)) - mesh%xyz(:, mesh%tris(1, t))
      area = 0.5_dp * norm2([a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), &
         a(1) * b(2) - a(2) * b(1)])
   end function tri_area

   !> Sum of tet_volume over all tetrahedra, or over `subset`.
   function total_volume(mesh, subset) result(volume)
      type(mesh_t), intent(in) :: mesh
      integer(ip), intent(in), optional :: subset(:)
      real(dp) :: volume
      integer(ip) :: e
      volume = 0.0_dp
      if (present(subset)) then
         do e = 1, size(subset, kind=ip)
            volume = volume + tet_volume(mesh, subset(e))
         end do
      else
         do e = 1, mesh%num_tets()
            volume = volume + tet_volume(mesh, e)
         end do
      end if
   end function total_volume

   !> Area of the triangles of physical surface `name`.
   subroutine group_area(mesh, name, area, error)
      type(mesh_t), intent(in) :: mesh
      character(len=*), intent(in) :: name
      real(dp), intent(out) :: area
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: triangles(:)
      integer(ip) :: t
      area = 0.0_dp
      call mesh%group_triangles(name, triangles, error)
      if (allocated(error)) return
      do t = 1, size(triangles, kind=ip)
         area = area + tri_area(mesh, triangles(t))
      end do
   end subroutine group_area

   !> Error unless `error` exists with `code` and its message holds every one of `parts`.
   subroutine check_message(error, code, parts, result)
      type(error_t), allocatable, intent(in) :: error
      integer, intent(in) :: code
      character(len=*), intent(in) :: parts(:)
      type(error_t), allocatable, intent(out) :: result
      integer :: i
      if (.not. allocated(error)) then
         call fatal_error(result, FFRF_NUMERIC_ERROR, 'no error raised')
         return
      end if
      call report('message: ' // error%message)
      if (error%code /= code) then
         call fatal_error(result, FFRF_NUMERIC_ERROR, 'code ' // to_str(error%code) // &
            ', expected ' // to_str(code) // ': ' // error%message)
         return
      end if
      do i = 1, size(parts)
         if (index(error%message, trim(parts(i))) == 0) then
            call fatal_error(result, FFRF_NUMERIC_ERROR, 'message lacks "' // trim(parts(i)) // &
               '": ' // error%message)
            return
         end if
      end do
   end subroutine check_message

   !> The same gmsh mesh (box.geo, -order 2) written as MSH 4.1 ASCII, MSH 4.1 binary and MSH 2.2
   !> reads to the same nodes, tags, tetrahedra, triangles and entities (exactly), and to the same
   !> coordinates within print_rtol (ASCII holds 16 significant digits; binary is exact). MSH 2.2
   !> writes the triangles of "left" and "right" twice (they are in "x_faces" too): kept once.
   subroutine test_formats_agree(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: ascii, binary, msh22
      real(dp) :: worst_binary, worst_22
      call read_ok(built('box_o2_41.msh'), ascii, error)
      if (.not. allocated(error)) call read_ok(built('box_o2_41b.msh'), binary, error)
      if (.not. allocated(error)) call read_ok(built('box_o2_22.msh'), msh22, error)
      if (allocated(error)) return
      call check(error, 'Tet10 in MSH 4.1 ASCII', ascii%nodes_per_tet == 10 .and. &
         ascii%nodes_per_tri == 6 .and. ascii%num_tets() > 100)
      if (allocated(error)) return
      call same_mesh(ascii, binary, 'MSH 4.1 binary', worst_binary, error)
      if (allocated(error)) return
      call same_mesh(ascii, msh22, 'MSH 2.2', worst_22, error)
      if (allocated(error)) return
      call report(to_str(ascii%num_nodes) // ' nodes, ' // to_str(ascii%num_tets()) // &
         ' Tet10; largest relative coordinate difference to ASCII 4.1: binary ' // &
         to_str(worst_binary, 3) // ', MSH 2.2 ' // to_str(worst_22, 3))
   end subroutine test_formats_agree

   !> Integer content and physical groups equal, coordinates within print_rtol relative (each
   !> coordinate).
   subroutine same_mesh(reference, other, what, worst, error)
      type(mesh_t), intent(in) :: reference, other
      character(len=*), intent(in) :: what
      real(dp), intent(out) :: worst
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: i, j
      worst = 0.0_dp
      call check(error, what // ': node count ' // to_str(other%num_nodes) // ' vs ' // &
         to_str(reference%num_nodes), other%num_nodes == reference%num_nodes)
      if (allocated(error)) return
      call check(error, what // ': node tags', all(other%node_tags == reference%node_tags))
      if (allocated(error)) return
      call check(error, what // ': element shapes', &
         other%nodes_per_tet == reference%nodes_per_tet .and. &
         other%nodes_per_tri == reference%nodes_per_tri .and. &
         other%num_tets() == reference%num_tets() .and. other%num_tris() == reference%num_tris())
      if (allocated(error)) return
      call check(error, what // ': tetrahedra', all(other%tets == reference%tets) .and. &
         all(other%tet_entity == reference%tet_entity))
      if (allocated(error)) return
      call check(error, what // ': triangles', all(other%tris == reference%tris) .and. &
         all(other%tri_entity == reference%tri_entity))
      if (allocated(error)) return
      call check(error, what // ': number of physical groups', &
         size(other%groups) == size(reference%groups))
      if (allocated(error)) return
      do i = 1, size(reference%groups, kind=ip)
         call check(error, what // ': physical group ' // reference%groups(i)%name, &
            other%groups(i)%dim == reference%groups(i)%dim .and. &
            other%groups(i)%tag == reference%groups(i)%tag .and. &
            other%groups(i)%name == reference%groups(i)%name .and. &
            size(other%groups(i)%entities) == size(reference%groups(i)%entities))
         if (allocated(error)) return
         call check(error, what // ': entities of ' // reference%groups(i)%name, &
            all(other%groups(i)%entities == reference%groups(i)%entities))
         if (allocated(error)) return
      end do
      do i = 1, reference%num_nodes
         do j = 1, 3
            if (reference%xyz(j, i) /= 0.0_dp) then
               worst = max(worst, abs(other%xyz(j, i) - reference%xyz(j, i)) / &
                  abs(reference%xyz(j, i)))
            else if (other%xyz(j, i) /= 0.0_dp) then
               worst = huge(1.0_dp)
            end if
         end do
      end do
      call check_close(error, what // ': largest relative coordinate difference', worst, &
         0.0_dp, atol=print_rtol)
   end subroutine same_mesh

   !> The tetrahedra tile the box: sum of det/6 = 0.3*0.2*0.1 m^3 within sum_rtol, for Tet4 and
   !> Tet10 (straight edges; the corner tetrahedra of a Tet10 mesh tile it too), every
   !> tetrahedron positively oriented (Gmsh's convention the FE code relies on).
   subroutine test_box_volume(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: files(2) = [character(len=16) :: 'box_o1_41.msh', &
         'box_o2_41b.msh']
      type(mesh_t) :: mesh
      real(dp) :: smallest
      integer(ip) :: f, e
      do f = 1, size(files, kind=ip)
         call read_ok(built(trim(files(f))), mesh, error)
         if (allocated(error)) return
         call check(error, trim(files(f)) // ': Tet' // to_str(mesh%nodes_per_tet), &
            mesh%nodes_per_tet == merge(4, 10, f == 1))
         if (allocated(error)) return
         call check_close(error, trim(files(f)) // ': volume', total_volume(mesh), &
            box_lx * box_ly * box_lz, rtol=sum_rtol)
         if (allocated(error)) return
         smallest = huge(1.0_dp)
         do e = 1, mesh%num_tets()
            smallest = min(smallest, tet_volume(mesh, e))
         end do
         call check(error, trim(files(f)) // ': a tetrahedron of volume ' // &
            to_str(smallest) // ' <= 0', smallest > 0.0_dp)
         if (allocated(error)) return
         call report(mesh%summary() // ', volume error ' // &
            to_str(total_volume(mesh) / (box_lx * box_ly * box_lz) - 1.0_dp, 3))
      end do
   end subroutine test_box_volume

   !> Physical surfaces "left" (x = 0) and "right" (x = 0.3) have area 0.2*0.1 m^2 within
   !> sum_rtol, and all their nodes (edge nodes of Tri6 included) lie on their plane to
   !> 1e-15 m (OCC places face nodes on the plane up to round-off of the box coordinates);
   !> "x_faces" (both faces) has twice that area, its triangles counted once.
   subroutine test_face_areas(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: files(2) = [character(len=16) :: 'box_o1_41.msh', &
         'box_o2_22.msh']
      character(len=*), parameter :: names(2) = [character(len=5) :: 'left', 'right']
      real(dp), parameter :: plane_x(2) = [0.0_dp, box_lx]
      type(mesh_t) :: mesh
      integer(ip), allocatable :: nodes(:)
      real(dp) :: area
      integer(ip) :: f, s
      do f = 1, size(files, kind=ip)
         call read_ok(built(trim(files(f))), mesh, error)
         if (allocated(error)) return
         do s = 1, 2
            call group_area(mesh, trim(names(s)), area, error)
            if (allocated(error)) return
            call check_close(error, trim(files(f)) // ': area of ' // trim(names(s)), area, &
               box_ly * box_lz, rtol=sum_rtol)
            if (allocated(error)) return
            call mesh%group_nodes(2_ip, trim(names(s)), nodes, error)
            if (allocated(error)) return
            call check(error, trim(files(f)) // ': nodes of ' // trim(names(s)) // &
               ' sorted, unique', size(nodes) > 3 .and. all(nodes(2:) > nodes(:size(nodes) - 1)))
            if (allocated(error)) return
            call check_close(error, trim(files(f)) // ': largest |x - plane| of ' // &
               trim(names(s)), maxval(abs(mesh%xyz(1, nodes) - plane_x(s))), 0.0_dp, &
               atol=1.0e-15_dp)
            if (allocated(error)) return
         end do
         call group_area(mesh, 'x_faces', area, error)
         if (allocated(error)) return
         call check_close(error, trim(files(f)) // ': area of x_faces', area, &
            2.0_dp * box_ly * box_lz, rtol=sum_rtol)
         if (allocated(error)) return
      end do
   end subroutine test_face_areas

   !> Groups are found by exact name and dimension; the listing for messages is right.
   subroutine test_groups_by_name(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      integer(ip), allocatable :: tets(:), nodes(:)
      integer(ip) :: k
      call read_ok(built('box_o2_41.msh'), mesh, error)
      if (allocated(error)) return
      call check(error, 'find_group: block/left/right (also blank-padded) found; wrong ' // &
         'dim, case or leading blank not', &
         mesh%find_group(3_ip, 'block') > 0 .and. mesh%find_group(2_ip, 'left') > 0 .and. &
         mesh%find_group(2_ip, 'right') > 0 .and. mesh%find_group(3_ip, 'left') == 0 .and. &
         mesh%find_group(2_ip, 'Left') == 0 .and. mesh%find_group(2_ip, ' left') == 0 .and. &
         mesh%find_group(2_ip, 'left    ') == mesh%find_group(2_ip, 'left'))
      if (allocated(error)) return
      call check(error, 'group_names(2) = "' // mesh%group_names(2_ip) // '"', &
         mesh%group_names(2_ip) == 'left, right, x_faces' .and. &
         mesh%group_names(3_ip) == 'block' .and. mesh%group_names(1_ip) == 'x_edge')
      if (allocated(error)) return
      call mesh%group_tets('block', tets, error)
      if (allocated(error)) return
      call check(error, 'group_tets(block) = all tetrahedra', size(tets) == mesh%num_tets() &
         .and. all(tets == [(k, k=1, mesh%num_tets())]))
      if (allocated(error)) return
      ! In this mesh every node belongs to a tetrahedron of "block".
      call mesh%group_nodes(3_ip, 'block', nodes, error)
      if (allocated(error)) return
      call check(error, 'group_nodes(3, block) = all nodes', size(nodes) == mesh%num_nodes)
   end subroutine test_groups_by_name

   !> The node order documented in ffrf_mesh_gmsh: on the straight edges of the box every Tet10
   !> edge node k = 5..10 is the midpoint of corners (1,2), (2,3), (1,3), (1,4), (3,4), (2,4) and
   !> every Tri6 edge node 4..6 that of (1,2), (2,3), (1,3). Gmsh computes midpoints from the
   !> corner coordinates (or the flat face's parametrisation): 1e-15 m on a 0.3 m box.
   subroutine test_tet10_node_order(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), parameter :: tet_edges(2, 6) = reshape([1, 2, 2, 3, 1, 3, 1, 4, 3, 4, 2, 4], &
         [2, 6])
      integer(ip), parameter :: tri_edges(2, 3) = reshape([1, 2, 2, 3, 1, 3], [2, 3])
      type(mesh_t) :: mesh
      real(dp) :: worst_tet, worst_tri
      integer(ip) :: e, k
      call read_ok(built('box_o2_41b.msh'), mesh, error)
      if (allocated(error)) return
      worst_tet = 0.0_dp
      do e = 1, mesh%num_tets()
         do k = 1, 6
            worst_tet = max(worst_tet, maxval(abs(mesh%xyz(:, mesh%tets(4 + k, e)) - 0.5_dp * &
               (mesh%xyz(:, mesh%tets(tet_edges(1, k), e)) + &
               mesh%xyz(:, mesh%tets(tet_edges(2, k), e))))))
         end do
      end do
      worst_tri = 0.0_dp
      do e = 1, mesh%num_tris()
         do k = 1, 3
            worst_tri = max(worst_tri, maxval(abs(mesh%xyz(:, mesh%tris(3 + k, e)) - 0.5_dp * &
               (mesh%xyz(:, mesh%tris(tri_edges(1, k), e)) + &
               mesh%xyz(:, mesh%tris(tri_edges(2, k), e))))))
         end do
      end do
      call report('largest edge-node distance to its edge midpoint: Tet10 ' // &
         to_str(worst_tet, 3) // ' m, Tri6 ' // to_str(worst_tri, 3) // ' m')
      call check_close(error, 'Tet10 edge node off its edge midpoint (m)', worst_tet, 0.0_dp, &
         atol=1.0e-15_dp)
      if (allocated(error)) return
      call check_close(error, 'Tri6 edge node off its edge midpoint (m)', worst_tri, 0.0_dp, &
         atol=1.0e-15_dp)
   end subroutine test_tet10_node_order

   !> tests/data/mesh/gaps41.msh, known entry by entry: tags 10, 500, 20, 35, 7, 1000000 (sparse
   !> and unsorted: the binary-search map), a parametric node, skipped point/line elements and
   !> $NodeData; tetrahedra of volumes 1/6 and 1/3 (exact in binary floating point up to one
   !> rounding: 1e-15 relative).
   subroutine test_hand_written_41(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      integer(ip), allocatable :: indices(:)
      integer(ip) :: k
      call read_ok(data_file('gaps41.msh'), mesh, error)
      if (allocated(error)) return
      call check(error, 'node tags in file order', mesh%num_nodes == 6 .and. &
         all(mesh%node_tags == [10_i8, 500_i8, 20_i8, 35_i8, 7_i8, 1000000_i8]))
      if (allocated(error)) return
      call check(error, 'coordinates of tags 500 (parametric) and 1000000', &
         all(mesh%xyz(:, 2) == [0.5_dp, 0.0_dp, 0.0_dp]) .and. &
         all(mesh%xyz(:, 6) == [1.0_dp, 1.0_dp, 1.0_dp]))
      if (allocated(error)) return
      call check(error, 'two Tet4 by tag', mesh%nodes_per_tet == 4 .and. mesh%num_tets() == 2 &
         .and. all(mesh%node_tags(mesh%tets(:, 1)) == [10_i8, 20_i8, 35_i8, 7_i8]) .and. &
         all(mesh%node_tags(mesh%tets(:, 2)) == [20_i8, 35_i8, 7_i8, 1000000_i8]) .and. &
         all(mesh%tet_entity == [1, 2]) .and. all(mesh%tet_tags == [4_i8, 5_i8]))
      if (allocated(error)) return
      call check(error, 'one Tri3 (point and line skipped)', mesh%num_tris() == 1 .and. &
         mesh%nodes_per_tri == 3 .and. all(mesh%node_tags(mesh%tris(:, 1)) == &
         [10_i8, 20_i8, 35_i8]) .and. mesh%tri_tags(1) == 3_i8)
      if (allocated(error)) return
      call check_close(error, 'volume of tet 1', tet_volume(mesh, 1_ip), 1.0_dp / 6.0_dp, &
         rtol=1.0e-15_dp)
      if (.not. allocated(error)) call check_close(error, 'volume of tet 2', &
         tet_volume(mesh, 2_ip), 1.0_dp / 3.0_dp, rtol=1.0e-15_dp)
      if (allocated(error)) return
      call check(error, 'groups (dim, tag, name) sorted', size(mesh%groups) == 5 .and. &
         all(mesh%groups%dim == [1, 2, 2, 3, 3]) .and. all(mesh%groups%tag == [5, 3, 4, 1, 2]))
      if (allocated(error)) return
      k = mesh%find_group(3_ip, 'second')
      call check(error, 'group "second" holds entity 2', k == 5)
      if (allocated(error)) return
      call check(error, 'entities of "second"', all(mesh%groups(k)%entities == [2]) .and. &
         mesh%groups(1)%name == 'edge')
      if (allocated(error)) return
      call mesh%group_tets('second', indices, error)
      if (allocated(error)) return
      call check(error, 'group_tets(second) = [2]', all(indices == [2]) .and. size(indices) == 1)
      if (allocated(error)) return
      call mesh%group_nodes(3_ip, 'first', indices, error)
      if (allocated(error)) return
      call check(error, 'group_nodes(3, first) = [1, 3, 4, 5]', size(indices) == 4 .and. &
         all(indices == [1, 3, 4, 5]))
      if (allocated(error)) return
      call mesh%group_triangles('faces', indices, error)
      if (allocated(error)) return
      call check(error, 'group_triangles(faces) = [1]', size(indices) == 1)
   end subroutine test_hand_written_41

   !> tests/data/mesh/gaps22.msh: MSH 2.2 with gaps in dense tags (direct map), groups from the
   !> element tags, and a triangle written twice (two physical surfaces) kept once.
   subroutine test_hand_written_22(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      integer(ip), allocatable :: indices(:)
      integer(ip) :: k
      call read_ok(data_file('gaps22.msh'), mesh, error)
      if (allocated(error)) return
      call check(error, 'node tags', mesh%num_nodes == 5 .and. &
         all(mesh%node_tags == [10_i8, 20_i8, 35_i8, 7_i8, 64_i8]))
      if (allocated(error)) return
      call check(error, 'two Tet4 by tag', mesh%num_tets() == 2 .and. &
         all(mesh%node_tags(mesh%tets(:, 1)) == [10_i8, 20_i8, 35_i8, 7_i8]) .and. &
         all(mesh%node_tags(mesh%tets(:, 2)) == [20_i8, 35_i8, 7_i8, 64_i8]) .and. &
         all(mesh%tet_entity == [1, 2]))
      if (allocated(error)) return
      call check(error, 'the repeated triangle once, first copy kept', mesh%num_tris() == 1 &
         .and. mesh%tri_tags(1) == 2_i8 .and. mesh%tri_entity(1) == 1)
      if (allocated(error)) return
      call check_close(error, 'volume', total_volume(mesh), 0.5_dp, rtol=1.0e-15_dp)
      if (allocated(error)) return
      k = mesh%find_group(3_ip, 'first')
      call check(error, 'group "first" = entities [1, 2]', k > 0)
      if (allocated(error)) return
      call check(error, 'entities of "first"', all(mesh%groups(k)%entities == [1, 2]) .and. &
         size(mesh%groups) == 3)
      if (allocated(error)) return
      call mesh%group_triangles('bottom', indices, error)
      if (allocated(error)) return
      call check(error, 'bottom = [1]', size(indices) == 1)
      if (allocated(error)) return
      call mesh%group_triangles('faces', indices, error)
      if (allocated(error)) return
      call check(error, 'faces = [1]', size(indices) == 1)
   end subroutine test_hand_written_22

   !> two_blocks.geo: extract_body keeps the tetrahedra of the named volumes (volumes 6e-3 and
   !> 4e-3 m^3 within sum_rtol), their nodes in increasing old order with their tags and
   !> coordinates (exactly), and the triangles inside the body: "left" and "interface" (0.02 m^2
   !> each) for left_block, not "right".
   subroutine test_extract_body(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh, body
      integer(ip), allocatable :: tets(:), nodes(:), triangles(:)
      real(dp) :: area
      integer(ip) :: e, num_left, num_interface
      call read_ok(built('two_blocks_o2_41.msh'), mesh, error)
      if (allocated(error)) return
      call mesh%group_tets('left_block', tets, error)
      if (.not. allocated(error)) call mesh%group_nodes(3_ip, 'left_block', nodes, error)
      if (allocated(error)) return
      call extract_body(mesh, ['left_block'], body, error)
      if (allocated(error)) return
      call check(error, 'sizes', body%num_tets() == size(tets) .and. body%num_nodes == &
         size(nodes) .and. body%num_nodes < mesh%num_nodes .and. body%nodes_per_tet == 10)
      if (allocated(error)) return
      call check(error, 'node tags kept in increasing old order', &
         all(body%node_tags == mesh%node_tags(nodes)))
      if (allocated(error)) return
      do e = 1, body%num_tets()
         if (any(body%xyz(:, body%tets(:, e)) /= mesh%xyz(:, mesh%tets(:, tets(e))))) then
            call check(error, 'tetrahedron ' // to_str(e) // ' renumbered wrongly', .false.)
            return
         end if
      end do
      call check_close(error, 'left_block volume', total_volume(body), &
         box_lx * box_ly * box_lz, rtol=sum_rtol)
      if (allocated(error)) return
      call mesh%group_triangles('left', triangles, error)
      if (allocated(error)) return
      num_left = size(triangles, kind=ip)
      call mesh%group_triangles('interface', triangles, error)
      if (allocated(error)) return
      num_interface = size(triangles, kind=ip)
      call check(error, 'body triangles = left + interface', &
         body%num_tris() == num_left + num_interface)
      if (allocated(error)) return
      call group_area(body, 'interface', area, error)
      if (allocated(error)) return
      call check_close(error, 'interface area in body', area, box_ly * box_lz, rtol=sum_rtol)
      if (allocated(error)) return
      ! "right" is not on left_block: an error naming the file and the body's volume
      block
         type(error_t), allocatable :: raised
         call body%group_triangles('right', triangles, raised)
         call check_message(raised, FFRF_INPUT_ERROR, [character(len=60) :: &
            'two_blocks_o2_41.msh', 'physical surface ''right'' has no triangles in the body', &
            '''left_block'''], error)
         if (allocated(error)) return
      end block

      call extract_body(mesh, ['right_block'], body, error)
      if (allocated(error)) return
      call check_close(error, 'right_block volume', total_volume(body), &
         0.2_dp * box_ly * box_lz, rtol=sum_rtol)
      if (allocated(error)) return
      call extract_body(mesh, [character(len=11) :: 'right_block', 'left_block'], body, error)
      if (allocated(error)) return
      call check(error, 'both blocks = the whole mesh', body%num_tets() == mesh%num_tets() &
         .and. body%num_tris() == mesh%num_tris() .and. all(body%tets == mesh%tets))
   end subroutine test_extract_body

   !> A missing file: FFRF_IO_ERROR naming the file.
   subroutine test_error_missing_file(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(error_t), allocatable :: raised
      call read_gmsh(built('no_such_mesh.msh'), mesh, raised)
      call check_message(raised, FFRF_IO_ERROR, ['no_such_mesh.msh'], error)
   end subroutine test_error_missing_file

   !> An unknown volume in extract_body (and in group_tets) names it, the file and the volumes.
   subroutine test_error_unknown_group(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh, body
      type(error_t), allocatable :: raised
      integer(ip), allocatable :: tets(:)
      call read_ok(built('two_blocks_o2_41.msh'), mesh, error)
      if (allocated(error)) return
      call extract_body(mesh, [character(len=10) :: 'left_block', 'rihgt_blok'], body, raised)
      call check_message(raised, FFRF_INPUT_ERROR, [character(len=50) :: &
         'two_blocks_o2_41.msh', 'no physical volume ''rihgt_blok''', &
         'volumes: left_block, right_block'], error)
      if (allocated(error)) return
      call mesh%group_tets('left', tets, raised)
      call check_message(raised, FFRF_INPUT_ERROR, [character(len=50) :: &
         'no physical volume ''left''', 'volumes: left_block, right_block'], error)
   end subroutine test_error_unknown_group

   !> surface_only.geo has a physical surface and no Physical Volume: gmsh -3 saves no
   !> tetrahedra (toolchain pitfall 13) and the reader says so.
   subroutine test_error_no_tetrahedra(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(error_t), allocatable :: raised
      call read_gmsh(built('surface_only_41.msh'), mesh, raised)
      call check_message(raised, FFRF_INPUT_ERROR, [character(len=30) :: &
         'surface_only_41.msh', 'no tetrahedra', 'pitfall 13', 'Physical Volume'], error)
   end subroutine test_error_no_tetrahedra

   !> MSH 3.0 is refused, naming the version.
   subroutine test_error_version(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(error_t), allocatable :: raised
      call read_gmsh(data_file('version30.msh'), mesh, raised)
      call check_message(raised, FFRF_INPUT_ERROR, [character(len=30) :: 'version30.msh', &
         'MSH version 3.0', 'line 2'], error)
   end subroutine test_error_version

   !> An element naming an absent node tag: the element, the tag and the line.
   subroutine test_error_missing_node(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(error_t), allocatable :: raised
      call read_gmsh(data_file('bad_node.msh'), mesh, raised)
      call check_message(raised, FFRF_INPUT_ERROR, [character(len=30) :: 'bad_node.msh', &
         '$Elements, line 19', 'refers to node 99'], error)
   end subroutine test_error_missing_node

   !> Tet4 and Tet10 in one file are refused.
   subroutine test_error_mixed_order(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(error_t), allocatable :: raised
      call read_gmsh(data_file('mixed_order.msh'), mesh, raised)
      call check_message(raised, FFRF_INPUT_ERROR, [character(len=30) :: 'mixed_order.msh', &
         'mixes Tet4 and Tet10'], error)
   end subroutine test_error_mixed_order

   !> The binary box mesh cut after 60 % of its bytes: an error saying where (byte offset) and
   !> that the file looks truncated, not a crash or garbage.
   subroutine test_error_truncated_binary(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: bytes, cut_name
      character(len=256) :: message
      type(mesh_t) :: mesh
      type(error_t), allocatable :: raised
      integer(i8) :: file_size
      integer :: unit, stat
      open (newunit=unit, file=built('box_o2_41b.msh'), access='stream', form='unformatted', &
         status='old', action='read', iostat=stat, iomsg=message)
      if (stat == 0) then
         inquire (unit=unit, size=file_size)
         allocate (character(len=file_size * 6 / 10) :: bytes)
         read (unit, iostat=stat, iomsg=message) bytes
         close (unit)
      end if
      cut_name = built('truncated_b.msh')
      if (stat == 0) open (newunit=unit, file=cut_name, access='stream', form='unformatted', &
         status='replace', action='write', iostat=stat, iomsg=message)
      if (stat == 0) then
         write (unit, iostat=stat, iomsg=message) bytes
         close (unit)
      end if
      if (stat /= 0) then
         call fatal_error(error, FFRF_IO_ERROR, 'cannot make the truncated copy: ' // &
            trim(message))
         return
      end if
      call read_gmsh(cut_name, mesh, raised)
      call check_message(raised, FFRF_INPUT_ERROR, [character(len=30) :: 'truncated_b.msh', &
         ', byte ', 'truncated'], error)
   end subroutine test_error_truncated_binary

   !> crank_lc8 (input/crank.geo, lc 8 mm, Tet10, gmsh 4.8.4) still reads and passes every body
   !> check with the counts it had before the checks: 8498 nodes (input/CMakeLists.txt), 4678
   !> Tet10 and 412 Tri6 (read on main before this change); the body "crank" keeps all of them
   !> and each interface surface B1, B2, B3 has triangles.
   subroutine test_crank_lc8_counts(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh, body
      integer(ip), allocatable :: triangles(:)
      integer :: k
      character(len=2), parameter :: surfaces(3) = ['B1', 'B2', 'B3']
      call read_ok(test_mesh_dir() // '/crank_lc8.msh', mesh, error)
      if (allocated(error)) return
      call check(error, 'crank_lc8: ' // mesh%summary(), mesh%num_nodes == 8498 .and. &
         mesh%num_tets() == 4678 .and. mesh%num_tris() == 412 .and. mesh%nodes_per_tet == 10)
      if (allocated(error)) return
      call extract_body(mesh, ['crank'], body, error)
      if (allocated(error)) return
      call check(error, 'body crank: ' // body%summary(), body%num_nodes == 8498 .and. &
         body%num_tets() == 4678 .and. body%num_tris() == 412)
      if (allocated(error)) return
      do k = 1, size(surfaces)
         call body%group_triangles(surfaces(k), triangles, error)
         if (allocated(error)) return
         call check(error, surfaces(k) // ' has triangles', size(triangles) > 0)
         if (allocated(error)) return
      end do
   end subroutine test_crank_lc8_counts

   !> The valid two-tetrahedron block of tests/data/mesh/bad/make_bad_meshes.py in MSH 4.1 ASCII,
   !> 4.1 binary and 2.2 reads and passes the body checks (5 nodes, 2 Tet4, the triangle "face");
   !> so does its Tet10 version (14 nodes, the Tri6 on the Tet10 face).
   subroutine test_valid_small_meshes(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: files(3) = [character(len=20) :: 'valid_base.msh', &
         'valid_base_bin.msh', 'valid_base_22.msh']
      type(mesh_t) :: mesh, body
      integer(ip), allocatable :: triangles(:)
      integer :: k
      do k = 1, size(files)
         call read_ok(data_file('bad/' // trim(files(k))), mesh, error)
         if (allocated(error)) return
         call extract_body(mesh, ['block'], body, error)
         if (.not. allocated(error)) call body%group_triangles('face', triangles, error)
         if (allocated(error)) return
         call check(error, trim(files(k)) // ': ' // body%summary(), body%num_nodes == 5 .and. &
            body%num_tets() == 2 .and. size(triangles) == 1)
         if (allocated(error)) return
      end do
      call read_ok(data_file('bad/tet10_ok.msh'), mesh, error)
      if (allocated(error)) return
      call extract_body(mesh, ['block'], body, error)
      if (allocated(error)) return
      call check(error, 'tet10_ok.msh: ' // body%summary(), body%num_nodes == 14 .and. &
         body%nodes_per_tet == 10 .and. body%num_tris() == 1)
   end subroutine test_valid_small_meshes

   !> Each bad mesh of tests/data/mesh/bad (one defect each, see make_bad_meshes.py) read and cut
   !> into the body "block" gives FFRF_INPUT_ERROR naming the file and the entity; run in the
   !> checked build too (bounds of the new checks). The driver cases are in
   !> tests/regression/mesh_errors.cmake.
   subroutine test_bad_meshes(error)
      type(error_t), allocatable, intent(out) :: error
      integer, parameter :: num_cases = 24
      character(len=28) :: files(num_cases)
      character(len=60) :: parts(num_cases), expected(2)
      type(mesh_t) :: mesh, body
      type(error_t), allocatable :: raised
      integer(ip), allocatable :: triangles(:)
      integer :: k
      files = [character(len=28) :: 'hex_in_body.msh', 'prism_in_body_22.msh', &
         'pyramid_in_body_bin.msh', 'unknown_type.msh', 'type_dimension.msh', &
         'node_tag_zero.msh', 'node_tag_zero_22.msh', 'element_count.msh', 'node_range.msh', &
         'node_count_22.msh', 'huge_nodes.msh', 'huge_block.msh', 'missing_coordinate.msh', &
         'nan_coordinate.msh', 'nan_coordinate_bin.msh', 'duplicate_names.msh', &
         'surface_outside.msh', 'duplicate_tet.msh', 'tet10_crack.msh', 'tet10_crack_22.msh', &
         'two_pieces.msh', 'not_a_face.msh', 'tet10_midside_corner.msh', &
         'tet10_midside_two_edges.msh']
      parts = [character(len=60) :: '1 Hex8 (Gmsh type 5, first element 4', &
         '1 Prism6 (Gmsh type 6', '1 Pyramid5 (Gmsh type 7', 'has element type 200', &
         'holds Tet4 elements, which have dimension 3', 'node tag 0 is not allowed', &
         'node tag 0 is not allowed', 'hold 3 elements, the header announced 4', &
         'header gives node tags 1..6', '$Nodes announces 6 nodes', &
         'number of nodes = 2000000000 cannot be right', &
         'elements in block = 2000000000 cannot be right', &
         'node 3: the line holds 2 of the node''s 3 coordinates', &
         'node 4 has the coordinate ''nan''', 'node 4 has a non-finite coordinate', &
         'two physical volumes are named ''block''', &
         'physical surface ''far'' has no triangles in the body', &
         'tetrahedra 2 and 4', 'edge (2, 3) has two mid-side nodes', &
         'edge (2, 3) has two mid-side nodes', 'is in 2 pieces', &
         'triangle 1 of physical surface ''face'' (surface entity 1', &
         'node 5 is a mid-side node of tetrahedron 2 and a corner', &
         'node 6 is the mid-side node of edge (3, 5) of tetrahedron 3']
      do k = 1, num_cases
         call read_gmsh(data_file('bad/' // trim(files(k))), mesh, raised)
         if (.not. allocated(raised)) call extract_body(mesh, ['block'], body, raised)
         if (.not. allocated(raised)) then
            if (files(k) == 'surface_outside.msh') then
               call body%group_triangles('far', triangles, raised)
            else
               call body%group_triangles('face', triangles, raised)
            end if
         end if
         expected(1) = files(k)
         expected(2) = parts(k)
         call check_message(raised, FFRF_INPUT_ERROR, expected, error)
         if (allocated(error)) then
            error%message = trim(files(k)) // ': ' // error%message
            return
         end if
         if (index(raised%message, achar(10)) > 0) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, trim(files(k)) // ': two lines')
            return
         end if
      end do
   end subroutine test_bad_meshes

   !> A folder as mesh file: FFRF_IO_ERROR before anything is read.
   subroutine test_error_not_regular(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(error_t), allocatable :: raised
      call read_gmsh(data_file('bad'), mesh, raised)
      call check_message(raised, FFRF_IO_ERROR, [character(len=30) :: 'mesh file', &
         'is a folder'], error)
   end subroutine test_error_not_regular

end module test_mesh_gmsh

program main_mesh_gmsh
   use ffrf_testing, only: unittest_t, run_suite
   use test_mesh_gmsh, only: collect_mesh_gmsh
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mesh_gmsh(tests)
   call run_suite('test_mesh_gmsh', tests)
end program main_mesh_gmsh
