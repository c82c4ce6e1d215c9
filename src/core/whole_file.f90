!> A whole file read into one string with one stream read, inside the input-file serial section
!> (Fortran connects a file to one unit at a time in the process: two threads reading one mesh
!> or case take turns). The caller words the error: this reports which step failed and the
!> runtime's message.
module ffrf_core_whole_file
   use, intrinsic :: iso_c_binding, only: c_int, c_long_long, c_char, c_null_char
   use ffrf_core_kinds, only: i8
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_FILES
   implicit none
   private
   public :: read_whole_file, READ_OK, READ_OPEN_FAILED, READ_TOO_LARGE, READ_NO_MEMORY, &
      READ_FAILED, read_file_head, content_end

   integer, parameter :: READ_OK = 0           !< text holds the file
   integer, parameter :: READ_OPEN_FAILED = 1  !< open failed (message: the runtime's)
   integer, parameter :: READ_TOO_LARGE = 2    !< size unknown or above max_bytes (size: as seen)
   integer, parameter :: READ_NO_MEMORY = 3    !< the text could not be allocated
   integer, parameter :: READ_FAILED = 4       !< the read failed (message: the runtime's)

   interface
      integer(c_int) function c_content_end(path, end, nul_after) &
            bind(c, name='ffrf_content_end')
         import :: c_int, c_long_long, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_long_long), intent(out) :: end
         integer(c_int), intent(out) :: nul_after
      end function c_content_end
   end interface

contains

   !> The bytes of the regular file `file_name` from byte `first` on (at most len(head); `got` of
   !> them), read before the file is read whole so that a file of another kind is refused at
   !> once (a 2 GB sparse file named .msh). stat /= 0: the open or read failed (message: the
   !> runtime's).
   subroutine read_file_head(file_name, first, head, got, stat, message)
      character(len=*), intent(in) :: file_name
      !> First byte to read (1-based)
      integer(i8), intent(in) :: first
      character(len=*), intent(out) :: head
      integer, intent(out) :: got, stat
      character(len=*), intent(out) :: message
      integer :: unit, closed
      integer(i8) :: size
      message = ''
      head = ''
      got = 0
      call enter_serial_section(SECTION_FILES)
      open (newunit=unit, file=file_name, access='stream', form='unformatted', status='old', &
         action='read', iostat=stat, iomsg=message)
      if (stat == 0) then
         inquire (unit=unit, size=size)
         got = int(max(0_i8, min(size - first + 1, len(head, kind=i8))))
         if (got > 0) read (unit, pos=first, iostat=stat, iomsg=message) head(:got)
         close (unit, iostat=closed)
      end if
      call leave_serial_section(SECTION_FILES)
   end subroutine read_file_head

   !> The content of the regular file `file_name` ends at byte `end` (1-based; 0: none): the
   !> bytes after it are NUL or blank (`nul_after`: some are NUL, holes of a sparse file
   !> included). Found from the end of the file without reading it whole (file_content.c);
   !> stat: 0 or the errno of a failure.
   subroutine content_end(file_name, end, nul_after, stat)
      character(len=*), intent(in) :: file_name
      integer(i8), intent(out) :: end
      logical, intent(out) :: nul_after
      integer, intent(out) :: stat
      integer(c_long_long) :: c_end
      integer(c_int) :: c_nul
      stat = int(c_content_end(file_name // c_null_char, c_end, c_nul))
      end = int(c_end, i8)
      nul_after = c_nul /= 0
   end subroutine content_end

   !> The bytes of `file_name` into `text`; `step` READ_OK or the step that failed, `size` the
   !> file's size in bytes as inquired (0 when unknown and not checked), `message` the
   !> runtime's text of a failed open or read.
   subroutine read_whole_file(file_name, text, step, size, message, max_bytes, content_bytes)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable, intent(out) :: text
      integer, intent(out) :: step
      integer(i8), intent(out) :: size
      character(len=*), intent(out) :: message
      !> Refuse a size that is unknown (< 0) or above this (READ_TOO_LARGE); absent: a negative
      !> size counts as 0 bytes
      integer(i8), intent(in), optional :: max_bytes
      !> Read only the first `content_bytes` bytes (the content of content_end), when fewer
      !> than the file's size
      integer(i8), intent(in), optional :: content_bytes
      integer :: unit, stat
      message = ''
      size = 0
      call enter_serial_section(SECTION_FILES)
      open (newunit=unit, file=file_name, access='stream', form='unformatted', status='old', &
         action='read', iostat=stat, iomsg=message)
      if (stat /= 0) then
         step = READ_OPEN_FAILED
      else
         step = READ_OK
         inquire (unit=unit, size=size)
         if (present(max_bytes)) then
            if (size < 0 .or. size > max_bytes) step = READ_TOO_LARGE
         else if (size < 0) then
            size = 0
         end if
         if (present(content_bytes)) size = max(0_i8, min(size, content_bytes))
         if (step == READ_OK) then
            allocate (character(len=size) :: text, stat=stat)
            if (stat /= 0) step = READ_NO_MEMORY
         end if
         if (step == READ_OK .and. size > 0) then
            read (unit, iostat=stat, iomsg=message) text
            if (stat /= 0) step = READ_FAILED
         end if
         close (unit, iostat=stat)
      end if
      call leave_serial_section(SECTION_FILES)
   end subroutine read_whole_file

end module ffrf_core_whole_file
