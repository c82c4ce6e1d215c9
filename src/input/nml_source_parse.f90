!> The strict pre-parse of a case's text (ffrf_input_nml_source, header): groups, keys and
!> value items scanned with their lines, each occurrence recorded.
submodule (ffrf_input_nml_source) ffrf_input_nml_source_parse
   implicit none

contains

   module procedure source_parse
      type(scanner_t) :: s
      character(len=:), allocatable :: name
      character(len=1) :: c
      integer :: g, k, start_line
      self%file_name = file_name
      self%groups = groups
      allocate (self%occurrences(16))
      allocate (self%group_count(size(groups)), source=0)
      ! a UTF-8 byte-order mark (editors on Windows write one) is skipped; UTF-16 is named
      if (len(text) >= 3) then
         if (text(1:3) == UTF8_BOM) s%pos = 4
      end if
      if (len(text) >= 2) then
         if (text(1:2) == char(255) // char(254) .or. text(1:2) == char(254) // char(255)) then
            call fail(error, &
               self%file_name // ':1: a UTF-16 byte-order mark; save the case as ' // &
               'UTF-8 or ASCII text')
            return
         end if
      end if
      do
         if (.not. next_significant(text, s, c)) exit
         if (c /= '&') then
            call fail(error, self%file_name // ':' // to_str(s%line) // ': text outside a ' // &
               'namelist group: "' // quote(line_rest(text, s%pos)) // '"; outside groups ' // &
               'only blank lines and ! comments are allowed')
            return
         end if
         start_line = s%line
         if (self%used >= MAX_GROUPS) then
            call fail(error, self%file_name // ':' // to_str(start_line) // ': more than ' // &
               to_str(MAX_GROUPS) // ' namelist groups; a case holds fewer')
            return
         end if
         s%pos = s%pos + 1
         name = to_lower(identifier(text, s))
         if (len(name) == 0) then
            call fail(error, &
               self%file_name // ':' // to_str(start_line) // ': ''&'' without a ' // &
               'group name; groups are &' // join_words(groups%name, ', &'))
            return
         end if
         g = 0
         do k = 1, size(groups)
            if (trim(groups(k)%name) == name) g = k
         end do
         if (g == 0) then
            call fail(error, self%file_name // ':' // to_str(start_line) // &
               ': unknown namelist group &' // name // '; groups are &' // &
               join_words(groups%name, ', &'))
            return
         end if
         if (s%pos <= len(text)) then
            if (index(' ' // achar(9) // achar(13) // achar(10) // '/!,', &
               text(s%pos:s%pos)) == 0) then
               call fail(error, self%file_name // ':' // to_str(start_line) // ': &' // name // &
                  ': unexpected "' // quote(text(s%pos:s%pos)) // '" after the group name; ' // &
                  'write &' // name // ' key = value, ... /')
               return
            end if
         end if
         k = self%group_count(g)
         if (.not. groups(g)%repeatable .and. k > 0) then
            call fail(error, self%file_name // ':' // to_str(start_line) // ': &' // name // &
               ': a second &' // name // ' group (the first is on line ' // &
               to_str(first_line(self, g)) // '); give it once')
            return
         end if
         call parse_group(self, text, s, g, k + 1, start_line, error)
         if (allocated(error)) return
      end do
   end procedure source_parse

   !> The keys of one group occurrence, up to and including its '/'.
   subroutine parse_group(self, text, s, g, number, start_line, error)
      type(nml_source_t), intent(inout) :: self
      character(len=*), intent(in) :: text
      type(scanner_t), intent(inout) :: s
      integer, intent(in) :: g, number, start_line
      type(error_t), allocatable, intent(out) :: error
      type(occurrence_t) :: occ
      type(entry_t) :: entry
      type(item_t), allocatable :: items(:)
      character(len=:), allocatable :: gname, key, raw, problem, at
      character(len=1) :: c
      integer :: k, key_line, e
      gname = '&' // trim(self%groups(g)%name)
      occ%group = g
      occ%number = number
      occ%line = start_line
      allocate (occ%entries(0))
      do
         if (.not. next_significant(text, s, c)) then
            call fail(error, self%file_name // ':' // to_str(start_line) // ': ' // gname // &
               ': not closed by ''/'' (end of the file reached); end every group with /')
            return
         end if
         select case (c)
         case (',')
            s%pos = s%pos + 1
         case ('/')
            s%pos = s%pos + 1
            call skip_blank(text, s, .false.)
            if (s%pos <= len(text)) then
               if (text(s%pos:s%pos) /= '!' .and. text(s%pos:s%pos) /= achar(10)) then
                  call fail(error, self%file_name // ':' // to_str(s%line) // ': ' // gname // &
                     ': text after the closing ''/'': "' // quote(line_rest(text, s%pos)) // &
                     '"; only a ! comment may follow / on its line')
                  return
               end if
            end if
            call append_occurrence(self, occ)
            return
         case ('&', '$')
            call fail(error, self%file_name // ':' // to_str(start_line) // ': ' // gname // &
               ': not closed by ''/'' before the next group on line ' // to_str(s%line) // &
               '; end every group with /')
            return
         case default
            key_line = s%line
            key = to_lower(identifier(text, s))
            if (len(key) == 0) then
               call fail(error, self%file_name // ':' // to_str(s%line) // ': ' // gname // &
                  ': unexpected "' // quote(line_rest(text, s%pos)) // '"; write key = value')
               return
            end if
            ! the start of every message about this key: FILE:LINE: &group key
            at = self%file_name // ':' // to_str(key_line) // ': ' // gname // ' ' // key
            call skip_blank(text, s, .false.)
            if (s%pos <= len(text)) then
               if (text(s%pos:s%pos) == '(') then
                  call fail(error, at // '(...): array elements are not accepted; give the ' // &
                     'whole array, ' // key // ' = v1, v2, ...')
                  return
               end if
            end if
            if (s%pos > len(text)) then
               c = ' '
            else
               c = text(s%pos:s%pos)
            end if
            if (c /= '=') then
               call fail(error, at // ': expected "=" after the key name; write ' // key // &
                  ' = value')
               return
            end if
            s%pos = s%pos + 1
            call parse_items(text, s, items, raw, problem)
            if (len(problem) > 0) then
               call fail(error, at // ' = ' // quote(raw) // ': ' // problem)
               return
            end if
            k = 0
            do e = 1, size(self%groups(g)%keys)
               if (trim(self%groups(g)%keys(e)%name) == key) k = e
            end do
            if (k == 0) then
               call fail(error, at // ' = ' // quote(raw) // ': unknown key; the keys of ' // &
                  gname // ' are ' // join_words(self%groups(g)%keys%name, ', '))
               return
            end if
            do e = 1, size(occ%entries)
               if (occ%entries(e)%key == k) then
                  call fail(error, at // ' = ' // quote(raw) // ': given twice in this ' // &
                     'group (also ' // &
                     'on line ' // to_str(occ%entries(e)%line) // '); give each key once')
                  return
               end if
            end do
            entry%key = k
            entry%line = key_line
            entry%raw = raw
            call check_value(self%groups(g)%keys(k), items, entry%canonical, problem)
            if (len(problem) > 0) then
               call fail(error, at // ' = ' // quote(raw) // ': ' // problem)
               return
            end if
            occ%entries = [occ%entries, entry]
         end select
      end do
   end subroutine parse_group

   module procedure parse_items
      type(scanner_t) :: mark
      character(len=1) :: c
      character(len=:), allocatable :: token
      logical :: need_item
      integer :: start, k, piece, used
      allocate (items(0))
      raw = ''
      problem = ''
      need_item = .true.
      do
         if (.not. next_significant(text, s, c)) exit
         if (c == '/' .or. c == '&' .or. c == '$') exit
         if (c == ',') then
            if (need_item) then
               problem = 'an empty value (a comma with no value before it); give every value'
               call add_raw(',')
               return
            end if
            need_item = .true.
            s%pos = s%pos + 1
            cycle
         end if
         if (c == '''' .or. c == '"') then
            if (size(items) >= MAX_VALUES) then
               problem = 'more than ' // to_str(MAX_VALUES) // ' values; no key takes so many'
               return
            end if
            start = s%pos
            s%pos = s%pos + 1
            ! the string ends on this line: a buffer of the rest of the line holds it
            piece = index(text(s%pos:), achar(10))
            if (piece == 0) piece = len(text) - s%pos + 2
            if (allocated(token)) deallocate (token)
            allocate (character(len=piece) :: token)
            used = 0
            piece = s%pos
            do
               if (s%pos > len(text)) exit
               if (text(s%pos:s%pos) == achar(10)) exit
               if (is_control(text(s%pos:s%pos))) then
                  call add_raw(text(start:s%pos))
                  problem = control_problem(text(s%pos:s%pos))
                  return
               end if
               if (text(s%pos:s%pos) == c) then
                  if (s%pos < len(text)) then
                     if (text(s%pos + 1:s%pos + 1) == c) then
                        token(used + 1:used + s%pos - piece + 1) = text(piece:s%pos)
                        used = used + s%pos - piece + 1
                        s%pos = s%pos + 2
                        piece = s%pos
                        cycle
                     end if
                  end if
                  exit
               end if
               s%pos = s%pos + 1
            end do
            if (s%pos > len(text)) then
               call add_raw(text(start:))
               problem = 'the string is not closed on its line; end it with ' // c
               return
            end if
            if (text(s%pos:s%pos) /= c) then
               call add_raw(text(start:s%pos - 1))
               problem = 'the string is not closed on its line; end it with ' // c
               return
            end if
            token(used + 1:used + s%pos - piece) = text(piece:s%pos - 1)
            used = used + s%pos - piece
            token = token(:used)
            s%pos = s%pos + 1
            call add_raw(text(start:s%pos - 1))
            call append_item(items, .true., token)
            need_item = .false.
            cycle
         end if
         ! bare token; it is the next key when an '=' follows it
         mark = s
         start = s%pos
         do while (s%pos <= len(text))
            if (index(' ,/!=''"&' // achar(9) // achar(10) // achar(13), &
               text(s%pos:s%pos)) > 0) exit
            s%pos = s%pos + 1
         end do
         token = text(start:s%pos - 1)
         if (len(token) == 0) then
            ! a lone '='
            call add_raw(text(start:start))
            problem = 'an "=" where a value is expected'
            return
         end if
         k = s%pos
         call skip_blank(text, s, .true.)
         if (s%pos <= len(text)) then
            if (text(s%pos:s%pos) == '=' .or. text(s%pos:s%pos) == '(') then
               s = mark
               exit
            end if
         end if
         s%pos = k
         s%line = mark%line
         if (size(items) >= MAX_VALUES) then
            problem = 'more than ' // to_str(MAX_VALUES) // ' values; no key takes so many'
            return
         end if
         call add_raw(token)
         call append_item(items, .false., token)
         need_item = .false.
      end do
      if (size(items) == 0) problem = 'no value given'
   contains
      subroutine add_raw(piece)
         character(len=*), intent(in) :: piece
         if (piece == ',') then
            raw = raw // ','
         else
            if (len(raw) > 0) raw = raw // ', '
            raw = raw // piece
         end if
      end subroutine add_raw
   end procedure parse_items

   integer function first_line(self, g) result(line)
      type(nml_source_t), intent(in) :: self
      integer, intent(in) :: g
      integer :: k
      line = 0
      do k = 1, self%used
         if (self%occurrences(k)%group == g) then
            line = self%occurrences(k)%line
            return
         end if
      end do
   end function first_line

   !> Skip blanks (space, tab, CR); new lines too when `lines`.
   subroutine skip_blank(text, s, lines)
      character(len=*), intent(in) :: text
      type(scanner_t), intent(inout) :: s
      logical, intent(in) :: lines
      do while (s%pos <= len(text))
         select case (iachar(text(s%pos:s%pos)))
         case (32, 9, 13)
            s%pos = s%pos + 1
         case (10)
            if (.not. lines) return
            s%pos = s%pos + 1
            s%line = s%line + 1
         case default
            return
         end select
      end do
   end subroutine skip_blank

   !> An input error of the case text (`message`: FILE:LINE, what is wrong, what is allowed).
   subroutine fail(error, message)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: message
      call fatal_error(error, FFRF_INPUT_ERROR, message)
   end subroutine fail

   !> The next character `c` that is neither blank nor in a '!' comment, the scanner on it;
   !> .false. at the end of the text.
   logical function next_significant(text, s, c) result(found)
      character(len=*), intent(in) :: text
      type(scanner_t), intent(inout) :: s
      character, intent(out) :: c
      c = ' '
      do
         call skip_blank(text, s, .true.)
         found = s%pos <= len(text)
         if (.not. found) return
         c = text(s%pos:s%pos)
         if (c /= '!') return
         call skip_line(text, s)
      end do
   end function next_significant

   !> To the start of the next line.
   subroutine skip_line(text, s)
      character(len=*), intent(in) :: text
      type(scanner_t), intent(inout) :: s
      integer :: nl
      nl = index(text(s%pos:), achar(10))
      if (nl == 0) then
         s%pos = len(text) + 1
      else
         s%pos = s%pos + nl
         s%line = s%line + 1
      end if
   end subroutine skip_line

   !> A name [A-Za-z][A-Za-z0-9_]* at the scanner ('' if none), the scanner after it.
   function identifier(text, s) result(name)
      character(len=*), intent(in) :: text
      type(scanner_t), intent(inout) :: s
      character(len=:), allocatable :: name
      integer :: start
      start = s%pos
      if (s%pos <= len(text)) then
         if (verify(text(s%pos:s%pos), 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ') &
            == 0) then
            do while (s%pos <= len(text))
               if (verify(text(s%pos:s%pos), 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUV' // &
                  'WXYZ0123456789_') /= 0) exit
               s%pos = s%pos + 1
            end do
         end if
      end if
      name = text(start:s%pos - 1)
   end function identifier

   !> The rest of the line from pos, without the new line.
   pure function line_rest(text, pos) result(rest)
      character(len=*), intent(in) :: text
      integer, intent(in) :: pos
      character(len=:), allocatable :: rest
      integer :: nl
      nl = index(text(pos:), achar(10))
      if (nl == 0) then
         rest = text(pos:)
      else
         rest = text(pos:pos + nl - 2)
      end if
   end function line_rest

   !> A control character (codes 0-31, TAB included, and 127): refused in every string value.
   elemental logical function is_control(c)
      character, intent(in) :: c
      is_control = iachar(c) < 32 .or. iachar(c) == 127
   end function is_control

   module procedure append_item
      type(item_t), allocatable :: grown(:)
      integer :: k, n
      n = size(items)
      allocate (grown(n + 1))
      do k = 1, n
         grown(k)%quoted = items(k)%quoted
         call move_alloc(items(k)%text, grown(k)%text)
      end do
      grown(n + 1)%quoted = quoted
      grown(n + 1)%text = text
      call move_alloc(grown, items)
   end procedure append_item

   module procedure append_occurrence
      type(occurrence_t), allocatable :: bigger(:)
      integer :: k
      if (self%used == size(self%occurrences)) then
         allocate (bigger(2 * size(self%occurrences)))
         do k = 1, self%used
            call move_alloc(self%occurrences(k)%entries, bigger(k)%entries)
            bigger(k)%group = self%occurrences(k)%group
            bigger(k)%number = self%occurrences(k)%number
            bigger(k)%line = self%occurrences(k)%line
         end do
         call move_alloc(bigger, self%occurrences)
      end if
      self%used = self%used + 1
      self%occurrences(self%used) = occ
      self%group_count(occ%group) = self%group_count(occ%group) + 1
   end procedure append_occurrence

   module procedure quote
      integer :: k
      shown = text(:min(len(text), MAX_QUOTE))
      do k = 1, len(shown)
         if (iachar(shown(k:k)) < 32 .or. iachar(shown(k:k)) == 127) shown(k:k) = '?'
      end do
      shown = trim(shown)
      if (len(text) > MAX_QUOTE) shown = shown // '...'
   end procedure quote

end submodule ffrf_input_nml_source_parse
