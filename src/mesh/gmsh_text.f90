!> Bodies of ffrf_mesh_gmsh, first of a chain of submodules (each sees the one before):
!> the reader state, the whole file in memory and its scanning (blanks, integers, reals,
!> line ends), the element type tables. Next: gmsh_tokens.f90.
submodule(ffrf_mesh_gmsh) ffrf_mesh_gmsh_text
   use, intrinsic :: iso_fortran_env, only: int32
   use, intrinsic :: iso_c_binding, only: c_char, c_double, c_ptr, c_null_char, c_loc, &
      c_associated
   use ffrf_core_kinds, only: dp, ip, i8
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_core_posix, only: file_kind, check_input_file, FILE_MISSING
   use ffrf_mesh_mesh, only: physical_group_t, dimension_word, element_type_name
   implicit none

   !> Largest mesh file read, bytes (4 GiB; the lc = 3 mm Tet10 crank, 10^5 nodes, is 11 MB)
   integer(i8), parameter :: MAX_MESH_BYTES = 4_i8 * 1024_i8**3

   !> Exact powers of ten for the fast real parser (10**22 < 2**53 * 2**22 is still exact).
   real(dp), parameter :: powers_of_ten(0:22) = [1.0e0_dp, 1.0e1_dp, 1.0e2_dp, 1.0e3_dp, &
      1.0e4_dp, 1.0e5_dp, 1.0e6_dp, 1.0e7_dp, 1.0e8_dp, 1.0e9_dp, 1.0e10_dp, 1.0e11_dp, &
      1.0e12_dp, 1.0e13_dp, 1.0e14_dp, 1.0e15_dp, 1.0e16_dp, 1.0e17_dp, 1.0e18_dp, 1.0e19_dp, &
      1.0e20_dp, 1.0e21_dp, 1.0e22_dp]
   !> Largest integer every smaller one of which a double holds exactly, 2**53
   integer(i8), parameter :: exact_mantissa = 9007199254740992_i8

   interface
      !> C strtod: correctly rounded, the conversion libgfortran's list-directed read ends in;
      !> `end` points after the last character used.
      function c_strtod(text, end) result(value) bind(c, name='strtod')
         import :: c_char, c_ptr, c_double
         character(kind=c_char), intent(in) :: text(*)
         type(c_ptr), intent(out) :: end
         real(c_double) :: value
      end function c_strtod
   end interface

   !> The whole file in memory and the read position in it.
   type :: cursor_t
      !> File contents
      character(len=:), allocatable :: text
      !> Next byte to read
      integer(i8) :: pos = 1
      !> Line of `pos` (meaningful in ASCII parts)
      integer(i8) :: line = 1
      !> Inside binary data (messages give byte offsets, not lines)
      logical :: binary = .false.
      !> For messages
      character(len=:), allocatable :: file_name
      !> Section being read, for messages ("$Nodes")
      character(len=:), allocatable :: section
   end type cursor_t

   !> Node tag -> node index: a direct table when the tags are dense, else sorted tags.
   type :: tag_map_t
      !> Direct table in use
      logical :: dense = .true.
      !> Smallest tag
      integer(i8) :: min_tag = 0
      !> Largest tag
      integer(i8) :: max_tag = -1
      !> Index of tag min_tag + k - 1, 0 if absent (dense)
      integer(ip), allocatable :: direct(:)
      !> Tags ascending (sparse)
      integer(i8), allocatable :: sorted_tags(:)
      !> Node index of sorted_tags(k) (sparse)
      integer(ip), allocatable :: sorted_index(:)
   end type tag_map_t

   !> Elements of one kind (tetrahedra or triangles) while reading; grown by doubling.
   type :: element_list_t
      !> "Tet" or "Tri", for messages
      character(len=3) :: kind = ''
      !> 4/10 or 3/6 once the first element is seen, 0 before
      integer(ip) :: nodes_per_element = 0
      !> Elements stored
      integer(ip) :: count = 0
      !> (nodes_per_element, capacity) node indices
      integer(ip), allocatable :: nodes(:, :)
      !> Gmsh element tags
      integer(i8), allocatable :: tags(:)
      !> Entity tag of each element
      integer(ip), allocatable :: entity(:)
   end type element_list_t

   !> Everything gathered while reading one file.
   type :: reader_t
      type(cursor_t) :: c
      !> "4.1" or "2.2"
      character(len=3) :: version = ''
      !> Binary file (MSH 4.1 file type 1)
      logical :: binary_file = .false.
      !> $Nodes and $Elements seen
      logical :: have_nodes = .false., have_elements = .false.
      !> $PhysicalNames: dim, tag, name of each (entities unused)
      type(physical_group_t), allocatable :: names(:)
      !> (dim, physical tag, entity tag) triples, consecutive repeats dropped
      integer(ip), allocatable :: links(:, :)
      !> Triples stored in `links`
      integer(ip) :: num_links = 0
      !> Number of nodes
      integer(ip) :: num_nodes = 0
      !> (3, num_nodes) coordinates
      real(dp), allocatable :: xyz(:, :)
      !> Gmsh tag of each node
      integer(i8), allocatable :: node_tags(:)
      type(tag_map_t) :: map
      type(element_list_t) :: tets, tris
      !> Elements of the skipped types
      integer(i8) :: num_skipped = 0
      !> Nodes of the point and line elements: (dimension, entity tag, node index) columns
      integer(i8), allocatable :: curve_point_nodes(:, :)
      !> Columns stored in `curve_point_nodes`
      integer(ip) :: num_curve_point_nodes = 0
      !> Skipped volume elements: (entity, type, count, first element tag) per run of a block
      integer(i8), allocatable :: other_volume(:, :)
      !> Columns stored in `other_volume`
      integer(ip) :: num_other_volume = 0
      !> Smallest and largest element tag seen (MSH 4.1 header check)
      integer(i8) :: min_element_tag = 0, max_element_tag = 0
   end type reader_t

contains
   ! ------------------------------------------------------------------------------------------
   ! File and tokens
   ! ------------------------------------------------------------------------------------------

   !> The whole file into `c%text` with one stream read.
   subroutine load_file(file_name, c, error)
      character(len=*), intent(in) :: file_name
      type(cursor_t), intent(out) :: c
      type(error_t), allocatable, intent(out) :: error
      character(len=512) :: message
      character(len=64) :: head
      integer(i8) :: file_size, content_bytes
      integer :: step, kind, got, stat, first, last_line
      logical :: nul_after
      c%file_name = file_name
      content_bytes = huge(1_i8)
      c%section = 'start of file'
      ! A FIFO or device would block or never end, a folder cannot be read: only a regular file
      ! of bounded size is opened (a missing one gets the open error below, with its hint).
      call file_kind(file_name, kind, file_size, error)
      if (allocated(error)) then
         error%message = 'mesh ''' // file_name // ''': ' // error%message
         return
      end if
      if (kind /= FILE_MISSING) then
         call check_input_file(file_name, 'mesh file', MAX_MESH_BYTES, error)
         if (allocated(error)) return
         ! bounded reads (docs/input.md "Input rules"): the first bytes say whether it is a mesh at
         ! all, and only its content (up to the last byte that is not NUL or blank) is read
         call read_file_head(file_name, 1_i8, head, got, stat, message)
         if (stat == 0) then
            first = verify(head(:got), ' ' // achar(9) // achar(10) // achar(13))
            if (first == 0 .or. index(head(max(first, 1):got), '$MeshFormat') /= 1) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_name // ''' (' // &
                  to_str(file_size) // ' bytes) is not a Gmsh MSH file: it does not start ' // &
                  'with $MeshFormat (first bytes: "' // printable(head(:min(got, 24))) // '")')
               return
            end if
            call content_end(file_name, content_bytes, nul_after, stat)
            if (stat /= 0) content_bytes = huge(1_i8)
         end if
         ! only after a complete last section ($End... line) is the rest padding: a file cut in
         ! binary data may end in zero bytes of that data, and is read whole (the parser then
         ! says where it ends)
         if (stat == 0) call read_file_head(file_name, max(1_i8, content_bytes - 63_i8), head, &
            got, stat, message)
         if (stat == 0) then
            ! the tail of the content only (the padding after it is not looked at)
            got = int(min(int(got, i8), content_bytes - max(1_i8, content_bytes - 63_i8) + 1))
            last_line = index(head(:got), achar(10), back=.true.) + 1
            if (index(head(last_line:got), '$End') /= 1) content_bytes = huge(1_i8)
            if (index(head(last_line:got), '$End') /= 1) nul_after = .false.
         end if
         if (stat == 0 .and. nul_after) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'mesh ''' // file_name // ''': ' // &
               to_str(file_size - content_bytes) // ' bytes of NUL padding after its last ' // &
               'section (content ends at byte ' // to_str(content_bytes) // ' of ' // &
               to_str(file_size) // '); a mesh file ends with its last $End... line: was ' // &
               'it cut short or padded? write it again with gmsh')
            return
         end if
         ! the content and the line end after it (a trailing blank run is not read)
         if (stat == 0) content_bytes = min(content_bytes, huge(1_i8) - 1) + 1
      end if
      call read_whole_file(file_name, c%text, step, file_size, message, &
         content_bytes=content_bytes)
      select case (step)
      case (READ_OPEN_FAILED)
         call fatal_error(error, FFRF_IO_ERROR, 'mesh ''' // file_name // ''': cannot open: ' // &
            trim(message) // '; build the mesh first (gmsh -3 ... -o ' // file_name // ')')
      case (READ_NO_MEMORY)
         call fatal_error(error, FFRF_IO_ERROR, 'mesh ''' // file_name // ''': out of memory ' // &
            'for ' // to_str(file_size) // ' bytes')
      case (READ_FAILED)
         call fatal_error(error, FFRF_IO_ERROR, 'mesh ''' // file_name // ''': cannot ' // &
            'read: ' // trim(message))
      end select
   end subroutine load_file

   !> `text` with control characters and bytes above 126 as '?', for a one-line message.
   pure function printable(text) result(shown)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: shown
      integer :: k
      shown = text
      do k = 1, len(shown)
         if (iachar(shown(k:k)) < 32 .or. iachar(shown(k:k)) > 126) shown(k:k) = '?'
      end do
   end function printable

   !> Skip blanks and line ends, counting lines.
   pure subroutine skip_space(text, pos, line)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: pos, line
      integer(i8) :: n
      n = len(text, kind=i8)
      do while (pos <= n)
         select case (iachar(text(pos:pos)))
         case (10)
            line = line + 1
         case (9, 13, 32)
         case default
            return
         end select
         pos = pos + 1
      end do
   end subroutine skip_space

   !> Whether `ch` separates tokens (blank, tab, CR, LF).
   elemental function is_separator(ch) result(yes)
      character, intent(in) :: ch
      logical :: yes
      select case (iachar(ch))
      case (9, 10, 13, 32)
         yes = .true.
      case default
         yes = .false.
      end select
   end function is_separator

   !> Integer token after white space. On failure `ok` is false and `pos` stays at the token.
   pure subroutine scan_int(text, pos, line, value, ok)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: pos, line
      integer(i8), intent(out) :: value
      logical, intent(out) :: ok
      integer(i8) :: n, p
      logical :: negative, digits_ok
      call skip_space(text, pos, line)
      n = len(text, kind=i8)
      p = pos
      value = 0
      ok = .false.
      if (p > n) return
      call scan_sign(text, p, negative)
      call scan_digits(text, p, 18, value, digits_ok)
      if (.not. digits_ok) return
      if (p <= n) then
         if (.not. is_separator(text(p:p))) return
      end if
      if (negative) value = -value
      ok = .true.
      pos = p
   end subroutine scan_int

   !> An optional '+' or '-' at text(p:), p moved past it; `negative` for '-'.
   pure subroutine scan_sign(text, p, negative)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: p
      logical, intent(out) :: negative
      negative = .false.
      if (p > len(text, kind=i8)) return
      if (text(p:p) == '-' .or. text(p:p) == '+') then
         negative = text(p:p) == '-'
         p = p + 1
      end if
   end subroutine scan_sign

   !> The decimal digits at text(p:), p moved past them, as `value`; `ok` when there are 1 to
   !> max_digits of them (a longer run stops at digit max_digits + 1 with `ok` false).
   pure subroutine scan_digits(text, p, max_digits, value, ok)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: p
      integer, intent(in) :: max_digits
      integer(i8), intent(out) :: value
      logical, intent(out) :: ok
      integer :: digit, digits
      value = 0
      ok = .false.
      digits = 0
      do while (p <= len(text, kind=i8))
         digit = iachar(text(p:p)) - 48
         if (digit < 0 .or. digit > 9) exit
         if (digits == max_digits) return
         value = 10 * value + digit
         digits = digits + 1
         p = p + 1
      end do
      ok = digits > 0
   end subroutine scan_digits

   !> Real token after white space, correctly rounded: exact fast path (mantissa <= 2**53,
   !> |decimal exponent| <= 22: one IEEE multiply or divide of exact operands), else C strtod
   !> (strtod_token) or an internal read. On failure `ok` is false and `pos` stays at the token.
   subroutine scan_real(text, pos, line, value, ok)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: pos, line
      real(dp), intent(out) :: value
      logical, intent(out) :: ok
      integer(i8) :: n, p, mantissa, exponent_part
      integer :: digit, significant, exponent, stat
      logical :: negative, exact, any_digit, negative_exponent, converted, digits_ok
      call skip_space(text, pos, line)
      n = len(text, kind=i8)
      p = pos
      value = 0.0_dp
      ok = .false.
      if (p > n) return
      call scan_sign(text, p, negative)
      mantissa = 0
      significant = 0
      exponent = 0
      exact = .true.
      any_digit = .false.
      ! Integer part
      do while (p <= n)
         digit = iachar(text(p:p)) - 48
         if (digit < 0 .or. digit > 9) exit
         any_digit = .true.
         if (mantissa > 0 .or. digit > 0) then
            if (significant < 18) then
               mantissa = 10 * mantissa + digit
               significant = significant + 1
            else
               exponent = exponent + 1
               if (digit /= 0) exact = .false.
            end if
         end if
         p = p + 1
      end do
      ! Fraction
      if (p <= n) then
         if (text(p:p) == '.') then
            p = p + 1
            do while (p <= n)
               digit = iachar(text(p:p)) - 48
               if (digit < 0 .or. digit > 9) exit
               any_digit = .true.
               if (mantissa == 0 .and. digit == 0) then
                  exponent = exponent - 1
               else if (significant < 18) then
                  mantissa = 10 * mantissa + digit
                  significant = significant + 1
                  exponent = exponent - 1
               else if (digit /= 0) then
                  exact = .false.
               end if
               p = p + 1
            end do
         end if
      end if
      if (.not. any_digit) return
      ! Exponent
      if (p <= n) then
         if (text(p:p) == 'e' .or. text(p:p) == 'E' .or. text(p:p) == 'd' .or. &
             text(p:p) == 'D') then
            p = p + 1
            call scan_sign(text, p, negative_exponent)
            call scan_digits(text, p, 5, exponent_part, digits_ok)
            if (.not. digits_ok) return
            if (negative_exponent) exponent_part = -exponent_part
            exponent = exponent + int(exponent_part)
         end if
      end if
      if (p <= n) then
         if (.not. is_separator(text(p:p))) return
      end if
      if (mantissa == 0) then
         value = 0.0_dp
      else if (exact .and. mantissa <= exact_mantissa .and. abs(exponent) <= 22) then
         if (exponent >= 0) then
            value = real(mantissa, dp) * powers_of_ten(exponent)
         else
            value = real(mantissa, dp) / powers_of_ten(-exponent)
         end if
      else
         call strtod_token(text(pos:p - 1), value, converted)
         if (.not. converted) then
            read (text(pos:p - 1), *, iostat=stat) value
            if (stat /= 0) return
         end if
         negative = .false.
      end if
      if (negative) value = -value
      ok = .true.
      pos = p
   end subroutine scan_real

   !> A real token already checked by scan_real (sign, digits, point, exponent with e, E, d or
   !> D), converted by C strtod, the correctly rounded conversion behind the internal read,
   !> without the cost of Fortran I/O. `ok` false (the caller does the internal read) for a
   !> long token, one strtod does not take whole (a locale with a decimal comma) and a result
   !> that is not finite or is zero.
   subroutine strtod_token(token, value, ok)
      character(len=*), intent(in) :: token
      real(dp), intent(out) :: value
      logical, intent(out) :: ok
      character(kind=c_char), target :: buffer(64)
      type(c_ptr) :: end
      integer :: k
      value = 0.0_dp
      ok = .false.
      if (len(token) >= size(buffer)) return
      do k = 1, len(token)
         select case (token(k:k))
         case ('d', 'D')
            buffer(k) = 'e'
         case default
            buffer(k) = token(k:k)
         end select
      end do
      buffer(len(token) + 1) = c_null_char
      value = c_strtod(buffer, end)
      ok = c_associated(end, c_loc(buffer(len(token) + 1))) .and. ieee_is_finite(value) .and. &
         value /= 0.0_dp
   end subroutine strtod_token

   !> Next white-space delimited word ('' at end of file).
   function next_word(c) result(word)
      type(cursor_t), intent(inout) :: c
      character(len=:), allocatable :: word
      integer(i8) :: start, n
      call skip_space(c%text, c%pos, c%line)
      n = len(c%text, kind=i8)
      start = c%pos
      do while (c%pos <= n)
         if (is_separator(c%text(c%pos:c%pos))) exit
         c%pos = c%pos + 1
      end do
      word = c%text(start:c%pos - 1)
   end function next_word

   !> Past the end of the current line, wherever in it the cursor is.
   subroutine skip_line(c)
      type(cursor_t), intent(inout) :: c
      integer(i8) :: found
      found = index(c%text(c%pos:), achar(10), kind=i8)
      if (found == 0) then
         c%pos = len(c%text, kind=i8) + 1
      else
         c%pos = c%pos + found
         c%line = c%line + 1
      end if
   end subroutine skip_line

   !> Only blanks may remain on the current line; step past its end (ok false, pos at the
   !> offending text, if something else comes first).
   pure subroutine skip_line_end(text, pos, line, ok)
      character(len=*), intent(in) :: text
      integer(i8), intent(inout) :: pos, line
      logical, intent(out) :: ok
      integer(i8) :: n
      n = len(text, kind=i8)
      ok = .true.
      do while (pos <= n)
         select case (iachar(text(pos:pos)))
         case (9, 13, 32)
            pos = pos + 1
         case (10)
            pos = pos + 1
            line = line + 1
            return
         case default
            ok = .false.
            return
         end select
      end do
   end subroutine skip_line_end

   !> Nodes per element and dimension of Gmsh element `element_type`, both -1 if unknown to ffrf.
   pure subroutine type_size(element_type, nodes, dim)
      integer(i8), intent(in) :: element_type
      integer(ip), intent(out) :: nodes, dim
      !> Nodes and dimension of types 1..31
      integer(ip), parameter :: nodes_table(31) = [2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, &
         1, 8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5, 6, 20, 35, 56]
      integer(ip), parameter :: dim_table(31) = [1, 2, 2, 3, 3, 3, 3, 1, 2, 2, 3, 3, 3, 3, 0, &
         2, 3, 3, 3, 2, 2, 2, 2, 2, 2, 1, 1, 1, 3, 3, 3]
      select case (element_type)
      case (1:31)
         nodes = nodes_table(element_type)
         dim = dim_table(element_type)
      case (92)
         nodes = 64
         dim = 3
      case (93)
         nodes = 125
         dim = 3
      case default
         nodes = -1
         dim = -1
      end select
   end subroutine type_size

   !> "Tet10", "Tri3" ... for messages.
   function type_name(element_type) result(name)
      integer(i8), intent(in) :: element_type
      character(len=:), allocatable :: name
      name = element_type_name(element_type)
   end function type_name

   !> Permutation putting the columns of `keys` in lexicographic order (a stable bottom-up
   !> merge sort; one row: the values in ascending order).
   subroutine merge_permutation(keys, perm)
      integer(i8), intent(in) :: keys(:, :)
      integer(ip), allocatable, intent(out) :: perm(:)
      integer(ip), allocatable :: work(:)
      integer(ip) :: n, width, left, mid, right, i, a, b
      n = size(keys, 2, kind=ip)
      perm = [(i, i=1, n)]
      allocate (work(n))
      width = 1
      do while (width < n)
         do left = 1, n, 2 * width
            mid = min(left + width - 1, n)
            right = min(left + 2 * width - 1, n)
            a = left
            b = mid + 1
            do i = left, right
               if (b > right) then
                  work(i) = perm(a)
                  a = a + 1
               else if (a > mid) then
                  work(i) = perm(b)
                  b = b + 1
               else if (column_less(keys(:, perm(b)), keys(:, perm(a)))) then
                  work(i) = perm(b)
                  b = b + 1
               else
                  work(i) = perm(a)
                  a = a + 1
               end if
            end do
         end do
         perm = work
         width = 2 * width
      end do
   end subroutine merge_permutation

   !> Whether column `x` comes strictly before column `y` lexicographically.
   pure function column_less(x, y) result(less)
      integer(i8), intent(in) :: x(:), y(:)
      logical :: less
      integer :: k
      less = .false.
      do k = 1, size(x)
         if (x(k) /= y(k)) then
            less = x(k) < y(k)
            return
         end if
      end do
   end function column_less

end submodule ffrf_mesh_gmsh_text
