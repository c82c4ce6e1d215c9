!> The value checks of the strict pre-parse (ffrf_input_nml_source, header): each value of
!> its key's type, range, length and choices, and its canonical form for the namelist reads.
submodule (ffrf_input_nml_source) ffrf_input_nml_source_values
   implicit none

contains

   module procedure check_value
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
   end procedure check_value

   module procedure control_problem
      problem = 'a control character (code ' // to_str(iachar(c(1:1))) // ') in a value; ' // &
         'use printable characters (no TAB, new line or NUL)'
   end procedure control_problem

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

   module procedure allowed
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
   end procedure allowed

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

end submodule ffrf_input_nml_source_values
