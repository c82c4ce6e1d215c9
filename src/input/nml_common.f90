!> Shared helper of the namelist readers: the error text of a failed namelist read (a fallback:
!> ffrf_input_nml_source checks groups, keys and types before any namelist read).
module ffrf_input_nml_common
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: namelist_read_error

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

end module ffrf_input_nml_common
