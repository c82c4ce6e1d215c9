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
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: physical_group_t, mesh_t, extract_body, dimension_word, element_type_name
   public :: face_connected_parts

   !> Tet10 edge k (node 4 + k) joins corners tet_edges(1, k) and tet_edges(2, k) (Gmsh order)
   integer(ip), parameter :: tet_edges(2, 6) = reshape([1, 2, 2, 3, 1, 3, 1, 4, 3, 4, 2, 4], &
      [2, 6])
   !> Face k of a tetrahedron: the corners other than corner k
   integer(ip), parameter :: tet_faces(3, 4) = reshape([2, 3, 4, 1, 3, 4, 1, 2, 4, 1, 2, 3], &
      [3, 4])
   !> Tri6 edge k (node 3 + k) joins corners tri_edges(1, k) and tri_edges(2, k)
   integer(ip), parameter :: tri_edges(2, 3) = reshape([1, 2, 2, 3, 1, 3], [2, 3])

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

contains

   !> Number of tetrahedra.
   pure function mesh_num_tets(self) result(count)
      class(mesh_t), intent(in) :: self
      integer(ip) :: count
      count = 0
      if (allocated(self%tets)) count = size(self%tets, 2, kind=ip)
   end function mesh_num_tets

   !> Number of triangles.
   pure function mesh_num_tris(self) result(count)
      class(mesh_t), intent(in) :: self
      integer(ip) :: count
      count = 0
      if (allocated(self%tris)) count = size(self%tris, 2, kind=ip)
   end function mesh_num_tris

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
      k = self%find_group(3_ip, name)
      if (k == 0) then
         call unknown_group_error(self, 3_ip, name, error)
         return
      end if
      indices = pack_indices(in_entities(self%tet_entity, self%groups(k)%entities))
   end subroutine mesh_group_tets

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
      k = self%find_group(2_ip, name)
      if (k == 0) then
         call unknown_group_error(self, 2_ip, name, error)
         return
      end if
      indices = pack_indices(in_entities(self%tri_entity, self%groups(k)%entities))
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

   !> Sorted unique node indices of the elements (tetrahedra for dim 3, triangles for dim 2) of
   !> the physical group `name`; all element nodes count, edge nodes of Tet10/Tri6 included.
   subroutine mesh_group_nodes(self, dim, name, nodes, error)
      class(mesh_t), intent(in) :: self
      !> 2 (physical surface) or 3 (physical volume)
      integer(ip), intent(in) :: dim
      !> Physical name
      character(len=*), intent(in) :: name
      !> Node indices 1..num_nodes, ascending
      integer(ip), allocatable, intent(out) :: nodes(:)
      type(error_t), allocatable, intent(out) :: error
      logical, allocatable :: used(:)
      integer(ip) :: k
      if (dim /= 2 .and. dim /= 3) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // self%file_name // &
            ''': physical group ''' // name // ''' of dimension ' // to_str(dim) // &
            ': only surface (2) and volume (3) groups hold elements')
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
      else
         call mark_nodes(self%tris, in_entities(self%tri_entity, self%groups(k)%entities), used)
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

   !> A new mesh holding one body: the tetrahedra of the physical volumes `volume_names`, only the
   !> nodes they use (renumbered 1..n in increasing order of the old index, `node_tags` kept),
   !> the triangles all of whose nodes are in the body and which are faces of its tetrahedra
   !> (renumbered) and all physical groups.
   !>
   !> The body is checked once here (FFRF_INPUT_ERROR naming the file and the element, node or
   !> group): its volumes hold no other volume elements than tetrahedra; no two tetrahedra have
   !> the same corners; in a Tet10 mesh every edge has one mid-side node and every mid-side node
   !> one edge (a crack otherwise); the tetrahedra form one piece (node-connected); every
   !> triangle all of whose nodes are in the body is a face of a tetrahedron of the mesh and, if
   !> a Tri6, has that face's mid-side nodes. Each check is O(n) with hashing or arrays indexed by
   !> node. Inverted and degenerate tetrahedra are refused where the elements are integrated
   !> (`tet_check_jacobian`, ffrf_fe_tet), with the element tag.
   subroutine extract_body(mesh, volume_names, body, error)
      !> Whole mesh
      type(mesh_t), intent(in) :: mesh
      !> Physical volumes that make up the body
      character(len=*), intent(in) :: volume_names(:)
      !> The body's mesh
      type(mesh_t), intent(out) :: body
      type(error_t), allocatable, intent(out) :: error
      logical, allocatable :: keep_tet(:), keep_tri(:), used(:)
      integer(ip), allocatable :: new_index(:), selected(:)
      integer(ip) :: i, k, n, stat

      if (mesh%num_tets() == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(mesh) // &
            ''' holds no tetrahedra, so no body can be cut from it; Gmsh saves only the ' // &
            'elements of physical groups once any group exists (toolchain pitfall 13): add a ' // &
            'Physical Volume and mesh with gmsh -3')
         return
      end if
      if (size(volume_names) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(mesh) // &
            ''': no physical volume named for the body; volumes: ' // mesh%group_names(3_ip))
         return
      end if

      allocate (keep_tet(mesh%num_tets()), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(mesh) // &
            ''': out of memory for ' // to_str(mesh%num_tets()) // ' tetrahedra')
         return
      end if
      keep_tet = .false.
      do i = 1, size(volume_names, kind=ip)
         k = mesh%find_group(3_ip, trim(volume_names(i)))
         if (k == 0) then
            call unknown_group_error(mesh, 3_ip, trim(volume_names(i)), error)
            return
         end if
         keep_tet = keep_tet .or. in_entities(mesh%tet_entity, mesh%groups(k)%entities)
      end do
      call check_other_volume_elements(mesh, volume_names, error)
      if (allocated(error)) return
      if (.not. any(keep_tet)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(mesh) // &
            ''': physical volumes ' // quoted_list(volume_names) // ' hold no tetrahedra; ' // &
            'check that the Physical Volume lists the meshed volumes')
         return
      end if

      ! Nodes: keep the used ones, in increasing order of the old index.
      allocate (used(mesh%num_nodes), new_index(mesh%num_nodes))
      used = .false.
      call mark_nodes(mesh%tets, keep_tet, used)
      n = 0
      do i = 1, mesh%num_nodes
         if (used(i)) then
            n = n + 1
            new_index(i) = n
         else
            new_index(i) = 0
         end if
      end do

      ! Triangles: those all of whose nodes are in the body, if faces of its tetrahedra.
      allocate (keep_tri(mesh%num_tris()))
      do i = 1, mesh%num_tris()
         keep_tri(i) = all(used(mesh%tris(:, i)))
      end do
      call check_triangle_faces(mesh, keep_tet, keep_tri, error)
      if (allocated(error)) return

      ! A body of every node (one body per file, the usual case) keeps the node indices.
      body%num_nodes = n
      if (n == mesh%num_nodes) then
         body%xyz = mesh%xyz
         body%node_tags = mesh%node_tags
      else
         selected = pack_indices(used)
         body%xyz = mesh%xyz(:, selected)
         body%node_tags = mesh%node_tags(selected)
      end if

      body%nodes_per_tet = mesh%nodes_per_tet
      if (all(keep_tet)) then
         if (n == mesh%num_nodes) then
            body%tets = mesh%tets
         else
            body%tets = renumbered(mesh%tets, pack_indices(keep_tet), new_index)
         end if
         body%tet_tags = mesh%tet_tags
         body%tet_entity = mesh%tet_entity
      else
         selected = pack_indices(keep_tet)
         body%tets = renumbered(mesh%tets, selected, new_index)
         body%tet_tags = mesh%tet_tags(selected)
         body%tet_entity = mesh%tet_entity(selected)
      end if

      selected = pack_indices(keep_tri)
      body%nodes_per_tri = mesh%nodes_per_tri
      if (size(selected) == 0) body%nodes_per_tri = 0
      allocate (body%tris(body%nodes_per_tri, size(selected)))
      allocate (body%tri_tags(size(selected)), body%tri_entity(size(selected)))
      if (size(selected) > 0) then
         body%tris = renumbered(mesh%tris, selected, new_index)
         body%tri_tags = mesh%tri_tags(selected)
         body%tri_entity = mesh%tri_entity(selected)
      end if

      if (allocated(mesh%groups)) then
         body%groups = mesh%groups
      else
         allocate (body%groups(0))
      end if
      allocate (body%other_volume_elements(4, 0))
      body%file_name = file_of(mesh)
      body%volumes = quoted_list(volume_names)
      body%off_body_tri_entity = pack(mesh%tri_entity, .not. keep_tri)

      call check_duplicate_tets(body, error)
      if (allocated(error)) return
      call check_tet_nodes(body, error)
   end subroutine extract_body

   !> The body's volumes must hold tetrahedra only: a hexahedron, prism or pyramid the reader
   !> skipped would be missing from mass and stiffness.
   subroutine check_other_volume_elements(mesh, volume_names, error)
      type(mesh_t), intent(in) :: mesh
      character(len=*), intent(in) :: volume_names(:)
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: counts(0:100), first_tag(0:100), entity(0:100), group(0:100)
      character(len=:), allocatable :: found
      integer(ip) :: i, k, g, t
      logical :: higher_order
      if (.not. allocated(mesh%other_volume_elements)) return
      if (size(mesh%other_volume_elements, 2) == 0) return
      counts = 0
      do i = 1, size(mesh%other_volume_elements, 2, kind=ip)
         do g = 1, size(volume_names, kind=ip)
            k = mesh%find_group(3_ip, trim(volume_names(g)))
            if (k == 0) cycle
            if (.not. any(mesh%groups(k)%entities == mesh%other_volume_elements(1, i))) cycle
            t = int(min(100_i8, max(0_i8, mesh%other_volume_elements(2, i))), ip)
            if (counts(t) == 0) then
               first_tag(t) = mesh%other_volume_elements(4, i)
               entity(t) = mesh%other_volume_elements(1, i)
               group(t) = g
            end if
            counts(t) = counts(t) + mesh%other_volume_elements(3, i)
            exit
         end do
      end do
      if (all(counts == 0)) return
      found = ''
      higher_order = .false.
      do t = 0, 100
         if (counts(t) == 0) cycle
         if (len(found) > 0) found = found // ', '
         found = found // to_str(counts(t)) // ' ' // element_type_name(int(t, i8)) // &
            ' (Gmsh type ' // to_str(t) // ', first element ' // to_str(first_tag(t)) // &
            ', physical volume ''' // trim(volume_names(group(t))) // ''', volume entity ' // &
            to_str(entity(t)) // ')'
         if (t == 29 .or. t == 30 .or. t == 31) higher_order = .true.
      end do
      found = 'mesh ''' // file_of(mesh) // ''': the body''s volumes hold ' // found // &
         ' besides tetrahedra; ffrf uses only Tet4 and Tet10 volume elements, so mass and ' // &
         'stiffness would be wrong: mesh the volumes with tetrahedra only'
      if (higher_order) then
         call fatal_error(error, FFRF_INPUT_ERROR, found // ' of order 1 or 2 ' // &
            '(-setnumber order 1 or 2, Mesh.ElementOrder <= 2)')
      else
         call fatal_error(error, FFRF_INPUT_ERROR, found // ' (no Recombine or ' // &
            'Mesh.Recombine3DAll, Mesh.SubdivisionAlgorithm = 0, a tetrahedral ' // &
            'Mesh.Algorithm3D such as 1 Delaunay or 10 HXT, no transfinite volumes)')
      end if
   end subroutine check_other_volume_elements

   !> Every candidate triangle (keep_tri) must be a face of a tetrahedron of the mesh: of the
   !> body's (kept, with a Tri6's mid-side nodes those of the face) or, only, of another body's
   !> (dropped: it lies on that body). Only tetrahedra with three corners on candidate triangles
   !> are looked at; the triangles are found through a hash table of their sorted corners.
   subroutine check_triangle_faces(mesh, keep_tet, keep_tri, error)
      type(mesh_t), intent(in) :: mesh
      logical, intent(in) :: keep_tet(:)
      logical, intent(inout) :: keep_tri(:)
      type(error_t), allocatable, intent(out) :: error
      logical, allocatable :: on_triangle(:), in_body(:), anywhere(:)
      integer(ip), allocatable :: table(:), keys(:, :)
      integer(ip) :: t, e, f, slot, mask, key(3), hits, j
      if (mesh%num_tris() == 0 .or. .not. any(keep_tri)) return
      allocate (on_triangle(mesh%num_nodes), keys(3, mesh%num_tris()))
      on_triangle = .false.
      mask = hash_mask(count(keep_tri, kind=ip))
      allocate (table(0:mask), source=0_ip)
      do t = 1, mesh%num_tris()
         if (.not. keep_tri(t)) cycle
         keys(:, t) = sorted3(mesh%tris(1:3, t))
         on_triangle(keys(:, t)) = .true.
         slot = hash_slot(key_hash(keys(:, t)), mask)
         do while (table(slot) /= 0)
            slot = iand(slot + 1, mask)
         end do
         table(slot) = t
      end do
      allocate (in_body(mesh%num_tris()), anywhere(mesh%num_tris()))
      in_body = .false.
      anywhere = .false.
      do e = 1, mesh%num_tets()
         hits = 0
         do j = 1, 4
            if (on_triangle(mesh%tets(j, e))) hits = hits + 1
         end do
         if (hits < 3) cycle
         do f = 1, 4
            if (.not. all(on_triangle(mesh%tets(tet_faces(:, f), e)))) cycle
            key = sorted3(mesh%tets(tet_faces(:, f), e))
            slot = hash_slot(key_hash(key), mask)
            do while (table(slot) /= 0)
               t = table(slot)
               if (all(keys(:, t) == key)) then
                  anywhere(t) = .true.
                  if (keep_tet(e) .and. .not. in_body(t)) then
                     in_body(t) = .true.
                     if (mesh%nodes_per_tri == 6 .and. mesh%nodes_per_tet == 10) then
                        call check_tri6_edges(mesh, t, e, error)
                        if (allocated(error)) return
                     end if
                  end if
               end if
               slot = iand(slot + 1, mask)
            end do
         end do
      end do
      do t = 1, mesh%num_tris()
         if (.not. keep_tri(t)) cycle
         if (.not. anywhere(t)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(mesh) // &
               ''': triangle ' // to_str(mesh%tri_tags(t)) // ' of ' // &
               entity_groups(mesh, 2_ip, mesh%tri_entity(t)) // ' (surface entity ' // &
               to_str(mesh%tri_entity(t)) // '; nodes ' // tag_list(mesh, mesh%tris(1:3, t)) // &
               ') is not a face of any tetrahedron, so its area and centroid are not those ' // &
               'of the body''s surface; mesh surfaces and volumes together (gmsh -3) and ' // &
               'do not edit the elements')
            return
         end if
         keep_tri(t) = in_body(t)
      end do
   end subroutine check_triangle_faces

   !> The mid-side nodes of Tri6 `t` are those of the same edges of Tet10 `e`, of which it is a
   !> face.
   subroutine check_tri6_edges(mesh, t, e, error)
      type(mesh_t), intent(in) :: mesh
      integer(ip), intent(in) :: t, e
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: k, m, a, b
      do k = 1, 3
         a = mesh%tris(tri_edges(1, k), t)
         b = mesh%tris(tri_edges(2, k), t)
         do m = 1, 6
            associate (p => mesh%tets(tet_edges(1, m), e), q => mesh%tets(tet_edges(2, m), e))
               if (.not. ((p == a .and. q == b) .or. (p == b .and. q == a))) cycle
               if (mesh%tets(4 + m, e) /= mesh%tris(3 + k, t)) then
                  call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(mesh) // &
                     ''': triangle ' // to_str(mesh%tri_tags(t)) // ' of ' // &
                     entity_groups(mesh, 2_ip, mesh%tri_entity(t)) // ' has mid-side node ' // &
                     to_str(mesh%node_tags(mesh%tris(3 + k, t))) // ' on its edge ' // &
                     tag_list(mesh, [a, b]) // ', tetrahedron ' // to_str(mesh%tet_tags(e)) // &
                     ' has node ' // to_str(mesh%node_tags(mesh%tets(4 + m, e))) // &
                     ' there; the surface mesh does not conform to the volume mesh')
                  return
               end if
            end associate
         end do
      end do
   end subroutine check_tri6_edges

   !> No two tetrahedra with the same corners (a duplicate doubles mass and stiffness there):
   !> open-addressing table of the hashes of the sorted corners, each with its tetrahedron (hash
   !> times 2**32 plus index, 8 bytes a slot); an equal hash is verified against that tetrahedron.
   subroutine check_duplicate_tets(body, error)
      type(mesh_t), intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      integer(i8), parameter :: low32 = 4294967295_i8
      integer(i8), allocatable :: table(:)
      integer(i8) :: entry
      integer(ip) :: e, f, slot, mask, h, key(4)
      mask = hash_mask(body%num_tets())
      allocate (table(0:mask), source=0_i8)
      do e = 1, body%num_tets()
         key = sorted4(body%tets(1:4, e))
         h = key_hash(key)
         slot = hash_slot(h, mask)
         do
            entry = table(slot)
            if (entry == 0) exit
            if (ishft(entry, -32) == h) then
               f = int(iand(entry, low32), ip)
               if (all(sorted4(body%tets(1:4, f)) == key)) then
                  call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(body) // &
                     ''': tetrahedra ' // to_str(body%tet_tags(f)) // ' and ' // &
                     to_str(body%tet_tags(e)) // ' of physical volume(s) ' // &
                     body%volumes // ' have the same corner nodes ' // tag_list(body, key) // &
                     '; a duplicate element doubles mass and stiffness: remove it (or re-mesh)')
                  return
               end if
            end if
            slot = iand(slot + 1, mask)
         end do
         table(slot) = ior(ishft(int(h, i8), 32), int(e, i8))
      end do
   end subroutine check_duplicate_tets

   !> Tet10 conformity and connectivity, in one pass over the tetrahedra with arrays indexed by
   !> node: O(n).
   !>
   !> Tet10: every mid-side node sits on one edge (pair of corners) only and is no corner, and
   !> every edge has one mid-side node. Two mid-side nodes on one edge are a crack: the
   !> neighbours are not connected along it.
   !>
   !> Connectivity: the tetrahedra form one piece, by union-find over their corners (with the
   !> Tet10 checks passed a mid-side node joins nothing its edge's corners do not). Each further
   !> piece would add six rigid-body modes the modal reduction takes for flexible ones.
   subroutine check_tet_nodes(body, error)
      type(mesh_t), intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      !> Union-find forest over the corners; 0 for a node not (yet) seen as a corner
      integer(ip), allocatable :: parent(:)
      !> edge(:, m) = (low, high) corners of the edge of mid-side node m, 0 for other nodes
      integer(ip), allocatable :: edge(:, :)
      !> Open-addressing table of the mid-side nodes (0 empty), hashed by their edges
      integer(ip), allocatable :: table(:)
      integer(ip) :: e, k, f, j, a, b, low, high, m, other, slot, mask, root, corner(4)
      integer(ip) :: num_corners, num_midside, num_pieces
      logical :: tet10
      tet10 = body%nodes_per_tet == 10
      allocate (parent(body%num_nodes), source=0_ip)
      if (tet10) allocate (edge(2, body%num_nodes), source=0_ip)
      num_corners = 0
      num_midside = 0
      num_pieces = 0
      do e = 1, body%num_tets()
         corner = body%tets(1:4, e)
         do k = 1, 4
            if (parent(corner(k)) /= 0) cycle
            parent(corner(k)) = corner(k)
            num_corners = num_corners + 1
         end do
         root = find_root(parent, corner(1))
         do k = 2, 4
            other = find_root(parent, corner(k))
            if (other /= root) then
               ! Attach the larger index under the smaller: roots are the smallest nodes
               if (other < root) then
                  parent(root) = other
                  root = other
               else
                  parent(other) = root
               end if
               num_pieces = num_pieces - 1
            end if
         end do
         if (.not. tet10) cycle
         do k = 1, 6
            a = corner(tet_edges(1, k))
            b = corner(tet_edges(2, k))
            m = body%tets(4 + k, e)
            low = min(a, b)
            high = max(a, b)
            if (edge(1, m) == 0) then
               edge(1, m) = low
               edge(2, m) = high
               num_midside = num_midside + 1
            else if (edge(1, m) /= low .or. edge(2, m) /= high) then
               call shared_midside_error(body, m, edge(:, m), [low, high], e, error)
               return
            end if
         end do
      end do
      if (tet10) then
         ! Every edge has one mid-side node: a second node on one edge is a crack. The table
         ! holds the first mid-side node of each edge; an equal edge is found on probing.
         mask = hash_mask(num_midside)
         allocate (table(0:mask), source=0_ip)
         do m = 1, body%num_nodes
            if (edge(1, m) == 0) cycle
            slot = hash_slot(key_hash(edge(:, m)), mask)
            do while (table(slot) /= 0)
               other = table(slot)
               if (edge(1, other) == edge(1, m) .and. edge(2, other) == edge(2, m)) then
                  call two_midside_error(body, other, m, edge(:, m), error)
                  return
               end if
               slot = iand(slot + 1, mask)
            end do
            table(slot) = m
         end do
         ! Every node of the body is a corner or a mid-side node: more of both than nodes
         ! means a node is both.
         if (num_corners + num_midside /= body%num_nodes) then
            do f = 1, body%num_tets()
               do j = 5, 10
                  if (parent(body%tets(j, f)) == 0) cycle
                  call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(body) // &
                     ''': node ' // to_str(body%node_tags(body%tets(j, f))) // ' is a ' // &
                     'mid-side node of tetrahedron ' // to_str(body%tet_tags(f)) // ' and a ' // &
                     'corner of another one; the Tet10 mesh is not conforming: re-mesh ' // &
                     '(gmsh -3 with order 2)')
                  return
               end do
            end do
         end if
      end if
      num_pieces = num_pieces + num_corners
      if (num_pieces > 1) call pieces_error(body, parent, num_pieces, error)
   end subroutine check_tet_nodes


   !> Mid-side node m of edge `new_edge` of tetrahedron e sits on `old_edge` too.
   subroutine shared_midside_error(body, m, old_edge, new_edge, e, error)
      type(mesh_t), intent(in) :: body
      integer(ip), intent(in) :: m, old_edge(2), new_edge(2), e
      type(error_t), allocatable, intent(out) :: error
      call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(body) // ''': node ' // &
         to_str(body%node_tags(m)) // ' is the mid-side node of edge ' // &
         tag_list(body, new_edge) // ' of tetrahedron ' // to_str(body%tet_tags(e)) // &
         ' and of edge ' // tag_list(body, old_edge) // '; the Tet10 mesh is not ' // &
         'conforming: re-mesh (gmsh -3 with order 2)')
   end subroutine shared_midside_error

   !> Edge `edge` has the mid-side nodes m1 and m2: name them and a tetrahedron of each.
   subroutine two_midside_error(body, m1, m2, edge, error)
      type(mesh_t), intent(in) :: body
      integer(ip), intent(in) :: m1, m2, edge(2)
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: t1, t2, f, j
      t1 = 1
      t2 = 1
      do f = body%num_tets(), 1, -1
         do j = 5, 10
            if (body%tets(j, f) == m1) t1 = f
            if (body%tets(j, f) == m2) t2 = f
         end do
      end do
      call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(body) // ''': edge ' // &
         tag_list(body, edge) // ' has two mid-side nodes, ' // to_str(body%node_tags(m1)) // &
         ' (tetrahedron ' // to_str(body%tet_tags(t1)) // ') and ' // &
         to_str(body%node_tags(m2)) // ' (tetrahedron ' // to_str(body%tet_tags(t2)) // &
         '): the neighbours are not connected along it (a crack); the Tet10 mesh is not ' // &
         'conforming: re-mesh (gmsh -3 with order 2)')
   end subroutine two_midside_error


   !> The body is in `num_pieces` pieces: name them (nodes, tetrahedra, first tetrahedron,
   !> bounding box), the largest first, five at most.
   subroutine pieces_error(body, parent, num_pieces, error)
      type(mesh_t), intent(in) :: body
      integer(ip), intent(inout) :: parent(:)
      integer(ip), intent(in) :: num_pieces
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: piece_of_root(:), num_tets(:), num_nodes(:), first_tet(:)
      integer(ip), allocatable :: piece_of_node(:)
      real(dp), allocatable :: low(:, :), high(:, :)
      character(len=:), allocatable :: text
      integer(ip) :: e, k, p, root, shown, best
      logical, allocatable :: listed(:)
      allocate (piece_of_root(body%num_nodes), piece_of_node(body%num_nodes))
      allocate (num_tets(num_pieces), num_nodes(num_pieces), first_tet(num_pieces))
      allocate (low(3, num_pieces), high(3, num_pieces), listed(num_pieces))
      piece_of_root = 0
      piece_of_node = 0
      num_tets = 0
      num_nodes = 0
      low = huge(1.0_dp)
      high = -huge(1.0_dp)
      p = 0
      do e = 1, body%num_tets()
         root = find_root(parent, body%tets(1, e))
         if (piece_of_root(root) == 0) then
            p = p + 1
            piece_of_root(root) = p
            first_tet(p) = e
         end if
         num_tets(piece_of_root(root)) = num_tets(piece_of_root(root)) + 1
         do k = 1, size(body%tets, 1, kind=ip)
            if (piece_of_node(body%tets(k, e)) /= 0) cycle
            piece_of_node(body%tets(k, e)) = piece_of_root(root)
            num_nodes(piece_of_root(root)) = num_nodes(piece_of_root(root)) + 1
            low(:, piece_of_root(root)) = min(low(:, piece_of_root(root)), &
               body%xyz(:, body%tets(k, e)))
            high(:, piece_of_root(root)) = max(high(:, piece_of_root(root)), &
               body%xyz(:, body%tets(k, e)))
         end do
      end do
      text = 'mesh ''' // file_of(body) // ''': the body of physical volume(s) ' // &
         body%volumes // ' is in ' // to_str(num_pieces) // ' pieces that share no node'
      listed = .false.
      do shown = 1, min(5_ip, num_pieces)
         best = 0
         do p = 1, num_pieces
            if (listed(p)) cycle
            if (best == 0) then
               best = p
            else if (num_tets(p) > num_tets(best)) then
               best = p
            end if
         end do
         listed(best) = .true.
         text = text // merge(': ', '; ', shown == 1) // 'piece ' // to_str(shown) // ' has ' // &
            to_str(num_nodes(best)) // ' nodes and ' // to_str(num_tets(best)) // &
            ' tetrahedra (first ' // to_str(body%tet_tags(first_tet(best))) // '), box (' // &
            to_str(low(1, best)) // ', ' // to_str(low(2, best)) // ', ' // &
            to_str(low(3, best)) // ') .. (' // to_str(high(1, best)) // ', ' // &
            to_str(high(2, best)) // ', ' // to_str(high(3, best)) // ')'
      end do
      if (num_pieces > 5) text = text // '; ...'
      call fatal_error(error, FFRF_INPUT_ERROR, text // '; each piece would move freely: ' // &
         'join the volumes so they share nodes (BooleanFragments or Coherence before meshing) ' // &
         'or make each piece a body of its own')
   end subroutine pieces_error

   !> The parts of the body's tetrahedra connected through shared faces (three common corners):
   !> union-find over the tetrahedra, each face matched in the list of tetrahedra at one of its
   !> corners. extract_body has made the body one node-connected piece; more than one face-
   !> connected part means parts that hinge on a node or an edge, each joint a motion without
   !> strain. O(tetrahedra x tetrahedra per node).
   subroutine face_connected_parts(body, num_parts, part_of_tet)
      !> The body's mesh
      type(mesh_t), intent(in) :: body
      !> Number of face-connected parts
      integer(ip), intent(out) :: num_parts
      !> Part of each tetrahedron, 1..num_parts in the order of their first tetrahedron
      integer(ip), allocatable, intent(out) :: part_of_tet(:)
      integer(ip), allocatable :: start(:), list(:), fill(:), parent(:), part_of_root(:)
      integer(ip) :: e, f, k, p, t, a, root, other, nt, corner(3)
      nt = body%num_tets()
      allocate (start(body%num_nodes + 1), source=0_ip)
      do e = 1, nt
         do k = 1, 4
            start(body%tets(k, e) + 1) = start(body%tets(k, e) + 1) + 1
         end do
      end do
      start(1) = 1
      do k = 1, body%num_nodes
         start(k + 1) = start(k + 1) + start(k)
      end do
      allocate (list(start(body%num_nodes + 1) - 1), fill(body%num_nodes))
      fill = start(1:body%num_nodes)
      do e = 1, nt
         do k = 1, 4
            a = body%tets(k, e)
            list(fill(a)) = e
            fill(a) = fill(a) + 1
         end do
      end do
      parent = [(e, e=1, nt)]
      do e = 1, nt
         do f = 1, 4
            corner = body%tets(tet_faces(:, f), e)
            do p = start(corner(1)), start(corner(1) + 1) - 1
               t = list(p)
               if (t == e) cycle
               if (.not. (any(body%tets(1:4, t) == corner(2)) .and. &
                          any(body%tets(1:4, t) == corner(3)))) cycle
               root = find_root(parent, e)
               other = find_root(parent, t)
               if (root /= other) parent(max(root, other)) = min(root, other)
            end do
         end do
      end do
      allocate (part_of_root(nt), source=0_ip)
      allocate (part_of_tet(nt))
      num_parts = 0
      do e = 1, nt
         root = find_root(parent, e)
         if (part_of_root(root) == 0) then
            num_parts = num_parts + 1
            part_of_root(root) = num_parts
         end if
         part_of_tet(e) = part_of_root(root)
      end do
   end subroutine face_connected_parts

   !> Root of node `i` in the union-find forest, halving the path.
   function find_root(parent, i) result(root)
      integer(ip), intent(inout) :: parent(:)
      integer(ip), intent(in) :: i
      integer(ip) :: root
      root = i
      do while (parent(root) /= root)
         parent(root) = parent(parent(root))
         root = parent(root)
      end do
   end function find_root

   !> Mask (slots - 1) of an open-addressing table of at least 2 n slots, a power of 2.
   pure function hash_mask(n) result(mask)
      integer(ip), intent(in) :: n
      integer(ip) :: mask
      integer(ip) :: num_slots
      num_slots = 64
      do while (num_slots < 2 * n)
         num_slots = 2 * num_slots
      end do
      mask = num_slots - 1
   end function hash_mask

   !> Hash 1 .. 2**31 - 1 of a key of node indices (< 2**31): a polynomial modulo 2**31 (each
   !> product < 2**51); 0 marks an empty slot.
   pure function key_hash(key) result(h)
      integer(ip), intent(in) :: key(:)
      integer(ip) :: h
      integer(i8), parameter :: low31 = 2147483647_i8
      integer(i8) :: value
      integer :: k
      value = 0
      do k = 1, size(key)
         value = iand(value * 1000003_i8 + key(k), low31)
      end do
      h = int(max(1_i8, value), ip)
   end function key_hash

   !> First slot of hash h in a table of mask + 1 (a power of 2, at most 2**31) slots:
   !> Fibonacci hashing, the upper bits of h times 2**32 / golden ratio (< 2**63).
   pure function hash_slot(h, mask) result(slot)
      integer(ip), intent(in) :: h, mask
      integer(ip) :: slot
      slot = int(iand(ishft(int(h, i8) * 2654435761_i8, -28), int(mask, i8)), ip)
   end function hash_slot

   !> The three values ascending.
   pure function sorted3(x) result(y)
      integer(ip), intent(in) :: x(3)
      integer(ip) :: y(3)
      y = x
      if (y(1) > y(2)) y(1:2) = y([2, 1])
      if (y(2) > y(3)) y(2:3) = y([3, 2])
      if (y(1) > y(2)) y(1:2) = y([2, 1])
   end function sorted3

   !> The four values ascending (a sorting network of five compare-exchanges).
   pure function sorted4(x) result(y)
      integer(ip), intent(in) :: x(4)
      integer(ip) :: y(4)
      integer(ip) :: a, b, c, d, t
      a = min(x(1), x(2))
      b = max(x(1), x(2))
      c = min(x(3), x(4))
      d = max(x(3), x(4))
      t = min(a, c)
      c = max(a, c)
      a = t
      t = max(b, d)
      b = min(b, d)
      d = t
      y(1) = a
      y(2) = min(b, c)
      y(3) = max(b, c)
      y(4) = d
   end function sorted4

   !> "(tags 3, 7, 9)" of node indices, for messages.
   function tag_list(mesh, nodes) result(text)
      type(mesh_t), intent(in) :: mesh
      integer(ip), intent(in) :: nodes(:)
      character(len=:), allocatable :: text
      integer :: k
      text = '('
      do k = 1, size(nodes)
         if (k > 1) text = text // ', '
         text = text // to_str(mesh%node_tags(nodes(k)))
      end do
      text = text // ')'
   end function tag_list

   !> "physical surface 'B2'" (or "physical surfaces 'a', 'b'", or "no physical surface") of the
   !> groups of dimension `dim` holding `entity`.
   function entity_groups(mesh, dim, entity) result(text)
      type(mesh_t), intent(in) :: mesh
      integer(ip), intent(in) :: dim, entity
      character(len=:), allocatable :: text
      integer(ip) :: k, found
      text = ''
      found = 0
      if (allocated(mesh%groups)) then
         do k = 1, size(mesh%groups, kind=ip)
            if (mesh%groups(k)%dim /= dim) cycle
            if (.not. any(mesh%groups(k)%entities == entity)) cycle
            found = found + 1
            if (found > 1) text = text // ', '
            if (len(mesh%groups(k)%name) > 0) then
               text = text // '''' // mesh%groups(k)%name // ''''
            else
               text = text // '(tag ' // to_str(mesh%groups(k)%tag) // ')'
            end if
         end do
      end if
      if (found == 0) then
         text = 'no physical ' // dimension_word(dim)
      else if (found == 1) then
         text = 'physical ' // dimension_word(dim) // ' ' // text
      else
         text = 'physical ' // dimension_word(dim) // 's ' // text
      end if
   end function entity_groups

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
      select case (dim)
      case (0)
         word = 'point'
      case (1)
         word = 'curve'
      case (2)
         word = 'surface'
      case (3)
         word = 'volume'
      case default
         word = 'dimension-' // to_str(dim)
      end select
   end function dimension_word

   !> "mesh 'crank.msh': no physical volume 'crnk'; volumes: crank".
   subroutine unknown_group_error(mesh, dim, name, error)
      type(mesh_t), intent(in) :: mesh
      integer(ip), intent(in) :: dim
      character(len=*), intent(in) :: name
      type(error_t), allocatable, intent(out) :: error
      call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(mesh) // &
         ''': no physical ' // dimension_word(dim) // ' ''' // trim(name) // '''; ' // &
         dimension_word(dim) // 's: ' // mesh%group_names(dim))
   end subroutine unknown_group_error

   !> The file name, or "(unnamed)" for a mesh not read from a file.
   pure function file_of(mesh) result(name)
      type(mesh_t), intent(in) :: mesh
      character(len=:), allocatable :: name
      if (allocated(mesh%file_name)) then
         name = mesh%file_name
      else
         name = '(unnamed)'
      end if
   end function file_of

   !> "'a', 'b'" for messages.
   pure function quoted_list(words) result(text)
      character(len=*), intent(in) :: words(:)
      character(len=:), allocatable :: text
      integer :: i
      text = ''
      do i = 1, size(words)
         if (i > 1) text = text // ', '
         text = text // '''' // trim(words(i)) // ''''
      end do
   end function quoted_list

   !> For each element, whether its entity tag is one of `entities`.
   pure function in_entities(element_entity, entities) result(inside)
      !> Entity tag of each element
      integer(ip), intent(in) :: element_entity(:)
      !> Entity tags of a physical group
      integer(ip), intent(in) :: entities(:)
      logical :: inside(size(element_entity))
      logical, allocatable :: lookup(:)
      integer(ip) :: low, high, i
      inside = .false.
      if (size(element_entity) == 0 .or. size(entities) == 0) return
      ! A direct table over the range of element entity tags (entity tags are small integers);
      ! a plain search if they are spread far apart.
      low = minval(element_entity)
      high = maxval(element_entity)
      if (int(high, i8) - low > 4_i8 * size(element_entity) + 1024_i8) then
         do i = 1, size(element_entity, kind=ip)
            inside(i) = any(entities == element_entity(i))
         end do
         return
      end if
      allocate (lookup(low:high))
      lookup = .false.
      do i = 1, size(entities, kind=ip)
         if (entities(i) >= low .and. entities(i) <= high) lookup(entities(i)) = .true.
      end do
      do i = 1, size(element_entity, kind=ip)
         inside(i) = lookup(element_entity(i))
      end do
   end function in_entities

   !> Set used(node) for every node of the selected elements.
   pure subroutine mark_nodes(elements, selected, used)
      !> (nodes_per_element, num_elements) node indices
      integer(ip), intent(in) :: elements(:, :)
      !> Which elements count
      logical, intent(in) :: selected(:)
      !> Node flags, set where used
      logical, intent(inout) :: used(:)
      integer(ip) :: e, k
      do e = 1, size(elements, 2, kind=ip)
         if (.not. selected(e)) cycle
         do k = 1, size(elements, 1, kind=ip)
            used(elements(k, e)) = .true.
         end do
      end do
   end subroutine mark_nodes

   !> Columns `selected` of `elements` with every node index i replaced by new_index(i).
   pure function renumbered(elements, selected, new_index) result(subset)
      !> (nodes_per_element, num_elements) node indices
      integer(ip), intent(in) :: elements(:, :)
      !> Elements to keep, in this order
      integer(ip), intent(in) :: selected(:)
      !> New index of every old node index
      integer(ip), intent(in) :: new_index(:)
      integer(ip) :: subset(size(elements, 1), size(selected))
      integer(ip) :: e, k
      do e = 1, size(selected, kind=ip)
         do k = 1, size(elements, 1, kind=ip)
            subset(k, e) = new_index(elements(k, selected(e)))
         end do
      end do
   end function renumbered

   !> Positions of the true entries of `mask`, ascending.
   pure function pack_indices(mask) result(indices)
      logical, intent(in) :: mask(:)
      integer(ip), allocatable :: indices(:)
      integer(ip) :: i, n
      allocate (indices(count(mask)))
      n = 0
      do i = 1, size(mask, kind=ip)
         if (mask(i)) then
            n = n + 1
            indices(n) = i
         end if
      end do
   end function pack_indices

end module ffrf_mesh_mesh
