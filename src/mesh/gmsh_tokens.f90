!> ffrf_mesh_gmsh: tokens of a section (counts, sizes, tags, reals, ASCII or binary) and the
!> located error messages. Next: gmsh_sections.f90.
submodule(ffrf_mesh_gmsh:ffrf_mesh_gmsh_text) ffrf_mesh_gmsh_tokens
   implicit none

contains

   !> "$EndX" closing the current section "$X".
   subroutine expect_end(c, error)
      type(cursor_t), intent(inout) :: c
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: word
      integer(i8) :: start
      call skip_space(c%text, c%pos, c%line)
      start = c%pos
      word = next_word(c)
      if (word /= '$End' // c%section(2:)) then
         c%pos = start
         call syntax_error(c, 'expected $End' // c%section(2:) // ' (the section holds ' // &
            'more or fewer items than its counts announce)', error)
      end if
   end subroutine expect_end

   !> Integer with a message on failure.
   subroutine read_int(c, what, value, error)
      type(cursor_t), intent(inout) :: c
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      logical :: ok
      call scan_int(c%text, c%pos, c%line, value, ok)
      if (.not. ok) call syntax_error(c, 'expected an integer (' // what // ')', error)
   end subroutine read_int

   !> Non-negative integer that fits `ip`.
   subroutine read_count(c, what, value, error)
      type(cursor_t), intent(inout) :: c
      character(len=*), intent(in) :: what
      integer(ip), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: long
      value = 0
      call read_int(c, what, long, error)
      if (allocated(error)) return
      if (long < 0 .or. long > huge(0_ip)) then
         call location_error(c, what // ' = ' // to_str(long) // ' is out of range', error)
         return
      end if
      value = int(long, ip)
   end subroutine read_count

   !> A size_t (binary) or a non-negative integer (ASCII); counts that must fit `ip` are
   !> checked where they are used.
   subroutine read_size(c, binary, what, value, error)
      type(cursor_t), intent(inout) :: c
      logical, intent(in) :: binary
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: p
      if (binary) then
         call binary_take(c, 8_i8, what, p, error)
         if (allocated(error)) return
         value = transfer(c%text(p:p + 7), 0_i8)
      else
         call read_int(c, what, value, error)
         if (allocated(error)) return
      end if
      if (value < 0) then
         call location_error(c, what // ' = ' // to_str(value) // ' is negative', error)
      end if
   end subroutine read_size

   !> An int (binary, 4 bytes) or an integer (ASCII).
   subroutine read_tag(c, binary, what, value, error)
      type(cursor_t), intent(inout) :: c
      logical, intent(in) :: binary
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      if (binary) then
         call binary_int(c, what, value, error)
      else
         call read_int(c, what, value, error)
      end if
   end subroutine read_tag

   !> The header of a $Nodes or $Elements section (4.1) of `item`s ("node", "element"): number
   !> of blocks, number of items, smallest and largest tag.
   subroutine read_section_header(c, binary, item, num_blocks, num_items, min_tag, max_tag, &
      error)
      type(cursor_t), intent(inout) :: c
      logical, intent(in) :: binary
      character(len=*), intent(in) :: item
      integer(i8), intent(out) :: num_blocks, num_items, min_tag, max_tag
      type(error_t), allocatable, intent(out) :: error
      call read_size(c, binary, 'number of ' // item // ' blocks', num_blocks, error)
      if (.not. allocated(error)) call read_size(c, binary, 'number of ' // item // 's', &
         num_items, error)
      if (.not. allocated(error)) call read_size(c, binary, 'smallest ' // item // ' tag', &
         min_tag, error)
      if (.not. allocated(error)) call read_size(c, binary, 'largest ' // item // ' tag', &
         max_tag, error)
   end subroutine read_section_header

   !> The blocks of a $Nodes or $Elements section (4.1) hold as many `item`s as its header
   !> announced.
   subroutine check_blocks_total(c, item, total, announced, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: item
      integer(i8), intent(in) :: total, announced
      type(error_t), allocatable, intent(out) :: error
      if (total /= announced) then
         call location_error(c, item // ' blocks hold ' // to_str(total) // ' ' // item // &
            's, the header announced ' // to_str(announced), error)
      end if
   end subroutine check_blocks_total

   !> The header of one block of a $Nodes or $Elements section (4.1): entity dimension, entity
   !> tag, the block's `third` value (`third_what`: "parametric flag", "element type") and its
   !> count of `item`s; `block_name` ("a node block") for messages.
   subroutine read_block_header(c, binary, block_name, item, third_what, dim, entity, third, n, &
      error)
      type(cursor_t), intent(inout) :: c
      logical, intent(in) :: binary
      character(len=*), intent(in) :: block_name, item, third_what
      integer(i8), intent(out) :: dim, entity, third, n
      type(error_t), allocatable, intent(out) :: error
      call read_tag(c, binary, 'entity dimension of ' // block_name, dim, error)
      if (.not. allocated(error)) call read_tag(c, binary, 'entity tag', entity, error)
      if (.not. allocated(error)) call read_tag(c, binary, third_what, third, error)
      if (.not. allocated(error)) call read_size(c, binary, item // 's in block', n, error)
   end subroutine read_block_header

   !> A double (binary) or a real (ASCII).
   subroutine read_real(c, binary, what, value, error)
      type(cursor_t), intent(inout) :: c
      logical, intent(in) :: binary
      character(len=*), intent(in) :: what
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: p
      logical :: ok
      if (binary) then
         call binary_take(c, 8_i8, what, p, error)
         if (allocated(error)) return
         value = transfer(c%text(p:p + 7), 0.0_dp)
      else
         call scan_real(c%text, c%pos, c%line, value, ok)
         if (.not. ok) call syntax_error(c, 'expected a real (' // what // ')', error)
      end if
   end subroutine read_real

   !> Step over the line end after a section header: binary data starts right after it.
   subroutine start_binary(c, error)
      type(cursor_t), intent(inout) :: c
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: n
      n = len(c%text, kind=i8)
      do while (c%pos <= n)
         if (c%text(c%pos:c%pos) /= ' ' .and. c%text(c%pos:c%pos) /= achar(13)) exit
         c%pos = c%pos + 1
      end do
      if (c%pos > n) then
         call location_error(c, 'file ends before the binary data', error)
         return
      end if
      if (c%text(c%pos:c%pos) /= achar(10)) then
         call syntax_error(c, 'expected the end of the line before binary data', error)
         return
      end if
      c%pos = c%pos + 1
      c%line = c%line + 1
      c%binary = .true.
   end subroutine start_binary

   !> Reserve `bytes` of binary data: `first` is where they start.
   subroutine binary_take(c, bytes, what, first, error)
      type(cursor_t), intent(inout) :: c
      integer(i8), intent(in) :: bytes
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: first
      type(error_t), allocatable, intent(out) :: error
      first = c%pos
      if (bytes < 0 .or. c%pos + bytes - 1 > len(c%text, kind=i8)) then
         call location_error(c, 'file ends inside the ' // what // ' (truncated file?)', error)
         return
      end if
      c%pos = c%pos + bytes
   end subroutine binary_take

   !> A 4-byte int of binary data.
   subroutine binary_int(c, what, value, error)
      type(cursor_t), intent(inout) :: c
      character(len=*), intent(in) :: what
      integer(i8), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: p
      value = 0
      call binary_take(c, 4_i8, what, p, error)
      if (allocated(error)) return
      value = transfer(c%text(p:p + 3), 0_int32)
   end subroutine binary_int

   ! ------------------------------------------------------------------------------------------
   ! Messages
   ! ------------------------------------------------------------------------------------------

   !> "mesh 'box.msh': $Nodes, line 12" or "..., byte 1234".
   function location(c) result(text)
      type(cursor_t), intent(in) :: c
      character(len=:), allocatable :: text
      text = 'mesh ''' // c%file_name // ''': ' // c%section
      if (c%binary) then
         text = text // ', byte ' // to_str(c%pos - 1)
      else
         text = text // ', line ' // to_str(c%line)
      end if
   end function location

   !> Error at the cursor.
   subroutine location_error(c, message, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: message
      type(error_t), allocatable, intent(out) :: error
      call fatal_error(error, FFRF_INPUT_ERROR, location(c) // ': ' // message)
   end subroutine location_error

   !> Error at the cursor quoting the text found there.
   subroutine syntax_error(c, message, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: message
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: found
      integer(i8) :: last, n
      n = len(c%text, kind=i8)
      if (c%pos > n) then
         found = 'end of file'
      else
         last = c%pos
         do while (last < n .and. last < c%pos + 39)
            if (is_separator(c%text(last + 1:last + 1))) exit
            last = last + 1
         end do
         found = '''' // c%text(c%pos:last) // ''''
      end if
      call location_error(c, message // ', found ' // found, error)
   end subroutine syntax_error

   subroutine missing_node_error(c, element_tag, element_type, node_tag, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: element_tag, element_type, node_tag
      type(error_t), allocatable, intent(out) :: error
      call location_error(c, 'element ' // to_str(element_tag) // ' (' // &
         type_name(element_type) // ') refers to node ' // to_str(node_tag) // &
         ', which $Nodes does not list', error)
   end subroutine missing_node_error

   subroutine duplicate_tag_error(c, tag, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      call location_error(c, 'node tag ' // to_str(tag) // ' appears twice', error)
   end subroutine duplicate_tag_error

   !> A node or element (`what`) tag below 1.
   subroutine bad_tag_error(c, what, tag, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: what
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      call location_error(c, what // ' tag ' // to_str(tag) // ' is not allowed: Gmsh ' // what &
         // ' tags are 1 or more', error)
   end subroutine bad_tag_error

   !> An element type the reader does not know: its node count, and so the file layout, is
   !> unknown, wherever the element lies.
   subroutine unknown_type_error(c, element_type, where, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: element_type
      character(len=*), intent(in) :: where
      type(error_t), allocatable, intent(out) :: error
      call location_error(c, where // ' has element type ' // to_str(element_type) // &
         ', which ffrf does not know (it knows Gmsh types 1-31, 92 and 93 and uses Tet4 and ' // &
         'Tet10 volumes with Tri3 and Tri6 surfaces); re-mesh with gmsh -3 and ' // &
         'Mesh.ElementOrder 1 or 2', error)
   end subroutine unknown_type_error

   !> A coordinate could not be read: a NaN or Inf token is named as such.
   subroutine coordinate_error(c, tag, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: tag
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: token
      integer(i8) :: last, n
      n = len(c%text, kind=i8)
      last = c%pos - 1
      do while (last < n .and. last < c%pos + 39)
         if (is_separator(c%text(last + 1:last + 1))) exit
         last = last + 1
      end do
      token = to_lower(c%text(c%pos:last))
      if (len(token) > 0) then
         if (token(1:1) == '+' .or. token(1:1) == '-') token = token(2:)
      end if
      if (index(token, 'nan') == 1 .or. index(token, 'inf') == 1) then
         call location_error(c, 'node ' // to_str(tag) // ' has the coordinate ''' // &
            c%text(c%pos:last) // ''', which is not a finite number', error)
      else
         call syntax_error(c, 'expected a coordinate of node ' // to_str(tag), error)
      end if
   end subroutine coordinate_error

   !> Whether the cursor stands at a "$End..." line.
   pure function at_section_end(c) result(yes)
      type(cursor_t), intent(in) :: c
      logical :: yes
      yes = .false.
      if (c%pos + 3 <= len(c%text, kind=i8)) yes = c%text(c%pos:c%pos + 3) == '$End'
   end function at_section_end

   !> `what` was expected: where the section ends instead, its counts announced more items than
   !> it holds (`announced` says which); else a syntax error quoting what is there.
   subroutine missing_item_error(c, what, announced, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: what, announced
      type(error_t), allocatable, intent(out) :: error
      if (at_section_end(c)) then
         call location_error(c, announced, error)
      else
         call syntax_error(c, 'expected ' // what, error)
      end if
   end subroutine missing_item_error

   !> Error on ASCII line `line` of the current section (a value missing from that line).
   subroutine line_error(c, line, message, error)
      type(cursor_t), intent(in) :: c
      integer(i8), intent(in) :: line
      character(len=*), intent(in) :: message
      type(error_t), allocatable, intent(out) :: error
      call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // c%file_name // ''': ' // &
         c%section // ', line ' // to_str(line) // ': ' // message)
   end subroutine line_error

   !> A count read from the file must fit the bytes left in it, each item taking `min_bytes` at
   !> least; checked before anything is allocated for the items, so a corrupt count cannot make
   !> the reader allocate more than a small multiple of the file size.
   subroutine check_count_fits(c, what, count, min_bytes, error)
      type(cursor_t), intent(in) :: c
      character(len=*), intent(in) :: what
      integer(i8), intent(in) :: count, min_bytes
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: left
      left = max(0_i8, len(c%text, kind=i8) - c%pos + 1)
      if (count > left / min_bytes) then
         call location_error(c, what // ' = ' // to_str(count) // ' cannot be right: the ' // &
            to_str(left) // ' bytes left in the file hold at most ' // to_str(left / min_bytes) // &
            ' (truncated or corrupt file?)', error)
      end if
   end subroutine check_count_fits

end submodule ffrf_mesh_gmsh_tokens
