!> ffrf_mesh_gmsh: the section $Elements (4.1, 2.2), one element record at a time, and the
!> skipped volume elements. Next: gmsh_build.f90.
submodule(ffrf_mesh_gmsh:ffrf_mesh_gmsh_sections) ffrf_mesh_gmsh_elements
   implicit none

contains

   !> $Elements (4.1): blocks of (entityDim, entityTag, type, count), then per element its tag
   !> and node tags (one line each in ASCII). The header's element count and tag range must
   !> match the blocks, every type must be known and of its entity's dimension.
   subroutine read_elements_41(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: num_blocks, num_elements, block, dim, entity, element_type, n, k, e, j
      integer(i8), allocatable :: values(:)
      integer(i8) :: node_tag, min_tag, max_tag, total, tag, first_tag, data_start
      integer(ip) :: nodes_per_element, type_dim, index
      logical :: binary, ok

      binary = r%binary_file
      if (binary) call start_binary(r%c, error)
      if (allocated(error)) return
      call read_section_header(r%c, binary, 'element', num_blocks, num_elements, min_tag, &
         max_tag, error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of elements', num_elements, merge(16_i8, 4_i8, binary), &
         error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of element blocks', num_blocks, &
         merge(20_i8, 8_i8, binary), error)
      if (allocated(error)) return
      total = 0
      r%min_element_tag = huge(0_i8)
      r%max_element_tag = -huge(0_i8)
      do block = 1, num_blocks
         call read_block_header(r%c, binary, 'an element block', 'element', 'element type', dim, &
            entity, element_type, n, error)
         if (allocated(error)) return
         if (n > huge(0_ip)) then
            call location_error(r%c, to_str(n) // ' elements in one block: more than ffrf''s ' // &
               '32-bit indices hold', error)
            return
         end if
         call type_size(element_type, nodes_per_element, type_dim)
         if (nodes_per_element < 0) then
            call unknown_type_error(r%c, element_type, 'the element block of ' // &
               dimension_word(int(max(0_i8, min(3_i8, dim)), ip)) // ' entity ' // &
               to_str(entity), error)
            return
         end if
         if (type_dim /= dim) then
            call location_error(r%c, 'an element block of entity dimension ' // to_str(dim) // &
               ' (entity ' // to_str(entity) // ') holds ' // type_name(element_type) // &
               ' elements, which have dimension ' // to_str(type_dim), error)
            return
         end if
         call check_count_fits(r%c, 'elements in block', n, &
            merge(8_i8, 2_i8, binary) * (nodes_per_element + 1), error)
         if (allocated(error)) return
         total = total + n
         if (total > num_elements) then
            call location_error(r%c, 'element blocks hold more elements than the ' // &
               to_str(num_elements) // ' announced in the section header', error)
            return
         end if
         if (.not. binary) then
            call skip_line_end(r%c%text, r%c%pos, r%c%line, ok)
            if (.not. ok) then
               call syntax_error(r%c, 'expected the end of the line after the element block ' // &
                  'header', error)
               return
            end if
         end if
         select case (element_type)
         case (4, 11, 2, 9)
            if (binary) then
               call binary_take(r%c, 8 * n * (nodes_per_element + 1), 'element data', k, error)
               if (allocated(error)) return
               if (n == 0) cycle
               values = transfer(r%c%text(k:k + 8 * n * (nodes_per_element + 1) - 1), 0_i8, &
                  int(n * (nodes_per_element + 1)))
               data_start = k
            end if
            do e = 1, n
               if (element_type == 4 .or. element_type == 11) then
                  call start_element(r%c, r%tets, nodes_per_element, int(n - e + 1, ip), error)
               else
                  call start_element(r%c, r%tris, nodes_per_element, int(n - e + 1, ip), error)
               end if
               if (allocated(error)) return
               if (binary) then
                  k = (e - 1) * (nodes_per_element + 1)
                  if (values(k + 1) < 1) then
                     r%c%pos = data_start + 8 * k
                     call bad_tag_error(r%c, 'element', values(k + 1), error)
                     return
                  end if
                  do j = 1, nodes_per_element
                     node_tag = values(k + 1 + j)
                     index = node_index(r%map, node_tag)
                     if (index == 0) then
                        call missing_node_error(r%c, values(k + 1), element_type, node_tag, error)
                        return
                     end if
                     call store_node(r, element_type, int(j, ip), index)
                  end do
                  call finish_element(r, element_type, values(k + 1), int(entity, ip))
               else
                  call read_element_record(r, element_type, nodes_per_element, int(entity, ip), &
                     -1_i8, error)
                  if (allocated(error)) return
               end if
            end do
         case default
            r%num_skipped = r%num_skipped + n
            first_tag = 0
            if (binary) then
               call binary_take(r%c, 8 * n * (nodes_per_element + 1), 'element data', k, error)
               if (allocated(error)) return
            end if
            do e = 1, n
               if (binary) then
                  j = k + 8 * (e - 1) * (nodes_per_element + 1)
                  tag = transfer(r%c%text(j:j + 7), 0_i8)
                  if (tag < 1) r%c%pos = j
               else
                  call scan_int(r%c%text, r%c%pos, r%c%line, tag, ok)
                  if (.not. ok) then
                     call missing_item_error(r%c, 'an element tag', 'the block announces ' // &
                        to_str(n) // ' elements, the section ends after ' // to_str(e - 1), &
                        error)
                     return
                  end if
                  ! a point or line element: its nodes, for the physical points and curves
                  if (type_dim <= 1 .and. tag >= 1) call read_curve_point_element(r, &
                     element_type, nodes_per_element, type_dim, int(entity, ip), tag, 0_i8, &
                     error)
                  if (allocated(error)) return
                  call skip_line(r%c)
               end if
               if (tag < 1) then
                  call bad_tag_error(r%c, 'element', tag, error)
                  return
               end if
               if (binary .and. type_dim <= 1) then
                  call read_curve_point_element(r, element_type, nodes_per_element, type_dim, &
                     int(entity, ip), tag, j + 8, error)
                  if (allocated(error)) return
               end if
               if (e == 1) first_tag = tag
               r%min_element_tag = min(r%min_element_tag, tag)
               r%max_element_tag = max(r%max_element_tag, tag)
            end do
            if (dim == 3 .and. n > 0) call add_other_volume(r, entity, element_type, n, first_tag)
         end select
      end do
      call check_blocks_total(r%c, 'element', total, num_elements, error)
      if (allocated(error)) return
      if (total > 0 .and. (r%min_element_tag /= min_tag .or. r%max_element_tag /= max_tag)) then
         call location_error(r%c, 'the header gives element tags ' // to_str(min_tag) // '..' // &
            to_str(max_tag) // ', the elements have tags ' // to_str(r%min_element_tag) // &
            '..' // to_str(r%max_element_tag), error)
         return
      end if
      r%c%binary = .false.
      r%have_elements = .true.
      call expect_end(r%c, error)
   end subroutine read_elements_41

   !> $Elements (2.2): count, then "tag type num_tags tags... nodes..." lines; the first tag is
   !> the physical group (0: none), the second the elementary entity.
   subroutine read_elements_22(r, error)
      type(reader_t), intent(inout) :: r
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: num_elements, e, nodes_per_element, dim
      integer(i8) :: tag, element_type, num_tags, value, physical, elementary, j
      logical :: ok

      call read_count(r%c, 'number of elements', num_elements, error)
      if (allocated(error)) return
      call check_count_fits(r%c, 'number of elements', int(num_elements, i8), 8_i8, error)
      if (allocated(error)) return
      do e = 1, num_elements
         call skip_space(r%c%text, r%c%pos, r%c%line)
         if (at_section_end(r%c)) then
            call location_error(r%c, '$Elements announces ' // to_str(num_elements) // &
               ' elements, the section ends after ' // to_str(e - 1), error)
            return
         end if
         call read_int(r%c, 'element tag', tag, error)
         if (.not. allocated(error)) call read_int(r%c, 'element type', element_type, error)
         if (.not. allocated(error)) call read_int(r%c, 'number of tags', num_tags, error)
         if (allocated(error)) return
         if (tag < 1) then
            call bad_tag_error(r%c, 'element', tag, error)
            return
         end if
         physical = 0
         elementary = 0
         do j = 1, num_tags
            call scan_int(r%c%text, r%c%pos, r%c%line, value, ok)
            if (.not. ok) then
               call syntax_error(r%c, 'expected a tag of element ' // to_str(tag), error)
               return
            end if
            if (j == 1) physical = value
            if (j == 2) elementary = value
         end do
         call type_size(element_type, nodes_per_element, dim)
         if (nodes_per_element < 0) then
            call unknown_type_error(r%c, element_type, 'element ' // to_str(tag), error)
            return
         end if
         if (physical /= 0) call add_link(r, dim, int(physical, ip), int(elementary, ip))
         select case (element_type)
         case (4, 11, 2, 9)
            if (element_type == 4 .or. element_type == 11) then
               call start_element(r%c, r%tets, nodes_per_element, 1_ip, error)
            else
               call start_element(r%c, r%tris, nodes_per_element, 1_ip, error)
            end if
            if (allocated(error)) return
            call read_element_record(r, element_type, nodes_per_element, int(elementary, ip), &
               tag, error)
            if (allocated(error)) return
         case default
            r%num_skipped = r%num_skipped + 1
            if (dim == 3) call add_other_volume(r, elementary, element_type, 1_i8, tag)
            ! a point or line element: its nodes, for the physical points and curves
            if (dim <= 1) call read_curve_point_element(r, element_type, nodes_per_element, &
               dim, int(elementary, ip), tag, 0_i8, error)
            if (allocated(error)) return
            call skip_line(r%c)
         end select
      end do
      r%have_elements = .true.
      call expect_end(r%c, error)
   end subroutine read_elements_22

   !> Index of node `tag`, 0 if no node has it.
   pure function node_index(map, tag) result(index)
      type(tag_map_t), intent(in) :: map
      integer(i8), intent(in) :: tag
      integer(ip) :: index
      integer(ip) :: low, high, mid
      index = 0
      if (tag < map%min_tag .or. tag > map%max_tag) return
      if (map%dense) then
         index = map%direct(tag - map%min_tag + 1)
         return
      end if
      low = 1
      high = size(map%sorted_tags, kind=ip)
      do while (low <= high)
         mid = low + (high - low) / 2
         if (map%sorted_tags(mid) == tag) then
            index = map%sorted_index(mid)
            return
         else if (map%sorted_tags(mid) < tag) then
            low = mid + 1
         else
            high = mid - 1
         end if
      end do
   end function node_index

   !> Check the element order of `list` (no Tet4 with Tet10) and make room for `remaining` more.
   subroutine start_element(c, list, nodes_per_element, remaining, error)
      type(cursor_t), intent(in) :: c
      type(element_list_t), intent(inout) :: list
      integer(ip), intent(in) :: nodes_per_element
      !> Elements still to come in this block (room is made for all at once)
      integer(ip), intent(in) :: remaining
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: nodes(:, :), entity(:)
      integer(i8), allocatable :: tags(:)
      integer(i8) :: capacity
      integer :: stat

      if (list%nodes_per_element == 0) then
         list%nodes_per_element = nodes_per_element
      else if (list%nodes_per_element /= nodes_per_element) then
         call location_error(c, 'the mesh mixes ' // list%kind // &
            to_str(list%nodes_per_element) // ' and ' // list%kind // to_str(nodes_per_element) // &
            ' elements; ffrf needs one element order per mesh: mesh all volumes with the same ' // &
            '-order', error)
         return
      end if
      if (allocated(list%tags)) then
         if (size(list%tags, kind=i8) > list%count) return
         capacity = max(int(list%count, i8) + remaining, 2_i8 * size(list%tags, kind=i8))
      else
         capacity = max(int(remaining, i8), 1024_i8)
      end if
      capacity = min(capacity, int(huge(0_ip), i8))
      allocate (nodes(nodes_per_element, capacity), tags(capacity), entity(capacity), stat=stat)
      if (stat /= 0) then
         call location_error(c, 'out of memory for ' // to_str(capacity) // ' elements', error)
         return
      end if
      if (list%count > 0) then
         nodes(:, :list%count) = list%nodes(:, :list%count)
         tags(:list%count) = list%tags(:list%count)
         entity(:list%count) = list%entity(:list%count)
      end if
      call move_alloc(nodes, list%nodes)
      call move_alloc(tags, list%tags)
      call move_alloc(entity, list%entity)
   end subroutine start_element

   !> Node j of the element being added.
   pure subroutine store_node(r, element_type, j, index)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: element_type
      integer(ip), intent(in) :: j, index
      if (element_type == 4 .or. element_type == 11) then
         r%tets%nodes(j, r%tets%count + 1) = index
      else
         r%tris%nodes(j, r%tris%count + 1) = index
      end if
   end subroutine store_node

   !> Close the element being added: its tag and entity.
   pure subroutine finish_element(r, element_type, tag, entity)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: element_type, tag
      integer(ip), intent(in) :: entity
      r%min_element_tag = min(r%min_element_tag, tag)
      r%max_element_tag = max(r%max_element_tag, tag)
      if (element_type == 4 .or. element_type == 11) then
         r%tets%count = r%tets%count + 1
         r%tets%tags(r%tets%count) = tag
         r%tets%entity(r%tets%count) = entity
      else
         r%tris%count = r%tris%count + 1
         r%tris%tags(r%tris%count) = tag
         r%tris%entity(r%tris%count) = entity
      end if
   end subroutine finish_element

   !> One ASCII element line (from the element tag on if `tag` < 0, else from the node tags on):
   !> node tags mapped to indices, then the end of the line.
   subroutine read_element_record(r, element_type, nodes_per_element, entity, tag, error)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: element_type
      integer(ip), intent(in) :: nodes_per_element, entity
      !> Element tag already read (2.2), or -1 to read it here (4.1)
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: element_tag, node_tag, line, n, p
      integer(ip) :: j, index
      integer :: digit, digits
      logical :: ok

      element_tag = tag
      if (tag < 0) then
         call scan_int(r%c%text, r%c%pos, r%c%line, element_tag, ok)
         if (.not. ok) then
            call missing_item_error(r%c, 'an element tag', 'the element block holds fewer ' // &
               'elements than its header announces', error)
            return
         end if
         if (element_tag < 1) then
            call bad_tag_error(r%c, 'element', element_tag, error)
            return
         end if
      end if
      line = r%c%line
      n = len(r%c%text, kind=i8)
      do j = 1, nodes_per_element
         ! Fast path for the common "blanks, digits, separator" on this line; anything else
         ! (signs, tabs, line ends, errors) goes through scan_int
         p = r%c%pos
         do while (p <= n)
            if (iachar(r%c%text(p:p)) /= 32) exit  ! not a blank (no len_trim call)
            p = p + 1
         end do
         node_tag = 0
         digits = 0
         do while (p <= n .and. digits < 18)
            digit = iachar(r%c%text(p:p)) - 48
            if (digit < 0 .or. digit > 9) exit
            node_tag = 10 * node_tag + digit
            digits = digits + 1
            p = p + 1
         end do
         ok = digits > 0 .and. digits < 18
         if (ok .and. p <= n) ok = is_separator(r%c%text(p:p))
         if (ok) then
            r%c%pos = p
         else
            call scan_int(r%c%text, r%c%pos, r%c%line, node_tag, ok)
         end if
         call check_node_read(r%c, line, ok, element_tag, element_type, j, nodes_per_element, &
            error)
         if (allocated(error)) return
         ! The direct table inline (this loop reads every node of every element)
         index = 0
         if (r%map%dense) then
            if (node_tag >= r%map%min_tag .and. node_tag <= r%map%max_tag) &
               index = r%map%direct(node_tag - r%map%min_tag + 1)
         else
            index = node_index(r%map, node_tag)
         end if
         if (index == 0) then
            call missing_node_error(r%c, element_tag, element_type, node_tag, error)
            return
         end if
         call store_node(r, element_type, j, index)
      end do
      call skip_line_end(r%c%text, r%c%pos, r%c%line, ok)
      if (.not. ok) then
         call syntax_error(r%c, 'expected the end of the line after the ' // &
            to_str(nodes_per_element) // ' nodes of element ' // to_str(element_tag) // &
            ' (' // type_name(element_type) // ')', error)
         return
      end if
      call finish_element(r, element_type, element_tag, entity)
   end subroutine read_element_record

   !> After node j of an ASCII element line was scanned (ok: an integer was read): an error if
   !> the scan left the element's line (`line`: a node is missing) or found no integer.
   subroutine check_node_read(c, line, ok, element_tag, element_type, j, nodes_per_element, &
                              error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: line, element_tag, element_type
      logical, intent(in) :: ok
      integer(ip), intent(in) :: j, nodes_per_element
      type(error_t), allocatable, intent(out) :: error
      if (c%line /= line) then
         call line_error(c, line, 'element ' // to_str(element_tag) // ' (' // &
            type_name(element_type) // ') lists ' // to_str(j - 1) // ' of its ' // &
            to_str(nodes_per_element) // ' nodes; a node is missing', error)
      else if (.not. ok) then
         call syntax_error(c, 'expected node ' // to_str(j) // ' of element ' // &
            to_str(element_tag) // ' (' // type_name(element_type) // ')', error)
      end if
   end subroutine check_node_read

   !> The nodes of point or line element `tag` (dimension `dim` 0 or 1) of `entity`, appended
   !> to r%curve_point_nodes: read from the ASCII line after the element's tags (start = 0), or
   !> from the binary record whose node tags begin at byte `start`.
   subroutine read_curve_point_element(r, element_type, nodes_per_element, dim, entity, tag, &
                                       start, error)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: element_type, tag, start
      integer(ip), intent(in) :: nodes_per_element, dim, entity
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: node_tag, line
      integer(ip) :: j, index
      logical :: ok
      line = r%c%line
      do j = 1, nodes_per_element
         if (start > 0) then
            node_tag = transfer(r%c%text(start + 8 * (j - 1):start + 8 * j - 1), 0_i8)
         else
            call scan_int(r%c%text, r%c%pos, r%c%line, node_tag, ok)
            call check_node_read(r%c, line, ok, tag, element_type, j, nodes_per_element, error)
            if (allocated(error)) return
         end if
         index = node_index(r%map, node_tag)
         if (index == 0) then
            if (start > 0) r%c%pos = start + 8 * (j - 1)
            call missing_node_error(r%c, tag, element_type, node_tag, error)
            return
         end if
         call append_column(r%curve_point_nodes, r%num_curve_point_nodes, &
            int([dim, entity, index], i8))
      end do
   end subroutine read_curve_point_element

   !> Record `count` skipped volume elements of `element_type` in `entity` (a run continues the
   !> previous column when entity and type are the same).
   subroutine add_other_volume(r, entity, element_type, count, first_tag)
      type(reader_t), intent(inout) :: r
      integer(i8), intent(in) :: entity, element_type, count, first_tag
      integer(ip) :: n
      n = r%num_other_volume
      if (n > 0) then
         if (r%other_volume(1, n) == entity .and. r%other_volume(2, n) == element_type) then
            r%other_volume(3, n) = r%other_volume(3, n) + count
            return
         end if
      end if
      call append_column(r%other_volume, r%num_other_volume, &
         [entity, element_type, count, first_tag])
   end subroutine add_other_volume

   !> Append `column` after the first n columns of `list` (room for 16 at first, then doubled).
   pure subroutine append_column(list, n, column)
      integer(i8), allocatable, intent(inout) :: list(:, :)
      integer(ip), intent(inout) :: n
      integer(i8), intent(in) :: column(:)
      integer(i8), allocatable :: grown(:, :)
      if (.not. allocated(list)) allocate (list(size(column), 16))
      if (n == size(list, 2)) then
         allocate (grown(size(list, 1), 2 * n))
         grown(:, :n) = list
         call move_alloc(grown, list)
      end if
      n = n + 1
      list(:, n) = column
   end subroutine append_column

end submodule ffrf_mesh_gmsh_elements
