!> Nastran bulk data as a mesh (docs/input.md "Nastran bulk data"): a deck (.bdf, .dat, .nas,
!> .blk) read into the same mesh_t as a Gmsh file. This module reads the text into cards: free
!> (comma) fields, small (8-character) and large (16-character, name ending in `*`) fixed fields,
!> continuation lines (first field blank, `+` or `*`; a marker in field 10 asks for one), reals
!> without E (`2.1+11`, `-1.-3`) or with D, `$` comments, BEGIN BULK and ENDDATA, and INCLUDE
!> (a quoted path relative to the including deck). The submodule bulk_data_cards turns the cards
!> (GRID, CORD2R, CTETRA, PSOLID, MAT1, RBE2, RBE3, SPC1, SET1) into the mesh.
!>
!> Every card keeps its file and line, every field its line: errors read "deck 'a.bdf': line 12,
!> GRID 7, field 3 (X1): '1.2.3' is not a real ...".
module ffrf_mesh_bulk_data
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_str, to_lower
   use ffrf_core_paths, only: folder_of, join_path
   use ffrf_core_posix, only: check_input_file
   use ffrf_core_whole_file, only: read_whole_file, READ_OK
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_mesh_gmsh, only: read_gmsh
   implicit none
   private
   public :: read_bulk_data, read_mesh_file, is_bulk_data_file

   !> Longest field text kept (a free field may be longer than 16 characters)
   integer, parameter :: FIELD_LEN = 40
   !> Deepest INCLUDE nesting (a cycle stops here)
   integer, parameter :: MAX_DEPTH = 16
   !> Largest deck file read
   integer(i8), parameter :: MAX_DECK_BYTES = 4_i8 * 1024_i8**3

   !> The cards of a deck as text: card c has fields first(c) .. first(c) + count(c) - 1 of
   !> `field` (data fields 1.., the name and continuation markers left out).
   type :: deck_t
      character(len=FIELD_LEN), allocatable :: field(:)
      !> Line of each field
      integer, allocatable :: field_line(:)
      integer :: num_fields = 0
      !> Card name, lower case without `*`
      character(len=8), allocatable :: name(:)
      integer, allocatable :: first(:), count(:), file(:), line(:)
      integer :: num_cards = 0
      !> The files read (card%file indexes them)
      character(len=1024), allocatable :: files(:)
      integer :: num_files = 0
      !> ENDDATA was read
      logical :: ended = .false.
      !> A card is open (continuation lines may follow)
      logical :: open = .false.
      !> The open card's last line has a continuation marker in field 10
      logical :: wants_continuation = .false.
      integer :: marker_line = 0
   end type deck_t

   interface
      !> The mesh of the cards of `deck` (bulk_data_cards.f90).
      module subroutine build_mesh(deck, mesh, error)
         type(deck_t), intent(in) :: deck
         type(mesh_t), intent(out) :: mesh
         type(error_t), allocatable, intent(out) :: error
      end subroutine build_mesh

      !> "deck 'a.bdf': line 12" of line `line` of file k.
      module function deck_where(deck, k, line) result(text)
         type(deck_t), intent(in) :: deck
         integer, intent(in) :: k, line
         character(len=:), allocatable :: text
      end function deck_where

      !> `text` in upper case (card names in messages).
      pure module function to_upper(text) result(upper)
         character(len=*), intent(in) :: text
         character(len=len_trim(text)) :: upper
      end function to_upper
   end interface

contains

   !> .bdf, .dat, .nas or .blk (any case): read as Nastran bulk data.
   pure logical function is_bulk_data_file(file_name)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable :: lower
      integer :: n
      lower = to_lower(trim(file_name))
      n = len(lower)
      is_bulk_data_file = .false.
      if (n < 5) return
      select case (lower(n - 3:n))
      case ('.bdf', '.dat', '.nas', '.blk')
         is_bulk_data_file = .true.
      end select
   end function is_bulk_data_file

   !> A mesh file read by its suffix: Nastran bulk data (is_bulk_data_file) or Gmsh.
   subroutine read_mesh_file(file_name, mesh, error)
      character(len=*), intent(in) :: file_name
      type(mesh_t), intent(out) :: mesh
      type(error_t), allocatable, intent(out) :: error
      if (is_bulk_data_file(file_name)) then
         call read_bulk_data(file_name, mesh, error)
      else
         call read_gmsh(file_name, mesh, error)
      end if
   end subroutine read_mesh_file

   !> Read the deck `file_name` (and its INCLUDEs) into `mesh`.
   subroutine read_bulk_data(file_name, mesh, error)
      character(len=*), intent(in) :: file_name
      type(mesh_t), intent(out) :: mesh
      type(error_t), allocatable, intent(out) :: error
      type(deck_t) :: deck
      allocate (deck%field(1024), deck%field_line(1024), deck%name(256), deck%first(256), &
         deck%count(256), deck%file(256), deck%line(256), deck%files(4))
      call check_input_file(file_name, 'mesh file (Nastran bulk data)', MAX_DECK_BYTES, error)
      if (allocated(error)) return
      call read_deck_file(deck, file_name, 0, error)
      if (allocated(error)) return
      call build_mesh(deck, mesh, error)
   end subroutine read_bulk_data

   !> One file of the deck: its lines in order; INCLUDE reads the named file there.
   recursive subroutine read_deck_file(deck, file_name, depth, error)
      type(deck_t), intent(inout) :: deck
      character(len=*), intent(in) :: file_name
      !> 0 for the deck named by mesh_file, +1 per INCLUDE
      integer, intent(in) :: depth
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: text, raw, lower
      character(len=512) :: message
      character(len=1024), allocatable :: grown(:)
      integer(i8) :: size, pos, last
      integer :: step, line, k, here
      logical :: in_bulk

      call read_whole_file(file_name, text, step, size, message, max_bytes=MAX_DECK_BYTES)
      if (step /= READ_OK) then
         call fatal_error(error, FFRF_IO_ERROR, 'deck ''' // file_name // ''': cannot read: ' // &
            trim(message))
         return
      end if
      if (deck%num_files == size_of(deck%files)) then
         allocate (grown(2 * deck%num_files))
         grown(:deck%num_files) = deck%files(:deck%num_files)
         call move_alloc(grown, deck%files)
      end if
      deck%num_files = deck%num_files + 1
      here = deck%num_files
      deck%files(here) = file_name
      ! the deck named by mesh_file may hold executive and case control before BEGIN BULK
      in_bulk = depth > 0 .or. .not. has_begin_bulk(text)
      pos = 1
      line = 0
      do while (pos <= len(text, kind=i8) .and. .not. deck%ended)
         last = index(text(pos:), achar(10), kind=i8)
         if (last == 0) then
            last = len(text, kind=i8)
         else
            last = pos + last - 2
         end if
         raw = text(pos:last)
         pos = last + 2
         line = line + 1
         if (len(raw) > 0) then
            if (raw(len(raw):) == achar(13)) raw = raw(:len(raw) - 1)
         end if
         k = index(raw, '$')
         if (k > 0) raw = raw(:k - 1)
         if (len_trim(raw) == 0) cycle
         raw = expand_tabs(raw)
         lower = to_lower(adjustl(raw))
         if (.not. in_bulk) then
            if (is_begin_bulk(lower)) in_bulk = .true.
            cycle
         end if
         if (starts_with(lower, 'enddata')) then
            call close_card(deck, here, error)
            deck%ended = .true.
            return
         else if (starts_with(lower, 'begin')) then
            if (.not. is_begin_bulk(lower) .or. index(lower, 'auxmodel') > 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, deck_where(deck, here, line) // ': ''' // &
                  trim(adjustl(raw)) // ''': part superelements and auxiliary models are not ' // &
                  'read; give the bulk data of one model')
               return
            end if
            cycle
         else if (starts_with(lower, 'include')) then
            call close_card(deck, here, error)
            if (.not. allocated(error)) call include_file(deck, here, line, raw, depth, error)
            if (allocated(error)) return
            cycle
         end if
         call read_line(deck, here, line, raw, error)
         if (allocated(error)) return
      end do
      call close_card(deck, here, error)
   end subroutine read_deck_file

   !> INCLUDE 'path' (path relative to the including file's folder unless absolute).
   recursive subroutine include_file(deck, here, line, raw, depth, error)
      type(deck_t), intent(inout) :: deck
      integer, intent(in) :: here, line, depth
      character(len=*), intent(in) :: raw
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: where, name, path
      integer :: q1, q2
      where = deck_where(deck, here, line) // ', INCLUDE'
      q1 = index(raw, '''')
      q2 = 0
      if (q1 > 0) q2 = index(raw(q1 + 1:), '''')
      if (q1 == 0 .or. q2 < 2) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': ''' // trim(adjustl(raw)) // &
            ''' names no file; write INCLUDE ''file.bdf'' (the path in quotes on one line)')
         return
      end if
      name = trim(adjustl(raw(q1 + 1:q1 + q2 - 1)))
      if (depth + 1 > MAX_DEPTH) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ' ''' // name // ''': more than ' // &
            to_str(MAX_DEPTH) // ' nested INCLUDEs; does a file include itself?')
         return
      end if
      path = join_path(folder_of(trim(deck%files(here))), name)
      call check_input_file(path, 'included file', MAX_DECK_BYTES, error)
      if (.not. allocated(error)) call read_deck_file(deck, path, depth + 1, error)
      if (allocated(error)) call add_context(error, where // ' ''' // name // '''')
   end subroutine include_file

   !> One line of bulk data: a new card, or a continuation of the open one.
   subroutine read_line(deck, here, line, raw, error)
      type(deck_t), intent(inout) :: deck
      integer, intent(in) :: here, line
      character(len=*), intent(in) :: raw
      type(error_t), allocatable, intent(out) :: error
      character(len=FIELD_LEN), allocatable :: items(:)
      character(len=FIELD_LEN) :: head
      character(len=80) :: fixed
      logical :: large
      integer :: per_line, k, n

      if (index(raw, ',') > 0) then
         call split_free(raw, items, n)
         if (n < 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, deck_where(deck, here, line) // &
               ': a free field is longer than ' // to_str(FIELD_LEN) // ' characters')
            return
         end if
         head = adjustl(items(1))
      else
         fixed = raw
         head = adjustl(fixed(1:8))
      end if
      if (len_trim(head) == 0 .or. head(1:1) == '+' .or. head(1:1) == '*') then
         if (.not. deck%open) then
            call fatal_error(error, FFRF_INPUT_ERROR, deck_where(deck, here, line) // &
               ': a continuation line (first field ''' // trim(head) // ''') with no card ' // &
               'before it to continue')
            return
         end if
         large = head(1:1) == '*'
      else
         call close_card(deck, here, error)
         if (allocated(error)) return
         large = head(len_trim(head):len_trim(head)) == '*'
         call open_card(deck, here, line, head, error)
         if (allocated(error)) return
      end if
      per_line = merge(4, 8, large)
      if (index(raw, ',') > 0) then
         if (n > per_line + 2) then
            call fatal_error(error, FFRF_INPUT_ERROR, deck_where(deck, here, line) // ', ' // &
               trim(head) // ': ' // to_str(n) // ' free fields on one line; at most ' // &
               to_str(per_line + 2) // ' (the name, ' // to_str(per_line) // ' data fields, ' // &
               'the continuation)')
            return
         end if
         do k = 2, per_line + 1
            if (k <= n) then
               call add_field(deck, adjustl(items(k)), line)
            else
               call add_field(deck, '', line)
            end if
         end do
         deck%wants_continuation = .false.
         if (n == per_line + 2) deck%wants_continuation = len_trim(items(n)) > 0
      else
         if (len_trim(raw) > 80) then
            call fatal_error(error, FFRF_INPUT_ERROR, deck_where(deck, here, line) // ', ' // &
               trim(head) // ': ' // to_str(len_trim(raw)) // ' columns; a fixed-field ' // &
               'line has 80 (write longer values in free (comma) or large (*) fields)')
            return
         end if
         do k = 1, per_line
            if (large) then
               call add_field(deck, adjustl(fixed(9 + 16*(k - 1):24 + 16*(k - 1))), line)
            else
               call add_field(deck, adjustl(fixed(1 + 8*k:8 + 8*k)), line)
            end if
         end do
         deck%wants_continuation = len_trim(fixed(73:80)) > 0
      end if
      deck%marker_line = line
   end subroutine read_line

   !> A new card called `head` (checked: a letter, then letters and digits, then `*` if large).
   subroutine open_card(deck, here, line, head, error)
      type(deck_t), intent(inout) :: deck
      integer, intent(in) :: here, line
      character(len=*), intent(in) :: head
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      integer :: c
      name = to_lower(trim(head))
      if (name(len(name):) == '*') name = name(:len(name) - 1)
      if (len(name) > 8 .or. len(name) == 0 .or. verify(name, &
         'abcdefghijklmnopqrstuvwxyz0123456789') /= 0 .or. verify(name(1:1), &
         'abcdefghijklmnopqrstuvwxyz') /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, deck_where(deck, here, line) // ': ''' // &
            trim(head) // ''' is no card name (a letter, then letters and digits, at most 8)')
         return
      end if
      if (deck%num_cards == size(deck%name)) call grow_cards(deck)
      deck%num_cards = deck%num_cards + 1
      c = deck%num_cards
      deck%name(c) = name
      deck%first(c) = deck%num_fields + 1
      deck%count(c) = 0
      deck%file(c) = here
      deck%line(c) = line
      deck%open = .true.
      deck%wants_continuation = .false.
   end subroutine open_card

   !> End the open card: its trailing blank fields dropped; a continuation marker in field 10
   !> of its last line without a continuation line is an error.
   subroutine close_card(deck, here, error)
      type(deck_t), intent(inout) :: deck
      integer, intent(in) :: here
      type(error_t), allocatable, intent(out) :: error
      integer :: c
      if (.not. deck%open) return
      c = deck%num_cards
      deck%open = .false.
      if (deck%wants_continuation) then
         call fatal_error(error, FFRF_INPUT_ERROR, deck_where(deck, here, deck%marker_line) // &
            ', ' // to_upper(deck%name(c)) // ' (card of line ' // to_str(deck%line(c)) // &
            '): unterminated continuation: field 10 holds a continuation marker but no ' // &
            'continuation line follows; add it or clear field 10')
         return
      end if
      deck%count(c) = deck%num_fields - deck%first(c) + 1
      do while (deck%count(c) > 0)
         if (len_trim(deck%field(deck%first(c) + deck%count(c) - 1)) > 0) exit
         deck%count(c) = deck%count(c) - 1
      end do
      deck%num_fields = deck%first(c) + deck%count(c) - 1
   end subroutine close_card

   subroutine add_field(deck, text, line)
      type(deck_t), intent(inout) :: deck
      character(len=*), intent(in) :: text
      integer, intent(in) :: line
      character(len=FIELD_LEN), allocatable :: grown(:)
      integer, allocatable :: grown_line(:)
      integer :: n
      n = deck%num_fields
      if (n == size(deck%field)) then
         allocate (grown(2*n), grown_line(2*n))
         grown(:n) = deck%field(:n)
         grown_line(:n) = deck%field_line(:n)
         call move_alloc(grown, deck%field)
         call move_alloc(grown_line, deck%field_line)
      end if
      deck%num_fields = n + 1
      deck%field(n + 1) = text
      deck%field_line(n + 1) = line
   end subroutine add_field

   subroutine grow_cards(deck)
      type(deck_t), intent(inout) :: deck
      character(len=8), allocatable :: names(:)
      integer :: n
      n = deck%num_cards
      allocate (names(2*n))
      names(:n) = deck%name(:n)
      call move_alloc(names, deck%name)
      call grow(deck%first)
      call grow(deck%count)
      call grow(deck%file)
      call grow(deck%line)
   contains
      subroutine grow(values)
         integer, allocatable, intent(inout) :: values(:)
         integer, allocatable :: bigger(:)
         allocate (bigger(2*n))
         bigger(:n) = values(:n)
         call move_alloc(bigger, values)
      end subroutine grow
   end subroutine grow_cards

   !> The comma-separated items of a free-field line; n = -1 when one is too long.
   subroutine split_free(raw, items, n)
      character(len=*), intent(in) :: raw
      character(len=FIELD_LEN), allocatable, intent(out) :: items(:)
      integer, intent(out) :: n
      integer :: start, k, comma
      allocate (items(count_commas(raw) + 1))
      n = 0
      start = 1
      do k = 1, size(items)
         comma = index(raw(start:), ',')
         if (comma == 0) then
            comma = len(raw) + 1
         else
            comma = start + comma - 1
         end if
         if (len_trim(adjustl(raw(start:comma - 1))) > FIELD_LEN) then
            n = -1
            return
         end if
         n = n + 1
         items(n) = adjustl(raw(start:comma - 1))
         start = comma + 1
      end do
   end subroutine split_free

   pure integer function count_commas(text)
      character(len=*), intent(in) :: text
      integer :: k
      count_commas = 0
      do k = 1, len(text)
         if (text(k:k) == ',') count_commas = count_commas + 1
      end do
   end function count_commas

   !> Tabs to blanks up to the next multiple of 8 columns (Nastran's tab stops).
   pure function expand_tabs(raw) result(text)
      character(len=*), intent(in) :: raw
      character(len=:), allocatable :: text
      integer :: k
      if (index(raw, achar(9)) == 0) then
         text = raw
         return
      end if
      text = ''
      do k = 1, len(raw)
         if (raw(k:k) == achar(9)) then
            text = text // repeat(' ', 8 - modulo(len(text), 8))
         else
            text = text // raw(k:k)
         end if
      end do
   end function expand_tabs

   !> The text holds a BEGIN BULK line (then what comes before it is not bulk data).
   logical function has_begin_bulk(text)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: lower
      integer(i8) :: k, start
      has_begin_bulk = .false.
      lower = to_lower(text)
      start = 1
      do
         k = index(lower(start:), 'begin', kind=i8)
         if (k == 0) return
         k = start + k - 1
         ! at a line start (after blanks)
         if (k == 1 .or. len_trim(line_before(lower, k)) == 0) then
            if (is_begin_bulk(lower(k:min(len(lower, kind=i8), k + 40)))) then
               has_begin_bulk = .true.
               return
            end if
         end if
         start = k + 5
      end do
   end function has_begin_bulk

   !> The part of the line of text(k:k) before k.
   pure function line_before(text, k) result(part)
      character(len=*), intent(in) :: text
      integer(i8), intent(in) :: k
      character(len=:), allocatable :: part
      integer(i8) :: s
      s = index(text(:k - 1), achar(10), back=.true., kind=i8)
      part = text(s + 1:k - 1)
   end function line_before

   !> "begin bulk" or "begin  bulk ..." (lower case, blanks before it removed).
   pure logical function is_begin_bulk(lower)
      character(len=*), intent(in) :: lower
      is_begin_bulk = .false.
      if (.not. starts_with(lower, 'begin')) return
      is_begin_bulk = starts_with(adjustl(lower(6:)), 'bulk')
   end function is_begin_bulk

   pure logical function starts_with(text, word)
      character(len=*), intent(in) :: text, word
      starts_with = .false.
      if (len(text) >= len(word)) starts_with = text(:len(word)) == word
   end function starts_with

   pure integer function size_of(names)
      character(len=*), intent(in) :: names(:)
      size_of = size(names)
   end function size_of

end module ffrf_mesh_bulk_data
