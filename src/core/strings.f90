!> String helpers: number formatting for messages and logs, case folding.
module ffrf_core_strings
   use ffrf_core_kinds, only: dp, ip, i8
   implicit none
   private
   public :: to_str, to_lower, join_words, join_ints

   !> Compact text of a number, for messages ("12", "2.1E+11", "0.25").
   interface to_str
      module procedure int_to_str, long_to_str, real_to_str, logical_to_str
   end interface to_str

contains

   pure function int_to_str(value) result(text)
      !> Number to format
      integer(ip), intent(in) :: value
      character(len=:), allocatable :: text
      text = long_to_str(int(value, i8))
   end function int_to_str

   pure function long_to_str(value) result(text)
      !> Number to format
      integer(i8), intent(in) :: value
      character(len=:), allocatable :: text
      character(len=24) :: buffer
      write (buffer, '(i0)') value
      text = trim(buffer)
   end function long_to_str

   !> Real with `digits` significant digits (default 6), without padding.
   pure function real_to_str(value, digits) result(text)
      !> Number to format
      real(dp), intent(in) :: value
      !> Significant digits, 1 to 17
      integer, intent(in), optional :: digits
      character(len=:), allocatable :: text
      character(len=40) :: buffer
      character(len=20) :: fmt
      integer :: d, decimals, e
      character(len=:), allocatable :: mantissa, exponent
      d = 6
      if (present(digits)) d = max(1, min(17, digits))
      if (value /= value) then
         text = 'NaN'
         return
      end if
      if (abs(value) >= 1.0e-3_dp .and. abs(value) < 1.0e6_dp .or. value == 0.0_dp) then
         ! Fixed notation with d significant digits, trailing zeros trimmed ("0.0373", "412.7").
         decimals = 0
         if (value /= 0.0_dp) decimals = max(0, d - 1 - floor(log10(abs(value))))
         write (fmt, '(a,i0,a)') '(f0.', decimals, ')'
         write (buffer, fmt) value
         text = trim(adjustl(buffer))
         if (index(text, '.') > 0) then
            do while (text(len(text):len(text)) == '0')
               text = text(1:len(text) - 1)
            end do
            if (text(len(text):len(text)) == '.') text = text(1:len(text) - 1)
         end if
         if (text(1:1) == '.') text = '0' // text
         if (text(1:min(2, len(text))) == '-.') text = '-0' // text(2:)
      else
         write (fmt, '(a,i0,a,i0,a)') '(es', d + 9, '.', d - 1, 'e3)'
         write (buffer, fmt) value
         text = trim(adjustl(buffer))
         ! Trim the mantissa's trailing zeros ("2.10000E+11" -> "2.1E+11").
         e = index(text, 'E')
         if (e > 0) then
            mantissa = text(:e - 1)
            do while (mantissa(len(mantissa):len(mantissa)) == '0')
               mantissa = mantissa(:len(mantissa) - 1)
            end do
            if (mantissa(len(mantissa):len(mantissa)) == '.') then
               mantissa = mantissa(:len(mantissa) - 1)
            end if
            ! Exponent with at least two digits ("E+011" -> "E+11", "E-300" stays).
            exponent = text(e + 2:)
            do while (len(exponent) > 2 .and. exponent(1:1) == '0')
               exponent = exponent(2:)
            end do
            text = mantissa // text(e:e + 1) // exponent
         end if
      end if
   end function real_to_str

   pure function logical_to_str(value) result(text)
      !> Flag to format
      logical, intent(in) :: value
      character(len=:), allocatable :: text
      if (value) then
         text = 'true'
      else
         text = 'false'
      end if
   end function logical_to_str

   !> Lower-case copy of `text` (ASCII).
   pure function to_lower(text) result(lower)
      !> Text to fold
      character(len=*), intent(in) :: text
      character(len=len(text)) :: lower
      integer :: i, code
      lower = text
      do i = 1, len(text)
         code = iachar(text(i:i))
         if (code >= iachar('A') .and. code <= iachar('Z')) lower(i:i) = achar(code + 32)
      end do
   end function to_lower

   !> Words joined by `separator`, trimmed ("Tx, Ty, Rz").
   pure function join_words(words, separator) result(text)
      !> Words to join
      character(len=*), intent(in) :: words(:)
      !> Separator between words
      character(len=*), intent(in) :: separator
      character(len=:), allocatable :: text
      integer :: i
      text = ''
      do i = 1, size(words)
         if (i > 1) text = text // separator
         text = text // trim(words(i))
      end do
   end function join_words

   !> Integers joined by `separator` ("3, 7, 9"), for messages.
   pure function join_ints(values, separator) result(text)
      integer(i8), intent(in) :: values(:)
      character(len=*), intent(in) :: separator
      character(len=:), allocatable :: text
      !> Each integer's text (an i8 has at most 20 characters)
      character(len=20) :: words(size(values))
      integer :: i
      do i = 1, size(values)
         words(i) = to_str(values(i))
      end do
      text = join_words(words, separator)
   end function join_ints

end module ffrf_core_strings
