!> Shared helpers of the namelist readers: the error text of a failed namelist read, and the
!> check that every group in a case file is one ffrf knows (a misspelt group name would
!> otherwise be skipped silently by the namelist reads).
module ffrf_io_nml_common
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_lower, to_str, join_words
   implicit none
   private
   public :: namelist_read_error, check_group_names

contains

   !> "&interface #2: Cannot match namelist object name rcc (keys: body, name, ...)".
   subroutine namelist_read_error(error, group, occurrence, message, keys)
      type(error_t), allocatable, intent(out) :: error
      !> Group name without '&'
      character(len=*), intent(in) :: group
      !> Which occurrence of a repeated group (0 for a single group)
      integer, intent(in) :: occurrence
      !> The iomsg of the read
      character(len=*), intent(in) :: message
      !> The valid keys of the group, for the hint
      character(len=*), intent(in) :: keys
      character(len=:), allocatable :: where
      where = '&' // group
      if (occurrence > 0) where = where // ' #' // to_str(occurrence)
      call fatal_error(error, FFRF_INPUT_ERROR, where // ': ' // trim(message) // &
         ' (valid keys: ' // keys // ')')
   end subroutine namelist_read_error

   !> Every line starting with '&' must name a known group.
   subroutine check_group_names(unit, known, error)
      !> Open case file
      integer, intent(in) :: unit
      !> Known group names (lower case, without '&')
      character(len=*), intent(in) :: known(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=512) :: line
      character(len=64) :: name
      integer :: stat, line_number, finish
      character(len=256) :: msg
      rewind (unit)
      line_number = 0
      do
         read (unit, '(a)', iostat=stat, iomsg=msg) line
         if (is_iostat_end(stat)) exit
         if (stat /= 0) then
            call fatal_error(error, FFRF_IO_ERROR, 'line ' // to_str(line_number + 1) // ': ' // &
               trim(msg))
            return
         end if
         line_number = line_number + 1
         line = adjustl(line)
         if (line(1:1) /= '&') cycle
         finish = scan(line(2:), ' /,')
         if (finish == 0) finish = len_trim(line)
         name = to_lower(line(2:finish))
         if (len_trim(name) == 0 .or. trim(name) == 'end') cycle
         if (.not. any(known == name)) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'line ' // to_str(line_number) // &
               ': unknown namelist group &' // trim(name) // '; groups are &' // &
               join_words(known, ', &'))
            return
         end if
      end do
      rewind (unit)
   end subroutine check_group_names

end module ffrf_io_nml_common
