!> The results schema's version (docs/results.md "Schema version"): the root attribute
!> `schema_version` = "MAJOR.MINOR" every results file carries, and the check a reader of a results
!> file makes before it trusts the layout (a newer major is refused, an older one or none is read).
module ffrf_io_schema
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_io_hdf5, only: h5_file_t
   implicit none
   private
   public :: RESULTS_SCHEMA_VERSION, check_schema_version

   !> The minor grows with additions, the major with a change an older reader would misread
   character(len=*), parameter :: RESULTS_SCHEMA_VERSION = '1.0'

contains

   !> Refuse an open results file whose schema major is newer than this ffrf's; a file without
   !> the attribute (written before it existed) is read. `where` names the file in the message.
   subroutine check_schema_version(h5, where, error)
      type(h5_file_t), intent(in) :: h5
      character(len=*), intent(in) :: where
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: version

      if (.not. h5%attribute_exists('/', 'schema_version')) return
      call h5%read_attribute('/', 'schema_version', version, error)
      if (allocated(error)) return
      if (schema_major(version) > schema_major(RESULTS_SCHEMA_VERSION) &
          .or. schema_major(version) < 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': results schema "' // version // &
            '", this ffrf reads up to ' // RESULTS_SCHEMA_VERSION(1:index(RESULTS_SCHEMA_VERSION, &
            '.')) // 'x; use the ffrf that wrote the file, or compute the modes again')
      end if
   end subroutine check_schema_version

   !> The MAJOR of "MAJOR.MINOR", or -1 when the text is not of that form
   integer function schema_major(version) result(major)
      character(len=*), intent(in) :: version
      integer :: dot, minor, status

      major = -1
      dot = index(version, '.')
      if (dot < 2 .or. dot == len_trim(version)) return
      if (verify(version(1:dot - 1), '0123456789') /= 0) return
      if (verify(trim(version(dot + 1:)), '0123456789') /= 0) return
      read (version(1:dot - 1), *, iostat=status) major
      if (status /= 0) major = -1
      read (version(dot + 1:), *, iostat=status) minor
      if (status /= 0) major = -1
   end function schema_major
end module ffrf_io_schema
