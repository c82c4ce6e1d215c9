!> Interfaces of a flexible body: a physical surface of the mesh, or a node set given by a host,
!> reduced to one 6-dof virtual node by an RBE2 (q_B = F q_V) or an RBE3 (q_V = G q_B), with the
!> reference conditions (forbidden virtual-node dofs, D q_V = 0) that define the floating frame
!> (Cammarata et al. 2022). RBE3 weights: theory.md 1.3.
module ffrf_mpc_interface
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   !> The MPC kinds and their table (rigid spider q_B = F q_V, interpolation element q_V = G q_B)
   !> and the RBE3 weighting kinds
   use ffrf_core_choices, only: MPC_RBE2, MPC_RBE3, mpc_choices, choice_name, WEIGHTING_UNIFORM, &
      WEIGHTING_AREA, WEIGHTING_AREA_CONSISTENT, WEIGHTING_GIVEN
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_fe_surface, only: surface_area_centroid, nodal_area_weights, nodal_consistent_weights
   use ffrf_la_sparse, only: sort_indices
   use ffrf_mpc_rbe2, only: rbe2_matrix, rbe2_pseudo_inverse
   use ffrf_mpc_rbe3, only: rbe3_matrix
   implicit none
   private
   public :: interface_spec_t, interface_t, build_interface, dofs_text
   public :: MPC_RBE2, MPC_RBE3, DOF_NAMES, mpc_name
   public :: WEIGHTING_UNIFORM, WEIGHTING_AREA, WEIGHTING_AREA_CONSISTENT, WEIGHTING_GIVEN
   public :: VIRTUAL_NODE_CENTROID, VIRTUAL_NODE_POSITION

   !> virtual node at the face's area centroid (node set: the weighted centroid of its nodes)
   integer, parameter :: VIRTUAL_NODE_CENTROID = 1
   integer, parameter :: VIRTUAL_NODE_POSITION = 2  !< virtual node at a given position
   !> Virtual-node dof names, in the order of q_V = [u; theta]
   character(len=2), parameter :: DOF_NAMES(6) = ['Tx', 'Ty', 'Tz', 'Rx', 'Ry', 'Rz']

   !> One interface as the model resolved it (from &interface: ffrf_model_specs).
   type :: interface_spec_t
      !> Physical surface name in the body's mesh (a node-set interface: its name)
      character(len=64) :: name = ''
      !> MPC_RBE2 or MPC_RBE3
      integer :: mpc = MPC_RBE3
      !> RBE3 node weights: WEIGHTING_UNIFORM (Nastran's default, every node weight 1),
      !> WEIGHTING_AREA (tributary), WEIGHTING_AREA_CONSISTENT (int N_i dA), or WEIGHTING_GIVEN
      !> (node-set interface: `weights`)
      integer :: weighting = WEIGHTING_UNIFORM
      !> Node-set interface (allocated: used instead of the surface `name`): body node indices,
      !> 1-based, each once, any order
      integer(ip), allocatable :: nodes(:)
      !> Their weights w_i > 0 when weighting = WEIGHTING_GIVEN, in the order of `nodes`
      real(dp), allocatable :: weights(:)
      !> Virtual node: VIRTUAL_NODE_CENTROID (area centroid of the face) or VIRTUAL_NODE_POSITION
      integer :: virtual_node = VIRTUAL_NODE_CENTROID
      !> Virtual node position when virtual_node = VIRTUAL_NODE_POSITION (m, body mesh frame)
      real(dp) :: position(3) = 0.0_dp
      !> Reference conditions: forbidden virtual-node dofs, Tx..Rz
      logical :: rc(6) = .false.
   end type interface_spec_t

   !> A reduced interface of a body.
   type :: interface_t
      !> Physical surface name (or the name of the node set)
      character(len=:), allocatable :: name
      !> MPC_RBE2 or MPC_RBE3
      integer :: mpc = MPC_RBE3
      !> RBE3 node weights as asked: WEIGHTING_* (interface_spec_t%weighting)
      integer :: weighting = WEIGHTING_UNIFORM
      !> Body node indices of the face (or node set), sorted
      integer(ip), allocatable :: nodes(:)
      !> Node weights (RBE3); ones for RBE2
      real(dp), allocatable :: weights(:)
      !> Virtual node position (m)
      real(dp) :: virtual_xyz(3) = 0.0_dp
      !> Face area (m^2); 0 for a node set
      real(dp) :: area = 0.0_dp
      !> Mean distance of the nodes from the virtual node (m), Nastran's Lc
      real(dp) :: length_scale = 0.0_dp
      !> Forbidden virtual-node dofs (reference conditions), Tx..Rz
      logical :: rc(6) = .false.
      !> RBE2: q_B = F q_V, (3 nB, 6)
      real(dp), allocatable :: F(:, :)
      !> q_V = G q_B, (6, 3 nB): RBE3's G; for RBE2 its pseudo-inverse F^+ (exact on range(F))
      real(dp), allocatable :: G(:, :)
      !> The nodes cannot carry a rotation (collinear)
      logical :: rank_deficient = .false.
      !> That rotation's axis
      real(dp) :: undefined_direction(3) = 0.0_dp
   end type interface_t

contains

   !> Build interface `spec%name` of `body` (mesh restricted to the body): nodes, weights,
   !> virtual node, F or G, reference conditions. The nodes are those of the physical surface
   !> `spec%name`, or the node set `spec%nodes` when it is allocated.
   subroutine build_interface(body, spec, iface, error)
      !> The body's mesh
      type(mesh_t), intent(in) :: body
      !> The interface, resolved
      type(interface_spec_t), intent(in) :: spec
      !> Result
      type(interface_t), intent(out) :: iface
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: node_xyz(:, :)
      real(dp) :: centroid(3)
      integer :: i

      iface%name = trim(spec%name)
      if (spec%mpc /= MPC_RBE2 .and. spec%mpc /= MPC_RBE3) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'interface "' // iface%name // '": mpc = ' // &
            to_str(spec%mpc) // ' is not known; use MPC_RBE2 or MPC_RBE3')
         return
      end if
      iface%mpc = spec%mpc
      iface%weighting = spec%weighting
      iface%rc = spec%rc

      if (allocated(spec%nodes)) then
         call node_set_interface(body, spec, iface, centroid, error)
      else
         call surface_interface(body, spec, iface, centroid, error)
      end if
      if (allocated(error)) return
      select case (spec%virtual_node)
      case (VIRTUAL_NODE_CENTROID)
         iface%virtual_xyz = centroid
      case (VIRTUAL_NODE_POSITION)
         iface%virtual_xyz = spec%position
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'interface "' // iface%name // &
            '": virtual_node = ' // to_str(spec%virtual_node) // ' is not known; use ' // &
            'VIRTUAL_NODE_CENTROID or VIRTUAL_NODE_POSITION')
         return
      end select

      node_xyz = body%xyz(:, iface%nodes)
      iface%length_scale = 0.0_dp
      do i = 1, size(iface%nodes)
         iface%length_scale = iface%length_scale + norm2(node_xyz(:, i) - iface%virtual_xyz)
      end do
      iface%length_scale = iface%length_scale / size(iface%nodes)
      if (iface%length_scale <= 0.0_dp) iface%length_scale = sqrt(iface%area)
      if (iface%length_scale <= 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'interface "' // iface%name // '": its ' // &
            to_str(size(iface%nodes)) // ' node(s) all sit at the virtual node; an interface ' // &
            'needs nodes around it that carry its rotations')
         return
      end if

      if (iface%mpc == MPC_RBE2) then
         call rbe2_matrix(node_xyz, iface%virtual_xyz, iface%F)
         call rbe2_pseudo_inverse(iface%F, iface%length_scale, iface%G, iface%rank_deficient, &
            iface%undefined_direction, error)
      else
         call rbe3_matrix(node_xyz, iface%weights, iface%virtual_xyz, iface%length_scale, &
            iface%G, iface%rank_deficient, iface%undefined_direction, error)
      end if
      if (allocated(error)) call add_context(error, 'interface "' // iface%name // '"')
   end subroutine build_interface

   !> Nodes, area, area centroid and weights of an interface on the physical surface spec%name.
   subroutine surface_interface(body, spec, iface, centroid, error)
      type(mesh_t), intent(in) :: body
      type(interface_spec_t), intent(in) :: spec
      type(interface_t), intent(inout) :: iface
      real(dp), intent(out) :: centroid(3)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: triangles(:)

      if (spec%weighting == WEIGHTING_GIVEN .or. allocated(spec%weights)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'interface "' // iface%name // &
            '": given weights need a node-set interface (nodes with their weights); a ' // &
            'surface takes WEIGHTING_UNIFORM, WEIGHTING_AREA or WEIGHTING_AREA_CONSISTENT')
         return
      end if
      call body%group_triangles(iface%name, triangles, error)
      if (allocated(error)) return
      if (size(triangles) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'physical surface "' // iface%name // &
            '" has no triangles in the body; check the mesh')
         return
      end if
      call body%group_nodes(2, iface%name, iface%nodes, error)
      if (allocated(error)) return
      call surface_area_centroid(body%xyz, body%tris(:, triangles), iface%area, centroid, error)
      if (allocated(error)) return

      select case (spec%weighting)
      case (WEIGHTING_UNIFORM)
         allocate (iface%weights(size(iface%nodes)), source=1.0_dp)
      case (WEIGHTING_AREA)
         call nodal_area_weights(body%xyz, body%tris(:, triangles), iface%nodes, iface%weights, &
            error)
      case (WEIGHTING_AREA_CONSISTENT)
         call nodal_consistent_weights(body%xyz, body%tris(:, triangles), iface%nodes, &
            iface%weights, error)
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'interface "' // iface%name // &
            '": weighting = ' // to_str(spec%weighting) // ' is not known; use ' // &
            'WEIGHTING_UNIFORM, WEIGHTING_AREA or WEIGHTING_AREA_CONSISTENT')
      end select
   end subroutine surface_interface

   !> Nodes (sorted), weights (uniform or given) and weighted centroid of the nodes of a
   !> node-set interface; its area is 0.
   subroutine node_set_interface(body, spec, iface, centroid, error)
      type(mesh_t), intent(in) :: body
      type(interface_spec_t), intent(in) :: spec
      type(interface_t), intent(inout) :: iface
      real(dp), intent(out) :: centroid(3)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: slot(:)
      integer(ip) :: i, n
      character(len=:), allocatable :: where

      where = 'interface "' // iface%name // '" (node set): '
      n = size(spec%nodes, kind=ip)
      if (n == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'no nodes; give at least one')
         return
      end if
      allocate (slot(body%num_nodes), source=0_ip)
      do i = 1, n
         if (spec%nodes(i) < 1 .or. spec%nodes(i) > body%num_nodes) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'node ' // to_str(i) // ' is ' // &
               to_str(spec%nodes(i)) // ', outside the body''s nodes 1..' // &
               to_str(body%num_nodes))
            return
         end if
         if (slot(spec%nodes(i)) /= 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'node ' // &
               to_str(spec%nodes(i)) // ' is listed twice (positions ' // &
               to_str(slot(spec%nodes(i))) // ' and ' // to_str(i) // ')')
            return
         end if
         slot(spec%nodes(i)) = i
      end do
      iface%nodes = spec%nodes
      call sort_indices(iface%nodes)

      select case (spec%weighting)
      case (WEIGHTING_UNIFORM)
         if (allocated(spec%weights)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'weights are given but the ' // &
               'weighting is uniform; use WEIGHTING_GIVEN')
            return
         end if
         allocate (iface%weights(n), source=1.0_dp)
      case (WEIGHTING_GIVEN)
         if (.not. allocated(spec%weights)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'WEIGHTING_GIVEN without weights')
            return
         else if (size(spec%weights, kind=ip) /= n) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // to_str(size(spec%weights)) // &
               ' weights for ' // to_str(n) // ' nodes')
            return
         end if
         do i = 1, n
            if (.not. (spec%weights(i) > 0.0_dp .and. spec%weights(i) <= huge(1.0_dp))) then
               call fatal_error(error, FFRF_INPUT_ERROR, where // 'weight ' // to_str(i) // &
                  ' (node ' // to_str(spec%nodes(i)) // ') is ' // to_str(spec%weights(i)) // &
                  '; weights must be positive and finite')
               return
            end if
         end do
         iface%weights = spec%weights(slot(iface%nodes))
      case (WEIGHTING_AREA, WEIGHTING_AREA_CONSISTENT)
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'area weights need a surface; ' // &
            'give the weights of the nodes (WEIGHTING_GIVEN) or use a surface interface')
         return
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'weighting = ' // &
            to_str(spec%weighting) // ' is not known; use WEIGHTING_UNIFORM or WEIGHTING_GIVEN')
         return
      end select

      centroid = matmul(body%xyz(:, iface%nodes), iface%weights) / sum(iface%weights)
      iface%area = 0.0_dp
   end subroutine node_set_interface

   !> "Tx Ty Tz Rz" for a dof selection (`none`, default '', if none).
   function dofs_text(dofs, none) result(text)
      !> Selected dofs
      logical, intent(in) :: dofs(6)
      !> The text when no dof is selected (default: empty)
      character(len=*), intent(in), optional :: none
      character(len=:), allocatable :: text
      integer :: d
      text = ''
      do d = 1, 6
         if (.not. dofs(d)) cycle
         if (len(text) > 0) text = text // ' '
         text = text // DOF_NAMES(d)
      end do
      if (len(text) == 0 .and. present(none)) text = none
   end function dofs_text

   !> 'RBE2' or 'RBE3'.
   pure function mpc_name(mpc) result(name)
      !> MPC_RBE2 or MPC_RBE3
      integer, intent(in) :: mpc
      character(len=4) :: name
      name = choice_name(mpc_choices, mpc, 'RBE3')
   end function mpc_name

end module ffrf_mpc_interface
