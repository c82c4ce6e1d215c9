!> A text file written in large chunks: lines are formatted into a memory buffer (numbers by
!> number_text.c, byte for byte as gfortran's `I0` and `ESw.dE3` edit descriptors write them)
!> and the buffer goes to a stream-access file one chunk at a time. Formatted WRITE statements
!> cost about 2 us per number; this path about a tenth of that, which is what a Gmsh animation
!> of ~10^6 numbers needs.
!>
!> Failures are sticky: the first failing write keeps its iostat and message in `stat` and `msg`
!> and later calls do nothing, so a writer checks once at the end (before closing the unit).
module ffrf_io_text_stream
   use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_char
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t
   use ffrf_core_posix, only: remove_file
   implicit none
   private
   public :: text_stream_t, es_e3_text

   !> Bytes gathered before they are written
   integer, parameter :: chunk_bytes = 2**20

   !> A text file open for writing, with its buffer.
   type :: text_stream_t
      !> The Fortran unit (stream access, unformatted: the buffer's bytes go to the file as they
      !> are)
      integer :: unit = -1
      !> iostat of the first failure (0: none)
      integer :: stat = 0
      !> Its message
      character(len=512) :: msg = ''
      !> Formatted text not yet written, buffer(1:used)
      character(len=:), allocatable :: buffer
      integer :: used = 0
   contains
      procedure :: open => text_stream_open
      procedure :: put_line => text_stream_put_line
      procedure :: put_integers => text_stream_put_integers
      procedure :: put_es => text_stream_put_es
      procedure :: put_tagged_es_lines => text_stream_put_tagged_es_lines
      procedure :: flush => text_stream_flush
   end type text_stream_t

   interface
      subroutine c_format_es_e3(value, digits, out) bind(c, name='ffrf_format_es_e3')
         import :: c_double, c_int, c_char
         real(c_double), value :: value
         integer(c_int), value :: digits
         character(kind=c_char), intent(inout) :: out(*)
      end subroutine c_format_es_e3
      integer(c_int64_t) function c_format_i0_line(count, values, out) &
         bind(c, name='ffrf_format_i0_line')
         import :: c_int, c_int64_t, c_char
         integer(c_int), value :: count
         integer(c_int), intent(in) :: values(*)
         character(kind=c_char), intent(inout) :: out(*)
      end function c_format_i0_line
      integer(c_int64_t) function c_format_tagged_es_lines(first_tag, num_lines, values, &
         digits, out) bind(c, name='ffrf_format_tagged_es_lines')
         import :: c_int, c_int64_t, c_double, c_char
         integer(c_int), value :: first_tag, num_lines, digits
         real(c_double), intent(in) :: values(*)
         character(kind=c_char), intent(inout) :: out(*)
      end function c_format_tagged_es_lines
   end interface

contains

   !> `value` as the edit descriptor ES(digits+7).(digits-1)E3 writes it (digits + 7
   !> characters): es_e3_text(x, 17) is the text of '(es24.16e3)', es_e3_text(x, 7) of
   !> '(es14.6e3)'. `digits` in 1 .. 17.
   function es_e3_text(value, digits) result(text)
      real(dp), intent(in) :: value
      integer, intent(in) :: digits
      character(len=digits + 7) :: text
      call c_format_es_e3(value, digits, text)
   end function es_e3_text

   !> Open (replace) `file_name` for writing; stat /= 0 and msg say why not.
   subroutine text_stream_open(self, file_name)
      class(text_stream_t), intent(out) :: self
      character(len=*), intent(in) :: file_name
      type(error_t), allocatable :: error
      ! a new file, never written through a link left at its name (issue 23): the name is
      ! removed first (a link itself, never its target); status 'new' creates it with O_EXCL,
      ! which refuses a link that reappears in between
      call remove_file(file_name, error)
      if (allocated(error)) then
         self%unit = -1
         self%stat = 1
         self%msg = error%message
         return
      end if
      open (newunit=self%unit, file=file_name, access='stream', form='unformatted', &
         status='new', action='write', iostat=self%stat, iomsg=self%msg)
      if (self%stat /= 0) then
         self%unit = -1
         return
      end if
      allocate (character(len=chunk_bytes) :: self%buffer)
      self%used = 0
   end subroutine text_stream_open

   !> Room for `bytes` more in the buffer: written out first when needed, grown when one item
   !> is larger than the buffer.
   subroutine make_room(self, bytes)
      class(text_stream_t), intent(inout) :: self
      integer(i8), intent(in) :: bytes
      if (self%used + bytes <= len(self%buffer, kind=i8)) return
      call self%flush()
      if (bytes > len(self%buffer, kind=i8)) then
         deallocate (self%buffer)
         allocate (character(len=bytes) :: self%buffer)
      end if
   end subroutine make_room

   !> `text` and a newline, as '(a)' writes it.
   subroutine text_stream_put_line(self, text)
      class(text_stream_t), intent(inout) :: self
      character(len=*), intent(in) :: text
      if (self%stat /= 0) return
      call make_room(self, len(text, kind=i8) + 1)
      if (self%stat /= 0) return
      self%buffer(self%used + 1:self%used + len(text)) = text
      self%used = self%used + len(text) + 1
      self%buffer(self%used:self%used) = new_line('a')
   end subroutine text_stream_put_line

   !> One line of integers as '(*(i0, :, 1x))' writes it.
   subroutine text_stream_put_integers(self, values)
      class(text_stream_t), intent(inout) :: self
      integer, intent(in) :: values(:)
      if (self%stat /= 0) return
      call make_room(self, 12_i8 * size(values) + 1)
      if (self%stat /= 0) return
      self%used = self%used + int(c_format_i0_line(size(values), values, &
         self%buffer(self%used + 1:)))
   end subroutine text_stream_put_integers

   !> One line with `value` as '(es(digits+7).(digits-1)e3)' writes it.
   subroutine text_stream_put_es(self, value, digits)
      class(text_stream_t), intent(inout) :: self
      real(dp), intent(in) :: value
      integer, intent(in) :: digits
      call self%put_line(es_e3_text(value, digits))
   end subroutine text_stream_put_es

   !> size(values)/3 lines as '(i0, 3(1x, esW.DE3))' writes them (W = digits + 7,
   !> D = digits - 1): line i is the tag first_tag + i - 1 and values(3i-2:3i).
   subroutine text_stream_put_tagged_es_lines(self, first_tag, values, digits)
      class(text_stream_t), intent(inout) :: self
      integer, intent(in) :: first_tag
      real(dp), intent(in), contiguous :: values(:)
      integer, intent(in) :: digits
      integer :: line_bytes, num_lines, done, batch
      line_bytes = 12 + 3 * (digits + 8)
      num_lines = size(values) / 3
      done = 0
      do while (done < num_lines .and. self%stat == 0)
         batch = min(num_lines - done, (len(self%buffer) - self%used) / line_bytes)
         if (batch < 1) then
            call make_room(self, int(line_bytes, i8))
            cycle
         end if
         self%used = self%used + int(c_format_tagged_es_lines(first_tag + done, batch, &
            values(3 * done + 1:), digits, self%buffer(self%used + 1:)))
         done = done + batch
      end do
   end subroutine text_stream_put_tagged_es_lines

   !> Write the buffered text to the file.
   subroutine text_stream_flush(self)
      class(text_stream_t), intent(inout) :: self
      if (self%stat /= 0 .or. self%used == 0) return
      write (self%unit, iostat=self%stat, iomsg=self%msg) self%buffer(1:self%used)
      self%used = 0
   end subroutine text_stream_flush

end module ffrf_io_text_stream
