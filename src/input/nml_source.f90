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
      character(len=256) :: choices = ''
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

   interface
      !> The whole case text: `file_name` '-' reads standard input (at most MAX_CASE_BYTES), any
      !> other name must be a regular file of at most MAX_CASE_BYTES (a FIFO, device or folder is
      !> refused with FFRF_IO_ERROR rather than read).
      module subroutine read_case_text(file_name, text, error)
         character(len=*), intent(in) :: file_name
         character(len=:), allocatable, intent(out) :: text
         type(error_t), allocatable, intent(out) :: error
      end subroutine read_case_text

      !> Parse and check `text` against `groups`; `file_name` names it in messages.
      module subroutine source_parse(self, file_name, text, groups, error)
         class(nml_source_t), intent(out) :: self
         character(len=*), intent(in) :: file_name, text
         type(group_spec_t), intent(in) :: groups(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine source_parse

      !> The values after `key =`, up to the next `key =`, '/' or '&'. problem /= '' on a
      !> malformed value (unclosed string, empty value).
      module subroutine parse_items(text, s, items, raw, problem)
         character(len=*), intent(in) :: text
         type(scanner_t), intent(inout) :: s
         type(item_t), allocatable, intent(out) :: items(:)
         character(len=:), allocatable, intent(out) :: raw, problem
      end subroutine parse_items

      !> Check the items against the key's type, count and range; canonical: the value text for
      !> the namelist read. problem /= '' when the value is not allowed.
      module subroutine check_value(key, items, canonical, problem)
         type(key_spec_t), intent(in) :: key
         type(item_t), intent(in) :: items(:)
         character(len=:), allocatable, intent(out) :: canonical, problem
      end subroutine check_value

      !> Occurrences of group `name` (lower case, without '&').
      integer module function source_count(self, name) result(n)
         class(nml_source_t), intent(in) :: self
         character(len=*), intent(in) :: name
      end function source_count

      !> .true. when occurrence `number` of `group` gives `key`.
      logical module function source_has_key(self, group, number, key) result(found)
         class(nml_source_t), intent(in) :: self
         character(len=*), intent(in) :: group, key
         integer, intent(in) :: number
      end function source_has_key

      !> "FILE:LINE: &group key = value" of a key as given; "FILE:LINE: &group #n" (the group's
      !> line) when the key is not given; "FILE: &group" when the group is absent. Callers
      !> append ': what is wrong, what is allowed'.
      module function source_where(self, group, number, key) result(text)
         class(nml_source_t), intent(in) :: self
         character(len=*), intent(in) :: group
         !> Occurrence (1 for a single group)
         integer, intent(in) :: number
         character(len=*), intent(in) :: key
         character(len=:), allocatable :: text
      end function source_where

      !> "FILE:LINE" of a key as given, else of its group occurrence, else "FILE".
      module function source_at(self, group, number, key) result(text)
         class(nml_source_t), intent(in) :: self
         character(len=*), intent(in) :: group, key
         integer, intent(in) :: number
         character(len=:), allocatable :: text
      end function source_at

      !> Value of an integer key read outside the namelist (in_namelist = .false.), or `default`.
      integer(i8) module function source_integer_value(self, group, number, key, default) &
         result(value)
         class(nml_source_t), intent(in) :: self
         character(len=*), intent(in) :: group, key
         integer, intent(in) :: number
         integer(i8), intent(in) :: default
      end function source_integer_value

      !> The checked groups, one key per line, to an open formatted unit (rewound after).
      module subroutine source_write_namelist(self, unit, error)
         class(nml_source_t), intent(in) :: self
         integer, intent(in) :: unit
         type(error_t), allocatable, intent(out) :: error
      end subroutine source_write_namelist

      !> Set `key` of group `group` to `value` after the parse (a command-line override), with the
      !> checks and messages of a key of the text; `origin` (e.g. "--set interface[B2].rc") takes
      !> the place of FILE:LINE in messages. A repeatable group is chosen by its `name` key
      !> (`name` /= ''; exactly one occurrence must carry it), a single group by `name` = '' (made
      !> when the text has none). `value` is namelist value text (`4`, `1, 0, 0`, `'Tx'`); a
      !> string key also takes a bare value, the whole of `value` then being the string.
      module subroutine source_set(self, group, name, key, value, origin, error)
         class(nml_source_t), intent(inout) :: self
         character(len=*), intent(in) :: group, name, key, value, origin
         type(error_t), allocatable, intent(out) :: error
      end subroutine source_set

      !> "a, b, c": the names (key `name`) of the occurrences of group `group`, 'none' if none.
      module function source_names(self, group) result(text)
         class(nml_source_t), intent(in) :: self
         character(len=*), intent(in) :: group
         character(len=:), allocatable :: text
      end function source_names

      !> Add a group occurrence, doubling the storage when full (linear time in the groups).
      module subroutine append_occurrence(self, occ)
         type(nml_source_t), intent(inout) :: self
         type(occurrence_t), intent(in) :: occ
      end subroutine append_occurrence

      !> Text for a one-line message: control characters as '?', at most MAX_QUOTE characters.
      pure module function quote(text) result(shown)
         character(len=*), intent(in) :: text
         character(len=:), allocatable :: shown
      end function quote

      !> The message of a control character `c(1:1)` in a value (case file, --set, sweep cell,
      !> --output: one rule, docs/input.md "Input rules").
      pure module function control_problem(c) result(problem)
         character(len=*), intent(in) :: c
         character(len=:), allocatable :: problem
      end function control_problem

      !> "a real in (0, 10] s", "an integer in 1..10000", for messages.
      module function allowed(key) result(text)
         type(key_spec_t), intent(in) :: key
         character(len=:), allocatable :: text
      end function allowed

      !> Append an item (grown by hand: gfortran 12 leaks the allocatable component of an
      !> item_t(...) constructor inside an array constructor, seen by valgrind in tests/capi).
      module subroutine append_item(items, quoted, text)
         type(item_t), allocatable, intent(inout) :: items(:)
         logical, intent(in) :: quoted
         character(len=*), intent(in) :: text
      end subroutine append_item
   end interface

contains

   !> A real key (count values, default 1), in [lower, upper] (open ends as asked).
   pure function real_key(name, lower, upper, unit, lower_open, upper_open, count) result(key)
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: lower, upper
      character(len=*), intent(in) :: unit
      logical, intent(in), optional :: lower_open, upper_open
      integer, intent(in), optional :: count
      type(key_spec_t) :: key
      key = key_spec_t(name, KEY_REAL, lower=lower, upper=upper, unit=unit)
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
      key = key_spec_t(name, KEY_INTEGER, int_lower=lower, int_upper=upper)
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

end module ffrf_input_nml_source
