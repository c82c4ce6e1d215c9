!> Checks of ffrf_mesh_mesh's extract_body on the elements of a body: volumes of tetrahedra
!> only, no repeated tetrahedron, triangles that are faces (Tri6: with their mid-side nodes), and
!> the hashing, sorting and union-find helpers; its child ffrf_mesh_mesh_extract uses them.
submodule (ffrf_mesh_mesh) ffrf_mesh_mesh_checks
   implicit none

   !> Tet10 edge k (node 4 + k) joins corners tet_edges(1, k) and tet_edges(2, k) (Gmsh order)
   integer(ip), parameter :: tet_edges(2, 6) = reshape([1, 2, 2, 3, 1, 3, 1, 4, 3, 4, 2, 4], &
      [2, 6])
   !> Face k of a tetrahedron: the corners other than corner k
   integer(ip), parameter :: tet_faces(3, 4) = reshape([2, 3, 4, 1, 3, 4, 1, 2, 4, 1, 2, 3], &
      [3, 4])
   !> Tri6 edge k (node 3 + k) joins corners tri_edges(1, k) and tri_edges(2, k)
   integer(ip), parameter :: tri_edges(2, 3) = reshape([1, 2, 2, 3, 1, 3], [2, 3])

contains

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
      text = '(' // join_ints(mesh%node_tags(nodes), ', ') // ')'
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

end submodule ffrf_mesh_mesh_checks
