!> ffrf_mesh_gmsh: read_gmsh (the sections in file order) and the mesh built from what was
!> read (elements without MSH 2.2 repeats, physical groups). Last of the chain.
submodule(ffrf_mesh_gmsh:ffrf_mesh_gmsh_elements) ffrf_mesh_gmsh_build
   implicit none

contains

   module procedure read_gmsh
      type(reader_t) :: r
      character(len=:), allocatable :: word
      logical :: seen_entities

      seen_entities = .false.
      r%tets%kind = 'Tet'
      r%tris%kind = 'Tri'
      call load_file(file_name, r%c, error)
      if (allocated(error)) return
      call read_mesh_format(r, error)
      if (allocated(error)) return
      do
         call skip_space(r%c%text, r%c%pos, r%c%line)
         if (r%c%pos > len(r%c%text, kind=i8)) exit
         r%c%section = 'after the last section'
         word = next_word(r%c)
         if (word(1:1) /= '$') then
            call syntax_error(r%c, 'expected a section header such as $Nodes', error)
            return
         end if
         r%c%section = word
         select case (word)
         case ('$PhysicalNames')
            if (allocated(r%names)) then
               call location_error(r%c, 'a second $PhysicalNames section; ffrf reads one', &
                  error)
            else
               call read_physical_names(r, error)
            end if
         case ('$Entities')
            if (seen_entities) then
               call location_error(r%c, 'a second $Entities section; ffrf reads one', error)
            else if (r%version == '4.1') then
               seen_entities = .true.
               call read_entities(r, error)
            else
               call skip_section(r%c, error)
            end if
         case ('$Nodes')
            if (r%have_nodes) then
               call location_error(r%c, 'a second $Nodes section; ffrf reads one', error)
            else if (r%version == '4.1') then
               call read_nodes_41(r, error)
            else
               call read_nodes_22(r, error)
            end if
         case ('$Elements')
            if (r%have_elements) then
               call location_error(r%c, 'a second $Elements section; ffrf reads one', error)
            else if (.not. r%have_nodes) then
               call location_error(r%c, '$Elements comes before $Nodes', error)
            else if (r%version == '4.1') then
               call read_elements_41(r, error)
            else
               call read_elements_22(r, error)
            end if
         case ('$PartitionedEntities')
            call location_error(r%c, 'partitioned meshes are not supported: save the mesh ' // &
               'without partitioning (no -part)', error)
         case ('$MeshFormat')
            call location_error(r%c, 'a second $MeshFormat section', error)
         case default
            call skip_section(r%c, error)
         end select
         if (allocated(error)) return
      end do
      r%c%section = 'end of file'
      if (.not. (r%have_nodes .and. r%have_elements)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_name // ''': no $Nodes ' // &
            'or no $Elements section; is it a mesh (gmsh -3) and not a geometry only?')
         return
      end if
      call build_mesh(r, mesh, error)
   end procedure read_gmsh

   !> Move what was read into `mesh`: elements (duplicates of MSH 2.2 removed), groups, the
   !> nodes of the point and line elements.
   subroutine build_mesh(r, mesh, error)
      type(reader_t), intent(inout) :: r
      type(mesh_t), intent(out) :: mesh
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: links(:, :), perm(:)
      logical :: shared(0:3)
      integer(ip) :: i

      if (r%tets%count == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // ''' has no ' // &
            'tetrahedra (Tet4 or Tet10; ' // to_str(r%tris%count) // ' triangles and ' // &
            to_str(r%num_skipped) // ' other elements). Gmsh saves only the elements of ' // &
            'physical groups once any group exists (toolchain pitfall 13): add a Physical ' // &
            'Volume for the body''s volumes to the .geo and mesh it in 3D (gmsh -3)')
         return
      end if

      ! Unique (dim, physical, entity) triples.
      if (r%num_links > 0) then
         links = unique_columns(r%links(:, :r%num_links))
      else
         allocate (links(3, 0))
      end if

      ! MSH 2.2 repeats an element once per physical group of its entity: drop the copies.
      shared = .false.
      if (r%version == '2.2' .and. size(links, 2) > 1) then
         call sort_columns(links([1, 3], :), perm)
         do i = 2, size(perm, kind=ip)
            if (all(links([1, 3], perm(i)) == links([1, 3], perm(i - 1)))) &
               shared(links(1, perm(i))) = .true.
         end do
      end if
      if (shared(3)) call drop_repeated(r%tets)
      if (shared(2)) call drop_repeated(r%tris)

      mesh%file_name = r%c%file_name
      mesh%num_nodes = r%num_nodes
      call move_alloc(r%xyz, mesh%xyz)
      call move_alloc(r%node_tags, mesh%node_tags)
      mesh%nodes_per_tet = r%tets%nodes_per_element
      if (size(r%tets%tags) == r%tets%count) then
         ! Filled to capacity (one block, the usual case): hand the arrays over, no copy
         call move_alloc(r%tets%nodes, mesh%tets)
         call move_alloc(r%tets%tags, mesh%tet_tags)
         call move_alloc(r%tets%entity, mesh%tet_entity)
      else
         mesh%tets = r%tets%nodes(:, :r%tets%count)
         mesh%tet_tags = r%tets%tags(:r%tets%count)
         mesh%tet_entity = r%tets%entity(:r%tets%count)
      end if
      mesh%nodes_per_tri = r%tris%nodes_per_element
      if (r%tris%count > 0) then
         mesh%tris = r%tris%nodes(:, :r%tris%count)
         mesh%tri_tags = r%tris%tags(:r%tris%count)
         mesh%tri_entity = r%tris%entity(:r%tris%count)
      else
         allocate (mesh%tris(0, 0), mesh%tri_tags(0), mesh%tri_entity(0))
      end if
      call build_groups(r, links, mesh%groups)
      if (r%num_curve_point_nodes > 0) then
         mesh%curve_point_nodes = int(r%curve_point_nodes(:, :r%num_curve_point_nodes), ip)
      else
         allocate (mesh%curve_point_nodes(3, 0))
      end if
      if (r%num_other_volume > 0) then
         mesh%other_volume_elements = r%other_volume(:, :r%num_other_volume)
      else
         allocate (mesh%other_volume_elements(4, 0))
      end if
   end subroutine build_mesh

   !> Keep the first of elements with the same entity and the same nodes in the same order.
   subroutine drop_repeated(list)
      type(element_list_t), intent(inout) :: list
      integer(ip), allocatable :: keys(:, :), perm(:)
      logical, allocatable :: keep(:)
      integer(ip) :: i, n, k
      n = list%count
      if (n < 2) return
      allocate (keys(list%nodes_per_element + 1, n))
      keys(1, :) = list%entity(:n)
      keys(2:, :) = list%nodes(:, :n)
      call sort_columns(keys, perm)
      allocate (keep(n))
      keep = .true.
      do i = 2, n
         ! The sort is stable: the earlier copy comes first and stays.
         if (all(keys(:, perm(i)) == keys(:, perm(i - 1)))) keep(perm(i)) = .false.
      end do
      k = 0
      do i = 1, n
         if (.not. keep(i)) cycle
         k = k + 1
         list%nodes(:, k) = list%nodes(:, i)
         list%tags(k) = list%tags(i)
         list%entity(k) = list%entity(i)
      end do
      list%count = k
   end subroutine drop_repeated

   !> Physical groups from the unique sorted (dim, physical, entity) triples and the names,
   !> sorted by dimension and tag.
   subroutine build_groups(r, links, groups)
      type(reader_t), intent(in) :: r
      integer(ip), intent(in) :: links(:, :)
      type(physical_group_t), allocatable, intent(out) :: groups(:)
      integer(ip), allocatable :: keys(:, :)
      integer(ip) :: num_names, i, k
      num_names = 0
      if (allocated(r%names)) num_names = size(r%names, kind=ip)
      allocate (keys(2, size(links, 2) + num_names))
      keys(:, :size(links, 2)) = links(1:2, :)
      do i = 1, num_names
         keys(:, size(links, 2) + i) = [r%names(i)%dim, r%names(i)%tag]
      end do
      keys = unique_columns(keys)
      allocate (groups(size(keys, 2)))
      do k = 1, size(groups, kind=ip)
         groups(k)%dim = keys(1, k)
         groups(k)%tag = keys(2, k)
         groups(k)%name = ''
         do i = 1, num_names
            if (r%names(i)%dim == keys(1, k) .and. r%names(i)%tag == keys(2, k)) &
               groups(k)%name = r%names(i)%name
         end do
         groups(k)%entities = pack(links(3, :), links(1, :) == keys(1, k) .and. &
            links(2, :) == keys(2, k))
      end do
   end subroutine build_groups

   ! ------------------------------------------------------------------------------------------
   ! Sorting (stable bottom-up merge sorts of a permutation)
   ! ------------------------------------------------------------------------------------------

   !> Permutation putting the columns of `keys` in lexicographic order (stable).
   subroutine sort_columns(keys, perm)
      integer(ip), intent(in) :: keys(:, :)
      integer(ip), allocatable, intent(out) :: perm(:)
      call merge_permutation(int(keys, i8), perm)
   end subroutine sort_columns

   !> The distinct columns of `keys`, in lexicographic order.
   function unique_columns(keys) result(unique)
      integer(ip), intent(in) :: keys(:, :)
      integer(ip), allocatable :: unique(:, :)
      integer(ip), allocatable :: perm(:)
      logical, allocatable :: first(:)
      integer(ip) :: i, n
      n = size(keys, 2, kind=ip)
      call sort_columns(keys, perm)
      allocate (first(n))
      do i = 1, n
         first(i) = .true.
         if (i > 1) first(i) = any(keys(:, perm(i)) /= keys(:, perm(i - 1)))
      end do
      unique = keys(:, pack(perm, first))
   end function unique_columns

end submodule ffrf_mesh_gmsh_build
