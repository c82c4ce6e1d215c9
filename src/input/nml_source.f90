!> Strict pre-parser of a case file's namelist text, run before the namelist reads of
!> src/input/nml_*.f90 so that nothing slips through them silently and no error comes back in the
!> compiler runtime's words. The case text is held in memory (read once: a regular file of at
!> most MAX_CASE_BYTES, or standard input for the case name '-'). Checked here:
!>   - only blank lines and '!' comments outside groups; every group opened by &name (a known
!>     group) and closed by '/', with nothing but a '!' comment after the '/' on its line;
!>   - single groups at most once; in each group occurrence every key known and given once;
!>   - every value of its key's type: a real (a finite number in the key's documented range),
!>     an integer (in range), a logical (.true./.false., t/f, true/false), a quoted string no
!>     longer than the field that receives it (one of the allowed words for a choice key); an
!>     array key takes between min_count and max_count values (3 for a vector, 6 for an inertia);
!>   - any line length (the text is scanned as a whole, never through a fixed-length buffer);
!>   - at most MAX_GROUPS (2000) groups and MAX_VALUES (64) values after one key, so that the
!>     work stays linear in the text (a case of 16 MiB is checked in well under a second).
!> Messages: `FILE:LINE: &group key = value: what is wrong, what is allowed`, one line.
!> The validated text is then handed to the namelist reads in a canonical form (one key per
!> line, strings re-quoted, numbers as written, so the values read are bitwise those of the
!> file); `where` gives the readers FILE:LINE of a key for their cross-key checks.
!> Overrides from outside the text (command line --set, a sweep table row) are set into the
!> parsed source with `set` (ffrf_input_overrides): the same value checks and messages, their
!> origin ("--set interface[B2].rc") in place of FILE:LINE, also in `where` and `at`.
!> Array elements (`position(2) = ...`), null values (`, ,`) and `&end` are not accepted: give
!> whole arrays. Repeat counts `r*value` are accepted for numbers and logicals. A string may not
!> hold '&' or '$' directly followed by a letter (the namelist reads would take it for a group).
module ffrf_input_nml_source
   use ffrf_core_whole_file, only: read_whole_file, READ_OPEN_FAILED, READ_TOO_LARGE, &
      READ_NO_MEMORY, READ_FAILED, read_file_head
   use, intrinsic :: iso_fortran_env, only: input_unit
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_str, to_lower, join_words
   use ffrf_core_posix, only: check_input_file
   implicit none
   private
   public :: key_spec_t, group_spec_t, nml_source_t, read_case_text
   public :: real_key, integer_key, logical_key, string_key, choice_key
   public :: KEY_REAL, KEY_INTEGER, KEY_LOGICAL, KEY_STRING, MAX_CASE_BYTES, UTF8_BOM

   !> Largest case file read (bytes): ~100 000 lines, far above any hand-written case
   integer(i8), parameter :: MAX_CASE_BYTES = 16_i8 * 1024_i8**2
   !> Key types
   integer, parameter :: KEY_REAL = 1, KEY_INTEGER = 2, KEY_LOGICAL = 3, KEY_STRING = 4
   !> Longest value text quoted in a message
   integer, parameter :: MAX_QUOTE = 60
   !> Most values after one key (no key takes more than 16) and most groups in a case: bounds
   !> that keep the work linear in the size of the text
   integer, parameter :: MAX_VALUES = 64, MAX_GROUPS = 2000
   !> The UTF-8 byte-order mark, skipped at the start of a case (docs/input.md "Input rules")
   character(len=*), parameter :: UTF8_BOM = char(239) // char(187) // char(191)
   !> Characters no value may hold (codes 0-31 and 127)
   character(len=*), parameter :: CONTROL_CHARACTERS = achar(0) // achar(1) // achar(2) // &
      achar(3) // achar(4) // achar(5) // achar(6) // achar(7) // achar(8) // achar(9) // &
      achar(10) // achar(11) // achar(12) // achar(13) // achar(14) // achar(15) // achar(16) // &
      achar(17) // achar(18) // achar(19) // achar(20) // achar(21) // achar(22) // achar(23) // &
      achar(24) // achar(25) // achar(26) // achar(27) // achar(28) // achar(29) // achar(30) // &
      achar(31) // achar(127)

   !> One key of a group: its type, how many values, and what is allowed.
   type :: key_spec_t
      character(len=32) :: name = ''
      integer :: kind = KEY_REAL
      !> Number of values: a scalar takes 1..1, a vector 3..3, a list 1..n
      integer :: min_count = 1, max_count = 1
      !> Strings: length of the field that receives the value
      integer :: length = 0
      !> Reals: allowed interval (open or closed at each end)
      real(dp) :: lower = -huge(1.0_dp), upper = huge(1.0_dp)
      logical :: lower_open = .false., upper_open = .false.
      !> Integers: allowed interval (closed)
      integer(i8) :: int_lower = -huge(1_i8), int_upper = huge(1_i8)
      !> Choice keys: the allowed words, ', '-separated (compared ignoring case); '' for any
      character(len=160) :: choices = ''
      !> Unit for messages ('s', 'Pa', ...)
      character(len=16) :: unit = ''
      !> .false.: not part of the group's namelist statement (read from the source by its
      !> reader, e.g. &integrator max_steps), left out of the canonical text
      logical :: in_namelist = .true.
   end type key_spec_t

   !> A namelist group ffrf knows.
   type :: group_spec_t
      character(len=16) :: name = ''
      !> .true. for &body, &interface, &marker, &joint, &load
      logical :: repeatable = .false.
      type(key_spec_t), allocatable :: keys(:)
   end type group_spec_t

   !> One `key = values` as found.
   type :: entry_t
      !> Index into the group's keys
      integer :: key = 0
      integer :: line = 0
      !> The value text as written (blanks collapsed), for messages
      character(len=:), allocatable :: raw
      !> The value text handed to the namelist read
      character(len=:), allocatable :: canonical
      !> Set by an override (set): where it came from, e.g. "--set interface[B2].rc", used in
      !> messages instead of FILE:LINE; unallocated for a key of the text
      character(len=:), allocatable :: origin
   end type entry_t

   !> One occurrence of a group.
   type :: occurrence_t
      !> Index into the group specs
      integer :: group = 0
      !> 1 for the first occurrence of its group, 2 for the second...
      integer :: number = 0
      !> Line of its &name
      integer :: line = 0
      type(entry_t), allocatable :: entries(:)
   end type occurrence_t

   !> The checked case text.
   type :: nml_source_t
      !> File name for messages ('stdin' for standard input)
      character(len=:), allocatable :: file_name
      type(group_spec_t), allocatable :: groups(:)
      !> The group occurrences in file order: occurrences(:used)
      type(occurrence_t), allocatable :: occurrences(:)
      integer :: used = 0
      !> Occurrences of each group so far (same order as groups)
      integer, allocatable :: group_count(:)
   contains
      procedure :: parse => source_parse
      procedure :: count => source_count
      procedure :: has_key => source_has_key
      procedure :: where => source_where
      procedure :: at => source_at
      procedure :: integer_value => source_integer_value
      procedure :: write_namelist => source_write_namelist
      procedure :: set => source_set
      procedure :: names => source_names
   end type nml_source_t

   !> Scanner state over the whole text.
   type :: scanner_t
      integer :: pos = 1
      integer :: line = 1
   end type scanner_t

   !> A value item: quoted string or bare token.
   type :: item_t
      logical :: quoted = .false.
      character(len=:), allocatable :: text
   end type item_t

contains

   ! ---------------------------------------------------------------------------------------------
   ! Key specs

   !> A real key (count values, default 1), in [lower, upper] (open ends as asked).
   pure function real_key(name, lower, upper, unit, lower_open, upper_open, count) result(key)
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: lower, upper
      character(len=*), intent(in) :: unit
      logical, intent(in), optional :: lower_open, upper_open
      integer, intent(in), optional :: count
      type(key_spec_t) :: key
      key%name = name
      key%kind = KEY_REAL
      key%lower = lower
      key%upper = upper
      key%unit = unit
      if (present(lower_open)) key%lower_open = lower_open
      if (present(upper_open)) key%upper_open = upper_open
      if (present(count)) then
         key%min_count = count
         key%max_count = count
      end if
   end function real_key

   !> An integer key in lower..upper.
   pure function integer_key(name, lower, upper, in_namelist) result(key)
      character(len=*), intent(in) :: name
      integer(i8), intent(in) :: lower, upper
      logical, intent(in), optional :: in_namelist
      type(key_spec_t) :: key
      key%name = name
      key%kind = KEY_INTEGER
      key%int_lower = lower
      key%int_upper = upper
      if (present(in_namelist)) key%in_namelist = in_namelist
   end function integer_key

   pure function logical_key(name) result(key)
      character(len=*), intent(in) :: name
      type(key_spec_t) :: key
      key%name = name
      key%kind = KEY_LOGICAL
   end function logical_key

   !> A string key for a field of `length` characters; max_count > 1: a list of 1..max_count.
   pure function string_key(name, length, max_count) result(key)
      character(len=*), intent(in) :: name
      integer, intent(in) :: length
      integer, intent(in), optional :: max_count
      type(key_spec_t) :: key
      key%name = name
      key%kind = KEY_STRING
      key%length = length
      if (present(max_count)) key%max_count = max_count
   end function string_key

   !> A string key that must be one of `choices` (', '-separated, any case).
   pure function choice_key(name, length, choices) result(key)
      character(len=*), intent(in) :: name
      integer, intent(in) :: length
      character(len=*), intent(in) :: choices
      type(key_spec_t) :: key
      key = string_key(name, length)
      key%choices = choices
   end function choice_key

   ! ---------------------------------------------------------------------------------------------
   ! Reading the text

   !> The whole case text: `file_name` '-' reads standard input (at most MAX_CASE_BYTES), any
   !> other name must be a regular file of at most MAX_CASE_BYTES (a FIFO, device or folder is
   !> refused with FFRF_IO_ERROR rather than read).
   subroutine read_case_text(file_name, text, error)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable, intent(out) :: text
      type(error_t), allocatable, intent(out) :: error
      integer :: step, got, stat, k, line, j
      integer(i8) :: size_bytes
      character(len=512) :: msg
      character(len=256) :: head
      if (file_name == '-') then
         call read_standard_input(text, error)
         return
      end if
      call check_input_file(file_name, 'case file', MAX_CASE_BYTES, error)
      if (allocated(error)) then
         if (index(error%message, 'give a regular file') > 0) error%message = error%message // &
            ' (or - to read the case from standard input)'
         return
      end if
      ! the first bytes before the whole file: a case starts with a group or a ! comment (after
      ! blanks and a UTF-8 byte-order mark; UTF-16 is named by the parse)
      call read_file_head(file_name, 1_i8, head, got, stat, msg)
      if (stat == 0 .and. got >= 2) then
         if (head(1:2) == char(255) // char(254) .or. head(1:2) == char(254) // char(255)) got = 0
      end if
      if (stat == 0) then
         k = 1
         if (got >= 3) then
            if (head(1:3) == UTF8_BOM) k = 4
         end if
         line = 1
         do while (k <= got)
            if (head(k:k) == achar(10)) line = line + 1
            if (index(' ' // achar(9) // achar(10) // achar(13), head(k:k)) == 0) exit
            k = k + 1
         end do
         if (k <= got) then
            if (head(k:k) /= '&' .and. head(k:k) /= '!') then
               ! its first line, bytes outside printable ASCII as '?'
               got = k - 1 + min(got - k + 1, 40)
               if (index(head(k:got), achar(10)) > 0) got = k - 2 + index(head(k:got), achar(10))
               do j = k, got
                  if (iachar(head(j:j)) > 126) head(j:j) = '?'
               end do
               call fatal_error(error, FFRF_INPUT_ERROR, file_name // ':' // to_str(line) // &
                  ': not a namelist case: it starts with "' // quote(head(k:got)) // '"; a ' // &
                  'case holds &group key = value / groups and ! comments')
               return
            end if
         end if
      end if
      call read_whole_file(file_name, text, step, size_bytes, msg, MAX_CASE_BYTES)
      select case (step)
      case (READ_OPEN_FAILED)
         call fatal_error(error, FFRF_IO_ERROR, 'cannot open case file "' // file_name // &
            '": ' // trim(msg))
      case (READ_TOO_LARGE)
         call fatal_error(error, FFRF_IO_ERROR, 'case file "' // file_name // '": size ' // &
            to_str(size_bytes) // ' bytes, unknown or above the ' // to_str(MAX_CASE_BYTES) // &
            ' allowed')
      case (READ_NO_MEMORY)
         call fatal_error(error, FFRF_IO_ERROR, 'case file "' // file_name // '": out of ' // &
            'memory for ' // to_str(size_bytes) // ' bytes')
      case (READ_FAILED)
         call fatal_error(error, FFRF_IO_ERROR, 'cannot read case file "' // file_name // &
            '": ' // trim(msg))
      end select
   end subroutine read_case_text

   !> Standard input to its end, at most MAX_CASE_BYTES, lines joined by new-line characters.
   subroutine read_standard_input(text, error)
      character(len=:), allocatable, intent(out) :: text
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: buffer
      character(len=4096) :: chunk
      character(len=512) :: msg
      integer :: stat, n
      integer(i8) :: used
      allocate (character(len=65536) :: buffer)
      used = 0
      do
         read (input_unit, '(a)', advance='no', iostat=stat, iomsg=msg, size=n) chunk
         if (stat /= 0 .and. .not. is_iostat_eor(stat) .and. .not. is_iostat_end(stat)) then
            call fatal_error(error, FFRF_IO_ERROR, 'cannot read the case from standard ' // &
               'input: ' // trim(msg))
            return
         end if
         if (is_iostat_end(stat)) exit
         if (is_iostat_eor(stat)) then
            call append(chunk(:n) // new_line('a'))
         else
            call append(chunk(:n))
         end if
         if (used > MAX_CASE_BYTES) then
            call fatal_error(error, FFRF_IO_ERROR, 'the case on standard input has more ' // &
               'than the ' // to_str(MAX_CASE_BYTES) // ' bytes allowed for a case')
            return
         end if
      end do
      text = buffer(:used)
   contains
      subroutine append(piece)
         character(len=*), intent(in) :: piece
         character(len=:), allocatable :: bigger
         if (used + len(piece) > len(buffer)) then
            allocate (character(len=2 * len(buffer) + len(piece)) :: bigger)
            bigger(:used) = buffer(:used)
            call move_alloc(bigger, buffer)
         end if
         buffer(used + 1:used + len(piece)) = piece
         used = used + len(piece)
      end subroutine append
   end subroutine read_standard_input

   ! ---------------------------------------------------------------------------------------------
   ! Parsing

   !> Parse and check `text` against `groups`; `file_name` names it in messages.
   subroutine source_parse(self, file_name, text, groups, error)
      class(nml_source_t), intent(out) :: self
      character(len=*), intent(in) :: file_name, text
      type(group_spec_t), intent(in) :: groups(:)
      type(error_t), allocatable, intent(out) :: error
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
            call fail(self%file_name // ':1: a UTF-16 byte-order mark; save the case as ' // &
               'UTF-8 or ASCII text')
            return
         end if
      end if
      do
         call skip_blank(text, s, .true.)
         if (s%pos > len(text)) exit
         c = text(s%pos:s%pos)
         if (c == '!') then
            call skip_line(text, s)
            cycle
         end if
         if (c /= '&') then
            call fail(self%file_name // ':' // to_str(s%line) // ': text outside a ' // &
               'namelist group: "' // quote(line_rest(text, s%pos)) // '"; outside groups ' // &
               'only blank lines and ! comments are allowed')
            return
         end if
         start_line = s%line
         if (self%used >= MAX_GROUPS) then
            call fail(self%file_name // ':' // to_str(start_line) // ': more than ' // &
               to_str(MAX_GROUPS) // ' namelist groups; a case holds fewer')
            return
         end if
         s%pos = s%pos + 1
         name = to_lower(identifier(text, s))
         if (len(name) == 0) then
            call fail(self%file_name // ':' // to_str(start_line) // ': ''&'' without a ' // &
               'group name; groups are &' // join_words(groups%name, ', &'))
            return
         end if
         g = 0
         do k = 1, size(groups)
            if (trim(groups(k)%name) == name) g = k
         end do
         if (g == 0) then
            call fail(self%file_name // ':' // to_str(start_line) // &
               ': unknown namelist group &' // name // '; groups are &' // &
               join_words(groups%name, ', &'))
            return
         end if
         if (s%pos <= len(text)) then
            if (index(' ' // achar(9) // achar(13) // achar(10) // '/!,', &
               text(s%pos:s%pos)) == 0) then
               call fail(self%file_name // ':' // to_str(start_line) // ': &' // name // &
                  ': unexpected "' // quote(text(s%pos:s%pos)) // '" after the group name; ' // &
                  'write &' // name // ' key = value, ... /')
               return
            end if
         end if
         k = self%group_count(g)
         if (.not. groups(g)%repeatable .and. k > 0) then
            call fail(self%file_name // ':' // to_str(start_line) // ': &' // name // &
               ': a second &' // name // ' group (the first is on line ' // &
               to_str(first_line(self, g)) // '); give it once')
            return
         end if
         call parse_group(self, text, s, g, k + 1, start_line, error)
         if (allocated(error)) return
      end do
   contains
      subroutine fail(message)
         character(len=*), intent(in) :: message
         call fatal_error(error, FFRF_INPUT_ERROR, message)
      end subroutine fail
   end subroutine source_parse

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
      character(len=:), allocatable :: gname, key, raw, problem
      character(len=1) :: c
      integer :: k, key_line, e
      gname = '&' // trim(self%groups(g)%name)
      occ%group = g
      occ%number = number
      occ%line = start_line
      allocate (occ%entries(0))
      do
         call skip_blank(text, s, .true.)
         if (s%pos > len(text)) then
            call fail(self%file_name // ':' // to_str(start_line) // ': ' // gname // &
               ': not closed by ''/'' (end of the file reached); end every group with /')
            return
         end if
         c = text(s%pos:s%pos)
         select case (c)
         case ('!')
            call skip_line(text, s)
         case (',')
            s%pos = s%pos + 1
         case ('/')
            s%pos = s%pos + 1
            call skip_blank(text, s, .false.)
            if (s%pos <= len(text)) then
               if (text(s%pos:s%pos) /= '!' .and. text(s%pos:s%pos) /= achar(10)) then
                  call fail(self%file_name // ':' // to_str(s%line) // ': ' // gname // &
                     ': text after the closing ''/'': "' // quote(line_rest(text, s%pos)) // &
                     '"; only a ! comment may follow / on its line')
                  return
               end if
            end if
            call append_occurrence(self, occ)
            return
         case ('&', '$')
            call fail(self%file_name // ':' // to_str(start_line) // ': ' // gname // &
               ': not closed by ''/'' before the next group on line ' // to_str(s%line) // &
               '; end every group with /')
            return
         case default
            key_line = s%line
            key = to_lower(identifier(text, s))
            if (len(key) == 0) then
               call fail(self%file_name // ':' // to_str(s%line) // ': ' // gname // &
                  ': unexpected "' // quote(line_rest(text, s%pos)) // '"; write key = value')
               return
            end if
            call skip_blank(text, s, .false.)
            if (s%pos <= len(text)) then
               if (text(s%pos:s%pos) == '(') then
                  call fail(self%file_name // ':' // to_str(key_line) // ': ' // gname // ' ' &
                     // key // '(...): array elements are not accepted; give the whole ' // &
                     'array, ' // key // ' = v1, v2, ...')
                  return
               end if
            end if
            if (s%pos > len(text)) then
               c = ' '
            else
               c = text(s%pos:s%pos)
            end if
            if (c /= '=') then
               call fail(self%file_name // ':' // to_str(key_line) // ': ' // gname // ' ' // &
                  key // ': expected "=" after the key name; write ' // key // ' = value')
               return
            end if
            s%pos = s%pos + 1
            call parse_items(text, s, items, raw, problem)
            if (len(problem) > 0) then
               call fail(self%file_name // ':' // to_str(key_line) // ': ' // gname // ' ' // &
                  key // ' = ' // quote(raw) // ': ' // problem)
               return
            end if
            k = 0
            do e = 1, size(self%groups(g)%keys)
               if (trim(self%groups(g)%keys(e)%name) == key) k = e
            end do
            if (k == 0) then
               call fail(self%file_name // ':' // to_str(key_line) // ': ' // gname // ' ' // &
                  key // ' = ' // quote(raw) // ': unknown key; the keys of ' // gname // &
                  ' are ' // join_words(self%groups(g)%keys%name, ', '))
               return
            end if
            do e = 1, size(occ%entries)
               if (occ%entries(e)%key == k) then
                  call fail(self%file_name // ':' // to_str(key_line) // ': ' // gname // ' ' &
                     // key // ' = ' // quote(raw) // ': given twice in this group (also ' // &
                     'on line ' // to_str(occ%entries(e)%line) // '); give each key once')
                  return
               end if
            end do
            entry%key = k
            entry%line = key_line
            entry%raw = raw
            call check_value(self%groups(g)%keys(k), items, entry%canonical, problem)
            if (len(problem) > 0) then
               call fail(self%file_name // ':' // to_str(key_line) // ': ' // gname // ' ' // &
                  key // ' = ' // quote(raw) // ': ' // problem)
               return
            end if
            occ%entries = [occ%entries, entry]
         end select
      end do
   contains
      subroutine fail(message)
         character(len=*), intent(in) :: message
         call fatal_error(error, FFRF_INPUT_ERROR, message)
      end subroutine fail
   end subroutine parse_group

   !> The values after `key =`, up to the next `key =`, '/' or '&'. problem /= '' on a
   !> malformed value (unclosed string, empty value).
   subroutine parse_items(text, s, items, raw, problem)
      character(len=*), intent(in) :: text
      type(scanner_t), intent(inout) :: s
      type(item_t), allocatable, intent(out) :: items(:)
      character(len=:), allocatable, intent(out) :: raw, problem
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
         call skip_blank(text, s, .true.)
         if (s%pos > len(text)) exit
         c = text(s%pos:s%pos)
         if (c == '!') then
            call skip_line(text, s)
            cycle
         end if
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
   end subroutine parse_items

   !> Check the items against the key's type, count and range; canonical: the value text for
   !> the namelist read. problem /= '' when the value is not allowed.
   subroutine check_value(key, items, canonical, problem)
      type(key_spec_t), intent(in) :: key
      type(item_t), intent(in) :: items(:)
      character(len=:), allocatable, intent(out) :: canonical, problem
      type(item_t), allocatable :: values(:)
      character(len=:), allocatable :: piece, what
      integer :: k, j, star, repeat, stat
      real(dp) :: x
      integer(i8) :: n
      canonical = ''
      problem = ''
      ! expand r*value
      allocate (values(0))
      do k = 1, size(items)
         star = 0
         if (.not. items(k)%quoted) star = index(items(k)%text, '*')
         if (star > 0) then
            if (.not. is_integer_text(items(k)%text(:star - 1)) .or. &
               star == len(items(k)%text)) then
               problem = 'a repeat count r*value needs a positive integer r and a value'
               return
            end if
            read (items(k)%text(:star - 1), *, iostat=stat) repeat
            if (stat /= 0 .or. repeat < 1 .or. repeat > max(key%max_count, 1)) then
               problem = 'repeat count ' // items(k)%text(:star - 1) // ' in ' // &
                  items(k)%text // ' is not in 1..' // to_str(key%max_count)
               return
            end if
            do j = 1, repeat
               call append_item(values, .false., items(k)%text(star + 1:))
            end do
         else
            call append_item(values, items(k)%quoted, items(k)%text)
         end if
      end do
      if (size(values) < key%min_count .or. size(values) > key%max_count) then
         if (key%min_count == key%max_count) then
            problem = to_str(size(values)) // ' value(s) given, ' // trim(key%name) // &
               ' takes exactly ' // to_str(key%min_count) // ' (' // type_name(key) // ')'
         else
            problem = to_str(size(values)) // ' values given, ' // trim(key%name) // &
               ' takes ' // to_str(key%min_count) // ' to ' // to_str(key%max_count) // &
               ' (' // type_name(key) // ')'
         end if
         return
      end if
      do k = 1, size(values)
         what = ''
         if (size(values) > 1) what = 'value ' // to_str(k) // ' (' // quote(values(k)%text) // &
            '): '
         select case (key%kind)
         case (KEY_REAL)
            if (values(k)%quoted) then
               problem = what // 'a string where a number is expected; give ' // allowed(key)
               return
            end if
            if (is_non_finite_text(values(k)%text)) then
               problem = what // 'not a finite number; give ' // allowed(key)
               return
            end if
            if (.not. is_real_text(values(k)%text)) then
               problem = what // 'not a number; give ' // allowed(key)
               return
            end if
            read (values(k)%text, *, iostat=stat) x
            if (stat /= 0 .or. .not. abs(x) <= huge(x)) then
               problem = what // 'not a finite number (beyond the range of a double); give ' &
                  // allowed(key)
               return
            end if
            if (.not. in_range(key, x)) then
               problem = what // 'out of range; give ' // allowed(key)
               return
            end if
            piece = values(k)%text
         case (KEY_INTEGER)
            if (values(k)%quoted .or. .not. is_integer_text(values(k)%text)) then
               problem = what // 'not an integer; give ' // allowed(key)
               return
            end if
            if (len(digits_of(values(k)%text)) > 18) then
               problem = what // 'out of range; give ' // allowed(key)
               return
            end if
            read (values(k)%text, *, iostat=stat) n
            if (stat /= 0 .or. n < key%int_lower .or. n > key%int_upper) then
               problem = what // 'out of range; give ' // allowed(key)
               return
            end if
            piece = values(k)%text
         case (KEY_LOGICAL)
            piece = ''
            if (.not. values(k)%quoted) then
               select case (to_lower(values(k)%text))
               case ('.true.', '.t.', 't', 'true')
                  piece = '.true.'
               case ('.false.', '.f.', 'f', 'false')
                  piece = '.false.'
               end select
            end if
            if (len(piece) == 0) then
               problem = what // 'not a logical; give .true. or .false.'
               return
            end if
         case default
            if (.not. values(k)%quoted) then
               problem = what // 'not a quoted string; write ' // trim(key%name) // &
                  ' = ''text'''
               if (len_trim(key%choices) > 0) problem = problem // ', one of ' // &
                  trim(key%choices)
               return
            end if
            if (scan(values(k)%text, CONTROL_CHARACTERS) > 0) then
               problem = what // control_problem(values(k)%text(scan(values(k)%text, &
                  CONTROL_CHARACTERS):))
               return
            end if
            if (len(values(k)%text) > key%length) then
               problem = what // 'has ' // to_str(len(values(k)%text)) // ' characters, ' // &
                  'more than the ' // to_str(key%length) // ' ' // trim(key%name) // &
                  ' can hold; shorten it (e.g. a shorter path or a symbolic link)'
               return
            end if
            if (len_trim(key%choices) > 0) then
               if (.not. is_choice(key%choices, values(k)%text)) then
                  problem = what // 'not allowed; ' // trim(key%name) // ' is one of ' // &
                     trim(key%choices)
                  return
               end if
            end if
            if (group_mark(values(k)%text)) then
               problem = what // 'holds & or $ followed by a letter, which the namelist ' // &
                  'reads take for the start of a group; put a blank after the & or $'
               return
            end if
            piece = '''' // doubled_quotes(values(k)%text) // ''''
         end select
         if (k > 1) canonical = canonical // ', '
         canonical = canonical // piece
      end do
   end subroutine check_value

   ! ---------------------------------------------------------------------------------------------
   ! Queries

   !> Occurrences of group `name` (lower case, without '&').
   integer function source_count(self, name) result(n)
      class(nml_source_t), intent(in) :: self
      character(len=*), intent(in) :: name
      integer :: k
      n = 0
      do k = 1, self%used
         if (trim(self%groups(self%occurrences(k)%group)%name) == name) n = n + 1
      end do
   end function source_count

   !> .true. when occurrence `number` of `group` gives `key`.
   logical function source_has_key(self, group, number, key) result(found)
      class(nml_source_t), intent(in) :: self
      character(len=*), intent(in) :: group, key
      integer, intent(in) :: number
      integer :: o, e
      call find(self, group, number, key, o, e)
      found = e > 0
   end function source_has_key

   !> "FILE:LINE: &group key = value" of a key as given; "FILE:LINE: &group #n" (the group's
   !> line) when the key is not given; "FILE: &group" when the group is absent. Callers
   !> append ': what is wrong, what is allowed'.
   function source_where(self, group, number, key) result(text)
      class(nml_source_t), intent(in) :: self
      character(len=*), intent(in) :: group
      !> Occurrence (1 for a single group)
      integer, intent(in) :: number
      character(len=*), intent(in) :: key
      character(len=:), allocatable :: text
      integer :: o, e
      call find(self, group, number, key, o, e)
      if (e > 0) then
         associate (entry => self%occurrences(o)%entries(e))
            if (allocated(entry%origin)) then
               text = entry%origin // ' = ' // quote(entry%raw)
            else
               text = self%file_name // ':' // to_str(entry%line) // ': &' // group // ' ' // &
                  key // ' = ' // quote(entry%raw)
            end if
         end associate
      else if (o > 0 .and. self%occurrences(max(o, 1))%line == 0) then
         ! a group made by an override
         text = self%file_name // ': &' // group
         if (len(key) > 0) text = text // ' (' // key // ' not given)'
      else if (o > 0) then
         text = self%file_name // ':' // to_str(self%occurrences(o)%line) // ': &' // group
         if (self%groups(self%occurrences(o)%group)%repeatable) text = text // ' #' // &
            to_str(number)
         if (len(key) > 0) text = text // ' (' // key // ' not given)'
      else
         text = self%file_name // ': &' // group
         if (len(key) > 0) text = text // ' (' // key // ' not given)'
      end if
   end function source_where

   !> "FILE:LINE" of a key as given, else of its group occurrence, else "FILE".
   function source_at(self, group, number, key) result(text)
      class(nml_source_t), intent(in) :: self
      character(len=*), intent(in) :: group, key
      integer, intent(in) :: number
      character(len=:), allocatable :: text
      integer :: o, e
      call find(self, group, number, key, o, e)
      if (e > 0) then
         if (allocated(self%occurrences(o)%entries(e)%origin)) then
            text = self%occurrences(o)%entries(e)%origin
         else
            text = self%file_name // ':' // to_str(self%occurrences(o)%entries(e)%line)
         end if
      else if (o > 0 .and. self%occurrences(max(o, 1))%line == 0) then
         text = self%file_name
      else if (o > 0) then
         text = self%file_name // ':' // to_str(self%occurrences(o)%line)
      else
         text = self%file_name
      end if
   end function source_at

   !> Value of an integer key read outside the namelist (in_namelist = .false.), or `default`.
   integer(i8) function source_integer_value(self, group, number, key, default) result(value)
      class(nml_source_t), intent(in) :: self
      character(len=*), intent(in) :: group, key
      integer, intent(in) :: number
      integer(i8), intent(in) :: default
      integer :: o, e, stat
      value = default
      call find(self, group, number, key, o, e)
      if (e == 0) return
      read (self%occurrences(o)%entries(e)%canonical, *, iostat=stat) value
      if (stat /= 0) value = default
   end function source_integer_value

   !> The checked groups, one key per line, to an open formatted unit (rewound after).
   subroutine source_write_namelist(self, unit, error)
      class(nml_source_t), intent(in) :: self
      integer, intent(in) :: unit
      type(error_t), allocatable, intent(out) :: error
      integer :: o, e, stat
      character(len=512) :: msg
      stat = 0
      msg = ''
      do o = 1, self%used
         associate (occ => self%occurrences(o), group => self%groups(self%occurrences(o)%group))
            write (unit, '(a)', iostat=stat, iomsg=msg) '&' // trim(group%name)
            do e = 1, size(occ%entries)
               if (stat /= 0) exit
               if (.not. group%keys(occ%entries(e)%key)%in_namelist) cycle
               write (unit, '(a)', iostat=stat, iomsg=msg) &
                  trim(group%keys(occ%entries(e)%key)%name) // ' = ' // occ%entries(e)%canonical
            end do
            if (stat == 0) write (unit, '(a)', iostat=stat, iomsg=msg) '/'
         end associate
         if (stat /= 0) exit
      end do
      if (stat == 0) rewind (unit, iostat=stat, iomsg=msg)
      if (stat /= 0) call fatal_error(error, FFRF_IO_ERROR, self%file_name // &
         ': cannot write the checked case to a scratch file: ' // trim(msg))
   end subroutine source_write_namelist

   ! ---------------------------------------------------------------------------------------------
   ! Overrides

   !> Set `key` of group `group` to `value` after the parse (a command-line override), with the
   !> checks and messages of a key of the text; `origin` (e.g. "--set interface[B2].rc") takes
   !> the place of FILE:LINE in messages. A repeatable group is chosen by its `name` key
   !> (`name` /= ''; exactly one occurrence must carry it), a single group by `name` = '' (made
   !> when the text has none). `value` is namelist value text (`4`, `1, 0, 0`, `'Tx'`); a
   !> string key also takes a bare value, the whole of `value` then being the string.
   subroutine source_set(self, group, name, key, value, origin, error)
      class(nml_source_t), intent(inout) :: self
      character(len=*), intent(in) :: group, name, key, value, origin
      type(error_t), allocatable, intent(out) :: error
      type(scanner_t) :: s
      type(item_t), allocatable :: items(:)
      type(occurrence_t) :: occ
      type(entry_t) :: entry
      character(len=:), allocatable :: raw, problem, gname
      integer :: g, k, o, e, matches
      ! one line of printable characters, as a value of a case file (TAB, NUL, new line refused)
      k = scan(value, CONTROL_CHARACTERS)
      if (k > 0) then
         call fail(origin // ' = ' // quote(value) // ': ' // control_problem(value(k:k)))
         return
      end if
      g = 0
      do k = 1, size(self%groups)
         if (trim(self%groups(k)%name) == to_lower(group)) g = k
      end do
      if (g == 0) then
         call fail(origin // ': unknown namelist group &' // group // '; groups are &' // &
            join_words(self%groups%name, ', &'))
         return
      end if
      gname = '&' // trim(self%groups(g)%name)
      k = 0
      do e = 1, size(self%groups(g)%keys)
         if (trim(self%groups(g)%keys(e)%name) == to_lower(key)) k = e
      end do
      if (k == 0) then
         call fail(origin // ': unknown key ' // key // ' of ' // gname // '; the keys of ' // &
            gname // ' are ' // join_words(self%groups(g)%keys%name, ', '))
         return
      end if
      ! the group occurrence
      o = 0
      if (self%groups(g)%repeatable) then
         if (len(name) == 0) then
            call fail(origin // ': ' // gname // ' is a repeatable group; choose one by its ' // &
               'name, ' // trim(self%groups(g)%name) // '[NAME].' // to_lower(key) // &
               '=VALUE (names: ' // self%names(trim(self%groups(g)%name)) // ')')
            return
         end if
         matches = 0
         do e = 1, self%used
            if (self%occurrences(e)%group /= g) cycle
            if (occurrence_name(self, e) /= name) cycle
            matches = matches + 1
            o = e
         end do
         if (matches /= 1) then
            if (matches == 0) then
               problem = 'no ' // gname // ' named "' // name // '" in ' // self%file_name
            else
               problem = to_str(matches) // ' ' // gname // ' groups are named "' // name // &
                  '" in ' // self%file_name // '; rename one to choose it'
            end if
            call fail(origin // ': ' // problem // ' (names: ' // &
               self%names(trim(self%groups(g)%name)) // ')')
            return
         end if
      else
         if (len(name) > 0) then
            call fail(origin // ': ' // gname // ' is a single group, chosen without a ' // &
               'name: ' // trim(self%groups(g)%name) // '.' // to_lower(key) // '=VALUE')
            return
         end if
         do e = 1, self%used
            if (self%occurrences(e)%group == g) o = e
         end do
         if (o == 0) then
            ! a single group the text leaves out: made here, defaults for its other keys
            occ%group = g
            occ%number = 1
            occ%line = 0
            allocate (occ%entries(0))
            call append_occurrence(self, occ)
            o = self%used
         end if
      end if
      ! the value, as the parse reads it
      if (is_bare_string(self%groups(g)%keys(k), value)) then
         allocate (items(0))
         call append_item(items, .true., value)
         raw = value
      else
         call parse_items(value, s, items, raw, problem)
         if (len(problem) == 0 .and. s%pos <= len(value)) problem = 'unexpected "' // &
            quote(value(s%pos:)) // '" after the value'
         if (len(problem) > 0) then
            call fail(origin // ' = ' // quote(value) // ': ' // problem)
            return
         end if
      end if
      entry%key = k
      entry%line = 0
      entry%raw = raw
      entry%origin = origin
      call check_value(self%groups(g)%keys(k), items, entry%canonical, problem)
      if (len(problem) > 0) then
         call fail(origin // ' = ' // quote(raw) // ': ' // problem)
         return
      end if
      associate (occ_o => self%occurrences(o))
         do e = 1, size(occ_o%entries)
            if (occ_o%entries(e)%key == k) then
               occ_o%entries(e) = entry
               return
            end if
         end do
         occ_o%entries = [occ_o%entries, entry]
      end associate
   contains
      subroutine fail(message)
         character(len=*), intent(in) :: message
         call fatal_error(error, FFRF_INPUT_ERROR, message)
      end subroutine fail
   end subroutine source_set

   !> A string key's value written without quotes (`rc=Tx` on a command line): one string.
   pure logical function is_bare_string(key, value) result(bare)
      type(key_spec_t), intent(in) :: key
      character(len=*), intent(in) :: value
      bare = key%kind == KEY_STRING .and. len(value) > 0
      if (bare) bare = value(1:1) /= '''' .and. value(1:1) /= '"'
   end function is_bare_string

   !> "a, b, c": the names (key `name`) of the occurrences of group `group`, 'none' if none.
   function source_names(self, group) result(text)
      class(nml_source_t), intent(in) :: self
      character(len=*), intent(in) :: group
      character(len=:), allocatable :: text
      integer :: o
      text = ''
      do o = 1, self%used
         if (trim(self%groups(self%occurrences(o)%group)%name) /= group) cycle
         if (len(text) > 0) text = text // ', '
         text = text // occurrence_name(self, o)
      end do
      if (len(text) == 0) text = 'none'
   end function source_names

   !> The string of key `name` of occurrence o (quotes undone), '' if not given.
   function occurrence_name(self, o) result(name)
      type(nml_source_t), intent(in) :: self
      integer, intent(in) :: o
      character(len=:), allocatable :: name
      character(len=:), allocatable :: quoted
      integer :: e, k
      name = ''
      associate (occ => self%occurrences(o))
         do e = 1, size(occ%entries)
            if (trim(self%groups(occ%group)%keys(occ%entries(e)%key)%name) /= 'name') cycle
            quoted = occ%entries(e)%canonical
            ! canonical strings are 'text' with inner quotes doubled
            k = 2
            do while (k < len(quoted))
               name = name // quoted(k:k)
               if (quoted(k:k) == '''') k = k + 1
               k = k + 1
            end do
         end do
      end associate
   end function occurrence_name

   ! ---------------------------------------------------------------------------------------------
   ! Helpers

   !> Add a group occurrence, doubling the storage when full (linear time in the groups).
   subroutine append_occurrence(self, occ)
      type(nml_source_t), intent(inout) :: self
      type(occurrence_t), intent(in) :: occ
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
   end subroutine append_occurrence

   subroutine find(self, group, number, key, o, e)
      type(nml_source_t), intent(in) :: self
      character(len=*), intent(in) :: group, key
      integer, intent(in) :: number
      integer, intent(out) :: o, e
      integer :: k
      e = 0
      do o = 1, self%used
         associate (occ => self%occurrences(o))
            if (trim(self%groups(occ%group)%name) /= group .or. occ%number /= number) cycle
            do k = 1, size(occ%entries)
               if (trim(self%groups(occ%group)%keys(occ%entries(k)%key)%name) == key) then
                  e = k
                  return
               end if
            end do
            return
         end associate
      end do
      o = 0
   end subroutine find

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

   !> Text for a one-line message: control characters as '?', at most MAX_QUOTE characters.
   pure function quote(text) result(shown)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: shown
      integer :: k
      shown = text(:min(len(text), MAX_QUOTE))
      do k = 1, len(shown)
         if (iachar(shown(k:k)) < 32 .or. iachar(shown(k:k)) == 127) shown(k:k) = '?'
      end do
      shown = trim(shown)
      if (len(text) > MAX_QUOTE) shown = shown // '...'
   end function quote

   !> A control character (codes 0-31, TAB included, and 127): refused in every string value.
   elemental logical function is_control(c)
      character, intent(in) :: c
      is_control = iachar(c) < 32 .or. iachar(c) == 127
   end function is_control

   !> The message of a control character `c(1:1)` in a value (case file, --set, sweep cell,
   !> --output: one rule, docs/input.md "Input rules").
   pure function control_problem(c) result(problem)
      character(len=*), intent(in) :: c
      character(len=:), allocatable :: problem
      problem = 'a control character (code ' // to_str(iachar(c(1:1))) // ') in a value; ' // &
         'use printable characters (no TAB, new line or NUL)'
   end function control_problem

   !> `text` has '&' or '$' followed by a letter (a group start to the namelist reads).
   pure logical function group_mark(text) result(found)
      character(len=*), intent(in) :: text
      integer :: k
      found = .false.
      do k = 1, len(text) - 1
         if (text(k:k) /= '&' .and. text(k:k) /= '$') cycle
         if (verify(text(k + 1:k + 1), 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ') &
            == 0) found = .true.
      end do
   end function group_mark

   pure function doubled_quotes(text) result(out)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: out
      integer :: k
      out = ''
      do k = 1, len(text)
         out = out // text(k:k)
         if (text(k:k) == '''') out = out // ''''
      end do
   end function doubled_quotes

   pure function digits_of(text) result(digits)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: digits
      digits = text
      if (len(digits) > 0) then
         if (digits(1:1) == '+' .or. digits(1:1) == '-') digits = digits(2:)
      end if
   end function digits_of

   !> [+-]digits
   pure logical function is_integer_text(text) result(ok)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: digits
      digits = digits_of(text)
      ok = len(digits) > 0 .and. verify(digits, '0123456789') == 0
   end function is_integer_text

   !> inf, infinity, nan, nan(...) with an optional sign, any case.
   pure logical function is_non_finite_text(text) result(yes)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: word
      word = to_lower(digits_of(text))
      yes = word == 'inf' .or. word == 'infinity' .or. word(:min(3, len(word))) == 'nan'
   end function is_non_finite_text

   !> [+-] (digits [. [digits]] | . digits) [(e|d) [+-] digits]
   pure logical function is_real_text(text) result(ok)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: t, mantissa, exponent
      integer :: e, dot
      ok = .false.
      t = to_lower(digits_of(text))
      e = scan(t, 'ed')
      if (e > 0) then
         mantissa = t(:e - 1)
         exponent = t(e + 1:)
         if (.not. is_integer_text(exponent)) return
      else
         mantissa = t
      end if
      dot = index(mantissa, '.')
      if (dot > 0) then
         if (len(mantissa) == 1) return
         if (verify(mantissa(:dot - 1), '0123456789') /= 0) return
         if (verify(mantissa(dot + 1:), '0123456789') /= 0) return
      else
         if (len(mantissa) == 0 .or. verify(mantissa, '0123456789') /= 0) return
      end if
      ok = .true.
   end function is_real_text

   pure logical function in_range(key, x) result(ok)
      type(key_spec_t), intent(in) :: key
      real(dp), intent(in) :: x
      if (key%lower_open) then
         ok = x > key%lower
      else
         ok = x >= key%lower
      end if
      if (key%upper_open) then
         ok = ok .and. x < key%upper
      else
         ok = ok .and. x <= key%upper
      end if
   end function in_range

   !> "a real in (0, 10] s", "an integer in 1..10000", for messages.
   function allowed(key) result(text)
      type(key_spec_t), intent(in) :: key
      character(len=:), allocatable :: text
      select case (key%kind)
      case (KEY_REAL)
         text = 'a finite real'
         if (key%max_count > 1) text = trim(key%name) // ' = ' // to_str(key%min_count) // &
            ' finite reals'
         if (key%lower > -huge(1.0_dp) .or. key%upper < huge(1.0_dp)) then
            text = text // ' in ' // merge('(', '[', key%lower_open) // to_str(key%lower) // &
               ', ' // to_str(key%upper) // merge(')', ']', key%upper_open)
         end if
         if (len_trim(key%unit) > 0) text = text // ' ' // trim(key%unit)
      case (KEY_INTEGER)
         text = 'an integer in ' // to_str(key%int_lower) // '..' // to_str(key%int_upper)
      case default
         text = type_name(key)
      end select
   end function allowed

   function type_name(key) result(text)
      type(key_spec_t), intent(in) :: key
      character(len=:), allocatable :: text
      select case (key%kind)
      case (KEY_REAL)
         text = 'finite reals'
         if (len_trim(key%unit) > 0) text = text // ', ' // trim(key%unit)
      case (KEY_INTEGER)
         text = 'integers'
      case (KEY_LOGICAL)
         text = '.true. or .false.'
      case default
         text = 'quoted strings'
      end select
   end function type_name

   !> `value` (any case, trailing blanks ignored) is one of the ', '-separated choices.
   pure logical function is_choice(choices, value) result(ok)
      character(len=*), intent(in) :: choices, value
      character(len=:), allocatable :: rest, word
      integer :: comma
      ok = .false.
      rest = to_lower(trim(choices))
      do while (len(rest) > 0)
         comma = index(rest, ',')
         if (comma == 0) then
            word = trim(adjustl(rest))
            rest = ''
         else
            word = trim(adjustl(rest(:comma - 1)))
            rest = rest(comma + 1:)
         end if
         if (word == to_lower(trim(value))) ok = .true.
      end do
   end function is_choice

   !> Append an item (grown by hand: gfortran 12 leaks the allocatable component of an
   !> item_t(...) constructor inside an array constructor, seen by valgrind in tests/capi).
   subroutine append_item(items, quoted, text)
      type(item_t), allocatable, intent(inout) :: items(:)
      logical, intent(in) :: quoted
      character(len=*), intent(in) :: text
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
   end subroutine append_item

end module ffrf_input_nml_source
