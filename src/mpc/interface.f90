!> Interfaces of a flexible body: a physical surface of the mesh reduced to one 6-dof virtual node
!> by an RBE2 (q_B = F q_V) or an RBE3 (q_V = G q_B), with the reference conditions (forbidden
!> virtual-node dofs, D q_V = 0) that define the floating frame (Cammarata et al. 2022).
module ffrf_mpc_interface
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_fe_surface, only: surface_area_centroid, nodal_area_weights
   use ffrf_mpc_rbe2, only: rbe2_matrix, rbe2_pseudo_inverse
   use ffrf_mpc_rbe3, only: rbe3_matrix
   implicit none
   private
   public :: interface_input_t, interface_t, build_interface, parse_dofs, dofs_text
   public :: MPC_RBE2, MPC_RBE3, DOF_NAMES, mpc_name

   integer, parameter :: MPC_RBE2 = 1  !< rigid spider, q_B = F q_V
   integer, parameter :: MPC_RBE3 = 2  !< interpolation element, q_V = G q_B
   !> Virtual-node dof names, in the order of q_V = [u; theta]
   character(len=2), parameter :: DOF_NAMES(6) = ['Tx', 'Ty', 'Tz', 'Rx', 'Ry', 'Rz']

   !> One interface as the user describes it (namelist group &interface).
   type :: interface_input_t
      !> Body the interface belongs to
      character(len=64) :: body = ''
      !> Physical surface name in the body's mesh
      character(len=64) :: name = ''
      !> 'RBE2' or 'RBE3'
      character(len=8) :: mpc = 'RBE3'
      !> RBE3 weights: 'uniform' (Nastran's default, every node weight 1) or 'area'
      character(len=16) :: weighting = 'uniform'
      !> Virtual node: 'centroid' (area centroid of the face) or 'position'
      character(len=16) :: virtual_node = 'centroid'
      !> Virtual node position when virtual_node = 'position' (m, body mesh frame)
      real(dp) :: position(3) = 0.0_dp
      !> Reference conditions: forbidden virtual-node dofs ('Tx Ty Tz Rz', or Nastran '1234')
      character(len=64) :: rc = ''
   end type interface_input_t

   !> A reduced interface of a body.
   type :: interface_t
      !> Physical surface name
      character(len=:), allocatable :: name
      !> MPC_RBE2 or MPC_RBE3
      integer :: mpc = MPC_RBE3
      !> Body node indices of the face, sorted
      integer(ip), allocatable :: nodes(:)
      !> Node weights (RBE3); ones for RBE2
      real(dp), allocatable :: weights(:)
      !> Virtual node position (m)
      real(dp) :: virtual_xyz(3) = 0.0_dp
      !> Face area (m^2)
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

   !> Build interface `input%name` of `body` (mesh restricted to the body): nodes, weights,
   !> virtual node, F or G, reference conditions.
   subroutine build_interface(body, input, iface, error)
      !> The body's mesh
      type(mesh_t), intent(in) :: body
      !> User description
      type(interface_input_t), intent(in) :: input
      !> Result
      type(interface_t), intent(out) :: iface
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: triangles(:)
      real(dp), allocatable :: node_xyz(:, :)
      real(dp) :: centroid(3)
      integer :: i

      iface%name = trim(input%name)
      select case (to_lower(trim(input%mpc)))
      case ('rbe2')
         iface%mpc = MPC_RBE2
      case ('rbe3')
         iface%mpc = MPC_RBE3
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'mpc = "' // trim(input%mpc) // &
            '" is not known; use "RBE2" (rigid) or "RBE3" (interpolation)')
         return
      end select
      call parse_dofs(input%rc, iface%rc, error)
      if (allocated(error)) then
         call add_context(error, 'rc = "' // trim(input%rc) // '"')
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

      select case (to_lower(trim(input%virtual_node)))
      case ('centroid')
         iface%virtual_xyz = centroid
      case ('position')
         iface%virtual_xyz = input%position
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'virtual_node = "' // &
            trim(input%virtual_node) // '" is not known; use "centroid" or "position"')
         return
      end select

      select case (to_lower(trim(input%weighting)))
      case ('uniform')
         allocate (iface%weights(size(iface%nodes)), source=1.0_dp)
      case ('area')
         call nodal_area_weights(body%xyz, body%tris(:, triangles), iface%nodes, iface%weights, &
            error)
         if (allocated(error)) return
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'weighting = "' // trim(input%weighting) // &
            '" is not known; use "uniform" (Nastran default) or "area"')
         return
      end select

      node_xyz = body%xyz(:, iface%nodes)
      iface%length_scale = 0.0_dp
      do i = 1, size(iface%nodes)
         iface%length_scale = iface%length_scale + norm2(node_xyz(:, i) - iface%virtual_xyz)
      end do
      iface%length_scale = iface%length_scale / size(iface%nodes)
      if (iface%length_scale <= 0.0_dp) iface%length_scale = sqrt(iface%area)

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

   !> Parse forbidden dofs: names Tx Ty Tz Rx Ry Rz (any case, separated by blanks or commas) or
   !> Nastran component digits ('123456'); '', 'none' or '-' mean no reference condition. A dof
   !> named twice ('Tx Tx', '113') is an error: it is a slip, not a stronger condition.
   subroutine parse_dofs(text, dofs, error)
      !> Text to parse
      character(len=*), intent(in) :: text
      !> Selected dofs, Tx..Rz
      logical, intent(out) :: dofs(6)
      type(error_t), allocatable, intent(out) :: error
      character(len=len(text)) :: words
      integer :: i, start, finish, d
      character(len=:), allocatable :: token
      dofs = .false.
      words = to_lower(text)
      do i = 1, len(words)
         if (words(i:i) == ',' .or. words(i:i) == ';') words(i:i) = ' '
      end do
      start = 1
      do
         do while (start <= len(words))
            if (words(start:start) /= ' ') exit
            start = start + 1
         end do
         if (start > len(words)) exit
         finish = index(words(start:), ' ') + start - 2
         if (finish < start) finish = len(words)
         token = words(start:finish)
         start = finish + 1
         if (token == 'none' .or. token == '-') cycle
         d = 0
         do i = 1, 6
            if (token == to_lower(DOF_NAMES(i))) d = i
         end do
         if (d > 0) then
            if (dofs(d)) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'dof ' // DOF_NAMES(d) // &
                  ' is given twice; name each dof once (Tx Ty Tz Rx Ry Rz or digits 1-6)')
               return
            end if
            dofs(d) = .true.
         else if (verify(token, '123456') == 0) then
            do i = 1, len(token)
               d = iachar(token(i:i)) - iachar('0')
               if (dofs(d)) then
                  call fatal_error(error, FFRF_INPUT_ERROR, 'dof ' // DOF_NAMES(d) // ' (' // &
                     token(i:i) // ') is given twice; name each dof once (Tx Ty Tz Rx Ry Rz ' // &
                     'or digits 1-6)')
                  return
               end if
               dofs(d) = .true.
            end do
         else
            call fatal_error(error, FFRF_INPUT_ERROR, 'unknown dof "' // token // &
               '"; use Tx Ty Tz Rx Ry Rz or Nastran digits 1-6')
            return
         end if
      end do
   end subroutine parse_dofs

   !> "Tx Ty Tz Rz" for a dof selection ('' if none).
   function dofs_text(dofs) result(text)
      !> Selected dofs
      logical, intent(in) :: dofs(6)
      character(len=:), allocatable :: text
      integer :: d
      text = ''
      do d = 1, 6
         if (.not. dofs(d)) cycle
         if (len(text) > 0) text = text // ' '
         text = text // DOF_NAMES(d)
      end do
   end function dofs_text

   !> 'RBE2' or 'RBE3'.
   pure function mpc_name(mpc) result(name)
      !> MPC_RBE2 or MPC_RBE3
      integer, intent(in) :: mpc
      character(len=4) :: name
      name = 'RBE3'
      if (mpc == MPC_RBE2) name = 'RBE2'
   end function mpc_name

end module ffrf_mpc_interface
