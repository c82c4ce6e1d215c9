!> Reading a case's text (ffrf_input_nml_source): a regular file of at most MAX_CASE_BYTES, or
!> standard input for the case name '-', held in memory whole.
submodule (ffrf_input_nml_source) ffrf_input_nml_source_read
   implicit none

contains

   module procedure read_case_text
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
   end procedure read_case_text

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

end submodule ffrf_input_nml_source_read
