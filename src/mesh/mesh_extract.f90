!> ffrf_mesh_mesh: extract_body (one body cut out of a mesh), the checks of its nodes (Tet10
!> mid-side nodes, one node-connected piece), its face-connected parts, and the helpers the module
!> shares with its submodules (file names, index lists, renumbering, group errors).
submodule (ffrf_mesh_mesh:ffrf_mesh_mesh_checks) ffrf_mesh_mesh_extract
   implicit none

contains

   !> A new mesh holding one body: the tetrahedra of the physical volumes `volume_names`, only the
   !> nodes they use (renumbered 1..n in increasing order of the old index, `node_tags` kept),
   !> the triangles all of whose nodes are in the body and which are faces of its tetrahedra
   !> (renumbered), the nodes of the physical points and curves (renumbered, 0 off the body)
   !> and all physical groups.
   !>
   !> The body is checked once here (FFRF_INPUT_ERROR naming the file and the element, node or
   !> group): its volumes hold no other volume elements than tetrahedra; no two tetrahedra have
   !> the same corners; in a Tet10 mesh every edge has one mid-side node and every mid-side node
   !> one edge (a crack otherwise); the tetrahedra form one piece (node-connected); every
   !> triangle all of whose nodes are in the body is a face of a tetrahedron of the mesh and, if
   !> a Tri6, has that face's mid-side nodes. Each check is O(n) with hashing or arrays indexed by
   !> node. Inverted and degenerate tetrahedra are refused where the elements are integrated
   !> (`tet_check_jacobian`, ffrf_fe_tet), with the element tag.
   module procedure extract_body
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
      ! the nodes of physical points and curves, renumbered (0: not on the body, which
      ! group_nodes refuses)
      if (allocated(mesh%curve_point_nodes)) then
         body%curve_point_nodes = mesh%curve_point_nodes
         body%curve_point_nodes(3, :) = new_index(mesh%curve_point_nodes(3, :))
      end if
      if (allocated(mesh%node_sets)) call cut_node_sets(mesh, new_index, body)
      if (allocated(mesh%materials)) body%materials = mesh%materials

      call check_duplicate_tets(body, error)
      if (allocated(error)) return
      call check_tet_nodes(body, error)
   end procedure extract_body

   !> The bulk-data interface elements of a body: their nodes renumbered (new_index); one with a
   !> grid that is not a node of the body's tetrahedra keeps no nodes and says which grid.
   subroutine cut_node_sets(mesh, new_index, body)
      type(mesh_t), intent(in) :: mesh
      !> New index of every node of `mesh`, 0 if not in the body
      integer(ip), intent(in) :: new_index(:)
      type(mesh_t), intent(inout) :: body
      integer(ip) :: k, j
      allocate (body%node_sets(size(mesh%node_sets)))
      do k = 1, size(mesh%node_sets, kind=ip)
         associate (from => mesh%node_sets(k), to => body%node_sets(k))
            to%name = from%name
            to%rbe = from%rbe
            to%weights = from%weights
            to%reference = from%reference
            to%origin = from%origin
            j = findloc(new_index(from%nodes) == 0, .true., dim=1, kind=ip)
            if (j == 0) then
               to%nodes = new_index(from%nodes)
            else
               to%off_body = 'its grid ' // to_str(mesh%node_tags(from%nodes(j))) // &
                  ' is not a node of the tetrahedra of physical volume(s) ' // body%volumes
            end if
         end associate
      end do
   end subroutine cut_node_sets

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
   module procedure face_connected_parts
      integer(ip), allocatable :: start(:), list(:), parent(:), part_of_root(:)
      integer(ip) :: e, f, p, t, root, other, nt, corner(3)
      nt = body%num_tets()
      call tets_of_nodes(body, start, list)
      parent = [(e, e=1, nt)]
      do e = 1, nt
         do f = 1, 4
            corner = body%tets(tet_faces(:, f), e)
            do p = start(corner(1)), start(corner(1) + 1) - 1
               t = list(p)
               if (.not. shares_face(body, t, e, corner)) cycle
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
   end procedure face_connected_parts

   module procedure boundary_faces
      integer(ip), allocatable :: start(:), list(:)
      integer(ip) :: e, f, p, n, corner(3)
      logical :: shared
      call tets_of_nodes(body, start, list)
      allocate (faces(2, 4 * body%num_tets()))
      n = 0
      do e = 1, body%num_tets()
         do f = 1, 4
            corner = body%tets(tet_faces(:, f), e)
            shared = .false.
            do p = start(corner(1)), start(corner(1) + 1) - 1
               shared = shares_face(body, list(p), e, corner)
               if (shared) exit
            end do
            if (shared) cycle
            n = n + 1
            faces(:, n) = [e, int(f, ip)]
         end do
      end do
      faces = faces(:, 1:n)
   end procedure boundary_faces

   !> The tetrahedra at each node as lists: those of node a are list(start(a):start(a + 1) - 1).
   subroutine tets_of_nodes(body, start, list)
      type(mesh_t), intent(in) :: body
      integer(ip), allocatable, intent(out) :: start(:), list(:)
      integer(ip), allocatable :: fill(:)
      integer(ip) :: e, k, a
      allocate (start(body%num_nodes + 1), source=0_ip)
      do e = 1, body%num_tets()
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
      do e = 1, body%num_tets()
         do k = 1, 4
            a = body%tets(k, e)
            list(fill(a)) = e
            fill(a) = fill(a) + 1
         end do
      end do
   end subroutine tets_of_nodes

   !> Tetrahedron t (another than e) holds the three corners `corner` (corner(1) is known to be
   !> one of its corners: t comes from that node's list).
   pure logical function shares_face(body, t, e, corner)
      type(mesh_t), intent(in) :: body
      integer(ip), intent(in) :: t, e, corner(3)
      shares_face = t /= e .and. any(body%tets(1:4, t) == corner(2)) .and. &
         any(body%tets(1:4, t) == corner(3))
   end function shares_face

   module procedure file_of
      if (allocated(mesh%file_name)) then
         name = mesh%file_name
      else
         name = '(unnamed)'
      end if
   end procedure file_of

   module procedure pack_indices
      integer(ip) :: i, n
      allocate (indices(count(mask)))
      n = 0
      do i = 1, size(mask, kind=ip)
         if (mask(i)) then
            n = n + 1
            indices(n) = i
         end if
      end do
   end procedure pack_indices

   module procedure renumbered
      integer(ip) :: e, k
      do e = 1, size(selected, kind=ip)
         do k = 1, size(elements, 1, kind=ip)
            subset(k, e) = new_index(elements(k, selected(e)))
         end do
      end do
   end procedure renumbered

   module procedure quoted_list
      integer :: i
      text = ''
      do i = 1, size(words)
         if (i > 1) text = text // ', '
         text = text // '''' // trim(words(i)) // ''''
      end do
   end procedure quoted_list

   module procedure mark_nodes
      integer(ip) :: e, k
      do e = 1, size(elements, 2, kind=ip)
         if (.not. selected(e)) cycle
         do k = 1, size(elements, 1, kind=ip)
            used(elements(k, e)) = .true.
         end do
      end do
   end procedure mark_nodes

   module procedure unknown_group_error
      call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_of(mesh) // &
         ''': no physical ' // dimension_word(dim) // ' ''' // trim(name) // '''; ' // &
         dimension_word(dim) // 's: ' // mesh%group_names(dim))
   end procedure unknown_group_error

   module procedure in_entities
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
   end procedure in_entities

end submodule ffrf_mesh_mesh_extract
