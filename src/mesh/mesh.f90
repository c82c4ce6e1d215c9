!> The mesh the rest of ffrf works on: node coordinates, Tet4 or Tet10 volume elements, Tri3 or
!> Tri6 surface elements and the Gmsh physical groups, as read by `ffrf_mesh_gmsh`.
!>
!> Elements hold node INDICES 1..num_nodes (not Gmsh tags) in Gmsh's node order; see the picture
!> in `ffrf_mesh_gmsh` for the Tet10 and Tri6 edge nodes. Physical groups name sets of geometric
!> entities; an element belongs to a group when its entity (`tet_entity`, `tri_entity`) does.
!> `extract_body` cuts one flexible body (one or more physical volumes) out of a mesh.
module ffrf_mesh_mesh
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str, join_ints
   implicit none
   private
   public :: physical_group_t, mesh_t, extract_body, dimension_word, element_type_name
   public :: face_connected_parts, boundary_faces, mesh_node_set_t, mesh_material_t

   !> A Gmsh physical group: a named set of geometric entities of one dimension.
   type :: physical_group_t
      !> 2 surface, 3 volume (0 points and 1 curves are kept too)
      integer(ip) :: dim = 0
      !> Gmsh physical tag
      integer(ip) :: tag = 0
      !> Gmsh physical name ('' if unnamed)
      character(len=:), allocatable :: name
      !> Entity tags (of this dim) in the group, sorted
      integer(ip), allocatable :: entities(:)
   end type physical_group_t

   !> A bulk-data interface element (RBE2 or RBE3, docs/input.md "Nastran bulk data"): the grids
   !> that are not its reference point, their weights and the reference point. Empty for Gmsh.
   type :: mesh_node_set_t
      !> Element id as text ('101'), the name &interface gives
      character(len=:), allocatable :: name
      !> MPC_RBE2 (independent GN, dependent GMi) or MPC_RBE3 (dependent REFGRID, weighted Gi,j)
      !> of ffrf_core_choices
      integer :: rbe = 0
      !> Node indices 1..num_nodes (the GMi of RBE2, the Gi,j of RBE3), in card order; not
      !> allocated in a body cut by extract_body when a grid is not on the body
      integer(ip), allocatable :: nodes(:)
      !> Weight of each node (RBE3's WTi; ones for RBE2)
      real(dp), allocatable :: weights(:)
      !> The reference point (RBE2 GN, RBE3 REFGRID) in basic coordinates (m)
      real(dp) :: reference(3) = 0.0_dp
      !> Where the card is and, in a body, why it is not on it, for messages
      character(len=:), allocatable :: origin, off_body
   end type mesh_node_set_t

   !> The material a bulk-data deck gives a volume (PSOLID -> MAT1). Empty for Gmsh.
   type :: mesh_material_t
      !> Volume entity tag (the PSOLID id)
      integer(ip) :: volume = 0
      !> Young's modulus (Pa), Poisson's ratio, density (kg/m^3)
      real(dp) :: young = 0.0_dp, poisson = 0.0_dp, density = 0.0_dp
      !> "MAT1 7 (deck.bdf:12)", for messages and the log
      character(len=:), allocatable :: origin
   end type mesh_material_t

   !> Nodes, tetrahedra, triangles and physical groups of a Gmsh mesh.
   type :: mesh_t
      !> Number of nodes
      integer(ip) :: num_nodes = 0
      !> Node coordinates (3, num_nodes), metres
      real(dp), allocatable :: xyz(:, :)
      !> Gmsh tag of node i (tags may have gaps)
      integer(i8), allocatable :: node_tags(:)
      !> 4 (Tet4) or 10 (Tet10); 0 = no tetrahedra
      integer(ip) :: nodes_per_tet = 0
      !> (nodes_per_tet, num_tets): node indices 1..num_nodes, Gmsh node order
      integer(ip), allocatable :: tets(:, :)
      !> Gmsh element tag of each tetrahedron (for messages)
      integer(i8), allocatable :: tet_tags(:)
      !> Volume entity tag of each tetrahedron
      integer(ip), allocatable :: tet_entity(:)
      !> 3 (Tri3) or 6 (Tri6); 0 = no triangles
      integer(ip) :: nodes_per_tri = 0
      !> (nodes_per_tri, num_tris): node indices 1..num_nodes, Gmsh node order
      integer(ip), allocatable :: tris(:, :)
      !> Gmsh element tag of each triangle
      integer(i8), allocatable :: tri_tags(:)
      !> Surface entity tag of each triangle
      integer(ip), allocatable :: tri_entity(:)
      !> Physical groups, sorted by dimension, then tag
      type(physical_group_t), allocatable :: groups(:)
      !> The nodes of the point and line elements (Gmsh types 15, 1, 8, ...: those of physical
      !> points and curves), (3, n): dimension (0 point, 1 curve), entity tag, node index, one
      !> column per element node; in a body cut by extract_body the node index is 0 where the
      !> node is not on the body. Not allocated: none read (bulk data)
      integer(ip), allocatable :: curve_point_nodes(:, :)
      !> File the mesh was read from (for messages)
      character(len=:), allocatable :: file_name
      !> Volume elements the reader skipped (not Tet4/Tet10), one column per run of one entity
      !> and type: volume entity tag, Gmsh element type, count, first element tag
      integer(i8), allocatable :: other_volume_elements(:, :)
      !> For a body cut by extract_body: its physical volumes, "'crank'" (for messages)
      character(len=:), allocatable :: volumes
      !> For a body cut by extract_body: the surface entity of each triangle of the whole mesh
      !> that is not a face of the body's tetrahedra (an interface surface must not hold any)
      integer(ip), allocatable :: off_body_tri_entity(:)
      !> Nastran bulk data only: the RBE2/RBE3 elements (interfaces named by element id)
      type(mesh_node_set_t), allocatable :: node_sets(:)
      !> Nastran bulk data only: the material of each PSOLID of the tetrahedra
      type(mesh_material_t), allocatable :: materials(:)
      !> Nastran bulk data only: the cards not read and their counts, "PARAM (2), SPC1 (1)"
      character(len=:), allocatable :: ignored_cards
   contains
      procedure :: num_tets => mesh_num_tets
      procedure :: num_tris => mesh_num_tris
      procedure :: find_group => mesh_find_group
      procedure :: group_tets => mesh_group_tets
      procedure :: group_triangles => mesh_group_triangles
      procedure :: group_nodes => mesh_group_nodes
      procedure :: group_names => mesh_group_names
      procedure :: summary => mesh_summary
   end type mesh_t

   interface
      !> A new mesh holding one body: the tetrahedra of the physical volumes `volume_names`, only
      !> the nodes they use (renumbered, `node_tags` kept), the triangles that are faces of its
      !> tetrahedra (renumbered), the nodes of the physical points and curves and all physical
      !> groups, the body checked once (the checks: the body in mesh_extract.f90).
      module subroutine extract_body(mesh, volume_names, body, error)
         !> Whole mesh
         type(mesh_t), intent(in) :: mesh
         !> Physical volumes that make up the body
         character(len=*), intent(in) :: volume_names(:)
         !> The body's mesh
         type(mesh_t), intent(out) :: body
         type(error_t), allocatable, intent(out) :: error
      end subroutine extract_body

      !> The parts of the body's tetrahedra connected through shared faces (three common corners).
      module subroutine face_connected_parts(body, num_parts, part_of_tet)
         !> The body's mesh
         type(mesh_t), intent(in) :: body
         !> Number of face-connected parts
         integer(ip), intent(out) :: num_parts
         !> Part of each tetrahedron, 1..num_parts in the order of their first tetrahedron
         integer(ip), allocatable, intent(out) :: part_of_tet(:)
      end subroutine face_connected_parts

      !> The faces of the body's tetrahedra that no other tetrahedron shares (the body's
      !> surface), each as (tetrahedron, local corner opposite the face), tetrahedra ascending.
      module subroutine boundary_faces(body, faces)
         !> The body's mesh
         type(mesh_t), intent(in) :: body
         !> (2, num_faces): tetrahedron index and the corner 1..4 the face does not hold
         integer(ip), allocatable, intent(out) :: faces(:, :)
      end subroutine boundary_faces

      !> The file name, or "(unnamed)" for a mesh not read from a file.
      module pure function file_of(mesh) result(name)
         type(mesh_t), intent(in) :: mesh
         character(len=:), allocatable :: name
      end function file_of

      !> Positions of the true entries of `mask`, ascending.
      module pure function pack_indices(mask) result(indices)
         logical, intent(in) :: mask(:)
         integer(ip), allocatable :: indices(:)
      end function pack_indices

      !> Columns `selected` of `elements` with every node index i replaced by new_index(i).
      module pure function renumbered(elements, selected, new_index) result(subset)
         !> (nodes_per_element, num_elements) node indices
         integer(ip), intent(in) :: elements(:, :)
         !> Elements to keep, in this order
         integer(ip), intent(in) :: selected(:)
         !> New index of every old node index
         integer(ip), intent(in) :: new_index(:)
         integer(ip) :: subset(size(elements, 1), size(selected))
      end function renumbered

      !> "'a', 'b'" for messages.
      module pure function quoted_list(words) result(text)
         character(len=*), intent(in) :: words(:)
         character(len=:), allocatable :: text
      end function quoted_list

      !> Set used(node) for every node of the selected elements.
      module pure subroutine mark_nodes(elements, selected, used)
         !> (nodes_per_element, num_elements) node indices
         integer(ip), intent(in) :: elements(:, :)
         !> Which elements count
         logical, intent(in) :: selected(:)
         !> Node flags, set where used
         logical, intent(inout) :: used(:)
      end subroutine mark_nodes

      !> "mesh 'crank.msh': no physical volume 'crnk'; volumes: crank".
      module subroutine unknown_group_error(mesh, dim, name, error)
         type(mesh_t), intent(in) :: mesh
         integer(ip), intent(in) :: dim
         character(len=*), intent(in) :: name
         type(error_t), allocatable, intent(out) :: error
      end subroutine unknown_group_error

      !> For each element, whether its entity tag is one of `entities`.
      module pure function in_entities(element_entity, entities) result(inside)
         !> Entity tag of each element
         integer(ip), intent(in) :: element_entity(:)
         !> Entity tags of a physical group
         integer(ip), intent(in) :: entities(:)
         logical :: inside(size(element_entity))
      end function in_entities
   end interface

contains

   !> Number of tetrahedra.
   pure function mesh_num_tets(self) result(count)
      class(mesh_t), intent(in) :: self
      integer(ip) :: count
      count = num_columns(self%tets)
   end function mesh_num_tets

   !> Number of triangles.
   pure function mesh_num_tris(self) result(count)
      class(mesh_t), intent(in) :: self
      integer(ip) :: count
      count = num_columns(self%tris)
   end function mesh_num_tris

   !> Number of elements of an element array (nodes, elements); 0 while it is not allocated.
   pure function num_columns(elements) result(count)
      integer(ip), allocatable, intent(in) :: elements(:, :)
      integer(ip) :: count
      count = 0
      if (allocated(elements)) count = size(elements, 2, kind=ip)
   end function num_columns

   !> Index into `groups` of the physical group of dimension `dim` called `name` (exact,
   !> case-sensitive compare of the whole group name with `name` without its trailing blanks,
   !> which a namelist string pads: a group named "left " is not "left"; the reader refuses
   !> two names equal up to trailing blanks); 0 if there is none.
   pure function mesh_find_group(self, dim, name) result(index)
      class(mesh_t), intent(in) :: self
      !> 0 point, 1 curve, 2 surface, 3 volume
      integer(ip), intent(in) :: dim
      !> Physical name
      character(len=*), intent(in) :: name
      integer(ip) :: index
      integer(ip) :: i
      index = 0
      if (.not. allocated(self%groups)) return
      do i = 1, size(self%groups, kind=ip)
         if (self%groups(i)%dim /= dim) cycle
         if (len(self%groups(i)%name) /= len_trim(name)) cycle
         if (self%groups(i)%name == name) then
            index = i
            return
         end if
      end do
   end function mesh_find_group

   !> Indices of the tetrahedra in the physical volume `name`, ascending.
   subroutine mesh_group_tets(self, name, indices, error)
      class(mesh_t), intent(in) :: self
      !> Physical volume name
      character(len=*), intent(in) :: name
      !> Tetrahedron indices 1..num_tets
      integer(ip), allocatable, intent(out) :: indices(:)
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: k
      call group_elements(self, 3_ip, name, self%tet_entity, k, indices, error)
   end subroutine mesh_group_tets

   !> Indices of the elements (entity tag of each: element_entity) in the physical group of
   !> dimension `dim` called `name`, ascending, and the group's index k; an unknown name is an
   !> error listing the groups of that dimension.
   subroutine group_elements(self, dim, name, element_entity, k, indices, error)
      class(mesh_t), intent(in) :: self
      integer(ip), intent(in) :: dim
      character(len=*), intent(in) :: name
      integer(ip), allocatable, intent(in) :: element_entity(:)
      integer(ip), intent(out) :: k
      integer(ip), allocatable, intent(out) :: indices(:)
      type(error_t), allocatable, intent(out) :: error
      k = self%find_group(dim, name)
      if (k == 0) then
         call unknown_group_error(self, dim, name, error)
         return
      end if
      indices = pack_indices(in_entities(element_entity, self%groups(k)%entities))
   end subroutine group_elements

   !> Indices of the triangles in the physical surface `name`, ascending; none is an error
   !> naming the file (an interface needs triangles).
   subroutine mesh_group_triangles(self, name, indices, error)
      class(mesh_t), intent(in) :: self
      !> Physical surface name
      character(len=*), intent(in) :: name
      !> Triangle indices 1..num_tris
      integer(ip), allocatable, intent(out) :: indices(:)
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: k, off_body
      call group_elements(self, 2_ip, name, self%tri_entity, k, indices, error)
      if (allocated(error)) return
      if (size(indices) > 0 .and. allocated(self%off_body_tri_entity)) then
         ! a surface that spans two bodies would silently be cut to the part on this one
         off_body = count(in_entities(self%off_body_tri_entity, self%groups(k)%entities), &
            kind=ip)
         if (off_body > 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(self) // &
               ''': physical surface ''' // trim(name) // ''' does not lie wholly on the ' // &
               'body of physical volume(s) ' // self%volumes // ': ' // to_str(off_body) // &
               ' of its ' // to_str(off_body + size(indices, kind=ip)) // ' triangles are ' // &
               'not faces of the body''s tetrahedra (its area and centroid would be those ' // &
               'of the part on the body); split the surface in the .geo so that each ' // &
               'interface names a surface of one body')
            return
         end if
      end if
      if (size(indices) == 0) then
         if (allocated(self%volumes)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(self) // &
               ''': physical surface ''' // trim(name) // ''' has no triangles in the body ' // &
               'of physical volume(s) ' // self%volumes // ': it is not on the boundary of ' // &
               'those volumes; name a surface of the body (surfaces: ' // &
               self%group_names(2_ip) // ')')
         else
            call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(self) // &
               ''': physical surface ''' // trim(name) // ''' has no triangles; is the ' // &
               'surface meshed (gmsh -3)?')
         end if
      end if
   end subroutine mesh_group_triangles

   !> Sorted unique node indices of the elements (tetrahedra for dim 3, triangles for dim 2, line
   !> elements for dim 1, point elements for dim 0) of the physical group `name`; all element
   !> nodes count, edge nodes of Tet10/Tri6/Line3 included. A curve or point with no node, or
   !> with a node off the body (a body cut by extract_body), is an error naming the group.
   subroutine mesh_group_nodes(self, dim, name, nodes, error)
      class(mesh_t), intent(in) :: self
      !> 0 (physical point), 1 (curve), 2 (surface) or 3 (volume)
      integer(ip), intent(in) :: dim
      !> Physical name
      character(len=*), intent(in) :: name
      !> Node indices 1..num_nodes, ascending
      integer(ip), allocatable, intent(out) :: nodes(:)
      type(error_t), allocatable, intent(out) :: error
      logical, allocatable :: used(:)
      integer(ip) :: k, i, off_body
      if (dim < 0 .or. dim > 3) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(self) // &
            ''': physical group ''' // name // ''' of dimension ' // to_str(dim) // &
            ': groups have dimension 0 (point) to 3 (volume)')
         return
      end if
      k = self%find_group(dim, name)
      if (k == 0) then
         call unknown_group_error(self, dim, name, error)
         return
      end if
      allocate (used(self%num_nodes))
      used = .false.
      if (dim == 3) then
         call mark_nodes(self%tets, in_entities(self%tet_entity, self%groups(k)%entities), used)
      else if (dim == 2) then
         call mark_nodes(self%tris, in_entities(self%tri_entity, self%groups(k)%entities), used)
      else
         off_body = 0
         if (allocated(self%curve_point_nodes)) then
            do i = 1, size(self%curve_point_nodes, 2, kind=ip)
               associate (column => self%curve_point_nodes(:, i))
                  if (column(1) /= dim) cycle
                  if (.not. any(self%groups(k)%entities == column(2))) cycle
                  if (column(3) == 0) then
                     off_body = off_body + 1
                  else
                     used(column(3)) = .true.
                  end if
               end associate
            end do
         end if
         if (off_body > 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(self) // &
               ''': physical ' // dimension_word(dim) // ' ''' // trim(name) // ''' does not ' // &
               'lie wholly on the body of physical volume(s) ' // self%volumes // ': ' // &
               to_str(off_body) // ' of its element nodes are not nodes of the body''s ' // &
               'tetrahedra; name a ' // dimension_word(dim) // ' of the body')
            return
         end if
         if (.not. any(used)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(self) // &
               ''': physical ' // dimension_word(dim) // ' ''' // trim(name) // ''' has no ' // &
               'nodes (no ' // trim(merge('point elements', 'line elements ', dim == 0)) // &
               ' of its entities in the file); mesh it with its physical group (gmsh -3 ' // &
               'saves the elements of physical groups)')
            return
         end if
      end if
      nodes = pack_indices(used)
   end subroutine mesh_group_nodes

   !> Names of the physical groups of dimension `dim` as one string, "a, b, c", for messages;
   !> an unnamed group shows as "(tag 5)", no group as "(none)".
   function mesh_group_names(self, dim) result(names)
      class(mesh_t), intent(in) :: self
      !> 0 point, 1 curve, 2 surface, 3 volume
      integer(ip), intent(in) :: dim
      character(len=:), allocatable :: names
      integer(ip) :: i
      names = ''
      if (allocated(self%groups)) then
         do i = 1, size(self%groups, kind=ip)
            if (self%groups(i)%dim /= dim) cycle
            if (len(names) > 0) names = names // ', '
            if (len(self%groups(i)%name) > 0) then
               names = names // self%groups(i)%name
            else
               names = names // '(tag ' // to_str(self%groups(i)%tag) // ')'
            end if
         end do
      end if
      if (len(names) == 0) names = '(none)'
   end function mesh_group_names

   !> One line for the log: "box.msh: 1234 nodes, 567 Tet10, 89 Tri6, 3 physical groups".
   function mesh_summary(self) result(text)
      class(mesh_t), intent(in) :: self
      character(len=:), allocatable :: text
      integer(ip) :: num_groups
      num_groups = 0
      if (allocated(self%groups)) num_groups = size(self%groups, kind=ip)
      text = ''
      if (allocated(self%file_name)) text = self%file_name // ': '
      text = text // to_str(self%num_nodes) // ' nodes, ' // to_str(self%num_tets()) // ' Tet' // &
         to_str(self%nodes_per_tet) // ', ' // to_str(self%num_tris()) // ' Tri' // &
         to_str(self%nodes_per_tri) // ', ' // to_str(num_groups) // ' physical groups'
   end function mesh_summary

   !> "Tet10", "Hex8", "Prism6" ... of a Gmsh element type, for messages.
   pure function element_type_name(element_type) result(name)
      !> Gmsh element type number
      integer(i8), intent(in) :: element_type
      character(len=:), allocatable :: name
      character(len=9), parameter :: names(31) = [character(len=9) :: 'Line2', 'Tri3', &
         'Quad4', 'Tet4', 'Hex8', 'Prism6', 'Pyramid5', 'Line3', 'Tri6', 'Quad9', 'Tet10', &
         'Hex27', 'Prism18', 'Pyramid14', 'Point', 'Quad8', 'Hex20', 'Prism15', 'Pyramid13', &
         'Tri9', 'Tri10', 'Tri12', 'Tri15', 'Tri15i', 'Tri21', 'Line4', 'Line5', 'Line6', &
         'Tet20', 'Tet35', 'Tet56']
      select case (element_type)
      case (1:31)
         name = trim(names(element_type))
      case (92)
         name = 'Hex64'
      case (93)
         name = 'Hex125'
      case default
         name = 'type ' // to_str(element_type)
      end select
   end function element_type_name

   !> "point", "curve", "surface" or "volume" for dimension 0..3.
   pure function dimension_word(dim) result(word)
      !> Entity dimension
      integer(ip), intent(in) :: dim
      character(len=:), allocatable :: word
      character(len=*), parameter :: words(0:3) = [character(len=7) :: 'point', 'curve', &
         'surface', 'volume']
      if (dim >= 0 .and. dim <= 3) then
         word = trim(words(dim))
      else
         word = 'dimension-' // to_str(dim)
      end if
   end function dimension_word

end module ffrf_mesh_mesh
