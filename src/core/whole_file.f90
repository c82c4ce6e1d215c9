!> A whole file read into one string with one stream read, inside the input-file serial section
!> (Fortran connects a file to one unit at a time in the process: two threads reading one mesh
!> or case take turns). The caller words the error: this reports which step failed and the
!> runtime's message.
module ffrf_core_whole_file
   use ffrf_core_kinds, only: i8
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_FILES
   implicit none
   private
   public :: read_whole_file, READ_OK, READ_OPEN_FAILED, READ_TOO_LARGE, READ_NO_MEMORY, &
      READ_FAILED

   integer, parameter :: READ_OK = 0           !< text holds the file
   integer, parameter :: READ_OPEN_FAILED = 1  !< open failed (message: the runtime's)
   integer, parameter :: READ_TOO_LARGE = 2    !< size unknown or above max_bytes (size: as seen)
   integer, parameter :: READ_NO_MEMORY = 3    !< the text could not be allocated
   integer, parameter :: READ_FAILED = 4       !< the read failed (message: the runtime's)

contains

   !> The bytes of `file_name` into `text`; `step` READ_OK or the step that failed, `size` the
   !> file's size in bytes as inquired (0 when unknown and not checked), `message` the
   !> runtime's text of a failed open or read.
   subroutine read_whole_file(file_name, text, step, size, message, max_bytes)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable, intent(out) :: text
      integer, intent(out) :: step
      integer(i8), intent(out) :: size
      character(len=*), intent(out) :: message
      !> Refuse a size that is unknown (< 0) or above this (READ_TOO_LARGE); absent: a negative
      !> size counts as 0 bytes
      integer(i8), intent(in), optional :: max_bytes
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
