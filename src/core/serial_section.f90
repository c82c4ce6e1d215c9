!> Process-wide serial sections around third-party libraries with global state (serial_section.c):
!> ARPACK's reverse communication, every MUMPS, METIS and HDF5 call, and
!> the reading of an input file. Inside a section one thread at a time;
!> the same thread may enter again (recursive). Everything else in ffrf lives in its handles.
module ffrf_core_serial_section
   use, intrinsic :: iso_c_binding, only: c_int
   implicit none
   private
   public :: SECTION_ARPACK, SECTION_HDF5, SECTION_MUMPS, SECTION_METIS, SECTION_FILES
   public :: enter_serial_section, leave_serial_section

   integer, parameter :: SECTION_ARPACK = 0  !< dsaupd ... dseupd of one eigenproblem
   integer, parameter :: SECTION_HDF5 = 1    !< one call of the HDF5 library (io/hdf5.f90)
   integer, parameter :: SECTION_MUMPS = 2   !< one call of MUMPS (la/mumps.f90)
   integer, parameter :: SECTION_METIS = 3   !< one METIS_NodeND (la/metis.f90)
   !> open ... close of an input file: Fortran connects a file to one unit at a time in the
   !> process (Fortran 2008, 9.5.4), so two threads reading one mesh would fail
   integer, parameter :: SECTION_FILES = 4

   interface
      integer(c_int) function c_serial_enter(k) bind(c, name='ffrf_serial_enter')
         import :: c_int
         integer(c_int), value :: k
      end function c_serial_enter
      integer(c_int) function c_serial_leave(k) bind(c, name='ffrf_serial_leave')
         import :: c_int
         integer(c_int), value :: k
      end function c_serial_leave
   end interface

contains

   !> Wait until no other thread is inside `section`, then enter it. pthread_mutex_lock on a
   !> valid recursive mutex cannot fail short of a corrupted process, so no status is returned.
   subroutine enter_serial_section(section)
      integer, intent(in) :: section
      integer(c_int) :: status
      status = c_serial_enter(int(section, c_int))
   end subroutine enter_serial_section

   !> Leave `section` (entered by this thread with enter_serial_section).
   subroutine leave_serial_section(section)
      integer, intent(in) :: section
      integer(c_int) :: status
      status = c_serial_leave(int(section, c_int))
   end subroutine leave_serial_section

end module ffrf_core_serial_section
