!> A point of a flexible body's mesh that is not a reduced interface (docs/mechanisms.md "Markers
!> at mesh points"): a node (Gmsh node tag), the RBE3 reference point of a physical surface, or
!> the centre of a physical curve's or point's nodes. Each is q_P = G q_B, a 6-row map from the
!> displacements q_B of its nodes:
!>   node:    G = [I3; 0] (3 translation rows, no rotation rows: a solid element's node has no
!>            rotation dofs), x_P the node;
!>   surface: the Nastran RBE3 of ffrf_mpc_rbe3 (translation and rotation of the weighted
!>            average) with the weights of &interface weighting, x_P the face's area centroid,
!>            as build_interface makes for an RBE3 interface;
!>   curve or point: the mean of its n nodes (those of its line or point elements), G = [I3/n
!>            ... I3/n; 0] (no rotation rows, as a node's: a curve's nodes may be collinear),
!>            x_P the mean of their positions; one node gives the node's G and x_P exactly.
!> No stiffness and no constraint is added: the point is read off the body's motion (its mode
!> rows G Psi_B) and a load there is spread as G^T f.
module ffrf_mpc_mesh_point
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mesh_mesh, only: mesh_t, dimension_word
   use ffrf_mpc_interface, only: interface_spec_t, interface_t, build_interface, MPC_RBE3, &
      WEIGHTING_UNIFORM
   implicit none
   private
   public :: mesh_point_t, build_mesh_point

   !> A mesh point: q_P = G q_B (module header).
   type :: mesh_point_t
      !> Body node indices of the point's nodes (1..num_nodes of the body's mesh)
      integer(ip), allocatable :: nodes(:)
      !> G (6, 3 size(nodes)): rows Tx..Rz of the point from the nodes' displacements
      real(dp), allocatable :: G(:, :)
      !> The point in the body's mesh frame (m)
      real(dp) :: xyz(3) = 0.0_dp
   end type mesh_point_t

contains

   !> The mesh point of node tag `node` (> 0), else of the physical group `group`: a surface, else
   !> a curve, else a point of that name.
   subroutine build_mesh_point(mesh, node, group, weighting, point, error)
      !> The body's mesh (cut by extract_body: its physical groups and node tags)
      type(mesh_t), intent(in) :: mesh
      !> Gmsh node tag (0: none)
      integer, intent(in) :: node
      !> Physical group name (used when node = 0)
      character(len=*), intent(in) :: group
      !> RBE3 weights of a surface: WEIGHTING_* of ffrf_mpc_interface
      integer, intent(in) :: weighting
      type(mesh_point_t), intent(out) :: point
      type(error_t), allocatable, intent(out) :: error
      type(interface_spec_t) :: spec
      type(interface_t) :: face
      integer :: i
      if (node > 0) then
         i = node
         if (allocated(mesh%node_tags)) i = findloc(mesh%node_tags, int(node, i8), dim=1)
         if (i < 1 .or. i > mesh%num_nodes) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'node = ' // to_str(node) // ' is not ' // &
               'a node of the body''s mesh (' // to_str(mesh%num_nodes) // ' nodes); give a ' // &
               'Gmsh node tag of its volumes')
            return
         end if
         point%nodes = [int(i, ip)]
         allocate (point%G(6, 3), source=0.0_dp)
         do i = 1, 3
            point%G(i, i) = 1.0_dp
         end do
         point%xyz = mesh%xyz(:, point%nodes(1))
         return
      end if
      if (mesh%find_group(2_ip, group) == 0) then
         call build_group_centre(mesh, group, weighting, point, error)
         return
      end if
      spec%name = group
      spec%mpc = MPC_RBE3
      spec%weighting = weighting
      call build_interface(mesh, spec, face, error)
      if (allocated(error)) then
         call add_context(error, 'group = ''' // trim(group) // '''')
         return
      end if
      point%nodes = face%nodes
      point%G = face%G
      point%xyz = face%virtual_xyz
   end subroutine build_mesh_point

   !> The mesh point of the physical curve, else point, `group`: the centre of its nodes (the
   !> mean of their positions, moving with their mean translation: G = [I/n ... I/n; 0], no
   !> rotation rows, as a node's). A group of one node is that node's point exactly.
   subroutine build_group_centre(mesh, group, weighting, point, error)
      type(mesh_t), intent(in) :: mesh
      character(len=*), intent(in) :: group
      integer, intent(in) :: weighting
      type(mesh_point_t), intent(inout) :: point
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: dim, c, i, n
      dim = -1
      if (mesh%find_group(1_ip, group) > 0) then
         dim = 1
      else if (mesh%find_group(0_ip, group) > 0) then
         dim = 0
      end if
      if (dim < 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'group = ''' // trim(group) // ''' is not ' // &
            'a physical surface, curve or point of the body''s mesh (surfaces: ' // &
            mesh%group_names(2_ip) // '; curves: ' // mesh%group_names(1_ip) // '; points: ' // &
            mesh%group_names(0_ip) // '); name one, or place the marker at a node (node = <tag>)')
         return
      end if
      if (weighting /= WEIGHTING_UNIFORM) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'group = ''' // trim(group) // ''' is a ' // &
            'physical ' // dimension_word(dim) // ', whose marker is the plain centre of its ' // &
            'nodes: weighting (the RBE3 weights of a surface) means nothing there; drop weighting')
         return
      end if
      call mesh%group_nodes(dim, group, point%nodes, error)
      if (allocated(error)) then
         call add_context(error, 'group = ''' // trim(group) // '''')
         return
      end if
      n = size(point%nodes, kind=ip)
      allocate (point%G(6, 3 * n), source=0.0_dp)
      do c = 1, n
         do i = 1, 3
            point%G(i, 3 * (c - 1) + i) = 1.0_dp / real(n, dp)
         end do
      end do
      point%xyz = sum(mesh%xyz(:, point%nodes), dim=2) / real(n, dp)
   end subroutine build_group_centre

end module ffrf_mpc_mesh_point
