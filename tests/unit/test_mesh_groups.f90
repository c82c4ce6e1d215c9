!> Physical curves and points of a Gmsh mesh (issue 24 item 1: markers at the centre of a
!> physical group of any dimension; docs/mechanisms.md "Markers at mesh points"). The box of
!> tests/data/mesh/box.geo (0.3 x 0.2 x 0.1 m) has the physical curve "x_edge" (its edge along x
!> at y = z = 0) and the physical point "origin" (its corner at 0), meshed by gmsh in MSH 4.1
!> (ASCII, binary, first and second order) and 2.2. References: the nodes of a group against the
!> nodes selected by their coordinates (the edge and the corner are exact zeros in y and z), the
!> point of a group against the node marker of the same node (bitwise) and the edge's centre
!> against its closed form, the errors by their messages.
module test_mesh_groups
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t
   use ffrf_mesh_mesh, only: mesh_t, extract_body
   use ffrf_mesh_gmsh, only: read_gmsh
   use ffrf_mpc_interface, only: WEIGHTING_UNIFORM, WEIGHTING_AREA
   use ffrf_mpc_mesh_point, only: mesh_point_t, build_mesh_point
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, test_mesh_dir, report
   implicit none
   private
   public :: collect_mesh_groups

   !> The box's edge length along x (m)
   real(dp), parameter :: box_lx = 0.3_dp
   !> A mean of ~13 coordinates of size 0.3: a few eps
   real(dp), parameter :: mean_atol = 1.0e-15_dp

contains

   subroutine collect_mesh_groups(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('curve_and_point_nodes', test_curve_and_point_nodes), &
         new_unittest('body_keeps_curve_nodes', test_body_keeps_curve_nodes), &
         new_unittest('mesh_point_of_groups', test_mesh_point_of_groups), &
         new_unittest('mesh_point_errors', test_mesh_point_errors)]
   end subroutine collect_mesh_groups

   !> A mesh gmsh built for the tests (tests/unit/mesh.cmake).
   function built(name) result(path)
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: path
      path = test_mesh_dir() // '/test_mesh/' // name
   end function built

   !> The box body (physical volume "block") of mesh file `name`.
   subroutine box_body(name, body, error)
      character(len=*), intent(in) :: name
      type(mesh_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      call read_gmsh(built(name), mesh, error)
      if (.not. allocated(error)) call extract_body(mesh, ['block'], body, error)
      if (allocated(error)) error%message = name // ': unexpected error: ' // error%message
   end subroutine box_body

   !> Indices of the nodes with |y| and |z| (and |x| if `corner`) at most 1e-12, ascending.
   function nodes_on_edge(mesh, corner) result(nodes)
      type(mesh_t), intent(in) :: mesh
      logical, intent(in) :: corner
      integer(ip), allocatable :: nodes(:)
      logical :: on(mesh%num_nodes)
      integer(ip) :: i
      do i = 1, mesh%num_nodes
         on(i) = abs(mesh%xyz(2, i)) <= 1.0e-12_dp .and. abs(mesh%xyz(3, i)) <= 1.0e-12_dp
         if (corner) on(i) = on(i) .and. abs(mesh%xyz(1, i)) <= 1.0e-12_dp
      end do
      nodes = pack([(i, i=1, mesh%num_nodes)], on)
   end function nodes_on_edge

   !> In every format and order, group_nodes of the curve are the nodes on the edge (those of its
   !> Line2 or Line3 elements, at least 7) and of the point the corner node, in the whole mesh
   !> (no body cut).
   subroutine test_curve_and_point_nodes(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: names(4) = [character(len=14) :: 'box_o1_41.msh', &
         'box_o2_41.msh', 'box_o2_41b.msh', 'box_o2_22.msh']
      type(mesh_t) :: mesh
      integer(ip), allocatable :: edge(:), corner(:), expected(:)
      integer :: k
      do k = 1, size(names)
         call read_gmsh(built(trim(names(k))), mesh, error)
         if (allocated(error)) return
         call mesh%group_nodes(1_ip, 'x_edge', edge, error)
         if (.not. allocated(error)) call mesh%group_nodes(0_ip, 'origin', corner, error)
         if (allocated(error)) return
         expected = nodes_on_edge(mesh, .false.)
         call check(error, trim(names(k)) // ': curve x_edge holds the nodes on the edge', &
            size(edge) == size(expected) .and. size(edge) >= 7)
         if (allocated(error)) return
         call check(error, trim(names(k)) // ': the same nodes', all(edge == expected))
         if (allocated(error)) return
         expected = nodes_on_edge(mesh, .true.)
         call check(error, trim(names(k)) // ': point origin is the corner node', &
            size(corner) == 1 .and. size(expected) == 1)
         if (allocated(error)) return
         call check(error, trim(names(k)) // ': the same node', all(corner == expected))
         if (allocated(error)) return
         call check(error, trim(names(k)) // ': group_names(1), (0)', &
            mesh%group_names(1_ip) == 'x_edge' .and. mesh%group_names(0_ip) == 'origin')
         if (allocated(error)) return
      end do
      call report('curve x_edge: ' // trim(adjustl(to_text(size(edge)))) // &
         ' nodes (Tet10 box, MSH 2.2), as selected by their coordinates')
   end subroutine test_curve_and_point_nodes

   !> An integer as text.
   function to_text(value) result(text)
      integer, intent(in) :: value
      character(len=16) :: text
      write (text, '(i0)') value
   end function to_text

   !> In a body cut by extract_body the curve's nodes are the body's nodes at the same places;
   !> a curve off the body and a curve without elements are refused naming the group.
   subroutine test_body_keeps_curve_nodes(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: failure
      type(mesh_t) :: body, changed
      integer(ip), allocatable :: edge(:)
      call box_body('box_o2_41.msh', body, error)
      if (allocated(error)) return
      call body%group_nodes(1_ip, 'x_edge', edge, error)
      if (allocated(error)) return
      call check(error, 'body: curve x_edge holds the nodes on the edge', &
         size(edge) == size(nodes_on_edge(body, .false.)) .and. &
         all(edge == nodes_on_edge(body, .false.)))
      if (allocated(error)) return
      changed = body
      changed%curve_point_nodes(3, :) = 0
      call changed%group_nodes(1_ip, 'x_edge', edge, failure)
      call expect_message(failure, [character(len=60) :: 'physical curve ''x_edge'' does ' // &
         'not lie wholly on the body', 'name a curve of the body'], error)
      if (allocated(error)) return
      changed = body
      deallocate (changed%curve_point_nodes)
      call changed%group_nodes(0_ip, 'origin', edge, failure)
      call expect_message(failure, [character(len=60) :: 'physical point ''origin'' has no ' // &
         'nodes (no point elements', 'gmsh -3'], error)
      if (allocated(error)) return
      call body%group_nodes(1_ip, 'left', edge, failure)
      call expect_message(failure, [character(len=60) :: 'no physical curve ''left''', &
         'curves: x_edge'], error)
   end subroutine test_body_keeps_curve_nodes

   !> The point of a physical point of one node is the node marker's point exactly (nodes, G,
   !> position); the point of the curve is the mean of its nodes: G = [I/n ... I/n; 0], the
   !> position the edge's centre (lx/2, 0, 0) (uniform nodes along the straight edge).
   subroutine test_mesh_point_of_groups(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: body
      type(mesh_point_t) :: group_point, node_point, curve
      integer(ip), allocatable :: edge(:)
      integer :: n, c
      call box_body('box_o2_41.msh', body, error)
      if (allocated(error)) return
      call build_mesh_point(body, 0, 'origin', WEIGHTING_UNIFORM, group_point, error)
      if (allocated(error)) return
      edge = nodes_on_edge(body, .true.)
      call build_mesh_point(body, int(body%node_tags(edge(1))), '', 0, node_point, error)
      if (allocated(error)) return
      call check(error, 'point group = node marker: nodes, G, position (bitwise)', &
         all(group_point%nodes == node_point%nodes) .and. &
         all(shape(group_point%G) == shape(node_point%G)) .and. &
         all(group_point%G == node_point%G) .and. all(group_point%xyz == node_point%xyz))
      if (allocated(error)) return
      call build_mesh_point(body, 0, 'x_edge', WEIGHTING_UNIFORM, curve, error)
      if (allocated(error)) return
      edge = nodes_on_edge(body, .false.)
      n = size(edge)
      call check(error, 'curve: its nodes and a G of 6 x 3n', &
         size(curve%nodes) == n .and. all(curve%nodes == edge) .and. &
         all(shape(curve%G) == [6, 3 * n]))
      if (allocated(error)) return
      do c = 1, n
         call check(error, 'curve: G block of node ' // trim(to_text(c)) // ' = [I/n; 0]', &
            all(curve%G(1:3, 3 * c - 2:3 * c) == reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], &
            [3, 3]) / real(n, dp)) .and. all(curve%G(4:6, 3 * c - 2:3 * c) == 0.0_dp))
         if (allocated(error)) return
      end do
      call check_close(error, 'curve centre x', curve%xyz(1), box_lx / 2.0_dp, atol=mean_atol)
      if (.not. allocated(error)) call check(error, 'curve centre y, z', &
         all(abs(curve%xyz(2:3)) <= 1.0e-12_dp))
   end subroutine test_mesh_point_of_groups

   !> A name of no surface, curve or point lists the three kinds; a weighting other than
   !> uniform at a curve is refused.
   subroutine test_mesh_point_errors(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: failure
      type(mesh_t) :: body
      type(mesh_point_t) :: point
      call box_body('box_o2_41.msh', body, error)
      if (allocated(error)) return
      call build_mesh_point(body, 0, 'nowhere', WEIGHTING_UNIFORM, point, failure)
      call expect_message(failure, [character(len=72) :: 'group = ''nowhere'' is not a ' // &
         'physical surface, curve or point', '(surfaces: left, right, x_faces; curves: ' // &
         'x_edge; points: origin)'], error)
      if (allocated(error)) return
      call build_mesh_point(body, 0, 'x_edge', WEIGHTING_AREA, point, failure)
      call expect_message(failure, [character(len=60) :: 'group = ''x_edge'' is a physical ' // &
         'curve', 'drop weighting'], error)
   end subroutine test_mesh_point_errors

   !> `failure` is set and its message holds every fragment.
   subroutine expect_message(failure, fragments, error)
      type(error_t), allocatable, intent(in) :: failure
      character(len=*), intent(in) :: fragments(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      call check(error, 'an error is raised (expected: ' // trim(fragments(1)) // ')', &
         allocated(failure))
      if (allocated(error)) return
      do k = 1, size(fragments)
         call check(error, 'message "' // failure%message // '" holds "' // &
            trim(fragments(k)) // '"', index(failure%message, trim(fragments(k))) > 0)
         if (allocated(error)) return
      end do
   end subroutine expect_message

end module test_mesh_groups

program main_mesh_groups
   use ffrf_testing, only: unittest_t, run_suite
   use test_mesh_groups, only: collect_mesh_groups
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_mesh_groups(tests)
   call run_suite('test_mesh_groups', tests)
end program main_mesh_groups
