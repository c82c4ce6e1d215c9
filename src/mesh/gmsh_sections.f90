!> ffrf_mesh_gmsh: the sections $MeshFormat, $PhysicalNames, $Entities and $Nodes (4.1, 2.2),
!> the node tag map. Next: gmsh_elements.f90.
submodule(ffrf_mesh_gmsh:ffrf_mesh_gmsh_tokens) ffrf_mesh_gmsh_sections
   implicit none

contains

   !> $MeshFormat: "4.1 0 8" (ASCII) or "4.1 1 8" plus the int 1 in this machine's byte order.
   subroutine read_mesh_format(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: word
      integer(i8) :: file_type, data_size, one

      r%c%section = 'start of file'
      word = next_word(r%c)
      if (word /= '$MeshFormat') then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // ''' is not ' // &
            'a Gmsh MSH file: it does not start with $MeshFormat')
         return
      end if
      r%c%section = '$MeshFormat'
      word = next_word(r%c)
      if (word /= '4.1' .and. word /= '2.2') then
         call location_error(r%c, 'MSH version ' // word // ' is not supported; ffrf reads ' // &
            'MSH 4.1 (ASCII or binary) and MSH 2.2 (ASCII): re-save with gmsh -format msh41', error)
         return
      end if
      r%version = word
      call read_int(r%c, 'file type', file_type, error)
      if (allocated(error)) return
      call read_int(r%c, 'data size', data_size, error)
      if (allocated(error)) return
      if (data_size /= 8) then
         call location_error(r%c, 'data size ' // to_str(data_size) // ' (sizeof(size_t)) ' // &
            'is not supported, only 8', error)
         return
      end if
      select case (file_type)
      case (0)
      case (1)
         if (r%version /= '4.1') then
            call location_error(r%c, 'binary MSH ' // r%version // ' is not supported: save ' // &
               'it as ASCII (-format msh22) or as MSH 4.1 (-format msh41 [-bin])', error)
            return
         end if
         call start_binary(r%c, error)
         if (allocated(error)) return
         call binary_int(r%c, 'the endianness check int 1', one, error)
         if (allocated(error)) return
         r%c%binary = .false.
         r%binary_file = .true.
         if (one /= 1) then
            call location_error(r%c, 'binary file written with the other byte order (the ' // &
               'int 1 reads as ' // to_str(one) // '); re-save it on this machine or as ASCII', &
               error)
            return
         end if
      case default
         call location_error(r%c, 'file type ' // to_str(file_type) // ' is neither 0 (ASCII) ' // &
            'nor 1 (binary)', error)
         return
      end select
      call expect_end(r%c, error)
   end subroutine read_mesh_format

   !> $PhysicalNames (ASCII also in binary files): count, then "dim tag "name"" lines.
   subroutine read_physical_names(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: num, i, j
      integer(i8) :: value, closing
      character(len=:), allocatable :: problem

      call read_count(r%c, 'number of physical names', num, error)
      if (allocated(error)) return
      ! dim, blank, tag, blank, two quotes, line end: 7 bytes at least
      call check_count_fits(r%c, 'number of physical names', int(num, i8), 7_i8, error)
      if (allocated(error)) return
      allocate (r%names(num))
      do i = 1, num
         call read_int(r%c, 'dimension of a physical name', value, error)
         if (allocated(error)) return
         r%names(i)%dim = int(value, ip)
         call read_int(r%c, 'tag of a physical name', value, error)
         if (allocated(error)) return
         r%names(i)%tag = int(value, ip)
         call skip_space(r%c%text, r%c%pos, r%c%line)
         closing = 0
         if (r%c%pos <= len(r%c%text, kind=i8)) then
            if (r%c%text(r%c%pos:r%c%pos) == '"') closing = index(r%c%text(r%c%pos + 1:), '"', &
               kind=i8)
         end if
         if (closing == 0) then
            call syntax_error(r%c, 'expected a quoted physical name', error)
            return
         end if
         r%names(i)%name = r%c%text(r%c%pos + 1:r%c%pos + closing - 1)
         if (scan(r%names(i)%name, achar(10) // achar(13) // achar(9)) > 0) then
            call location_error(r%c, 'the name of physical group ' // to_str(r%names(i)%tag) // &
               ' holds a line break or tab; write it on one line', error)
            return
         end if
         r%c%pos = r%c%pos + closing + 1
      end do
      call expect_end(r%c, error)
      if (allocated(error)) return
      ! One name per (dimension, tag) and one tag per (dimension, name): of two groups with one
      ! name, the first one found would be used silently wherever the name is given.
      do i = 2, num
         do j = 1, i - 1
            if (r%names(i)%dim /= r%names(j)%dim) cycle
            ! names are compared exactly, but a case's names are blank-padded strings: two
            ! names equal up to trailing blanks could not be told apart from a case
            if (r%names(i)%name == r%names(j)%name) then
               if (len(r%names(i)%name) == len(r%names(j)%name)) then
                  problem = 'are named ''' // r%names(i)%name // ''''
               else
                  problem = 'are named ''' // r%names(j)%name // ''' and ''' // &
                     r%names(i)%name // ''', equal up to trailing blanks'
               end if
               call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // &
                  ''': $PhysicalNames: two physical ' // dimension_word(r%names(i)%dim) // &
                  's ' // problem // ' (tags ' // to_str(r%names(j)%tag) // ' and ' // &
                  to_str(r%names(i)%tag) // '); give each physical group its own name in ' // &
                  'the .geo')
               return
            else if (r%names(i)%tag == r%names(j)%tag) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // &
                  ''': $PhysicalNames: physical ' // dimension_word(r%names(i)%dim) // ' ' // &
                  to_str(r%names(i)%tag) // ' has two names, ''' // r%names(j)%name // &
                  ''' and ''' // r%names(i)%name // '''')
               return
            end if
         end do
      end do
   end subroutine read_physical_names

   !> $Entities (4.1): points, curves, surfaces, volumes, each with its physical tags.
   subroutine read_entities(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: counts(0:3), tag, num_physical, physical, num_bounding, k, j
      integer(ip) :: dim
      logical :: binary
      real(dp) :: ignored

      binary = r%binary_file
      if (binary) call start_binary(r%c, error)
      if (allocated(error)) return
      do dim = 0, 3
         call read_size(r%c, binary, 'number of ' // dimension_word(dim) // ' entities', &
            counts(dim), error)
         if (allocated(error)) return
         ! an entity takes a tag, 3 or 6 coordinates and a count: 5 tokens of 2 bytes at least
         ! (ASCII), 4 + 3 * 8 + 8 bytes (binary)
         call check_count_fits(r%c, 'number of ' // dimension_word(dim) // ' entities', &
            counts(dim), merge(36_i8, 10_i8, binary), error)
         if (allocated(error)) return
      end do
      call check_count_fits(r%c, 'number of entities', sum(counts), merge(36_i8, 10_i8, binary), &
         error)
      if (allocated(error)) return
      do dim = 0, 3
         do k = 1, counts(dim)
            call read_tag(r%c, binary, dimension_word(dim) // ' entity tag', tag, error)
            if (allocated(error)) return
            ! Points: x y z; curves, surfaces, volumes: bounding box min x y z, max x y z.
            do j = 1, merge(3, 6, dim == 0)
               call read_real(r%c, binary, 'entity coordinate', ignored, error)
               if (allocated(error)) return
            end do
            call read_size(r%c, binary, 'number of physical tags', num_physical, error)
            if (allocated(error)) return
            do j = 1, num_physical
               call read_tag(r%c, binary, 'physical tag', physical, error)
               if (allocated(error)) return
               call add_link(r, dim, int(physical, ip), int(tag, ip))
            end do
            if (dim == 0) cycle
            call read_size(r%c, binary, 'number of bounding entities', num_bounding, error)
            if (allocated(error)) return
            do j = 1, num_bounding
               call read_tag(r%c, binary, 'bounding entity tag', physical, error)
               if (allocated(error)) return
            end do
         end do
      end do
      r%c%binary = .false.
      call expect_end(r%c, error)
   end subroutine read_entities

   !> $Nodes (4.1): blocks of (entityDim, entityTag, parametric, count), tags, coordinates.
   !> The header's node count and tag range must match the blocks.
   subroutine read_nodes_41(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: num_blocks, num_nodes, block, dim, entity, parametric, n, first, k, i
      integer(i8) :: values_per_node, min_tag, max_tag
      real(dp), allocatable :: values(:)
      logical :: binary

      binary = r%binary_file
      if (binary) call start_binary(r%c, error)
      if (allocated(error)) return
      call read_section_header(r%c, binary, 'node', num_blocks, num_nodes, min_tag, max_tag, error)
      if (allocated(error)) return
      ! A node takes a tag and three coordinates: 4 tokens of 2 bytes at least (ASCII), 8 + 3 * 8
      ! bytes (binary); a block header 4 tokens (ASCII), 3 ints and a size_t (binary).
      call check_count_fits(r%c, 'number of nodes', num_nodes, merge(32_i8, 8_i8, binary), error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of node blocks', num_blocks, merge(20_i8, 8_i8, binary), &
         error)
      if (allocated(error)) return
      call allocate_nodes(r, num_nodes, error)
      if (allocated(error)) return
      first = 0
      do block = 1, num_blocks
         call read_block_header(r%c, binary, 'a node block', 'node', 'parametric flag', dim, &
            entity, parametric, n, error)
         if (allocated(error)) return
         if (first + n > num_nodes) then
            call location_error(r%c, 'node blocks hold more nodes than the ' // &
               to_str(num_nodes) // ' announced in the section header', error)
            return
         end if
         values_per_node = 3
         if (parametric /= 0) values_per_node = 3 + max(0_i8, min(3_i8, dim))
         if (binary) then
            call binary_take(r%c, 8 * n, 'node tags', k, error)
            if (allocated(error)) return
            if (n > 0) r%node_tags(first + 1:first + n) = transfer(r%c%text(k:k + 8 * n - 1), &
               0_i8, int(n))
            do i = first + 1, first + n
               if (r%node_tags(i) < 1) then
                  r%c%pos = k + 8 * (i - first - 1)
                  call bad_tag_error(r%c, 'node', r%node_tags(i), error)
                  return
               end if
            end do
            call binary_take(r%c, 8 * n * values_per_node, 'node coordinates', k, error)
            if (allocated(error)) return
            if (n > 0) then
               values = transfer(r%c%text(k:k + 8 * n * values_per_node - 1), 0.0_dp, &
                  int(n * values_per_node))
               do i = 1, n
                  r%xyz(:, first + i) = values((i - 1) * values_per_node + 1: &
                     (i - 1) * values_per_node + 3)
               end do
            end if
         else
            call read_node_block_ascii(r, first, n, values_per_node, error)
            if (allocated(error)) return
         end if
         first = first + n
      end do
      call check_blocks_total(r%c, 'node', first, num_nodes, error)
      if (allocated(error)) return
      r%c%binary = .false.
      call check_coordinates(r, error)
      if (allocated(error)) return
      call build_tag_map(r, error)
      if (allocated(error)) return
      if (num_nodes > 0 .and. (r%map%min_tag /= min_tag .or. r%map%max_tag /= max_tag)) then
         call location_error(r%c, 'the header gives node tags ' // to_str(min_tag) // '..' // &
            to_str(max_tag) // ', the nodes have tags ' // to_str(r%map%min_tag) // '..' // &
            to_str(r%map%max_tag), error)
         return
      end if
      r%have_nodes = .true.
      call expect_end(r%c, error)
   end subroutine read_nodes_41

   !> Nodes first+1 .. first+n of an ASCII 4.1 block: n tags, then n lines of coordinates
   !> (x y z and, for parametric nodes, the parametric coordinates). A value missing from a
   !> line is reported on that line, not where the shifted values run out.
   subroutine read_node_block_ascii(r, first, n, values_per_node, error)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: first, n, values_per_node
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: i
      do i = first + 1, first + n
         call scan_node_tag(r, i, 'a node block', n, i - first - 1, error)
         if (allocated(error)) return
      end do
      do i = first + 1, first + n
         call scan_node_coordinates(r, i, values_per_node, -1_i8, error)
         if (allocated(error)) return
      end do
   end subroutine read_node_block_ascii

   !> $Nodes (2.2): count, then "tag x y z" lines.
   subroutine read_nodes_22(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: num_nodes, i
      integer(i8) :: tag_line

      call read_count(r%c, 'number of nodes', num_nodes, error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of nodes', int(num_nodes, i8), 8_i8, error)
      if (allocated(error)) return
      call allocate_nodes(r, int(num_nodes, i8), error)
      if (allocated(error)) return
      do i = 1, num_nodes
         call scan_node_tag(r, int(i, i8), '$Nodes', int(num_nodes, i8), int(i - 1, i8), error)
         if (allocated(error)) return
         tag_line = r%c%line
         call scan_node_coordinates(r, int(i, i8), 3_i8, tag_line, error)
         if (allocated(error)) return
      end do
      call check_coordinates(r, error)
      if (allocated(error)) return
      call build_tag_map(r, error)
      if (allocated(error)) return
      r%have_nodes = .true.
      call expect_end(r%c, error)
   end subroutine read_nodes_22

   !> The values_per_node coordinates of node i (x y z kept, parametric ones skipped), then the
   !> line end: all on line `line` (< 0: the line of the first value), a value missing from it
   !> reported on that line, not where the shifted values run out.
   subroutine scan_node_coordinates(r, i, values_per_node, line, error)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: i, values_per_node, line
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: j, node_line
      real(dp) :: value
      logical :: ok
      node_line = line
      do j = 1, values_per_node
         call scan_real(r%c%text, r%c%pos, r%c%line, value, ok)
         if (node_line < 0) node_line = r%c%line
         if (r%c%line /= node_line) then
            call line_error(r%c, node_line, 'node ' // to_str(r%node_tags(i)) // ': the line ' // &
               'holds ' // to_str(j - 1) // ' of the node''s ' // to_str(values_per_node) // &
               ' coordinates; one is missing', error)
            return
         end if
         if (.not. ok) then
            call coordinate_error(r%c, r%node_tags(i), error)
            return
         end if
         if (j <= 3) r%xyz(j, i) = value
      end do
      call skip_line_end(r%c%text, r%c%pos, r%c%line, ok)
      if (.not. ok) then
         call syntax_error(r%c, 'expected the end of the line after the ' // &
            to_str(values_per_node) // ' coordinates of node ' // to_str(r%node_tags(i)), error)
      end if
   end subroutine scan_node_coordinates

   !> Skip an unknown section up to its $End line.
   subroutine skip_section(c, error)
      type(cursor_t), intent(inout) :: c
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: marker
      integer(i8) :: found, p
      marker = '$End' // c%section(2:)
      found = index(c%text(c%pos:), marker, kind=i8)
      if (found == 0) then
         call location_error(c, 'no ' // marker // ' closes the section', error)
         return
      end if
      do p = c%pos, c%pos + found - 2
         if (c%text(p:p) == achar(10)) c%line = c%line + 1
      end do
      c%pos = c%pos + found - 1 + len(marker)
   end subroutine skip_section

   ! ------------------------------------------------------------------------------------------
   ! Nodes, elements, groups
   ! ------------------------------------------------------------------------------------------

   !> Room for `num_nodes` nodes.
   subroutine allocate_nodes(r, num_nodes, error)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: num_nodes
      type(error_t), allocatable, intent(out) :: error
      integer :: stat
      if (num_nodes < 0 .or. num_nodes > huge(0_ip)) then
         call location_error(r%c, 'number of nodes ' // to_str(num_nodes) // ' out of range', &
            error)
         return
      end if
      r%num_nodes = int(num_nodes, ip)
      allocate (r%xyz(3, r%num_nodes), r%node_tags(r%num_nodes), stat=stat)
      if (stat /= 0) call location_error(r%c, 'out of memory for ' // to_str(num_nodes) // &
         ' nodes', error)
   end subroutine allocate_nodes

   !> Map node tags to indices: a direct table when max - min + 1 <= 2 n + 1024, else sorted
   !> tags for a binary search. Duplicate tags are an error.
   subroutine build_tag_map(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: perm(:)
      integer(i8) :: span
      integer(ip) :: i, stat
      type(tag_map_t) :: map

      if (r%num_nodes == 0) then
         r%map = map
         allocate (r%map%direct(0))
         return
      end if
      map%min_tag = minval(r%node_tags)
      map%max_tag = maxval(r%node_tags)
      span = map%max_tag - map%min_tag + 1
      map%dense = span <= 2_i8 * r%num_nodes + 1024_i8
      if (map%dense) then
         allocate (map%direct(span), stat=stat)
         if (stat /= 0) then
            call location_error(r%c, 'out of memory for the node tag table', error)
            return
         end if
         map%direct = 0
         do i = 1, r%num_nodes
            if (map%direct(r%node_tags(i) - map%min_tag + 1) /= 0) then
               call duplicate_tag_error(r%c, r%node_tags(i), error)
               return
            end if
            map%direct(r%node_tags(i) - map%min_tag + 1) = i
         end do
      else
         if (all(r%node_tags(2:) > r%node_tags(:r%num_nodes - 1))) then
            perm = [(i, i=1, r%num_nodes)]
         else
            call sort_tags(r%node_tags, perm)
         end if
         map%sorted_tags = r%node_tags(perm)
         map%sorted_index = perm
         do i = 2, r%num_nodes
            if (map%sorted_tags(i) == map%sorted_tags(i - 1)) then
               call duplicate_tag_error(r%c, map%sorted_tags(i), error)
               return
            end if
         end do
      end if
      r%map = map
   end subroutine build_tag_map

   !> Record that `entity` of dimension `dim` is in physical group `physical`.
   subroutine add_link(r, dim, physical, entity)
      type(reader_t), intent(inout) :: r
      integer(ip), intent(in) :: dim, physical, entity
      integer(ip), allocatable :: grown(:, :)
      if (r%num_links > 0) then
         if (all(r%links(:, r%num_links) == [dim, physical, entity])) return
      end if
      if (.not. allocated(r%links)) allocate (r%links(3, 64))
      if (r%num_links == size(r%links, 2)) then
         allocate (grown(3, 2 * r%num_links))
         grown(:, :r%num_links) = r%links
         call move_alloc(grown, r%links)
      end if
      r%num_links = r%num_links + 1
      r%links(:, r%num_links) = [dim, physical, entity]
   end subroutine add_link

   !> Every coordinate finite: a NaN or Inf would surface later as a degenerate element or a
   !> failed factorisation far from its cause.
   subroutine check_coordinates(r, error)
      type(reader_t), intent(in) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: i
      do i = 1, r%num_nodes
         if (ieee_is_finite(r%xyz(1, i)) .and. ieee_is_finite(r%xyz(2, i)) .and. &
            ieee_is_finite(r%xyz(3, i))) cycle
         call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // r%c%file_name // ''': ' // &
            r%c%section // ': node ' // to_str(r%node_tags(i)) // ' has a non-finite ' // &
            'coordinate, (x, y, z) = (' // to_str(r%xyz(1, i)) // ', ' // to_str(r%xyz(2, i)) // &
            ', ' // to_str(r%xyz(3, i)) // '); every coordinate must be a finite number')
         return
      end do
   end subroutine check_coordinates

   !> Tag of node i (ASCII), at least 1; `who` announced `count` nodes of which `done` are read.
   subroutine scan_node_tag(r, i, who, count, done, error)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: i, count, done
      character(len=*), intent(in) :: who
      type(error_t), allocatable, intent(out) :: error
      logical :: ok
      call scan_int(r%c%text, r%c%pos, r%c%line, r%node_tags(i), ok)
      if (.not. ok) then
         call missing_item_error(r%c, 'a node tag', who // ' announces ' // to_str(count) // &
            ' nodes, the section ends after ' // to_str(done), error)
         return
      end if
      if (r%node_tags(i) < 1) call bad_tag_error(r%c, 'node', r%node_tags(i), error)
   end subroutine scan_node_tag

   !> Permutation putting `tags` in ascending order (stable).
   subroutine sort_tags(tags, perm)
      integer(i8), intent(in) :: tags(:)
      integer(ip), allocatable, intent(out) :: perm(:)
      call merge_permutation(reshape(tags, [1, size(tags)]), perm)
   end subroutine sort_tags

end submodule ffrf_mesh_gmsh_sections
