!> ffrf_mesh_bulk_data: the fields of a card read (integers, Nastran reals, component lists,
!> id lists with THRU), the grid-id look-up, and the located messages "deck 'a.bdf': line 12,
!> GRID 7, field 3 (X1)" every error of a deck carries. Parent of bulk_data_cards.
submodule(ffrf_mesh_bulk_data) ffrf_mesh_bulk_data_fields
   use ffrf_la_sparse, only: csr_t, csr_find, sort_indices
   implicit none

   !> The grids of the deck: ids in card order, and sorted for the look-up
   type :: grid_map_t
      integer(i8), allocatable :: id(:)
      type(csr_t) :: sorted
      integer(ip), allocatable :: index_of_sorted(:)
   end type grid_map_t

contains

   module procedure deck_where
      text = 'deck ''' // trim(deck%files(k)) // ''': line ' // to_str(line)
   end procedure deck_where

   module procedure to_upper
      integer :: k
      upper = text
      do k = 1, len(upper)
         if (upper(k:k) >= 'a' .and. upper(k:k) <= 'z') upper(k:k) = achar(iachar(upper(k:k)) - 32)
      end do
   end procedure to_upper

   !> Integer ids from field k on (blanks skipped, `A THRU B` expanded) until a real field.
   subroutine id_list_of(deck, c, k0, ids, error)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c, k0
      integer(i8), allocatable, intent(out) :: ids(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: text
      integer(i8) :: g, last, j
      real(dp) :: x
      integer :: k
      logical :: ok
      allocate (ids(0))
      k = k0
      do while (k <= deck%count(c))
         text = to_lower(trim(field(deck, c, k)))
         if (len(text) > 0) then
            call parse_int(text, g, ok)
            if (text == 'thru' .and. size(ids) > 0) then
               call get_int(deck, c, k + 1, 'THRU', last, error)
               if (allocated(error)) return
               if (last < ids(size(ids)) .or. last - ids(size(ids)) > 10000000_i8) then
                  call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k + 1, &
                     'THRU') // ': ' // to_str(ids(size(ids))) // ' THRU ' // to_str(last) // &
                     ' is no range')
                  return
               end if
               ids = [ids, [(j, j=ids(size(ids)) + 1, last)]]
               k = k + 1
            else if (ok) then
               ids = [ids, g]
            else
               call parse_real(text, x, ok)
               if (ok) exit
               call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, 'grid') // &
                  ': ''' // text // ''' is no grid id')
               return
            end if
         end if
         k = k + 1
      end do
   end subroutine id_list_of

   !> Component digits in field k: 1..6 each once; RBE3's REFC all six (`all_six`), the
   !> others at least 1, 2 and 3 (a solid's grid has translations only) unless any_dofs.
   subroutine check_components(deck, c, k, label, all_six, error, any_dofs)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c, k
      character(len=*), intent(in) :: label
      logical, intent(in) :: all_six
      type(error_t), allocatable, intent(out) :: error
      logical, intent(in), optional :: any_dofs
      character(len=:), allocatable :: text
      logical :: has(6)
      integer :: j, d
      text = trim(field(deck, c, k))
      has = .false.
      do j = 1, len(text)
         d = index('123456', text(j:j))
         if (d == 0) exit
         if (has(d)) exit
         has(d) = .true.
      end do
      if (len(text) == 0 .or. j <= len(text)) then
         call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, label) // ': ''' // &
            text // ''' is no component list (digits 1 to 6, each once)')
      else if (present(any_dofs)) then
         return
      else if (all_six .and. .not. all(has)) then
         call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, label) // ': ''' // &
            text // '''; ffrf''s RBE3 sets all six dofs of the reference grid: write 123456')
      else if (.not. all(has(1:3))) then
         call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, label) // ': ''' // &
            text // '''; ffrf ties all three translations of the grids (123, or 123456)')
      end if
   end subroutine check_components

   subroutine missing_grid(deck, c, k, g, error)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c, k
      integer(i8), intent(in) :: g
      type(error_t), allocatable, intent(out) :: error
      call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, 'grid') // ': grid ' // &
         to_str(g) // ' is no GRID of the deck; add its GRID card')
   end subroutine missing_grid

   !> Count one more card `name` not read.
   subroutine tally(names, counts, name)
      character(len=8), allocatable, intent(inout) :: names(:)
      integer, allocatable, intent(inout) :: counts(:)
      character(len=*), intent(in) :: name
      integer :: k
      k = findloc(names, name, dim=1)
      if (k == 0) then
         names = [character(len=8) :: names, name]
         counts = [counts, 1]
      else
         counts(k) = counts(k) + 1
      end if
   end subroutine tally

   !> Field k of card c ('' past its end).
   function field(deck, c, k) result(text)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c, k
      character(len=FIELD_LEN) :: text
      text = ''
      if (k <= deck%count(c)) text = deck%field(deck%first(c) + k - 1)
   end function field

   !> "deck 'a.bdf': line 12, GRID 7".
   function card_where(deck, c) result(text)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c
      character(len=:), allocatable :: text
      text = deck_where(deck, deck%file(c), deck%line(c)) // ', ' // to_upper(deck%name(c))
      if (deck%count(c) > 0) text = text // ' ' // trim(field(deck, c, 1))
   end function card_where

   !> "deck 'a.bdf': line 13, GRID 7, field 3 (X1)" (the line of the field).
   function field_where(deck, c, k, label) result(text)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c, k
      character(len=*), intent(in) :: label
      character(len=:), allocatable :: text
      integer :: line
      line = deck%line(c)
      if (k <= deck%count(c)) line = deck%field_line(deck%first(c) + k - 1)
      text = deck_where(deck, deck%file(c), line) // ', ' // to_upper(deck%name(c))
      if (deck%count(c) > 0) text = text // ' ' // trim(field(deck, c, 1))
      text = text // ', field ' // to_str(k) // ' (' // label // ')'
   end function field_where

   !> Integer field k; blank gives `default` when present, else an error.
   subroutine get_int(deck, c, k, label, value, error, default)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c, k
      character(len=*), intent(in) :: label
      integer(i8), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(i8), intent(in), optional :: default
      character(len=:), allocatable :: text
      logical :: ok
      text = trim(field(deck, c, k))
      value = 0
      if (len(text) == 0 .and. present(default)) then
         value = default
         return
      end if
      call parse_int(text, value, ok)
      if (.not. ok .or. len(text) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, label) // ': ''' // &
            text // ''' is no integer')
      end if
   end subroutine get_int

   !> Real field k (Nastran forms: 1., 2.1+11, -1.-3, 1.5E3, 1.5D3); blank gives `default`.
   subroutine get_real(deck, c, k, label, value, error, default)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c, k
      character(len=*), intent(in) :: label
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: default
      character(len=:), allocatable :: text
      logical :: ok
      text = trim(field(deck, c, k))
      value = 0.0_dp
      if (len(text) == 0 .and. present(default)) then
         value = default
         return
      end if
      call parse_real(text, value, ok)
      if (.not. ok) then
         call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, label) // ': ''' // &
            text // ''' is no real (a real has a decimal point: 1., 2.1+11, 7.85-9, 1.0E3)')
      end if
   end subroutine get_real

   !> An integer: optional sign, digits.
   pure subroutine parse_int(text, value, ok)
      character(len=*), intent(in) :: text
      integer(i8), intent(out) :: value
      logical, intent(out) :: ok
      integer :: s, stat
      value = 0
      s = 1
      if (len(text) > 0) then
         if (text(1:1) == '+' .or. text(1:1) == '-') s = 2
      end if
      ok = len(text) >= s .and. len(text) <= 18
      if (ok) ok = verify(text(s:), '0123456789') == 0
      if (ok) read (text, *, iostat=stat) value
      if (ok) ok = stat == 0
   end subroutine parse_int

   !> A Nastran real: [sign] mantissa with a point, then an exponent E/D[sign]digits or a
   !> bare sign and digits (2.1+11).
   pure subroutine parse_real(text, value, ok)
      character(len=*), intent(in) :: text
      real(dp), intent(out) :: value
      logical, intent(out) :: ok
      character(len=len(text) + 1) :: t
      integer :: s, e, stat
      value = 0.0_dp
      t = to_lower(text)
      s = 1
      ok = .false.
      if (len(text) == 0) return
      if (t(1:1) == '+' .or. t(1:1) == '-') s = 2
      e = scan(t(s:len(text)), 'ed+-')
      if (e > 0) then
         e = s + e - 1
         if (t(e:e) == 'd') t(e:e) = 'e'
         if (t(e:e) /= 'e') t = t(:e - 1) // 'e' // t(e:len(text))
         ! exponent: [sign] digits
         if (verify(t(e + 1:e + 1), '+-') == 0) then
            if (verify(trim(t(e + 2:)), '0123456789') /= 0 .or. len_trim(t(e + 2:)) == 0) return
         else
            if (verify(trim(t(e + 1:)), '0123456789') /= 0 .or. len_trim(t(e + 1:)) == 0) return
         end if
      else
         e = len(text) + 1
      end if
      ! mantissa: digits with one point, at least one digit
      if (index(t(s:e - 1), '.') == 0 .or. verify(t(s:e - 1), '0123456789.') /= 0) return
      if (count_char(t(s:e - 1), '.') /= 1 .or. e - 1 - s < 1) return
      read (t, *, iostat=stat) value
      ok = stat == 0 .and. abs(value) <= huge(1.0_dp)
   end subroutine parse_real

   pure integer function count_char(text, ch)
      character(len=*), intent(in) :: text
      character, intent(in) :: ch
      integer :: k
      count_char = 0
      do k = 1, len(text)
         if (text(k:k) == ch) count_char = count_char + 1
      end do
   end function count_char

   !> "1, 2, 7" for messages (the first 20).
   function id_list(ids) result(text)
      integer(i8), intent(in) :: ids(:)
      character(len=:), allocatable :: text
      integer :: k
      text = ''
      do k = 1, min(size(ids), 20)
         if (k > 1) text = text // ', '
         text = text // to_str(ids(k))
      end do
      if (size(ids) > 20) text = text // ', ...'
      if (size(ids) == 0) text = '(none)'
   end function id_list

   !> Grid index (card order) of grid id g, 0 if none.
   pure integer function grid_index(grids, g)
      type(grid_map_t), intent(in) :: grids
      integer(i8), intent(in) :: g
      integer(ip) :: k
      grid_index = 0
      if (g < 1 .or. g > huge(1_ip)) return
      k = csr_find(grids%sorted, 1_ip, int(g, ip))
      if (k > 0) grid_index = grids%index_of_sorted(k)
   end function grid_index

   !> grids%sorted (the ids ascending, as the one row of a CSR pattern, searched by csr_find)
   !> and grids%index_of_sorted (the card-order index of each) from grids%id; `duplicate` is an
   !> id given twice (0 if none).
   subroutine sort_grids(grids, duplicate)
      type(grid_map_t), intent(inout) :: grids
      integer(i8), intent(out) :: duplicate
      integer(ip) :: k, n
      n = size(grids%id, kind=ip)
      grids%sorted%num_rows = 1
      grids%sorted%num_cols = huge(1_ip)
      grids%sorted%row_ptr = [1_ip, n + 1_ip]
      grids%sorted%col = int(grids%id, ip)
      call sort_indices(grids%sorted%col)
      duplicate = 0
      do k = 2, n
         if (grids%sorted%col(k) == grids%sorted%col(k - 1)) then
            duplicate = grids%sorted%col(k)
            return
         end if
      end do
      allocate (grids%index_of_sorted(n))
      do k = 1, n
         grids%index_of_sorted(csr_find(grids%sorted, 1_ip, int(grids%id(k), ip))) = k
      end do
   end subroutine sort_grids

end submodule ffrf_mesh_bulk_data_fields
