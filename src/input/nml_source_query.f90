!> The parsed source's queries and overrides (ffrf_input_nml_source): counts, keys given,
!> FILE:LINE of a key, values, the canonical namelist text, and `set` (--set, sweeps).
submodule (ffrf_input_nml_source) ffrf_input_nml_source_query
   implicit none

contains

   module procedure source_count
      integer :: k
      n = 0
      do k = 1, self%used
         if (trim(self%groups(self%occurrences(k)%group)%name) == name) n = n + 1
      end do
   end procedure source_count

   module procedure source_has_key
      integer :: o, e
      call find(self, group, number, key, o, e)
      found = e > 0
   end procedure source_has_key

   module procedure source_where
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
   end procedure source_where

   module procedure source_at
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
   end procedure source_at

   module procedure source_integer_value
      integer :: o, e, stat
      value = default
      call find(self, group, number, key, o, e)
      if (e == 0) return
      read (self%occurrences(o)%entries(e)%canonical, *, iostat=stat) value
      if (stat /= 0) value = default
   end procedure source_integer_value

   module procedure source_write_namelist
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
   end procedure source_write_namelist

   module procedure source_set
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
   end procedure source_set

   !> A string key's value written without quotes (`rc=Tx` on a command line): one string.
   pure logical function is_bare_string(key, value) result(bare)
      type(key_spec_t), intent(in) :: key
      character(len=*), intent(in) :: value
      bare = key%kind == KEY_STRING .and. len(value) > 0
      if (bare) bare = value(1:1) /= '''' .and. value(1:1) /= '"'
   end function is_bare_string

   module procedure source_names
      integer :: o
      text = ''
      do o = 1, self%used
         if (trim(self%groups(self%occurrences(o)%group)%name) /= group) cycle
         if (len(text) > 0) text = text // ', '
         text = text // occurrence_name(self, o)
      end do
      if (len(text) == 0) text = 'none'
   end procedure source_names

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

end submodule ffrf_input_nml_source_query
