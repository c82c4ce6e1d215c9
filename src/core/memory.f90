!> Memory of the machine and of this process, for refusing a run that would not fit before it
!> is killed (the MUMPS memory check, ffrf_la_mumps): MemAvailable of /proc/meminfo (what can
!> still be allocated without swapping, page cache included) and VmRSS of /proc/self/status.
module ffrf_core_memory
   use ffrf_core_kinds, only: i8
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_FILES
   implicit none
   private
   public :: available_memory_mb, resident_memory_mb, read_proc_field

contains

   !> MemAvailable of /proc/meminfo in MB (10^6 bytes); -1 if unknown (no /proc).
   function available_memory_mb() result(mb)
      integer(i8) :: mb
      mb = proc_field_mb('/proc/meminfo', 'MemAvailable:')
   end function available_memory_mb

   !> Resident memory of this process (VmRSS of /proc/self/status) in MB; -1 if unknown.
   function resident_memory_mb() result(mb)
      integer(i8) :: mb
      mb = proc_field_mb('/proc/self/status', 'VmRSS:')
   end function resident_memory_mb

   !> The value of a "Name:  1234 kB" line of a /proc file, in MB (10^6 bytes); -1 if absent.
   function proc_field_mb(file_name, field) result(mb)
      character(len=*), intent(in) :: file_name, field
      integer(i8) :: mb, kib
      logical :: found
      mb = -1
      call read_proc_field(file_name, field, kib, found)
      if (found) mb = kib * 1024_i8 / 1000000_i8
   end function proc_field_mb

   !> The value (kB) of the first "Name:  1234 kB" line of a /proc file whose start is `field`
   !> ('VmHWM:'); `found` false if the file, the line or a number there is missing.
   subroutine read_proc_field(file_name, field, kib, found)
      character(len=*), intent(in) :: file_name, field
      integer(i8), intent(out) :: kib
      logical, intent(out) :: found
      character(len=256) :: line
      integer :: unit, stat
      kib = 0
      found = .false.
      ! one unit per file in the process (Fortran 2008, 9.5.4): threads take turns
      call enter_serial_section(SECTION_FILES)
      open (newunit=unit, file=file_name, action='read', status='old', iostat=stat)
      if (stat /= 0) then
         call leave_serial_section(SECTION_FILES)
         return
      end if
      do
         read (unit, '(a)', iostat=stat) line
         if (stat /= 0) exit
         if (line(1:len(field)) == field) then
            read (line(len(field) + 1:), *, iostat=stat) kib
            found = stat == 0
            exit
         end if
      end do
      close (unit)
      call leave_serial_section(SECTION_FILES)
   end subroutine read_proc_field

end module ffrf_core_memory
